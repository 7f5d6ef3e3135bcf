"""``vmach run --default-tool``: a CAM post's named tool that the library lacks gets the
stand-in's radius under G41/G42 and a default_tool warning at its tool change (never assumed
silently); without it the compensation stops the run (#32)."""

from __future__ import annotations

import json

from vmach.cli import main

PROGRAM = ('T="END MILL D10" D1 M6\nG0 X-20 Y0 Z5\nG1 Z-1 F300\nG41 G1 X-10 Y0\nG1 Y10\n'
           "G40 G1 X-20\nM30\n")


def test_the_stand_in_gives_the_radius_and_says_so(tmp_path, capsys):
    prog = tmp_path / "NAMED.MPF"
    prog.write_text(PROGRAM)
    trace = tmp_path / "t.jsonl"
    code = main(["run", str(prog), "--machine", "mill3", "--default-tool", "flat:d=8",
                 "--format", "json", "-o", str(trace)])
    err = capsys.readouterr().err
    assert code == 0
    assert "NAMED.MPF:1:1: warning[default_tool]" in err
    xs = [json.loads(line)["axes"]["X"] for line in trace.read_text().splitlines()
          if json.loads(line)["kind"] == "feed"]
    assert xs[1:3] == [-14.0, -14.0]          # 4 mm to the left of X-10 going +Y


def test_the_setup_files_default_tool_serves_run_too(tmp_path, capsys):
    (tmp_path / "NAMED.MPF").write_text(PROGRAM)
    (tmp_path / "vmach.toml").write_text('machine = "mill3"\ndefault_tool = "flat:d=10"\n')
    assert main(["run", str(tmp_path / "NAMED.MPF")]) == 0
    assert "warning[default_tool]" in capsys.readouterr().err


def test_without_a_stand_in_the_compensation_stops_the_run(tmp_path, capsys):
    (tmp_path / "NAMED.MPF").write_text(PROGRAM)
    assert main(["run", str(tmp_path / "NAMED.MPF"), "--machine", "mill3"]) == 1
    assert "NAMED.MPF:4:1: error[no_tool_radius]" in capsys.readouterr().err


def test_a_malformed_stand_in_is_a_usage_error(tmp_path, capsys):
    (tmp_path / "NAMED.MPF").write_text(PROGRAM)
    assert main(["run", str(tmp_path / "NAMED.MPF"), "--machine", "mill3", "--default-tool", "bogus"]) == 2
