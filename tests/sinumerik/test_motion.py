"""Motion and modal state: what the canonical commands carry."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from catalog import TURNMILL
from nc import error_of, moves, ok, run

from vmach.canon import ArcFeed, AxisSpec, ControlSpec
from vmach.machine.control import load_control

TURN = load_control(TURNMILL)


def last(r):
    return moves(r)[-1].axes


def test_absolute_incremental_and_word_modes(tmp_path):
    r = ok(tmp_path, "G90 G0 X10 Y10 Z10\nG91 X5 Y=AC(0)\nG90 Z=IC(-4)\nX=IC(1) Y-2.5\nM30\n")
    m = [tuple(x.axes[a] for a in "XYZ") for x in moves(r)]
    assert m == [(10, 10, 10), (15, 0, 10), (15, 0, 6), (16, -2.5, 6)]


def test_arcs_with_ijk_incremental_absolute_and_cr(tmp_path):
    r = ok(
        tmp_path,
        """
G17 G0 X10 Y0
G3 X0 Y10 I-10 J0 F200
G2 X10 Y0 I=AC(0) J=AC(0)
G3 X0 Y10 CR=10
G3 X10 Y0 CR=-10
G18 G0 X0 Y0 Z0
G2 Z20 X0 K10 I0 F100
M30
""",
    )
    arcs = [m for m in moves(r) if isinstance(m, ArcFeed)]
    for a in arcs[:4]:
        assert a.center == pytest.approx((0, 0), abs=1e-12)
    assert [a.clockwise for a in arcs] == [False, True, False, False, True]
    assert arcs[0].plane == ("X", "Y", "Z") and arcs[4].plane == ("Z", "X", "Y")
    assert arcs[4].center == pytest.approx((10, 0)) and arcs[4].feed == 100


def test_cr_picks_the_centre_side_by_sign(tmp_path):
    r = ok(
        tmp_path, "G0 X0 Y0\nG2 X10 Y0 CR=5 F100\nG0 X0 Y0\nG2 X6 Y0 CR=5\nG0 X0 Y0\nG2 X6 Y0 CR=-5\nM30\n"
    )
    arcs = [m for m in moves(r) if isinstance(m, ArcFeed)]
    assert arcs[0].center == pytest.approx((5, 0))
    # clockwise from (0,0) to (6,0), minor arc: centre below the chord; major arc: above
    assert arcs[1].center == pytest.approx((3, -4))
    assert arcs[2].center == pytest.approx((3, 4))


def test_helix_keeps_the_third_axis_end(tmp_path):
    r = ok(tmp_path, "G0 X10 Y0 Z0\nG3 X10 Y0 Z-5 I-10 TURN=2 F100\nM30\n")
    arc = moves(r)[-1]
    assert arc.turns == 2 and arc.axes["Z"] == -5


def test_diameter_programming_gives_radius(tmp_path):
    r = ok(tmp_path, "DIAMON\nG0 X50 Z0\nG91 X-10\nG90 DIAMOF X20\nDIAM90 X40\nG91 X2\nM30\n", TURN)
    assert [m.axes["X"] for m in moves(r)] == [25, 20, 20, 20, 22]


def test_settable_offsets_from_the_control_and_g53(tmp_path):
    ctl = replace(TURN, zero_offsets={"G54": {"Z": 100.0, "X": 1.0}})
    r = ok(tmp_path, "G54 G0 X10 Z5\nG0 G53 X325 Z300\nX10\nG500 X10 Z5\nM30\n", ctl)
    m = [(x.axes["X"], x.axes["Z"]) for x in moves(r)]
    assert m == [(11, 105), (325, 300), (11, 300), (10, 5)]


def test_trans_atrans_rot_arot(tmp_path):
    r = ok(
        tmp_path,
        """
TRANS X10 Y5
G0 X1 Y0
ATRANS X1
X0 Y0
ROT Z90
X1 Y0
AROT RPL=90
X1 Y0
TRANS
X1 Y0
M30
""",
    )
    pts = [(round(m.axes["X"], 9), round(m.axes["Y"], 9)) for m in moves(r)]
    assert pts == [(11, 5), (11, 5), (0, 1), (-1, 0), (1, 0)]


@pytest.mark.parametrize("frame", ["TRANS U1", "ATRANS U1", "TRANS U=1", "TRANS U1 C1"])
def test_trans_of_a_loose_axis_before_its_first_move(tmp_path, frame):
    # a machine without strict axes knows U only from its first word; a frame may come first
    # (this was a KeyError)
    r = ok(tmp_path, f"{frame}\nG0 U2\nM30\n")
    assert last(r)["U"] == 3


def test_rotated_frame_keeps_unprogrammed_axes_in_program_coordinates(tmp_path):
    r = ok(tmp_path, "G0 X10 Y0\nROT RPL=90\nX5\nM30\n")
    # after ROT the current point (10, 0) is (0, -10) in program coordinates; X5 -> (5, -10)
    a = last(r)
    assert (round(a["X"], 9), round(a["Y"], 9)) == (10, 5)


def test_modulo_axis_is_unwrapped_with_direction(tmp_path):
    r = ok(
        tmp_path,
        """
G0 C1=350
C1=ACP(10)
C1=ACN(350)
C1=DC(10)
C1=DC(190)
C1=10
C1=IC(-30)
C1=AC(200)
M30
""",
        TURN,
    )
    assert [m.axes["C1"] for m in moves(r)] == pytest.approx([350, 370, 350, 370, 550, 370, 340, 200])


def test_modulo_dc_mode_from_the_model(tmp_path):
    axes = tuple(replace(a, g90_mode="dc") if a.name == "C1" else a for a in TURN.axes)
    ctl = replace(TURN, axes=axes)
    r = ok(tmp_path, "G0 C1=350\nC1=10\nM30\n", ctl)
    assert [m.axes["C1"] for m in moves(r)] == pytest.approx([-10, 10])  # shortest way each time


def test_non_modulo_rotary_goes_directly(tmp_path):
    ctl = ControlSpec(
        axes=(AxisSpec("X"), AxisSpec("Y"), AxisSpec("Z"), AxisSpec("B", "rotary")), strict_axes=True
    )
    r = ok(tmp_path, "G0 B350\nB10\nM30\n", ctl)
    assert [m.axes["B"] for m in moves(r)] == [350, 10]
    assert error_of(run(tmp_path, "G0 B=ACP(10)\nM30\n", ctl)).kind == "invalid_value"


def test_spindles_tools_coolant_dwell_feed_modes(tmp_path):
    r = ok(
        tmp_path,
        """
T="GLOD D40" D1
SETMS(2)
G94 S640 M3
S2=700 M2=4 M1=3
M7 M8
G4 F2
G4 S10
G95 F0.2
T5
D0
M9
M30
""",
        TURN,
    )
    ev = [(c.kind, c.fields()) for c in r.commands if c.kind not in ("traverse", "feed")]
    assert ("tool_change", {"tool": "GLOD D40", "number": None, "offset": 1}) in ev
    assert ("master_spindle", {"spindle": 2}) in ev
    assert ("spindle", {"spindle": 2, "speed": 640.0, "direction": "cw"}) in ev
    assert ("spindle", {"spindle": 2, "speed": 700.0, "direction": "ccw"}) in ev
    assert ("spindle", {"spindle": 1, "speed": 0.0, "direction": "cw"}) in ev
    assert ("coolant", {"mode": "mist+flood"}) in ev
    assert ("dwell", {"seconds": 2.0, "revolutions": None}) in ev
    assert ("dwell", {"seconds": None, "revolutions": 10.0}) in ev
    assert ("feed_mode", {"mode": "per_rev"}) in ev
    assert ("tool_change", {"tool": "5", "number": 5, "offset": None}) in ev
    assert ("tool_offset", {"offset": 0}) in ev
    assert ("coolant", {"mode": "off"}) in ev


def test_g4_f_is_dwell_not_feed(tmp_path):
    r = ok(tmp_path, "G1 F300\nG4 F2\nX1\nM30\n")
    assert moves(r)[0].feed == 300


def test_inch_units_convert_to_mm(tmp_path):
    r = ok(tmp_path, "G70 G1 X1 F10\nG71 X1\nM30\n")
    m = moves(r)
    assert m[0].axes["X"] == pytest.approx(25.4) and m[0].feed == pytest.approx(254)
    assert m[1].axes["X"] == 1


def test_machine_cycles_and_strict_axes(tmp_path):
    r = ok(tmp_path, "C_AXIS_ON\nG0 C1=90\nC_AXIS_OFF\nM30\n", TURN)
    assert [c.name for c in r.commands if c.kind == "cycle"] == ["C_AXIS_ON", "C_AXIS_OFF"]
    from nc import check

    f = check(tmp_path, "G0 A10\nM30\n", TURN)
    assert [(x.kind, x.line, x.source.column) for x in f] == [("unknown_word", 1, 4)]


def test_every_move_carries_every_axis_and_its_source(tmp_path):
    r = ok(tmp_path, "N10 G0 X1\nN20 G1 C1=5 F10\nM30\n", TURN)
    for m in moves(r):
        assert set(m.axes) == {"X", "Y", "Z", "C1"}
    assert [m.source.line for m in moves(r)] == [1, 2]


def test_trig_in_addresses(tmp_path):
    r = ok(tmp_path, "R56=50 R57=1.8 R85=10\nG1 X=(R56/2)-R57*SIN(R85*3)+10 F1\nM30\n")
    assert last(r)["X"] == pytest.approx(25 - 1.8 * math.sin(math.radians(30)) + 10, abs=1e-12)
