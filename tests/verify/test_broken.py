"""A set of small, realistic broken programs and setups (``tests/verify/broken/*``, written for
this test, both dialects): each gives the finding it must and never a clean pass; the few
unbroken ones beside them (``clean``: a feed in the air after M5, T0) pass clean.

Each case directory holds a program, its ``vmach.toml`` (and tools), and ``expect.json``:
``exit`` (the exit code), ``errors`` (the exact errors as [kind, line]; line 0: no place),
``errors_include``, ``warnings`` (included), ``skipped`` (the stages report.json names),
``partial``/``stopped_at`` (an unfinished run), ``no_cycle_time``, ``simulated``, ``clean``,
``args`` (more options).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from vmach.cli import main

BROKEN = Path(__file__).resolve().parent / "broken"
CASES = sorted(p.name for p in BROKEN.iterdir() if (p / "expect.json").is_file())


def _run(tmp_path, name, capsys):
    job = tmp_path / name
    shutil.copytree(BROKEN / name, job)
    expect = json.loads((job / "expect.json").read_text())
    out = tmp_path / "out"
    code = main(["verify", str(job / expect["program"]), "--out", str(out), "--no-images", "--format", "json",
                 *expect.get("args", [])])
    cap = capsys.readouterr()
    return expect, code, cap


def _kl(findings, severity):
    return sorted((f["kind"], f["line"] or 0) for f in findings if f["severity"] == severity)


@pytest.mark.parametrize("name", CASES)
def test_broken_case_gives_its_finding(tmp_path, capsys, name):
    expect, code, cap = _run(tmp_path, name, capsys)
    assert code == expect["exit"], cap.out + cap.err
    if code == 2:
        # refused before anything ran: the diagnostics on stderr, one per problem, no report
        got = sorted((ln.split("error[")[1].split("]")[0], int(ln.split(":")[1]) if ln.split(":")[1].isdigit()
                      else 0) for ln in cap.err.splitlines() if "error[" in ln)
        assert got == sorted(map(tuple, expect["errors"]))
        assert not (tmp_path / "out" / "report.json").exists()
        return
    data = json.loads(cap.out)
    assert data == json.loads((tmp_path / "out" / "report.json").read_text())
    errors = _kl(data["findings"], "error")
    warnings = _kl(data["findings"], "warning")
    if "errors" in expect:
        assert errors == sorted(map(tuple, expect["errors"]))
    for want in expect.get("errors_include", []):
        assert tuple(want) in errors
    for kind, line in expect.get("warnings", []):
        assert any(k == kind and (line == 0 or n == line) for k, n in warnings), warnings
    if "skipped" in expect:
        assert sorted(data["skipped"]) == sorted(expect["skipped"])
        # each skipped stage is a warning finding too, and says why
        assert sorted(f["stage"] for f in data["findings"] if f["kind"] == "stage_skipped") == sorted(
            expect["skipped"])
    if expect.get("partial"):
        assert data["partial"] is True and data["program"]["completed"] is False
        assert data["program"]["stopped_at"]["file"].endswith(expect["program"])
        if "stopped_at" in expect:
            assert data["program"]["stopped_at"]["line"] == expect["stopped_at"]
    if expect.get("no_cycle_time") or expect.get("partial"):
        assert data["cycle_time_s"] is None and data["cycle_time"] is None
        assert "cycle_time" in data["skipped"]
    if expect.get("simulated"):
        assert data["simulation"] is not None and data["simulation"]["cutters"] > 0
    if expect.get("clean"):
        assert data["findings"] == [] and code == 0
    else:
        # never a clean pass: a broken case has an error, or at least a warning saying what is wrong
        assert errors or warnings


def test_partial_run_text_summary_says_where_it_stopped(tmp_path, capsys):
    job = tmp_path / "job"
    shutil.copytree(BROKEN / "s_runtime_stop", job)
    code = main(["verify", str(job / "FACE.MPF"), "--out", str(tmp_path / "out"), "--no-images"])
    text = capsys.readouterr().out
    assert code == 1
    assert f"stopped at {job / 'FACE.MPF'}:10" in text
    assert "moves (partial)" in text
    assert not any(ln.startswith("cycle time") for ln in text.splitlines())


def test_skipped_stages_are_in_the_text_summary(tmp_path, capsys):
    job = tmp_path / "job"
    shutil.copytree(BROKEN / "s_no_library", job)
    assert main(["verify", str(job / "SLOT.MPF"), "--out", str(tmp_path / "out"), "--no-images"]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert any(ln.startswith("skipped stock: no tool library") for ln in lines)
    assert any(ln.startswith("skipped fixture_collisions:") for ln in lines)
