"""Polar coordinates: poles G110/G111/G112 and moves by AP=/RP= (worked out by hand)."""

from __future__ import annotations

import math

import pytest
from nc import error_of, moves, ok, run

from vmach.canon import ArcFeed


def xy(r):
    return [(round(m.axes["X"], 9), round(m.axes["Y"], 9)) for m in moves(r)]


def test_g111_pole_and_polar_moves(tmp_path):
    r = ok(tmp_path, "G17 G0 X0 Y0\nG111 X10 Y20\nG1 AP=90 RP=5 F100\nAP=0\nRP=8\nAP=IC(90)\nM30\n")
    assert xy(r) == [(0, 0), (10, 25), (15, 20), (18, 20), (10, 28)]


def test_g110_and_g112_are_relative_to_the_position_and_the_last_pole(tmp_path):
    r = ok(tmp_path, "G17 G0 X5 Y5\nG110 X10\nG1 AP=180 RP=2 F100\nG112 AP=90 RP=10\nG1 AP=0 RP=1\nM30\n")
    # G110: pole (15, 5); G112 polar: (15, 15)
    assert xy(r)[1:] == [(13, 5), (16, 15)]


def test_without_a_pole_the_origin_is_the_pole_and_z_moves_along(tmp_path):
    r = ok(tmp_path, "G17 G0 X0 Y0 Z0\nG1 AP=30 RP=10 Z-2 F100\nM30\n")
    m = moves(r)[-1]
    assert (m.axes["X"], m.axes["Y"], m.axes["Z"]) == pytest.approx((10 * math.cos(math.pi / 6), 5, -2))


def test_a_polar_arc_turns_about_the_pole(tmp_path):
    r = ok(tmp_path, "G17 G0 X30 Y10\nG111 X20 Y10\nG3 AP=90 F100\nM30\n")
    arc = moves(r)[-1]
    assert isinstance(arc, ArcFeed) and arc.center == pytest.approx((20, 10)) and not arc.clockwise
    assert (arc.axes["X"], arc.axes["Y"]) == pytest.approx((20, 20))


def test_the_pole_follows_the_frame(tmp_path):
    r = ok(tmp_path, "G17 TRANS X100\nG111 X0 Y0\nG0 AP=90 RP=10\nM30\n")
    assert xy(r)[-1] == (100, 10)


@pytest.mark.parametrize("text, kind, line", [
    ("G17 G0 X0 Y0\nG1 X5 AP=30 RP=2 F100\nM30\n", "syntax", 2),
    ("G17 G111 X1 AP=5\nM30\n", "syntax", 1),
    ("G17 G0 AP=5 RP=-1\nM30\n", "invalid_value", 1),
])
def test_polar_words_in_conflict_are_errors(tmp_path, text, kind, line):
    f = error_of(run(tmp_path, text))
    assert (f.kind, f.line) == (kind, line)
