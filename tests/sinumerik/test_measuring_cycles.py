"""The workpiece measuring cycles (interpreters/sinumerik/cycles/measuring.py): probe moves
from the cycle's setpoints and measuring path, the nominal result in the info finding and in
_OVR/_OVI where the directory defines them."""

from __future__ import annotations

import math

import pytest
from nc import error_of, run

from vmach.canon import LinearFeed, Message, ProbeMove, RunOptions

R3 = RunOptions(tool_radius=lambda tool, d: 3.0)
HEAD = "T1 D1\nG17 G90 G0 X0 Y0 Z50\nS1000 M3 F300\n"
GUD = "DEF NCK REAL _OVR[32]\nDEF NCK INT _OVI[12]\nM30\n"


def go(tmp_path, body: str, line: int = 5):
    r = run(tmp_path, HEAD + body + "\nM30\n", options=R3, _N_GUD5_DEF=GUD)
    assert r.completed, [f.render() for f in r.findings]
    ms = [c for c in r.commands if isinstance(c, LinearFeed) and c.source.line == line]
    return r, ms


def test_cycle978_probes_through_the_setpoint_by_fa(tmp_path):
    """An edge at X = 0 probed in +X from X −20 with a Ø6 stylus, _FA 2: positioning to
    X −5 (a ball radius and _FA before), the measuring move to X −1, back to −20; the result
    is the setpoint, in _OVR[4] and the info finding."""
    r, ms = go(tmp_path, 'G0 X-20 Y10 Z-5\nCYCLE978(0, , , 1, 0, 2, 1, 1, 1, 1)\nR1=_OVR[4]\nR2=_OVI[2]\n'
               'MSG("R" << R1 << "/" << R2)')
    assert [(type(m), m.axes["X"]) for m in ms] == [(LinearFeed, -5), (ProbeMove, -1), (LinearFeed, -20)]
    assert all(m.axes["Y"] == 10 and m.axes["Z"] == -5 for m in ms)
    found = [f for f in r.findings if f.kind == "measurement"]
    assert len(found) == 1 and found[0].line == 5 and found[0].data["nominal"] == [0]
    assert [c.text for c in r.commands if isinstance(c, Message)] == ["R0/978"]


def test_cycle978_along_the_tool_axis_downwards(tmp_path):
    _, ms = go(tmp_path, "G0 X30 Y30 Z10\nCYCLE978(0, , , 1, -3, 2, 1, 3, 2, 1)")
    probe = [m for m in ms if isinstance(m, ProbeMove)]
    assert [m.axes["Z"] for m in ms] == [-1, -5, 10] and len(probe) == 1


def test_cycle977_hole_four_points_and_spigot_from_outside(tmp_path):
    _, ms = go(tmp_path, "G0 X30 Y30 Z-5\nCYCLE977(101, , , 1, 20, , , 2, 1, 0)")
    probes = [m for m in ms if isinstance(m, ProbeMove)]
    ends = sorted((round(m.axes["X"] - 30, 9) + 0.0, round(m.axes["Y"] - 30, 9) + 0.0) for m in probes)
    assert ends == [(-9, 0), (0, -9), (0, 9), (9, 0)]                    # 10 − 3 + 2
    assert {m.source.phase for m in probes} == {f"probing point {k}" for k in range(1, 5)}
    _, ms = go(tmp_path, "G0 X30 Y30 Z5\nCYCLE977(102, , , 1, 20, , , 2, 1, 0, -10)")
    probes = [m for m in ms if isinstance(m, ProbeMove)]
    assert {round(math.hypot(m.axes["X"] - 30, m.axes["Y"] - 30), 9) for m in probes} == {11}
    assert {m.axes["Z"] for m in probes} == {-5}                          # 10 down beside it
    starts = [ms[ms.index(m) - 1] for m in probes]
    assert {round(math.hypot(m.axes["X"] - 30, m.axes["Y"] - 30), 9) for m in starts} == {15}


def test_cycle998_two_points_along_the_offset_axis(tmp_path):
    """An edge at X = 0 at 10° to Y, probed at Y 0 and Y 20: the second contact is expected
    20·tan 10° further along X."""
    _, ms = go(tmp_path, "G0 X-10 Y0 Z-5\nCYCLE998(105, , , 1, 0, 10, , 2, 1, 201, 1, 20)")
    probes = [m for m in ms if isinstance(m, ProbeMove)]
    assert [m.axes["Y"] for m in probes] == [0, 20]
    assert probes[1].axes["X"] - probes[0].axes["X"] == pytest.approx(20 * math.tan(math.radians(10)))


def test_cycle979_three_points_on_the_segment(tmp_path):
    _, ms = go(tmp_path, "G0 X30 Y30 Z-5\nCYCLE979(1, , , 1, 20, 2, 1, 30, 30, 0, 120)")
    probes = [m for m in ms if isinstance(m, ProbeMove)]
    angles = [round(math.degrees(math.atan2(m.axes["Y"] - 30, m.axes["X"] - 30)), 6) for m in probes]
    assert angles == [0, 120, -120]


def test_measuring_errors(tmp_path):
    def err(body):
        f = error_of(run(tmp_path, HEAD + body + "\nM30\n", options=R3))
        return f.kind, f.line
    assert err("CYCLE978(0, , , 1, 0, 0, 1, 1, 1)") == ("cycle_parameter", 4)      # no _FA
    assert err("CYCLE978(0, , , 1, 0, 2, 1, 4, 1)") == ("cycle_parameter", 4)      # no such axis
    assert err("CYCLE977(109, , , 1, 20, , , 2)") == ("cycle_parameter", 4)
    assert err("CYCLE977(101, , , 1, 4, , , 2)") == ("cycle_parameter", 4)         # Ø4 hole, Ø6 stylus
    old = run(tmp_path, HEAD + "_MVAR=100 _SETVAL=0\nCYCLE978\nM30\n", options=R3,   # the older form
              _N_GUD5_DEF="DEF NCK INT _MVAR\nDEF NCK REAL _SETVAL\nM30\n")
    assert (error_of(old).kind, error_of(old).line) == ("unsupported", 5)
