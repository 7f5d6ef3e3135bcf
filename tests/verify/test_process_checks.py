"""Process checks on the move table and the verify pipeline's limit checks."""

from __future__ import annotations

import shutil

import numpy as np
from catalog import POLYGON_DIR, TURNMILL
from nc import ok

from vmach.checks.process import runs, spindle_off_cuts, unknown_tools, zero_feeds
from vmach.machine.control import load_control
from vmach.motion import build
from vmach.verify import VerifyOptions, verify

TURN = load_control(TURNMILL)


def test_runs_groups_consecutive_rows():
    assert runs(np.array([0, 1, 1, 0, 1, 0, 0, 1], bool)) == [(1, 2), (4, 4), (7, 7)]
    assert runs(np.zeros(3, bool)) == []


def test_spindle_off_and_wrong_spindle(tmp_path):
    r = ok(
        tmp_path,
        """
SETMS(2)
G0 X40 Y0 Z5
G1 Z-1 F100
Z-2
S2=500 M2=3
G1 Z-3
M2=5
S1=200 M1=3
G1 Z-4
Z-5
M30
""",
        TURN,
    )
    t = build(r.commands, TURN)
    f = spindle_off_cuts(t, tool_spindle=2)
    assert [(x.kind, x.line, x.data["moves"], x.data["wrong_spindle"]) for x in f] == [
        ("spindle_off_cut", 4, 2, False),
        ("spindle_off_cut", 10, 2, True),
    ]


def test_zero_feed_with_feed_per_revolution_and_stopped_spindle(tmp_path):
    r = ok(tmp_path, "G95 F0.2\nG0 X10\nG1 X5\nS100 M3\nG1 X4\nM30\n")
    f = zero_feeds(build(r.commands, r.commands and __import__("vmach.canon").canon.DEFAULT_CONTROL))
    assert [(x.kind, x.line) for x in f] == [("zero_feed", 3)]


class _Library:
    path = "lib.toml"

    def lookup(self, name):
        return object() if name == "GLOD D40" else None


def test_unknown_tool_at_the_t_line(tmp_path):
    r = ok(tmp_path, 'T="GLOD D40" D1\nT="NO SUCH" D1\nT7\nM30\n')
    assert [(x.kind, x.line, x.data["tool"]) for x in unknown_tools(r.commands, _Library())] == [
        ("unknown_tool", 2, "NO SUCH"),
        ("unknown_tool", 3, "7"),
    ]


def _variant(tmp_path, old: str, new: str):
    d = tmp_path / "job"
    shutil.copytree(POLYGON_DIR, d)
    (d / "vmach.toml").write_text('machine = "turnmill"\n')
    sub = d / "P3G_SHAFT.SPF"
    text = sub.read_text()
    assert old in text
    sub.write_text(text.replace(old, new))
    main = d / "POLY14.MPF"
    lines = sub.read_text().splitlines()
    return main, sub, next(i + 1 for i, ln in enumerate(lines) if new in ln)


def test_x_beyond_travel_is_an_axis_limit_at_its_line(tmp_path):
    main, sub, line = _variant(tmp_path, "N390 G0 X=R58/2+10 Z=30", "N390 G0 X=R58/2+400 Z=30")
    report = verify(main, VerifyOptions(images=False))
    f = [x for x in report.findings if x.kind == "axis_limit"]
    assert [(x.source.path.endswith("P3G_SHAFT.SPF"), x.line, x.data.get("axis")) for x in f] == [
        (True, line, "X")
    ]
    # without a tool library each T is an unknown tool too (issue 31: never assumed)
    assert {x.kind for x in report.findings if x.severity == "error"} == {"axis_limit", "unknown_tool"}


def test_fixture_without_a_tool_library_says_what_it_did_not_check(tmp_path):
    main, sub, _ = _variant(tmp_path, "N390 G0", "N390 G0")
    report = verify(main, VerifyOptions(images=False))
    t_lines = [i + 1 for i, ln in enumerate(sub.read_text().splitlines()) if " T=" in ln]
    assert sorted((x.kind, x.line) for x in report.findings if x.severity == "error") == [
        ("unknown_tool", n) for n in t_lines
    ]
    assert set(report.skipped) == {"stock", "fixture_collisions"}
    assert sorted(x.data["stage"] for x in report.findings if x.kind == "stage_skipped") == [
        "fixture_collisions", "stock"]
