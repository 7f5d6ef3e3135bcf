"""report.html from report.json, without a browser: what the page says for a partial run, for
skipped stages in either shape, for findings whose text holds markup, and its pictures."""

from __future__ import annotations

import base64
import re

from vmach.report.html import render_html, verdict, write_html

PNG = base64.b64decode(
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg==")


def report(**over) -> dict:
    data = {
        "vmach": "0.1.0",
        "program": {"path": "dir/P.MPF", "completed": True, "blocks": 10, "moves": 4},
        "machine": {"name": "s5d"}, "tools": "t.toml", "stock": "box:x=1,y=1,z=1",
        "summary": {"errors": 1, "warnings": 1, "infos": 0},
        "findings": [
            {"severity": "error", "kind": "rapid_into_stock", "file": "dir/P.MPF", "line": 7, "column": 1,
             "message": "a <b>bold</b> claim & more", "move_index": 3, "volume_mm3": 1.25,
             "at_mm": [-0.0, 1.0, 2.5]},
            {"severity": "warning", "kind": "near_miss", "file": "dir/P.MPF", "line": 9, "column": 1,
             "message": "close", "distance_mm": 0.4},
        ],
        "simulation": None, "profile": None, "cycle_time_s": 12.0, "images": {},
        "timings_s": {"total": 1.0},
    }
    data.update(over)
    return data


def rows(page: str) -> list[str]:
    return re.findall(r"<tr data-index='(\d+)' data-severity='(\w+)' data-kind='(\w+)'>", page)


def test_every_finding_is_a_row_with_its_source_line_and_numbers(tmp_path):
    page = render_html(report(), tmp_path, sources=["N70 G0 X<5", None])
    assert rows(page) == [("0", "error", "rapid_into_stock"), ("1", "warning", "near_miss")]
    assert "N70 G0 X&lt;5" in page and "P.MPF:7" in page and "P.MPF:9" in page
    assert "a &lt;b&gt;bold&lt;/b&gt; claim &amp; more" in page and "<b>bold</b>" not in page
    assert "volume_mm3=1.25" in page and "at_mm=[0, 1, 2.5]" in page and "distance_mm=0.4" in page
    assert verdict(report()) == ("fail", "FAIL")


def test_a_partial_run_and_skipped_stages_are_said(tmp_path):
    program = {"path": "P.MPF", "completed": False, "stopped_at": {"file": "P.MPF", "line": 5}}
    stopped = report(summary={"errors": 0, "warnings": 0, "infos": 0}, findings=[], partial=True,
                     program=program,
                     skipped={"stock": "no tool library (give --tools)"})
    assert verdict(stopped) == ("partial", "INCOMPLETE")
    page = render_html(stopped, tmp_path)
    assert "stopped at P.MPF:5" in page and "stock: no tool library (give --tools)" in page
    assert "<p>No findings.</p>" in page
    # a list of objects is shown as well, whatever report.json carries
    listed = render_html(report(skipped=[{"stage": "profile", "reason": "no stock", "code": 3}]), tmp_path)
    assert 'profile: no stock ({"code": 3})' in listed.replace("&quot;", '"')
    clean = report(summary={"errors": 0, "warnings": 0, "infos": 0}, findings=[], skipped={})
    assert verdict(clean) == ("pass", "PASS")


def test_pictures_are_embedded_and_a_picture_the_report_does_not_list_is_not(tmp_path):
    (tmp_path / "toolpath.png").write_bytes(PNG)
    (tmp_path / "old.png").write_bytes(PNG)
    out = write_html(tmp_path / "report.html", report(images={"toolpath": "toolpath.png"}))
    page = out.read_text(encoding="utf-8")
    assert page.count("data:image/png;base64,") == 1 and "old.png" not in page
    assert not re.search(r"""(src|href)=['"]?https?:""", page)
