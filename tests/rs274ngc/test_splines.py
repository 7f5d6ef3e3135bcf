"""Splines and NURBS in vmach's canonical stream: the sampled path lies on the curve.

rs274 prints only ``NURBS_FEED(count, ...)`` (the golden programs check that); the moves
vmach emits are LinuxCNC's sampling of the curve (biarcs between points of the curve), so
their end points must lie on the exact curve and the arcs stay close to it.
"""

from __future__ import annotations

import math

from interpreters.rs274ngc import run
from vmach.canon import ArcFeed, LinearFeed


def _moves(tmp_path, text: str):
    prog = tmp_path / "p.ngc"
    prog.write_text(text, encoding="utf-8")
    result = run(str(prog))
    assert result.completed, [f.render() for f in result.findings]
    return [c for c in result.commands if isinstance(c, (LinearFeed, ArcFeed))]


def test_quadratic_spline_ends_on_the_parabola(tmp_path):
    # G5.1 from (0,0), middle control point (10,10), end (20,0): y = x (20 - x) / 20
    moves = _moves(tmp_path, "G21 G17 F100\nG5.1 I10 J10 X20 Y0\nM2\n")
    assert len(moves) >= 12  # 4 x 3 steps, each one or two arcs
    for m in moves:
        x, y = m.axes["X"], m.axes["Y"]
        assert abs(y - x * (20 - x) / 20) < 0.02  # biarc joints lie near the curve
    assert (moves[-1].axes["X"], moves[-1].axes["Y"]) == (20.0, 0.0)
    assert any(isinstance(m, ArcFeed) for m in moves)


def test_rational_nurbs_quarter_circle_stays_on_the_circle(tmp_path):
    w = math.sqrt(0.5)
    text = f"G21 G17 F100\nG0 X10 Y0\nG5.2 X10 Y10 P{w:.12f}\nX0 Y10 P1\nG5.3\nM2\n"
    moves = _moves(tmp_path, text)
    for m in moves:
        assert abs(math.hypot(m.axes["X"], m.axes["Y"]) - 10.0) < 1e-3
        if isinstance(m, ArcFeed):  # each arc of the biarcs is nearly the circle itself
            cx, cy = m.center
            assert math.hypot(cx, cy) < 0.05
    assert abs(moves[-1].axes["X"]) < 1e-9 and abs(moves[-1].axes["Y"] - 10.0) < 1e-9
