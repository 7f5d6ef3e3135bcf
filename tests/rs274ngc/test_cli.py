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


def test_tool_table_applies_to_the_canonical_formats_too(tmp_path, capsys):
    """--tool-table is LinuxCNC's table for every format: its tool 7 exists and G41 takes
    its diameter (0.5 in: the path lies 6.35 mm beside the programmed one)."""
    (tmp_path / "t.tbl").write_text("T7 P7 Z2.0 D0.5\n", encoding="utf-8")
    prog = tmp_path / "p.ngc"
    prog.write_text("G21 G90 T7 M6\nG0 X0 Y-20\nG41 G1 Y0 F100\nG1 Y10\nG40 G0 X0 Y30\nM2\n",
                    encoding="utf-8")
    assert main(["run", str(prog), "--format", "json"]) == 1  # rs274's table has no tool 7
    capsys.readouterr()
    for fmt in ("json", "text"):
        assert main(["run", str(prog), "--format", fmt, "--tool-table",
                     str(tmp_path / "t.tbl")]) == 0
        out = capsys.readouterr().out
        if fmt == "json":
            feeds = [json.loads(line)["axes"] for line in out.splitlines()
                     if json.loads(line)["kind"] == "feed"]
            assert [round(f["X"], 6) for f in feeds] == [-6.35, -6.35]


def test_var_file_is_read_and_the_result_written_into_a_copy(tmp_path, capsys):
    var = tmp_path / "m.var"
    var.write_text("31\t2.000000\n5220\t1.000000\n5221\t1.000000\n", encoding="utf-8")
    prog = tmp_path / "p.ngc"
    prog.write_text("(PRINT,#31 #5221)\n#31 = [#31 + 1]\nG10 L2 P1 X5\nM2\n", encoding="utf-8")
    assert main(["run", str(prog), "--format", "rs274", "--var-file", str(var)]) == 0
    out = capsys.readouterr().out
    assert "2.000000 1.000000" in out  # read from the file (#5221 in inches)
    assert "SET_G5X_OFFSET(1, 25.4000," in out
    assert var.read_text(encoding="utf-8").startswith("31\t2.000000\n")  # untouched
    copy = tmp_path / "m.vmach.var"
    saved = dict(line.split("\t") for line in copy.read_text(encoding="utf-8").splitlines())
    assert float(saved["31"]) == 3.0
    assert abs(float(saved["5221"]) - 5 / 25.4) < 1e-6
    assert "5390" in saved  # LinuxCNC's required parameters are always written
    # asked to: into the file itself, the old one kept as .bak
    assert main(["run", str(prog), "--format", "text", "--var-file", str(var),
                 "--var-file-update"]) == 0
    assert (tmp_path / "m.var.bak").read_text(encoding="utf-8").startswith("31\t2.000000\n")
    assert var.read_text(encoding="utf-8").startswith("31\t3.000000\n")


def test_continue_after_error_reports_every_error_and_goes_on(tmp_path, capsys):
    prog = tmp_path / "p.ngc"
    prog.write_text("G0 X1\n#1 = [1/0]\nG0 X2\nG1 X3 F-1\nG0 X4\nM2\n", encoding="utf-8")
    assert main(["run", str(prog), "--format", "rs274"]) == 1
    assert "X4" not in capsys.readouterr().out
    assert main(["run", str(prog), "--format", "rs274", "--continue-after-error"]) == 1
    out, err = capsys.readouterr()
    assert "STRAIGHT_TRAVERSE(4.0000" in out and "PROGRAM_END()" in out
    assert [line.split(": ")[0] for line in err.splitlines() if "error[" in line] == [
        f"{prog}:2:6", f"{prog}:4:7"]


def test_ini_subroutine_path_is_searched_after_the_program_directory(tmp_path, capsys):
    lib = tmp_path / "cfg" / "lib"
    lib.mkdir(parents=True)
    (lib / "probe.ngc").write_text("o<probe> sub\n(PRINT,lib #<_ini[vars]depth>)\n"
                                   "o<probe> endsub\nM2\n", encoding="utf-8")
    ini = tmp_path / "cfg" / "machine.ini"
    ini.write_text("[RS274NGC]\nSUBROUTINE_PATH = lib\n[VARS]\nDEPTH = 4\n", encoding="utf-8")
    work = tmp_path / "work"
    work.mkdir()
    prog = work / "p.ngc"
    prog.write_text("o<probe> call\nM2\n", encoding="utf-8")
    assert main(["run", str(prog), "--format", "rs274"]) == 1  # not without the INI
    capsys.readouterr()
    assert main(["run", str(prog), "--format", "rs274", "--ini", str(ini)]) == 0
    assert "lib 4.000000" in capsys.readouterr().out
    (work / "probe.ngc").write_text("o<probe> sub\n(PRINT,beside)\no<probe> endsub\n",
                                    encoding="utf-8")
    assert main(["run", str(prog), "--format", "rs274", "--ini", str(ini)]) == 0
    assert "beside" in capsys.readouterr().out


def test_verify_honours_the_tool_table(tmp_path, capsys):
    """verify reads the LinuxCNC tool table too: tool 7 exists only in it."""
    (tmp_path / "v.tbl").write_text("T7 P7 Z0.5 D0.25\n", encoding="utf-8")
    prog = tmp_path / "v.ngc"
    prog.write_text("G21 G90 G17\nT7 M6\nS1000 M3\nG0 X-20 Y-20 Z5\nG41 G1 X0 Y0 Z-1 F200\n"
                    "G1 X30\nG1 Y30\nG40 G0 X50 Y50 Z5\nM5 M2\n", encoding="utf-8")
    base = ["verify", str(prog), "--machine", "s5d", "--stock", "box:x=40,y=40,z=10",
            "--no-images", "--quiet", "--format", "json"]
    assert main([*base, "--out", str(tmp_path / "a")]) == 1
    report = json.loads(capsys.readouterr().out)
    assert [f["kind"] for f in report["findings"] if f["severity"] == "error"] == ["tool_not_found"]
    assert report["partial"]
    # the tool table lets the run reach its end; the tool's solid is the --default-tool stand-in
    # (a LinuxCNC tool table gives offsets, not a cutter; without a stand-in: unknown_tool)
    assert main([*base, "--out", str(tmp_path / "b"), "--tool-table", str(tmp_path / "v.tbl"),
                 "--default-tool", "flat:d=0.5"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert [f for f in report["findings"] if f["severity"] == "error"] == []
    assert not report["partial"] and report["skipped"] == {}
