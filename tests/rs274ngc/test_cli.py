"""End to end through the command line: ``vmach run`` and ``vmach check`` on .ngc files."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vmach.cli import main

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "rs274ngc"


def _expected(name: str) -> str:
    return (FIXTURES / f"{name}.expected").read_text(encoding="utf-8")


@pytest.fixture
def in_fixtures(monkeypatch):
    monkeypatch.chdir(FIXTURES)


def test_run_format_rs274_prints_the_rs274_trace(in_fixtures, capsys):
    rc = main(["run", "arcs_helix_turns.ngc", "--format", "rs274"])
    out, err = capsys.readouterr()
    assert rc == 0
    assert out == _expected("arcs_helix_turns")
    assert err == ""


def test_run_format_rs274_with_tool_table(in_fixtures, capsys):
    rc = main(["run", "tools_table.ngc", "--format", "rs274", "--tool-table", "tools_table.tbl"])
    out, _ = capsys.readouterr()
    assert rc == 0
    assert out == _expected("tools_table")


def test_run_format_rs274_error_exit_code_and_diagnostic(in_fixtures, capsys):
    rc = main(["run", "error_arc_radius_mismatch.ngc", "--format", "rs274"])
    out, err = capsys.readouterr()
    assert rc == 1
    assert out == _expected("error_arc_radius_mismatch")
    first = err.splitlines()[0]
    assert first.startswith("error_arc_radius_mismatch.ngc:3:1: error[arc_radius_mismatch]: ")
    stderr = (FIXTURES / "error_arc_radius_mismatch.stderr").read_text().splitlines()
    assert first.endswith(stderr[1])


def test_run_format_json(capsys):
    rc = main(["run", str(FIXTURES / "g10_l2_l20.ngc"), "--format", "json"])
    out, _ = capsys.readouterr()
    assert rc == 0
    rows = [json.loads(line) for line in out.splitlines()]
    kinds = {r["kind"] for r in rows}
    assert {"traverse", "frame", "program_end"} <= kinds
    first_move = next(r for r in rows if r["kind"] == "traverse")
    assert first_move["axes"] == {"X": 10.0, "Y": 20.0, "Z": -5.0}  # G0 X0 Y0 Z0 in G54
    assert first_move["line"] == 4
    assert rows[-1] == {"kind": "program_end", "file": str(FIXTURES / "g10_l2_l20.ngc"),
                        "line": 11, "code": "M2"}


def test_run_text_format(capsys):
    rc = main(["run", str(FIXTURES / "basic_lines.ngc")])
    out, _ = capsys.readouterr()
    assert rc == 0
    assert "feed" in out and "X=25.4000" in out


def test_check_clean_ngc(capsys):
    rc = main(["check", str(FIXTURES / "sub_named_nested.ngc")])
    out, err = capsys.readouterr()
    assert rc == 0
    assert err == ""
    assert out.splitlines() == [f"{FIXTURES / 'sub_named_nested.ngc'}: 0 error(s), 0 warning(s)"]


def test_check_reports_diagnostics(capsys):
    rc = main(["check", str(FIXTURES / "error_nested_comment.ngc")])
    out, _ = capsys.readouterr()
    assert rc == 1
    assert "error_nested_comment.ngc:2:10: error[nested_comment]: Nested comment found" in out


def test_check_json(capsys):
    rc = main(["check", str(FIXTURES / "error_unknown_g.ngc"), "--format", "json"])
    out, _ = capsys.readouterr()
    assert rc == 1
    (finding,) = json.loads(out)
    assert (finding["kind"], finding["line"], finding["column"]) == ("unknown_g_code", 2, 1)
