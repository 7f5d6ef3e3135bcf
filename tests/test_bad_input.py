"""Holes bad input found in vmach (issue #30), each closed: a clear error with its place and
exit code, never a traceback, never a replaced special file. One test (or more) per defect; the
symlink escape (defect 1) is tests/test_path_escape.py, the slow limits (defect 6)
tests/test_limits_bite.py."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from catalog import ROOT, TURNMILL

from interpreters import rs274ngc, sinumerik
from vmach.cli import main
from vmach.errors import VmachError
from vmach.tol import tol

MILL_TOOLS = ROOT / "fixtures" / "milling" / "tools.toml"


def _prog(d: Path, text: str, name: str = "P.MPF") -> str:
    p = d / name
    p.write_text(text, encoding="utf-8")
    return str(p)


def _model_with(tmp_path: Path, old: str, new: str) -> tuple[Path, int]:
    """turnmill.toml with one line replaced; (the file, that line's number)."""
    text = TURNMILL.read_text(encoding="utf-8")
    assert old in text
    line = text[: text.index(old)].count("\n") + 1
    model = tmp_path / "m.toml"
    model.write_text(text.replace(old, new, 1), encoding="utf-8")
    return model, line


# -- 2: a value of the wrong type in a model ------------------------------------------------------
@pytest.mark.parametrize("value", ["{ a = 1 }", "[1, 2]", '["sinumerik"]', "1", "true", "1979-05-27"])
@pytest.mark.parametrize("command", ["check", "run"])
def test_a_model_dialect_that_is_not_a_name_is_an_error_at_its_key(tmp_path, capsys, command, value):
    model, line = _model_with(tmp_path, 'dialect = "sinumerik"', f"dialect = {value}")
    assert main([command, _prog(tmp_path, "G0 X1\nM30\n"), "--machine", str(model)]) == 2
    err = capsys.readouterr().err
    assert f"{model}:{line}:1: error[bad_value]" in err and "Traceback" not in err


# -- 3: a profile range beside the part ------------------------------------------------------------
GROOVE = ROOT / "fixtures" / "turnmill" / "GROOVE.MPF"
POLYGON_TOOLS = ROOT / "fixtures" / "polygon_shaft" / "tools.toml"


def test_a_profile_range_beside_the_part_is_an_error_finding_and_the_summary_holds(tmp_path, capsys):
    out = tmp_path / "o"
    args = ["verify", str(GROOVE), "--profile", "P3G:14", "--profile-z", "50:60", "--no-images",
            "--out", str(out)]
    assert main(args) == 1
    text = capsys.readouterr().out
    assert "profile P3G" in text and "report:" in text          # the summary ran to its end
    found = [f for f in json.loads((out / "report.json").read_text())["findings"]
             if f["kind"] == "profile_out_of_tolerance"]
    assert len(found) == 1 and found[0]["severity"] == "error"
    assert found[0]["z_range"] == "50:60" and len(found[0]["missing_z"]) == 7


def test_a_profile_range_from_the_setup_file_is_found_at_its_key(tmp_path, capsys):
    (tmp_path / "tools.toml").write_bytes(POLYGON_TOOLS.read_bytes())
    (tmp_path / "vmach.toml").write_text('machine = "turnmill"\ntools = "tools.toml"\n'
                                         'stock = "cylinder:d=40,l=60"\nprofile = "P3G:14"\n'
                                         'profile_z = "50:60"\n')
    p = _prog(tmp_path, GROOVE.read_text(encoding="utf-8"), "GROOVE.MPF")
    assert main(["verify", p, "--no-images", "--out", str(tmp_path / "o")]) == 1
    assert f"{tmp_path / 'vmach.toml'}:5:1: error[profile_out_of_tolerance]" in capsys.readouterr().out


# -- 4: sizes have a lower bound ------------------------------------------------------------------
@pytest.mark.parametrize("stock", ["cylinder:d=1e-300,l=1e-300", "cylinder:d=60,l=1e-9",
                                   "box:x=1e-300,y=10,z=10",
                                   "box:xmin=0,xmax=10,ymin=0,ymax=1e-300,zmin=0,zmax=1"])
def test_a_stock_below_the_smallest_size_is_a_usage_error(tmp_path, capsys, stock):
    p = _prog(tmp_path, "G0 X40 Z5\nM30\n")
    assert main(["verify", p, "--machine", "turnmill", "--tools", str(POLYGON_TOOLS), "--stock", stock,
                 "--no-images", "--out", str(tmp_path / "o")]) == 2
    assert "error[stock_spec]" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_a_tool_below_the_smallest_size_is_an_error_at_its_key(tmp_path, capsys):
    text = MILL_TOOLS.read_text(encoding="utf-8")
    line = text[: text.index("diameter = 10.0\n")].count("\n") + 1
    tools = tmp_path / "tools.toml"
    tools.write_text(text.replace("diameter = 10.0\n", "diameter = 1e-300\n", 1))
    assert main(["run", _prog(tmp_path, "G0 X1\nM30\n"), "--tools", str(tools)]) == 2
    assert f"{tools}:{line}:1: error[tool_library]" in capsys.readouterr().err
    assert tol.min_size > 0


# -- 5: program size and line length, before parsing -----------------------------------------------
def _too_big(path: Path) -> None:
    with open(path, "wb") as fh:                   # sparse: no disk, but read as zeros
        fh.write(b"G0 X1\n")
        fh.truncate(tol.max_program_bytes + 1)


@pytest.mark.parametrize("name, dialect", [("BIG.MPF", sinumerik), ("big.ngc", rs274ngc)])
def test_a_program_larger_than_the_limit_is_refused_at_its_first_line(tmp_path, name, dialect):
    p = tmp_path / name
    _too_big(p)
    found = _findings_of_run_and_check(dialect, p)
    assert found == [("resource_limit", 1)] * 2


@pytest.mark.parametrize("name, dialect, end", [("LONG.MPF", sinumerik, "M30"), ("long.ngc", rs274ngc, "M2")])
def test_a_line_longer_than_the_limit_is_refused_at_that_line(tmp_path, name, dialect, end):
    p = tmp_path / name
    p.write_text(f"G0 X1\nG0 X2\n;{'x' * tol.max_line_length}\n{end}\n")
    assert _findings_of_run_and_check(dialect, p) == [("resource_limit", 3)] * 2
    p.write_text(f"G0 X1\nG0 X2\n;{'x' * (tol.max_line_length - 1)}\n{end}\n")   # at the limit
    assert "resource_limit" not in {f.kind for f in dialect.run(p).findings}   # (LinuxCNC: 256)


def _findings_of_run_and_check(dialect, p: Path) -> list[tuple[str, int]]:
    out = []
    result = dialect.run(p)
    assert not result.completed and not result.commands
    out += [(f.kind, f.line) for f in result.findings if f.is_error]
    try:
        out += [(f.kind, f.line) for f in dialect.check(p) if f.is_error]
    except VmachError as exc:
        out += [(f.kind, f.line) for f in exc.findings()]
    return out


def test_the_cli_says_the_limit_with_its_place(tmp_path, capsys):
    p = tmp_path / "P.MPF"
    p.write_text(f"G0 X1\n;{'x' * 20_000}\nM30\n")
    assert main(["check", str(p)]) == 1
    assert f"{p}:2:1: error[resource_limit]" in capsys.readouterr().err
    assert main(["run", str(p)]) == 1
    assert f"{p}:2:1: error[resource_limit]" in capsys.readouterr().err


# -- 6: a limit bites as fast in verify as in run ----------------------------------------------------
@pytest.mark.parametrize("name, text", [("P.MPF", "LBL: G0 X1\nG0 X0\nR1=R1+1\nGOTOB LBL\nM30\n"),
                                        ("p.ngc", "o100 while [1]\nG0 X1\nG0 X0\no100 endwhile\nM2\n")])
def test_verify_checks_nothing_after_a_run_stopped_at_a_limit(tmp_path, capsys, name, text):
    """A runaway program stops at vmach's limit in the interpreter; verify then builds no move
    table from the moves made, and says of every stage that it was not checked (so the limit
    bites in verify as fast as in run)."""
    p = _prog(tmp_path, text, name)
    out = tmp_path / "o"
    assert main(["verify", p, "--machine", "s5d", "--stock", "box:x=40,y=40,z=10", "--default-tool",
                 "flat:d=10", "--max-blocks", "2000", "--no-images", "--out", str(out)]) == 1
    capsys.readouterr()
    report = json.loads((out / "report.json").read_text())
    assert [f["kind"] for f in report["findings"] if f["severity"] == "error"] == ["block_limit"]
    assert report["partial"] and report["program"]["moves"] == 0
    assert set(report["skipped"]) == {"stock", "fixture_collisions", "cycle_time"}
    assert all("block_limit" in reason for reason in report["skipped"].values())


# -- 7: outputs that are not regular files are written through -------------------------------------
def test_run_output_onto_a_fifo_writes_through_it(tmp_path):
    p = _prog(tmp_path, "G0 X1\nM30\n")
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got = {}
    import threading

    def reader():
        with open(fifo, "rb") as fh:
            got["data"] = fh.read()

    t = threading.Thread(target=reader, daemon=True)   # (left blocked if the pipe is replaced)
    t.start()
    assert main(["run", p, "-o", str(fifo)]) == 0
    t.join(30)
    assert fifo.is_fifo()                          # still the pipe, not a regular file
    assert b"program_end" in got["data"]


def test_run_output_onto_a_link_replaces_its_target_and_keeps_the_link(tmp_path):
    p = _prog(tmp_path, "G0 X1\nM30\n")
    real = tmp_path / "real.txt"
    real.write_text("old\n")
    link = tmp_path / "link.txt"
    link.symlink_to(real.name)
    assert main(["run", p, "-o", str(link)]) == 0
    assert link.is_symlink() and "program_end" in real.read_text()


def test_verify_report_into_a_directory_through_a_link_keeps_the_link(tmp_path, capsys):
    p = _prog(tmp_path, "G0 X40 Z5\nM30\n")
    (tmp_path / "o").mkdir()
    real = tmp_path / "elsewhere.json"
    real.write_text("{}")
    (tmp_path / "o" / "report.json").symlink_to(real)
    assert main(["verify", p, "--machine", "turnmill", "--no-images", "--out", str(tmp_path / "o")]) == 0
    assert (tmp_path / "o" / "report.json").is_symlink()
    assert json.loads(real.read_text())["summary"]["errors"] == 0


# -- 8: smaller ones -----------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["check", "run", "verify"])
def test_a_directory_given_as_the_program_is_named_a_directory(tmp_path, capsys, command):
    (tmp_path / "D.MPF").mkdir()
    assert main([command, str(tmp_path / "D.MPF")]) == 2
    err = capsys.readouterr().err
    assert "error[unreadable]" in err and "is a directory" in err and "no such file" not in err


@pytest.mark.parametrize("machine", ["/dev/null", "empty"])
def test_a_model_without_axes_is_refused(tmp_path, capsys, machine):
    if machine == "empty":
        machine = str(tmp_path / "empty.toml")
        Path(machine).write_text("# nothing\n")
    assert main(["check", _prog(tmp_path, "G0 X1\nM30\n"), "--machine", machine]) == 2
    err = capsys.readouterr().err
    assert "error[" in err and "Traceback" not in err


def test_tools_from_a_device_give_the_same_kind_in_run_and_verify(tmp_path, capsys):
    p = _prog(tmp_path, "G0 X1\nM30\n")
    assert main(["run", p, "--tools", "/dev/null"]) == 2
    run_err = capsys.readouterr().err
    assert main(["verify", p, "--machine", "turnmill", "--tools", "/dev/null", "--no-images",
                 "--out", str(tmp_path / "o")]) == 2
    verify_err = capsys.readouterr().err
    assert "error[unreadable]" in run_err and "error[unreadable]" in verify_err
    assert not (tmp_path / "o").exists()


def test_an_endless_file_as_a_linuxcnc_tool_table_is_refused_at_once(tmp_path, capsys):
    """``/dev/zero`` was read until the memory ran out; now at most 1 MiB is read."""
    p = _prog(tmp_path, "G0 X1\nM2\n", "p.ngc")
    assert main(["run", p, "--format", "rs274", "--tool-table", "/dev/zero"]) == 1
    assert "/dev/zero:1:1: error[unreadable]" in capsys.readouterr().err


@pytest.mark.parametrize("option", ["--machine", "--tools"])
def test_a_model_or_tool_library_larger_than_the_limit_is_refused_at_once(tmp_path, capsys, option):
    big = tmp_path / "big.toml"
    with open(big, "wb") as fh:                    # sparse: read as zeros, never parsed
        fh.truncate(tol.max_config_bytes + 1)
    assert main(["run", _prog(tmp_path, "G0 X1\nM30\n"), option, str(big)]) == 2
    assert f"{big}:1:1: error[input_limit]" in capsys.readouterr().err
