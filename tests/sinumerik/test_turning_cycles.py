"""SINUMERIK thread cutting G33/G34/G35 and the turning cycles (interpreters/sinumerik/turning/):
the moves each block or call makes, worked out from the Programming Manual (G33 lead along
the dominant axis) and the Cycles manual (CYCLE97's passes), and the errors of bad input."""

from __future__ import annotations

import math

import pytest
from catalog import TURNMILL
from nc import error_of, moves, ok, run

from interpreters.sinumerik.language import COMMANDS
from interpreters.sinumerik.turning import NAMES, SPECS
from vmach.canon import LinearFeed, Traverse
from vmach.machine.control import load_control

LATHE = load_control(TURNMILL)
HEAD = "G18 G90 G71 DIAMON\nT1 D1\n"


def cuts(result, line: int | None = None) -> list:
    return [m for m in moves(result) if isinstance(m, LinearFeed)
            and (line is None or m.source.line == line)]


def test_turning_cycles_are_data_and_no_longer_stop_a_run():
    assert NAMES == set(SPECS) == {"CYCLE97"}
    assert all(p.type in ("real", "int") and p.meaning for s in SPECS.values() for p in s.parameters)
    assert not any(COMMANDS.get(n) is not None and COMMANDS[n].kind == "cycle" for n in NAMES)


def test_g33_feed_is_the_lead_per_revolution_along_z(tmp_path):
    """G95: the feed of a longitudinal thread is K; of a taper, K·L/|ΔZ| (the lead is along Z)."""
    r = ok(tmp_path, HEAD + "G95 S500 M3\nG0 X30 Z5\nG33 Z-20 K2 SF=90\nG0 X40\nZ5 X30\n"
           "G33 X40 Z-15 K2.5\nM30\n", LATHE)
    a, b = cuts(r)
    assert (a.source.line, a.axes["Z"], a.axes["X"], a.feed) == (5, -20.0, 15.0, 2.0)
    assert b.feed == pytest.approx(2.5 * math.hypot(20, 5) / 20)
    assert [f.kind for f in r.findings] == ["thread_envelope"]


def test_g33_under_g94_feeds_lead_times_speed_and_keeps_the_lead(tmp_path):
    r = ok(tmp_path, HEAD + "G94 S400 M4\nG0 X30 Z5\nG33 Z-20 K1.5\nG0 X34\nZ5\nX29\nG33 Z-20\nM30\n", LATHE)
    assert [c.feed for c in cuts(r)] == [600.0, 600.0]


def test_g33_face_thread_takes_its_lead_from_i(tmp_path):
    r = ok(tmp_path, HEAD + "G95 S300 M3\nG0 X60 Z1\nG33 X10 Z1 I3\nM30\n", LATHE)
    (c,) = cuts(r)
    assert (c.axes["X"], c.feed) == (5.0, 3.0)


def test_g34_g35_feed_at_the_mean_lead(tmp_path):
    """G34 F0.02 over 20 mm from K2: the lead at the end is √(4 + 2·0.02·20); the block takes
    as many revolutions as at the mean of both leads (G35 the same, shrinking)."""
    r = ok(tmp_path, HEAD + "G95 S300 M3\nG0 X30 Z5\nG34 Z-15 K2 F0.02\nG0 X40\nZ5\nX30\n"
           "G35 Z-15 K2 F0.02\nM30\n", LATHE)
    up, down = cuts(r)
    assert up.feed == pytest.approx((2 + math.sqrt(4 + 0.8)) / 2)
    assert down.feed == pytest.approx((2 + math.sqrt(4 - 0.8)) / 2)


@pytest.mark.parametrize("body, kind, line", [
    ("G95 S500 M5\nG0 X30 Z5\nG33 Z-20 K2\n", "thread_spindle", 5),
    ("G95 S500 M3\nG0 X30 Z5\nG33 Z-20\n", "thread_lead", 5),
    ("G95 S500 M3\nG0 X30 Z5\nG33 Z-20 I1 K2\n", "thread_lead", 5),
    ("G95 S500 M3\nG0 X30 Z5\nG33 X40 K2\n", "thread_lead", 5),        # K along Z, no Z travel
    ("G95 S300 M3\nG0 X30 Z5\nG35 Z-55 K2 F0.05\n", "thread_lead", 5),  # the lead runs out
])
def test_g33_errors_at_their_line(tmp_path, body, kind, line):
    e = error_of(run(tmp_path, HEAD + body + "M30\n", LATHE))
    assert (e.kind, e.line) == (kind, line)


def test_cycle97_passes_follow_the_cycles_manual(tmp_path):
    """Outside M42 (MPIT 42: lead 4.5) from Z0 to Z-35, run-in 10, run-out 3, depth 1.23 in
    5 cuts of constant cross-section, no allowance, 2 idle passes, radial infeed."""
    r = ok(tmp_path, HEAD + "G95 S600 M3\nG0 X100 Z100\n"
           "CYCLE97(, 42, 0, -35, 42, 42, 10, 3, 1.23, 0, 0, 0, 5, 2, 3, 1)\nM30\n", LATHE)
    passes = cuts(r, 5)
    assert [round(c.axes["X"], 9) for c in passes] == pytest.approx(
        [21 - 1.23 * math.sqrt(k / 5) for k in range(1, 6)] + [21 - 1.23] * 2)
    assert {c.axes["Z"] for c in passes} == {-38.0} and {c.feed for c in passes} == {4.5}
    ms = [m for m in moves(r) if m.source.line == 5]
    assert (ms[0].axes["X"], ms[0].axes["Z"]) == (22.0, 10.0)            # lift 1 mm, on the run-in
    assert (ms[-1].axes["X"], ms[-1].axes["Z"]) == (22.0, 10.0)          # back at the start point
    assert all(isinstance(m, Traverse) for m in ms if not isinstance(m, LinearFeed))
    assert ms[3].source.phase == "start 1/1 cut 1/7 (roughing)"


def test_cycle97_inside_constant_depth_two_starts_alternating_flanks(tmp_path):
    r = ok(tmp_path, HEAD + "G95 S400 M3\nG0 X20 Z5\n"
           "CYCLE97(2, , 0, -20, 30, 30, 2, 2, 1.08, 0.08, -29, 0, 4, 0, 2, 2)\nM30\n", LATHE)
    passes = cuts(r, 5)
    assert len(passes) == 2 * 5
    assert [round(c.axes["X"], 9) for c in passes[:5]] == pytest.approx([15.25, 15.5, 15.75, 16.0, 16.08])
    ms = [m for m in moves(r) if m.source.line == 5]
    starts = [ms[i - 1].axes["Z"] for i, m in enumerate(ms) if isinstance(m, LinearFeed)]
    t = math.tan(math.radians(29))
    want = [2 + 0.25 * t, 2 - 0.5 * t, 2 + 0.75 * t, 2 - 1.0 * t, 2 + 1.08 * t]
    assert starts[:5] == starts[5:] == pytest.approx(want)


@pytest.mark.parametrize("args, kind", [
    ("2, , 0, -20, 30, 30, 2, 2, 1, 0, 0, 0, 4, 0, 5, 1", "cycle_parameter"),   # VARI 5
    (", 41, 0, -20, 30, 30, 2, 2, 1, 0, 0, 0, 4, 0, 1, 1", "cycle_parameter"),  # no M41
    ("2, 42, 0, -20, 30, 30, 2, 2, 1, 0, 0, 0, 4, 0, 1, 1", "cycle_parameter"),  # PIT ≠ MPIT's
    ("2, , 0, -20, 30, 30, 2, 2, 1, 1.5, 0, 0, 4, 0, 1, 1", "cycle_parameter"),  # FAL > TDEP
    ("2, , 0, -5, 30, 50, 2, 2, 1, 0, 0, 0, 4, 0, 1, 1", "unsupported"),         # face thread
])
def test_cycle97_bad_parameters_are_errors_at_the_call(tmp_path, args, kind):
    r = run(tmp_path, HEAD + f"G95 S400 M3\nG0 X40 Z5\nCYCLE97({args})\nM30\n", LATHE)
    e = error_of(r)
    assert (e.kind, e.line) == (kind, 5)


def test_cycle97_needs_g18_and_a_turning_spindle(tmp_path):
    r = run(tmp_path, "G17 G90\nT1 D1\nG95 S400 M3\nCYCLE97(2, , 0, -20, 30, 30, 2, 2, 1)\nM30\n", LATHE)
    assert (error_of(r).kind, error_of(r).line) == ("cycle_parameter", 4)
    r = run(tmp_path, HEAD + "G95 S400 M5\nG0 X40 Z5\nCYCLE97(2, , 0, -20, 30, 30, 2, 2, 1)\nM30\n", LATHE)
    assert (error_of(r).kind, error_of(r).line) == ("thread_spindle", 5)
