"""SCALE/ASCALE and MIRROR/AMIRROR frames: points, arcs (a mirror turns G2 into a
counter-clockwise motion of the machine) and tool radius compensation under them."""

from __future__ import annotations

import math

import pytest
from nc import RADII, error_of, moves, ok, plane_path, run

from vmach.canon import ArcFeed


def test_mirror_turns_points_and_arc_directions(tmp_path):
    r = ok(tmp_path, "G17 G0 X10 Y5\nMIRROR X0\nG0 X10 Y5\nG2 X20 Y15 I10 J0 F100\nMIRROR\nG0 X10 Y5\nM30\n")
    ms = moves(r)
    assert (ms[1].axes["X"], ms[1].axes["Y"]) == (-10, 5)
    arc = ms[2]
    assert isinstance(arc, ArcFeed) and (arc.axes["X"], arc.axes["Y"]) == (-20, 15)
    assert arc.center == pytest.approx((-20, 5)) and arc.clockwise is False
    assert (ms[3].axes["X"], ms[3].axes["Y"]) == (10, 5)          # MIRROR alone: off


def test_amirror_adds_to_a_translation_and_two_mirrors_cancel(tmp_path):
    r = ok(tmp_path, "G17 TRANS X100\nAMIRROR Y0\nG0 X10 Y5\nAMIRROR Y0\nX10 Y5\nM30\n")
    ms = moves(r)
    assert (ms[0].axes["X"], ms[0].axes["Y"]) == (110, -5)
    assert (ms[1].axes["X"], ms[1].axes["Y"]) == (110, 5)


def test_scale_and_ascale_multiply_lengths_and_arcs_stay_circles(tmp_path):
    r = ok(tmp_path, "G17 SCALE X2 Y2\nG0 X10 Y5\nASCALE X1.5 Y1.5\nG3 X0 Y20 CR=10 F100\nM30\n")
    ms = moves(r)
    assert (ms[0].axes["X"], ms[0].axes["Y"]) == (20, 10)
    arc = ms[1]
    assert (arc.axes["X"], arc.axes["Y"]) == pytest.approx((0, 60))
    c = arc.center
    assert math.dist((20, 10), c) == pytest.approx(math.dist((0, 60), c)) == pytest.approx(30)


def test_an_ellipse_and_a_zero_factor_are_errors(tmp_path):
    f = error_of(run(tmp_path, "G17 G0 X10 Y0\nSCALE X2 Y1\nG2 X0 Y-10 I-10 J0 F100\nM30\n"))
    assert (f.kind, f.line) == ("unsupported", 3)
    f = error_of(run(tmp_path, "SCALE X0\nM30\n"))
    assert (f.kind, f.line) == ("invalid_value", 1)


def test_a_mirrored_compensated_contour_keeps_the_tool_on_the_same_side_of_the_material(tmp_path):
    """G41 outside a square run clockwise; mirrored in X the tool stays outside the mirrored
    square (the control swaps G41/G42 itself): every point of the path mirrored back."""
    body = "T1 D1\nG17 G0 X-30 Y-30\nF500\n{m}G1 G41 X0 Y20\nY40\nX40\nY0\nX0\nY20\nG40 X-30 Y-30\nM30\n"
    plain = plane_path(run(tmp_path, body.format(m=""), options=RADII))
    mirrored = plane_path(run(tmp_path, body.format(m="MIRROR X0\n"), options=RADII))
    assert len(plain) == len(mirrored)
    for p, m in zip(plain[1:], mirrored[1:], strict=True):
        assert (m[1], m[2]) == pytest.approx((-p[1], p[2]))
        if p[0] == "A":
            assert m[4] is (not p[4]) and m[3] == pytest.approx((-p[3][0], p[3][1]))


def test_scaling_while_compensating_is_an_error(tmp_path):
    f = error_of(run(tmp_path, "T1 D1\nG0 X0 Y0\nF100\nG1 G41 X10\nSCALE X2 Y2\nY10\nM30\n", options=RADII))
    assert (f.kind, f.line) == ("cutcom", 5)
