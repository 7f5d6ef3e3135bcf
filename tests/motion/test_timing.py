"""Cycle time: exact answers for simple programs on a small model, and the polygon programs."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from catalog import POLY50, TURNMILL, reference_or_skip, split_reference
from nc import ok

from interpreters import sinumerik
from vmach import canon
from vmach.canon import RunOptions
from vmach.errors import ModelError
from vmach.machine import load_model
from vmach.motion import build
from vmach.motion.timing import cycle_time, format_seconds

# A small 4-axis machine with round numbers: X 100 mm/s, Y 50 mm/s, Z 100 mm/s, C 60 deg/s;
# every axis 1000 units/s²; G64 velocity jump 1000 · 0.2 · 0.004 = 0.8 units/s per axis.
SMALL = """
name = "small"
[control]
geometry = ["X", "Y", "Z"]
spindles = [1, 2]
master_spindle = 1
[[axes]]
name = "X"
[[axes]]
name = "Y"
[[axes]]
name = "Z"
[[axes]]
name = "C"
type = "rotary"
modulo = 360.0
[[joints]]
name = "X"
type = "prismatic"
parent = "base"
child = "x"
axis = [1.0, 0.0, 0.0]
max_rate = 6000.0
max_accel = 1000.0
[[joints]]
name = "Y"
type = "prismatic"
parent = "x"
child = "y"
axis = [0.0, 1.0, 0.0]
max_rate = 3000.0
max_accel = 1000.0
[[joints]]
name = "Z"
type = "prismatic"
parent = "y"
child = "z"
axis = [0.0, 0.0, 1.0]
max_rate = 6000.0
max_accel = 1000.0
[[joints]]
name = "C"
type = "revolute"
parent = "base"
child = "c"
axis = [0.0, 0.0, 1.0]
max_rate = 3600.0
max_accel = 1000.0
[work]
link = "c"
[tool]
link = "z"
[timing]
tool_change_s = 4.0
spindle_start_s = 1.5
spindle_stop_s = 0.5
spindle_change_s = 0.25
corner_overload = 1.2
ipo_cycle_s = 0.004
[timing.cycles]
M10 = 3.0
"""
A = 1000.0  # every axis' acceleration, units/s²
JUMP = A * 0.2 * 0.004  # G64 velocity jump per axis, units/s


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    path = tmp_path_factory.mktemp("model") / "small.toml"
    path.write_text(SMALL, encoding="utf-8")
    return load_model(path)


def timed(tmp_path, model, text, acceleration=True):
    r = ok(tmp_path, text, model.control)
    return cycle_time(build(r.commands, model.control), model, acceleration=acceleration)


def trapezoid(length, v, a=A, v0=0.0, v1=0.0):
    """Time of a trapezoidal profile that reaches v (checked by the caller)."""
    d_acc, d_dec = (v * v - v0 * v0) / (2 * a), (v * v - v1 * v1) / (2 * a)
    assert d_acc + d_dec <= length
    return (v - v0) / a + (v - v1) / a + (length - d_acc - d_dec) / v


# -- feeds ---------------------------------------------------------------------------------------


def test_single_feed_move_with_and_without_acceleration(tmp_path, small):
    prog = "G0 X0 Y0 Z0\nG1 X100 F6000\nM30\n"
    assert timed(tmp_path, small, prog, acceleration=False).total_s == pytest.approx(1.0)
    t = timed(tmp_path, small, prog)
    # ramp up and down at 1000 mm/s² to 100 mm/s: 0.1 s each over 5 mm; 90 mm cruise 0.9 s
    assert t.total_s == pytest.approx(0.1 + 0.9 + 0.1)
    assert t.feed_s == pytest.approx(1.1) and t.rapid_s == 0.0
    # a 4 mm move never reaches 100 mm/s: triangle with peak sqrt(a·L), time 2·sqrt(L/a)
    short = timed(tmp_path, small, "G0 X0 Y0 Z0\nG1 X4 F6000\nM30\n")
    assert short.total_s == pytest.approx(2 * math.sqrt(4 / A))


def test_rapid_is_limited_by_the_slowest_axis(tmp_path, small):
    prog = "G0 X100 Y100\nM30\n"
    assert timed(tmp_path, small, prog, acceleration=False).total_s == pytest.approx(2.0)
    # Y (50 mm/s) sets the pace; each axis ramps within 1000 units/s²: Y to 50 mm/s in 0.05 s
    t = timed(tmp_path, small, prog)
    assert t.rapid_s == pytest.approx(2.0 + 50 / A)


def test_g95_feed_uses_the_master_spindle(tmp_path, small):
    prog = """S1=2000 M1=3
SETMS(2)
S2=500 M2=3
G95 G1 X50 F0.2
M30
"""
    t = timed(tmp_path, small, prog, acceleration=False)
    assert t.feed_s == pytest.approx(50 / (0.2 * 500 / 60))  # 100 mm/min → 30 s
    assert [e.kind for e in t.events] == ["spindle_start", "spindle_start"]
    assert t.event_s == pytest.approx(2 * 1.5)


def test_g95_with_the_spindle_stopped_is_not_timed_and_noted(tmp_path, small):
    t = timed(tmp_path, small, "G95 G1 X50 F0.2\nM30\n")
    assert t.total_s == 0.0 and any("G95" in n for n in t.notes)


def test_g93_inverse_time(tmp_path, small):
    # F2 in G93: each block takes 1/2 minute, whatever its length
    t = timed(tmp_path, small, "G93 G1 X10 F2\nG1 X110 F2\nM30\n", acceleration=False)
    assert t.row_seconds.tolist() == pytest.approx([30.0, 30.0])
    # an arc is many chords; the block as a whole takes 1/F minutes
    arc = timed(tmp_path, small, "G0 X10 Y0\nG93 G3 X-10 Y0 I-10 J0 F4\nM30\n", False)
    assert len(arc.row_seconds) > 10 and arc.feed_s == pytest.approx(15.0)


def test_dwell_seconds_and_revolutions(tmp_path, small):
    t = timed(tmp_path, small, "G4 F2.5\nS600 M3\nG4 S10\nM30\n")
    dwells = [e.seconds for e in t.events if e.kind == "dwell"]
    assert dwells == pytest.approx([2.5, 1.0])  # 10 revolutions at 600 rpm
    assert t.total_s == pytest.approx(2.5 + 1.5 + 1.0)


# -- corners -------------------------------------------------------------------------------------


def test_corner_exact_stop_versus_continuous_path(tmp_path, small):
    corner = "G1 X50 F6000\nG1 Y50\nM30\n"
    g60 = timed(tmp_path, small, "G0 X0 Y0 Z0\nG60\n" + corner)
    g64 = timed(tmp_path, small, "G0 X0 Y0 Z0\nG64\n" + corner)
    g9 = timed(tmp_path, small, "G0 X0 Y0 Z0\nG64\nG9 G1 X50 F6000\nG1 Y50\nM30\n")
    # exact stop: X at 100 mm/s from and to standstill; Y capped at 50 mm/s by its rate
    exact = trapezoid(50, 100) + trapezoid(50, 50)
    assert g60.total_s == pytest.approx(exact) and g9.total_s == pytest.approx(exact)
    # G64: at the 90° corner X stops and Y starts; each may jump by 0.8 mm/s
    v = JUMP
    assert g64.exit_speed[1] == pytest.approx(v) and g64.entry_speed[2] == pytest.approx(v)
    assert g64.total_s == pytest.approx(trapezoid(50, 100, v1=v) + trapezoid(50, 50, v0=v))
    assert g64.total_s < g60.total_s


def test_straight_continuation_keeps_full_speed_under_g64(tmp_path, small):
    t = timed(tmp_path, small, "G0 X0 Y0 Z0\nG64 G1 X50 F6000\nG1 X100\nM30\n")
    assert t.exit_speed[1] == pytest.approx(100.0)
    assert t.total_s == pytest.approx(trapezoid(100, 100))


def test_a_timed_event_between_moves_stops_the_path(tmp_path, small):
    t = timed(tmp_path, small, "G0 X0 Y0 Z0\nG64 G1 X50 F6000\nM10\nG1 X100\nM30\n")
    assert t.exit_speed[1] == 0.0
    assert t.total_s == pytest.approx(2 * trapezoid(50, 100) + 3.0)


# -- rotary axes ---------------------------------------------------------------------------------


def test_rotary_feed_and_rate_limit(tmp_path, small):
    # C alone: F in deg/min; 1800 deg/min = 30 deg/s → 90° in 3 s
    assert timed(tmp_path, small, "G1 C90 F1800\nM30\n", False).total_s == pytest.approx(3.0)
    # C alone asked for 600 deg/s: its rate (60 deg/s) caps it → 1.5 s
    assert timed(tmp_path, small, "G1 C90 F36000\nM30\n", False).total_s == pytest.approx(1.5)
    # X with C: F is the path speed of X (10 mm/s → 1 s), but C would need 90 deg/s → 1.5 s
    assert timed(tmp_path, small, "G1 X10 C90 F600\nM30\n", False).total_s == pytest.approx(1.5)
    assert timed(tmp_path, small, "G1 X10 C30 F600\nM30\n", False).total_s == pytest.approx(1.0)
    # with ramps: C to 60 deg/s at 1000 deg/s², 90° → 1.5 + 0.06 s
    assert timed(tmp_path, small, "G1 C90 F36000\nM30\n").total_s == pytest.approx(1.5 + 0.06)


# -- events and operations -----------------------------------------------------------------------


def test_events_operations_and_totals(tmp_path, small):
    t = timed(tmp_path, small, """T="A" D1
S1000 M3
G1 X60 F6000
M1
T="B" D1
G1 X0
M5
M30
""", acceleration=False)
    kinds = [(e.kind, e.seconds) for e in t.events]
    assert kinds == [("tool_change", 4.0), ("spindle_start", 1.5), ("pause", 0.0),
                     ("tool_change", 4.0), ("spindle_stop", 0.5)]
    assert any("M0/M1" in n for n in t.notes)
    assert [(o.tool, o.line) for o in t.operations] == [("A", 1), ("B", 5)]
    assert [o.seconds for o in t.operations] == pytest.approx([4 + 1.5 + 0.6, 4 + 0.6 + 0.5])
    assert t.per_tool == pytest.approx({"A": 6.1, "B": 5.1})
    assert t.total_s == pytest.approx(t.row_seconds.sum() + t.event_seconds.sum())
    assert t.operations[0].name == "A @ TEST.MPF:1"
    assert t.to_json()["operations"][1]["seconds"] == pytest.approx(5.1)
    assert format_seconds(928.04) == "15 min 28.0 s"
    assert format_seconds(59.96) == "1 min 00.0 s"
    assert format_seconds(5.26) == "5.3 s"
    assert format_seconds(2e12) == "2e+12 s"


def test_sinumerik_path_modes_in_the_canonical_stream(tmp_path):
    r = ok(tmp_path, "G60\nSUB1\nG9 G1 X1 F100\nG64\nM30\n",
           SUB1_DOT_SPF="PROC SUB1 SAVE\nG64 G1 X2 F100\nM17\n")
    modes = [(c.mode, c.source.line) for c in r.commands if isinstance(c, canon.PathMode)]
    # G60; G64 in SUB1; restored to G60 on return (SAVE); G9 under G60 adds nothing; G64
    assert modes == [("exact", 1), ("continuous", 2), ("exact", 3), ("continuous", 4)]


# -- machine data --------------------------------------------------------------------------------


def test_timing_table_problems_are_reported_with_lines(tmp_path):
    bad = SMALL.replace("tool_change_s = 4.0", "tool_chnage_s = 4.0").replace(
        "corner_overload = 1.2", "corner_overload = 0.5").replace(
        "max_accel = 1000.0\n[[joints]]\nname = \"Y\"", "max_accel = -1.0\n[[joints]]\nname = \"Y\"")
    path = tmp_path / "bad.toml"
    path.write_text(bad, encoding="utf-8")
    with pytest.raises(ModelError) as exc:
        load_model(path)
    lines = bad.splitlines()
    found = {(f.kind, lines[f.line - 1].split("=")[0].strip()) for f in exc.value.problems}
    assert found == {("bad_value", "tool_chnage_s"), ("bad_value", "corner_overload"),
                     ("bad_value", "max_accel")}


def test_shipped_models_state_accelerations_and_times():
    m = load_model(TURNMILL)
    assert np.all(m.max_accel > 0) and m.timing.stated and m.timing.tool_change_s > 0
    assert {"C_AXIS_ON", "C_AXIS_OFF"} <= set(m.timing.cycles)
    for name in ("s5d", "hybrid5"):
        assert np.all(load_model(name).max_accel > 0)


# -- the polygon programs ------------------------------------------------------------------------


def programmed_feed_seconds(commands):
    """Σ straight XYZ distance / F over the LinearFeed commands (G94): no ramps, no rapids."""
    pos, total = None, 0.0
    for c in commands:
        if isinstance(c, canon.MOTIONS):
            p = np.array([c.axes["X"], c.axes["Y"], c.axes["Z"]])
            if isinstance(c, canon.LinearFeed) and pos is not None:
                total += np.linalg.norm(p - pos) / (c.feed / 60)
            pos = p
    return total


def polygon_timing(path):
    model = load_model(TURNMILL)
    r = sinumerik.run(path, model.control, RunOptions())
    assert r.completed
    table = build(r.commands, model.control)
    start = time.perf_counter()
    t = cycle_time(table, model)
    elapsed = time.perf_counter() - start
    return r, t, cycle_time(table, model, acceleration=False), elapsed


def test_reference_program_cycle_time_is_sane(tmp_path):
    reference_or_skip()
    r, t, flat, elapsed = polygon_timing(split_reference(tmp_path))
    feed_only = programmed_feed_seconds(r.commands)
    assert t.total_s > flat.total_s > feed_only
    assert flat.feed_s == pytest.approx(feed_only, rel=1e-6)
    # the control's own simulation reported 15 min 28 s (domain §4); same order of magnitude
    assert 0.6 * 928 < t.total_s < 1.5 * 928
    # roughing, by hand: about 96 plunges × 65 mm at F620 ≈ 600 s (domain §4)
    rough = t.operations[0]
    assert rough.tool == "GLOD D40" and rough.feed_s == pytest.approx(600, rel=0.05)
    assert [o.tool for o in t.operations] == ["GLOD D40", "GLOD D40", "GLOD D16_15", "GLOD D25"]
    assert elapsed < 1.0


def test_fixture_program_cycle_time_is_sane():
    r, t, flat, elapsed = polygon_timing(POLY50)
    assert t.total_s > flat.total_s > programmed_feed_seconds(r.commands)
    # roughing (blocks N310-N330): 3 passes × 24 plunges (360 / 15.323) × (10 + 45 + 10) mm
    # at F620; the first operation also faces the shoulder with the same cutter
    table = build(r.commands, load_model(TURNMILL).control)
    block = np.array([table.source(i).text.lstrip()[:5] in ("N310 ", "N320 ", "N330 ")
                      for i in range(len(table))])
    assert block.sum() == 3 * 24 * 3
    assert t.row_seconds[block].sum() == pytest.approx(3 * 24 * 65 / (620 / 60), rel=0.02)
    assert t.operations[0].feed_s > t.row_seconds[block].sum()
    # finishing: 4000 points (40 mm / 0.01) + 421 edge points at F700, each about 0.3-0.6 mm
    fin = t.operations[-1]
    assert fin.tool == "GLOD D25" and 4421 * 0.3 / (700 / 60) < fin.feed_s < 4421 * 0.6 / (700 / 60)
    assert 0.5 * 928 < t.total_s < 1.5 * 928
    assert elapsed < 1.0


def test_planned_speeds_respect_every_limit(tmp_path, small):
    """A random zig-zag under G64: caps, ramps and per-axis velocity jumps all hold."""
    rng = np.random.default_rng(7)
    pts = np.cumsum(rng.uniform(-3, 3, (200, 2)), axis=0)
    c = np.cumsum(rng.uniform(0, 5, 200))
    body = "".join(f"G1 X{x:.3f} Y{y:.3f} C{cc:.3f}\n" for (x, y), cc in zip(pts, c, strict=True))
    r = ok(tmp_path, "G0 X0 Y0 Z0\nG64 F3000\n" + body + "M30\n", small.control)
    table = build(r.commands, small.control)
    t = cycle_time(table, small)
    d = table.end - table.start
    s = np.linalg.norm(d[:, :3], axis=1)
    rows = np.flatnonzero(s > 0)
    u = d[rows] / s[rows, None]
    v0, v1 = t.entry_speed[rows], t.exit_speed[rows]
    rate = np.array([100.0, 50.0, 100.0, 60.0])  # units/s
    cap = np.minimum(50.0, (rate / np.maximum(np.abs(u), 1e-300)).min(axis=1))
    a = (A / np.maximum(np.abs(u), 1e-300)).min(axis=1)
    assert np.all(v0 <= cap * (1 + 1e-9)) and np.all(v1 <= cap * (1 + 1e-9))
    assert np.all(np.abs(v1**2 - v0**2) <= 2 * a * s[rows] * (1 + 1e-9))
    assert np.allclose(v1[:-1], v0[1:])  # one speed per junction
    jumps = np.abs(v1[:-1, None] * (u[1:] - u[:-1]))
    assert np.all(jumps <= JUMP * (1 + 1e-9))
    assert v0[0] == 0 and v1[-1] == 0
    # and each row takes at least its length at its cap, at most its length at its mean speed
    sec = t.row_seconds[rows]
    assert np.all(sec >= s[rows] / cap * (1 - 1e-9))
    assert np.all(sec <= s[rows] / np.maximum((v0 + v1) / 2, 1e-300) * (1 + 1e-9))
