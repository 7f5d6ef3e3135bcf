"""TRANSMIT (face-end polar transformation, #35) on the turn-mill: Cartesian X Y on the face
become the radius X and the spindle angle C1; every written point is on the programmed path
(FK of the turn-mill model), C1 steps stay within tol.angle_step, the path through the centre
turns C1 by 180° at the pole, and TRAFOOF continues from the turns really made."""

from __future__ import annotations

import math

import numpy as np
import pytest
from catalog import TURNMILL
from nc import error_of, moves, run

from vmach.machine import load_model
from vmach.machine.control import load_control
from vmach.tol import tol

TURN = load_control(TURNMILL)


def go(tmp_path, body):
    r = run(tmp_path, "G17 G90 G0 X20 Y0 Z5 C1=0\nTRANSMIT\n" + body + "TRAFOOF\nM30\n", TURN)
    assert r.completed, [f.render() for f in r.findings]
    return moves(r)


def tips(ms):
    m = load_model("turnmill")
    q = np.array([[c.axes[a] for a in m.axes] for c in ms])
    return m.fk(q).tip


def test_a_face_line_is_written_on_the_line(tmp_path):
    ms = [c for c in go(tmp_path, "G1 X10 Y10 F100\nX-10\n") if c.source.line == 4]
    t = tips(ms)
    assert np.abs(t[:, 1] - 10).max() < 1e-9 and np.abs(t[:, 2] - 5).max() < 1e-9
    assert t[-1, 0] == pytest.approx(-10, abs=1e-9) and all(c.axes["Y"] == 0 for c in ms)
    c = np.array([m.axes["C1"] for m in ms])
    assert np.abs(np.diff(c)).max() <= tol.angle_step + 1e-9 and c[-1] == pytest.approx(135)
    # between two written points the machine interpolates X and C1 linearly: the face path
    # stays within the chord tolerance of the line
    x, a = np.array([m.axes["X"] for m in ms]), np.radians(c)
    mid_r, mid_a = (x[1:] + x[:-1]) / 2, (a[1:] + a[:-1]) / 2
    assert np.abs(mid_r * np.sin(mid_a) - 10).max() < tol.chord


def test_through_the_centre_c_turns_at_the_pole(tmp_path):
    ms = [c for c in go(tmp_path, "G1 X-10 Y-10 F100\nX10 Y10\n") if c.source.line == 4]
    assert [(round(m.axes["X"], 9), round(m.axes["C1"], 9)) for m in ms] == [
        (0.0, -135.0), (round(math.hypot(10, 10), 9), 45.0)]


def test_an_arc_on_the_face(tmp_path):
    ms = [c for c in go(tmp_path, "G1 X10 Y0 F100\nG3 X-10 Y0 I-10 J0\n") if c.source.line == 4]
    t = tips(ms)
    assert np.abs(np.hypot(t[:, 0], t[:, 1]) - 10).max() < tol.chord + 1e-9   # chords of the arc
    assert ms[-1].axes["C1"] == pytest.approx(180)


def test_trafoof_keeps_the_turns(tmp_path):
    ms = go(tmp_path, "G1 X10 Y0 F100\nG3 X10 Y0 I-10 J0\nG3 X10 Y0 I-10 J0\n")
    r = run(tmp_path, "G0 X20 Y0 C1=0\nTRANSMIT\nG1 X10 Y0 F100\nG3 X10 Y0 I-10 J0\nTRAFOOF\nG0 X30\n"
            "TRANSMIT\nG1 Y5\nTRAFOOF\nM30\n", TURN)
    after = moves(r)
    assert ms[-1].axes["C1"] == pytest.approx(720)
    assert [c for c in after if c.source.line == 6][0].axes["C1"] == pytest.approx(360)
    last = [c for c in after if c.source.line == 8][-1]
    assert last.axes["C1"] == pytest.approx(360 + math.degrees(math.atan2(5, 30)))


def test_errors(tmp_path):
    f = error_of(run(tmp_path, "TRANSMIT\nG1 C1=10 F100\nM30\n", TURN))
    assert (f.kind, f.line) == ("syntax", 2)
    f = error_of(run(tmp_path, "G0 Y5\nTRANSMIT\nM30\n", TURN))
    assert (f.kind, f.line) == ("unsupported", 2)
    r = run(tmp_path, "TRANSMIT\nG1 X5 F100\nM30\n", TURN)
    assert ("left_active", 3) in [(f.kind, f.line) for f in r.findings]
