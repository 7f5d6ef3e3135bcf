"""The canonical command stream of RS274/NGC programs: mm, machine axes, SourceRef."""

from __future__ import annotations

import math

import pytest

from interpreters.rs274ngc import run
from vmach import canon as vc
from vmach.canon import AxisSpec, ControlSpec, RunOptions


def _run(tmp_path, text: str, name: str = "prog.ngc", **kw):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return run(path, **kw)


def _motions(result):
    return [c for c in result.commands if isinstance(c, vc.MOTIONS)]


def test_inch_program_comes_out_in_mm(tmp_path):
    r = _run(tmp_path, "G20 G0 X1 Y2 Z0.5\nG1 X2 F10\nM2\n")
    assert r.completed
    t, f = _motions(r)
    assert t.axes == pytest.approx({"X": 25.4, "Y": 50.8, "Z": 12.7})
    assert f.axes["X"] == pytest.approx(50.8)
    assert f.feed == pytest.approx(254.0)  # 10 in/min


def test_work_offsets_give_machine_values(tmp_path):
    text = """G21
G10 L2 P2 X100 Y50 Z-10
G55 G0 X1 Y2 Z3
G92 X0
G0 X5
M2
"""
    r = _run(tmp_path, text)
    a, b = _motions(r)
    assert a.axes == pytest.approx({"X": 101.0, "Y": 52.0, "Z": -7.0})
    assert b.axes["X"] == pytest.approx(106.0)  # G92 made the current X=101 the new 0
    frames = [c for c in r.commands if isinstance(c, vc.SetFrame)]
    assert frames[0].origin == pytest.approx({"X": 100.0, "Y": 50.0, "Z": -10.0})


def test_xy_rotation_rotates_targets(tmp_path):
    r = _run(tmp_path, "G21\nG10 L2 P1 X10 R90\nG54 G0 X5 Y0\nM2\n")
    (t,) = _motions(r)
    assert t.axes["X"] == pytest.approx(10.0, abs=1e-9)
    assert t.axes["Y"] == pytest.approx(5.0)


def test_arc_plane_center_and_turns(tmp_path):
    text = """G21 F100
G0 X10 Y0 Z0
G3 X10 Y0 Z-3 I-10 J0 P3
G18 G2 X0 Z-3 I-5 K5
M2
"""
    r = _run(tmp_path, text)
    helix, xz = [c for c in r.commands if isinstance(c, vc.ArcFeed)]
    assert helix.plane == ("X", "Y", "Z")
    assert helix.center == pytest.approx((0.0, 0.0))
    assert not helix.clockwise
    assert helix.turns == 2
    assert helix.axes["Z"] == pytest.approx(-3.0)
    assert xz.plane == ("Z", "X", "Y")
    assert xz.center == pytest.approx((2.0, 5.0))  # (Z, X) of the centre
    assert xz.clockwise


def test_state_commands_only_on_change(tmp_path):
    text = "G17 G94 S500 M3\nM3\nM8\nM8\nG17\nT2 M6\nG43 H2\nM0\nM1\nG4 P1.5\nM30\n"
    r = _run(tmp_path, text)
    kinds = [c.kind for c in r.commands]
    assert kinds == ["spindle", "coolant", "spindle", "tool_change", "tool_offset", "pause",
                     "pause", "dwell", "coolant", "program_end"]
    spindle = r.commands[0]
    assert (spindle.speed, spindle.direction) == (500.0, "cw")
    assert r.commands[2].direction == "stop"  # M6 stops the spindle
    assert r.commands[3].number == 2
    assert r.commands[4].offset == 2
    assert r.commands[6].optional
    assert r.commands[7].seconds == 1.5
    assert r.commands[-1].code == "M30"


def test_feed_modes(tmp_path):
    r = _run(tmp_path, "G21 G93 G1 X10 F2\nG95 S100 F0.1 G1 X20\nG94 F100 G1 X0\nM2\n")
    modes = [c.mode for c in r.commands if isinstance(c, vc.FeedMode)]
    assert modes == ["inverse_time", "per_rev", "per_minute"]
    feeds = [c.feed for c in _motions(r)]
    assert feeds == pytest.approx([2.0, 0.1, 100.0])


def test_source_refs_follow_subroutine_files(tmp_path):
    (tmp_path / "lib_move.ngc").write_text("o<lib_move> sub\nG0 X#1\no<lib_move> endsub\n")
    r = _run(tmp_path, "o<lib_move> call [7]\nG0 Y1\nM2\n")
    a, b = _motions(r)
    assert a.source.path.endswith("lib_move.ngc") and a.source.line == 2
    assert a.axes["X"] == 7.0
    assert b.source.path.endswith("prog.ngc") and b.source.line == 2


def test_subroutine_file_is_only_looked_up_beside_the_program(tmp_path):
    sub = tmp_path / "sub"
    sub.mkdir()
    (tmp_path / "outside.ngc").write_text("o<outside> sub\nG0 X1\no<outside> endsub\n")
    r = _run(sub, "o<outside> call\nM2\n")
    assert not r.completed
    assert r.findings[-1].kind == "seeking_o_word"


def test_canned_cycle_moves(tmp_path):
    r = _run(tmp_path, "G21 G0 Z10 F50\nG99 G81 X1 Y2 Z-3 R2\nG80\nM2\n")
    zs = [c.axes["Z"] for c in _motions(r)]
    assert zs == [10.0, 10.0, 2.0, -3.0, 2.0]
    assert isinstance(_motions(r)[3], vc.LinearFeed)


def test_rotary_axis_joins_the_axes_when_used(tmp_path):
    r = _run(tmp_path, "G0 X1\nG0 A90\nG0 X2\nM2\n")
    first, second, third = _motions(r)
    assert "A" not in first.axes
    assert second.axes["A"] == 90.0
    assert third.axes["A"] == 90.0


def test_strict_machine_rejects_unknown_axis(tmp_path):
    control = ControlSpec(axes=(AxisSpec("X"), AxisSpec("Z"), AxisSpec("C1", "rotary")),
                          strict_axes=True)
    r = _run(tmp_path, "G0 X1\nG0 Y2\nM2\n", control=control)
    assert not r.completed
    f = r.findings[-1]
    assert (f.kind, f.line) == ("unknown_axis", 2)
    assert r.commands[0].axes == {"X": 1.0, "Z": 0.0, "C1": 0.0, "Y": 0.0}


def test_block_limit_stops_endless_loops(tmp_path):
    r = _run(tmp_path, "o1 while [1]\nG0 X1\no1 endwhile\nM2\n",
             options=RunOptions(max_blocks=500))
    assert not r.completed
    assert r.findings[-1].kind == "block_limit"
    assert r.blocks == 501


def test_call_depth_limit(tmp_path):
    text = "o<deep> sub\no<deep> call\no<deep> endsub\no<deep> call\nM2\n"
    r = _run(tmp_path, text, options=RunOptions(max_call_depth=5))
    assert not r.completed
    assert r.findings[-1].kind == "call_depth"


def test_messages_and_comments(tmp_path):
    r = _run(tmp_path, "(MSG,Load part)\n(just a note)\n#1=3\n(DEBUG,n=#1)\nM2\n")
    texts = [(c.kind, c.text) for c in r.commands if c.kind in ("message", "comment")]
    assert texts == [("message", "Load part"), ("comment", "just a note"),
                     ("message", "n=3.000000")]


def test_trig_in_degrees(tmp_path):
    r = _run(tmp_path, "G21 G0 X[10*COS[60]] Y[ATAN[1]/[1]]\nM2\n")
    (t,) = _motions(r)
    assert t.axes["X"] == pytest.approx(5.0)
    assert t.axes["Y"] == pytest.approx(45.0)
    assert math.copysign(1.0, t.axes["Z"]) == 1.0


def test_canned_cycle_repeats_count_against_the_block_limit(tmp_path):
    """Found by fuzzing: `G81 ... L1000000000` in G91 filled the memory with drill moves
    from one block; every repeat now counts as a block."""
    r = _run(tmp_path, "G20 G91\nG81 X1 Y0 Z-1 R1 L1000000000 F10\nM2\n", options=RunOptions(max_blocks=500))
    assert not r.completed
    assert (r.findings[-1].kind, r.findings[-1].line) == ("block_limit", 2)
    r = _run(tmp_path, "G20 G91\nG81 X1 Y0 Z-1 R1 L5 F10\nM2\n", options=RunOptions(max_blocks=500))
    assert r.completed


def test_a_peck_cycle_beyond_vmachs_peck_limit_is_a_resource_limit(tmp_path):
    """Found by fuzzing: G83 with Q0.000001 made pecks until the memory ran out (and a Q too
    small to change the depth in floating point looped for ever)."""
    for q, z in (("0.000000001", "-5"), ("0.001", "-1000000000")):
        r = _run(tmp_path, f"G21 G90\nG0 X0 Y0 Z30\nG83 X10 Y10 Z{z} R2 Q{q} F100\nM2\n")
        assert not r.completed
        assert (r.findings[-1].kind, r.findings[-1].line) == ("resource_limit", 3)
    r = _run(tmp_path, "G21 G90\nG0 X0 Y0 Z30\nG83 X10 Y10 Z-5 R2 Q0.5 F100\nM2\n")
    assert r.completed
