"""Cylinder surface transformation TRACYL(d): the unwrapped Y turns the rotary axis by
Y·360/(π·d) degrees; arcs of the unwrapped surface become chords on it."""

from __future__ import annotations

import math

import pytest
from catalog import TURNMILL
from nc import error_of, moves, run

from vmach.canon import ArcFeed
from vmach.machine.control import load_control

TURN = load_control(TURNMILL)
K = 360 / (math.pi * 60)


def go(tmp_path, body, options=None):
    from vmach.canon import RunOptions

    r = run(tmp_path, "G19 G90 G0 X30 Y0 Z0\n" + body + "M30\n", TURN, options or RunOptions())
    assert r.completed, [f.render() for f in r.findings]
    return moves(r)


def test_lines_on_the_unwrapped_surface_turn_c1(tmp_path):
    ms = go(tmp_path, "TRACYL(60)\nG1 X27 F100\nY20 Z-5\nTRAFOOF\nG0 X40\n")
    assert [(m.axes["X"], m.axes["Y"], m.axes["Z"], round(m.axes["C1"], 9)) for m in ms[1:]] == [
        (27, 0, 0, 0), (27, 0, -5, round(20 * K, 9)), (40, 0, -5, round(20 * K, 9))]


def test_arcs_of_the_unwrapped_surface_become_chords_on_it(tmp_path):
    ms = go(tmp_path, "TRACYL(60)\nG1 X27 F100\nG2 Y10 Z-10 J10 K0\nTRAFOOF\n")
    chords = [m for m in ms if m.source.line == 4]
    assert len(chords) > 20 and not any(isinstance(m, ArcFeed) for m in chords)
    for m in chords:       # back on the unwrapped surface: on the circle about (10, 0), r 10
        y, z = m.axes["C1"] / K, m.axes["Z"]
        assert math.hypot(y - 10, z) == pytest.approx(10, abs=1e-9) and m.axes["Y"] == 0
    assert chords[-1].axes["C1"] == pytest.approx(10 * K) and chords[-1].axes["Z"] == pytest.approx(-10)


def test_y_zero_is_c1_at_a_whole_turn_and_the_rotary_axis_is_taken(tmp_path):
    ms = go(tmp_path, "G0 C1=725\nTRACYL(60)\nG1 Y10 F100\nTRAFOOF\n")
    assert ms[-1].axes["C1"] == pytest.approx(10 * K)
    f = error_of(run(tmp_path, "G19 G0 X30 Y0\nTRACYL(60)\nG1 C1=5 F100\nM30\n", TURN))
    assert (f.kind, f.line) == ("syntax", 3)


def test_compensation_works_on_the_unwrapped_surface(tmp_path):
    from vmach.canon import RunOptions

    radii = RunOptions(tool_radius=lambda tool, d: 4.0)
    ms = go(tmp_path, "T1 D1\nTRACYL(60)\nG1 X27 Y-10 F100\nG41 Y0 Z-20\nZ-40\nG40 Y-10 Z-60\nTRAFOOF\n",
            radii)
    # G41 moving −Z in the Y/Z plane (G19): left of −Z is +Y... the tool runs 4 mm to one side
    line = [m for m in ms if m.source.line == 6][0]
    assert abs(line.axes["C1"] / K) == pytest.approx(4)


@pytest.mark.parametrize("text, kind", [
    ("TRACYL\n", "syntax"), ("TRACYL(0.5)\n", "invalid_value"), ("TRACYL(60, 1, 2)\n", "unsupported")])
def test_bad_tracyl_calls_are_errors(tmp_path, text, kind):
    f = error_of(run(tmp_path, "G19 G0 X30\n" + text + "M30\n", TURN))
    assert (f.kind, f.line) == (kind, 2)


def test_a_program_ending_under_tracyl_is_warned(tmp_path):
    r = run(tmp_path, "G19 G0 X30 Y0 Z0\nTRACYL(60)\nG1 Y10 F100\nM30\n", TURN)
    assert r.completed
    assert [(f.kind, f.line, f.data["what"]) for f in r.findings] == [("left_active", 4, "TRACYL")]
