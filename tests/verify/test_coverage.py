"""The pieces of 'never a silent pass' (vmach/coverage.py, vmach/tooling/default.py) and the
report directory a second run leaves."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from vmach.cli import main
from vmach.coverage import merged
from vmach.errors import InputError
from vmach.findings import Finding
from vmach.source import SourceRef
from vmach.tooling.default import WithDefault, parse_default_tool

BROKEN = Path(__file__).resolve().parent / "broken"


def _f(kind, line, severity="error"):
    return Finding(kind, severity, kind, SourceRef("P.MPF", line))


def test_merged_says_a_defect_once_in_the_static_words():
    static = [_f("def_position", 3), _f("unknown_cycle", 6), _f("block_number_order", 8, "warning")]
    runtime = [_f("def_position", 3), _f("subprogram_not_found", 6), _f("undefined_variable", 9),
               _f("block_number_order", 8, "warning"), _f("missing_program_end", 8, "warning")]
    got = [(f.kind, f.line) for f in merged(static, runtime)]
    assert got == [("def_position", 3), ("unknown_cycle", 6), ("block_number_order", 8),
                   ("undefined_variable", 9), ("missing_program_end", 8)]


def test_default_tool_spec():
    t = parse_default_tool("flat:d=10")
    assert (t.kind, t.diameter, t.cutting_length) == ("flat", 10.0, 30.0)
    t = parse_default_tool(" Ball:d=6,l=20 ")
    assert (t.kind, t.diameter, t.cutting_length) == ("ball", 6.0, 20.0)
    assert parse_default_tool("drill:d=6.8").point_angle == 118.0
    for bad in ("em10", "flat", "flat:d=0", "flat:d=x", "flat:r=5", "flat:d=5,d=6", "cone:d=5", "flat:d=1e9"):
        with pytest.raises(InputError):
            parse_default_tool(bad)


def test_with_default_answers_the_stand_in_only_where_the_library_lacks_a_tool():
    class Lib:
        path = "lib.toml"

        def lookup(self, name):
            return "EM10-tool" if name == "EM10" else None

        def radius(self, name, d):
            return 5.0

    d = parse_default_tool("flat:d=8")
    w = WithDefault(Lib(), d)
    assert w.lookup("EM10") == "EM10-tool" and not w.stood_in("EM10") and w.radius("EM10", 1) == 5.0
    assert w.lookup("X") is d and w.stood_in("X") and w.radius("X", 1) == 4.0 and w.radius("X", 0) is None
    assert WithDefault(None, d).lookup("EM10") is d and WithDefault(None, d).path == "(no tool library)"


def test_a_run_without_pictures_leaves_no_older_picture_in_out(tmp_path, capsys):
    job = tmp_path / "job"
    shutil.copytree(BROKEN / "s_rapid_into_stock", job)
    out = tmp_path / "out"
    (out / "keep").mkdir(parents=True)
    (out / "notes.png").write_bytes(b"mine")              # a file no report listed stays
    assert main(["verify", str(job / "SLOT.MPF"), "--out", str(out), "--quiet"]) == 1
    first = json.loads((out / "report.json").read_text())["images"]
    assert first and all((out / name).is_file() for name in first.values())
    assert main(["verify", str(job / "SLOT.MPF"), "--out", str(out), "--no-images"]) == 1
    capsys.readouterr()
    assert json.loads((out / "report.json").read_text())["images"] == {}
    assert sorted(p.name for p in out.iterdir()) == ["keep", "notes.png", "report.html", "report.json"]
