"""Tool radius compensation G41/G42/G40 (NORM, G450/G451): compensated paths against the
offset contours worked out by hand (a 40 mm square, a Ø40 circle, tool radius 5 mm)."""

from __future__ import annotations

import math

import pytest
from nc import RADII, error_of, moves, plane_path, run

from vmach.canon import ArcFeed, LinearFeed, RunOptions

path = plane_path


def go(tmp_path, body, options=RADII):
    r = run(tmp_path, "T1 D1\nG17 G90 G0 X-20 Y-20 Z5\nF500\n" + body + "M30\n", options=options)
    assert r.completed, [f.render() for f in r.findings]
    return path(r)[1:]


SQUARE = "Y40\nX40\nY0\nX0\n"


def test_g41_outside_a_square_with_transition_arcs(tmp_path):
    got = go(tmp_path, "G1 G41 X0 Y0\n" + SQUARE + "G40 X-20 Y-20\n")
    assert got == [
        ("L", -5, 0),                                  # NORM: perpendicular to the first side
        ("L", -5, 40), ("A", 0, 45, (0, 40), True),    # G450: arc of r about the corner
        ("L", 40, 45), ("A", 45, 40, (40, 40), True),
        ("L", 45, 0), ("A", 40, -5, (40, 0), True),
        ("L", 0, -5),                                  # perpendicular end before G40
        ("L", -20, -20),                               # retract to the programmed point
    ]


def test_g451_runs_to_the_intersection_at_outside_corners(tmp_path):
    got = go(tmp_path, "G451 G1 G41 X0 Y0\n" + SQUARE + "G40 X-20 Y-20\n")
    assert got == [("L", -5, 0), ("L", -5, 45), ("L", 45, 45), ("L", 45, -5), ("L", 0, -5), ("L", -20, -20)]


def test_g42_inside_a_square_ends_each_side_at_the_intersection(tmp_path):
    got = go(tmp_path, "G1 G42 X0 Y0\n" + SQUARE + "G40 X-20 Y-20\n")
    assert got == [("L", 5, 0), ("L", 5, 35), ("L", 35, 35), ("L", 35, 5), ("L", 0, 5), ("L", -20, -20)]


def test_arcs_are_offset_concentrically_and_tangent_joins_need_no_transition(tmp_path):
    got = go(tmp_path, "G1 G41 X0 Y20\nG2 X20 Y0 I0 J-20\nG2 X0 Y-20 I-20 J0\nG40 G1 X-40 Y-20\n")
    assert got == [("L", 0, 25), ("A", 25, 0, (0, 0), True), ("A", 0, -25, (0, 0), True), ("L", -40, -20)]


def test_a_line_joins_a_tangent_arc_on_the_offset_circle(tmp_path):
    got = go(tmp_path, "G1 G41 X0 Y0\nX30\nG3 X50 Y20 I0 J20\nG40 G1 X60 Y20\n")
    assert got[1:4] == [("L", 30, 5), ("A", 45, 20, (30, 20), False), ("L", 60, 20)]


def test_inside_corner_between_a_line_and_an_arc(tmp_path):
    """G41 along y = 0 toward +x, then G3 about (20, 10) turning 45° left at (30, 0): the tool
    is inside the corner; the line ends where y = 5 meets the circle of radius √200 − 5."""
    got = go(tmp_path, "G1 G41 X0 Y0\nX30\nG3 X30 Y20 I-10 J10\nG40 G1 X40 Y20\n")
    rc = math.sqrt(200) - 5
    x = 20 + math.sqrt(rc * rc - 25)
    assert got[1][0] == "L" and got[1][1] == pytest.approx(x, abs=1e-9) and got[1][2] == pytest.approx(5)
    arc = got[2]
    assert arc[0] == "A" and arc[3] == pytest.approx((20, 10)) and arc[4] is False
    h = rc / math.sqrt(2)                          # the arc ends r along its end normal
    assert arc[1:3] == pytest.approx((20 + h, 10 + h), abs=1e-9)


def test_moves_of_other_axes_run_at_the_compensated_corner(tmp_path):
    got = go(tmp_path, "G1 G41 X0 Y0\nZ-5\nY40\nZ-6\nX40\nG40 X60 Y60\n")
    assert got[:6] == [("L", -5, 0), ("L", -5, 0), ("L", -5, 40), ("L", -5, 40),
                       ("A", 0, 45, (0, 40), True), ("L", 40, 45)]


def test_the_compensated_path_turns_with_the_frame(tmp_path):
    plain = go(tmp_path, "G1 G41 X0 Y0\n" + SQUARE + "G40 X-20 Y-20\n")
    turned = go(tmp_path, "ROT RPL=90\nG1 G41 X0 Y0\n" + SQUARE + "G40 X-20 Y-20\n")
    for p, t in zip(plain[1:], turned[1:], strict=True):   # (x, y) -> (−y, x)
        assert t[1] == pytest.approx(-p[2], abs=1e-9) and t[2] == pytest.approx(p[1], abs=1e-9)


def test_d_selects_the_offset_radius(tmp_path):
    got = go(tmp_path, "D2 G1 G41 X0 Y0\nY40\nG40 X-20 Y60\n")
    assert got[:2] == [("L", -2, 0), ("L", -2, 40)]


def test_a_tool_too_big_for_an_inside_corner_is_an_error_at_the_block(tmp_path):
    r = run(tmp_path, "T1 D1\nG0 X-20 Y-20\nF500\nG1 G42 X0 Y0\nY40\nX4\nY0\nM30\n", options=RADII)
    f = error_of(r)
    assert (f.kind, f.line) == ("cutcom_collision", 6)


def test_an_arc_smaller_than_the_tool_on_the_inside_is_an_error(tmp_path):
    r = run(tmp_path, "T1 D1\nG0 X-20 Y3\nF500\nG1 G42 X0 Y3\nG2 X3 Y0 I0 J-3\nM30\n", options=RADII)
    f = error_of(r)
    assert (f.kind, f.line) == ("cutcom_radius", 5)
    assert f.data["arc_radius"] == pytest.approx(3) and f.data["tool_radius"] == 5


@pytest.mark.parametrize("options, tool", [(RunOptions(), "T1 D1"), (RADII, "T1 D7"), (RADII, "T=\"NONE\"")])
def test_g41_without_a_known_radius_is_an_error_at_g41(tmp_path, options, tool):
    r = run(tmp_path, tool + "\nG0 X0 Y0\nG1 F100 G41 X10\nM30\n", options=options)
    f = error_of(r)
    assert (f.kind, f.line, f.source.column) == ("no_tool_radius", 3, 9)


def test_d0_and_g40_give_the_programmed_path(tmp_path):
    got = go(tmp_path, "D0 G1 G41 X0 Y0\nY40\nG40 X-20 Y60\n")
    assert got[:2] == [("L", 0, 0), ("L", 0, 40)]


def test_the_end_of_the_program_ends_the_compensation(tmp_path):
    got = go(tmp_path, "G1 G41 X0 Y0\nY40\n")
    assert got == [("L", -5, 0), ("L", -5, 40)]


def test_g41_in_a_block_without_plane_motion_applies_from_the_next_one(tmp_path):
    got = go(tmp_path, "G41\nZ0\nG1 X0 Y0\nY40\nG40 X-20 Y60\n")
    assert got[:3] == [("L", -20, -20), ("L", -5, 0), ("L", -5, 40)]


def test_feeds_and_lines_keep_their_source(tmp_path):
    r = run(tmp_path, "T1 D1\nG0 X-20 Y-20\nF500\nG1 G41 X0 Y0\nY40\nX40\nG40 X60 Y60\nM30\n", options=RADII)
    m = moves(r)
    assert [(type(c).__name__, c.source.line) for c in m[1:]] == [
        ("LinearFeed", 4), ("LinearFeed", 5), ("ArcFeed", 6), ("LinearFeed", 6), ("LinearFeed", 7)]
    assert all(c.feed == 500 for c in m[1:] if isinstance(c, (LinearFeed, ArcFeed)))


def test_changing_side_retracts_and_approaches_again(tmp_path):
    got = go(tmp_path, "G1 G41 X0 Y0\nY40\nG42 X40\nY0\nG40 X60 Y-20\n")
    # Y40 ends perpendicular (left of +y: x = −5); X40 is the new approach, ending right of
    # the next side (−y): x = 35; then that side ends perpendicular at its end
    assert got[:4] == [("L", -5, 0), ("L", -5, 40), ("L", 35, 40), ("L", 35, 0)]


def test_g40_then_g41_again_before_any_motion_keeps_the_pending_side(tmp_path):
    got = go(tmp_path, "G1 G41 X0 Y0\nY40\nG40\nG41\nX40\nY0\nG40 X60 Y-20\n")
    assert got[:2] == [("L", -5, 0), ("L", -5, 40)]
    assert got[2:4] == [("L", 45, 40), ("L", 45, 0)]


def _sampled(result, skip_first: int, skip_last: int):
    """Points (k, 2) along the compensated moves between the approach and the retract."""
    import numpy as np

    ms = moves(result)
    pts = []
    prev = (ms[skip_first - 1].axes["X"], ms[skip_first - 1].axes["Y"])
    for m in ms[skip_first:len(ms) - skip_last]:
        end = (m.axes["X"], m.axes["Y"])
        if isinstance(m, ArcFeed):
            c = np.array(m.center)
            a0 = math.atan2(prev[1] - c[1], prev[0] - c[0])
            a1 = math.atan2(end[1] - c[1], end[0] - c[0])
            sweep = (a0 - a1) % (2 * math.pi) if m.clockwise else (a1 - a0) % (2 * math.pi)
            t = np.linspace(0, sweep, 17) * (-1 if m.clockwise else 1) + a0
            rad = math.hypot(prev[0] - c[0], prev[1] - c[1])
            pts.append(np.column_stack([c[0] + rad * np.cos(t), c[1] + rad * np.sin(t)]))
        else:
            s = np.linspace(0, 1, 9)[:, None]
            pts.append(np.array(prev) * (1 - s) + np.array(end) * s)
        prev = end
    return np.concatenate(pts)


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("side, corner", [("G42", "G450"), ("G41", "G450"), ("G42", "G451")])
def test_a_convex_contour_is_followed_at_exactly_the_tool_radius(tmp_path, seed, side, corner):
    """A random convex polygon run counter-clockwise: G42 keeps the tool outside (G450: arcs
    about the corners), G41 inside (intersections). Every point of the compensated path lies
    exactly r from the polygon (shapely's distance); outside with G451 it is never nearer."""
    import numpy as np
    from shapely.geometry import Point as SPoint
    from shapely.geometry import Polygon

    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 9))
    while True:                     # sides of at least 0.35 rad, no turn of more than 2.6 rad
        ang = np.sort(rng.uniform(0, 2 * np.pi, n))
        gaps = np.diff(np.r_[ang, ang[0] + 2 * np.pi])
        if gaps.min() >= 0.35 and gaps.max() <= 2.6:
            break
    rad = rng.uniform(20, 30)
    poly = np.column_stack([rad * np.cos(ang), rad * np.sin(ang)]).round(4)
    r = float(rng.uniform(0.5, 2.0))
    mid = ((poly[-1] + poly[0]) / 2).round(4)   # start and end mid-side, as programmers do
    text = ("T1 D1\nG17 G0 X60 Y60 Z0\nF300\n" + corner + "\n"
            + f"G1 {side} X{mid[0]} Y{mid[1]}\n"
            + "".join(f"X{x} Y{y}\n" for x, y in poly) + f"X{mid[0]} Y{mid[1]}\n"
            + "G40 X60 Y60\nM30\n")
    result = run(tmp_path, text, options=RunOptions(tool_radius=lambda t, d: r))
    assert result.completed, [f.render() for f in result.findings]
    ring = Polygon(np.vstack([poly, mid])).exterior
    d = np.array([ring.distance(SPoint(p)) for p in _sampled(result, 2, 1)])
    if corner == "G451":            # outside, straight on to the intersections: never nearer
        assert d.min() >= r - 1e-6 and d.max() > r + 1e-3
        assert not any(isinstance(m, ArcFeed) for m in moves(result))
    else:
        assert np.abs(d - r).max() < 1e-6
    inside = Polygon(poly).contains(SPoint(_sampled(result, 2, 1)[3]))
    assert inside == (side == "G41")


def test_a_d_change_while_compensating_applies_from_the_next_element(tmp_path):
    got = go(tmp_path, "G1 G41 X0 Y0\nY40\nD2 X40\nY0\nG40 X60 Y-20\n")
    assert got == [("L", -5, 0), ("L", -5, 40),
                   ("L", 0, 42),                      # straight from the 5 mm path to the 2 mm one
                   ("L", 40, 42), ("A", 42, 40, (40, 40), True), ("L", 42, 0), ("L", 60, -20)]


def test_g451_meets_an_arc_on_its_compensated_circle(tmp_path):
    """x = −5 (the line's path) meets the circle about (20, 30) of radius √500 + 5."""
    got = go(tmp_path, "G451 G1 G41 X0 Y0\nY40\nG2 X40 Y40 I20 J-10\nG40 G1 X60 Y40\n")
    rc = math.sqrt(500) + 5
    assert got[1][0] == "L" and got[1][1:] == pytest.approx((-5, 30 + math.sqrt(rc * rc - 625)), abs=1e-9)
    arc = got[2]
    assert arc[0] == "A" and arc[3] == pytest.approx((20, 30)) and arc[4] is True
    n = (2 / math.sqrt(5), 1 / math.sqrt(5))          # the arc's end normal, outward
    assert arc[1:3] == pytest.approx((40 + 5 * n[0], 40 + 5 * n[1]), abs=1e-9)
    assert math.hypot(arc[1] - 20, arc[2] - 30) == pytest.approx(rc)


@pytest.mark.parametrize("body, what", [
    ("G1 G41 X0 Y0\nY40\n", "G41/G42"),
    ("MCALL CYCLE81(5, 0, 1, -3)\nX10\n", "MCALL"),
])
def test_a_program_that_ends_with_a_modal_function_on_is_warned(tmp_path, body, what):
    r = run(tmp_path, "T1 D1\nG17 G90 G0 X-20 Y-20 Z5\nF500\n" + body + "M30\n", options=RADII)
    assert r.completed
    warned = [f for f in r.findings if f.kind == "left_active"]
    assert [(f.severity, f.line, f.data["what"]) for f in warned] == [("warning", body.count("\n") + 4, what)]
    clean = run(tmp_path, "T1 D1\nG17 G0 X0 Y0\nF500\nG1 G41 X10\nG40 X20\nM30\n", options=RADII)
    assert [f for f in clean.findings if f.kind == "left_active"] == []
