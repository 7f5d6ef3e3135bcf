"""Chamfers and roundings between straight elements (CHF=, CHR=, RND=, RNDM=), alone and with
tool radius compensation, against the corner geometry worked out by hand."""

from __future__ import annotations

import math

import pytest
from nc import RADII, error_of, moves, run
from nc import plane_path as path


def go(tmp_path, body, options=RADII):
    r = run(tmp_path, "T1 D1\nG17 G90 G0 X0 Y0 Z0\nF500\n" + body + "M30\n", options=options)
    assert r.completed, [f.render() for f in r.findings]
    return path(r)[1:]


def test_rnd_joins_two_lines_with_a_tangent_arc(tmp_path):
    got = go(tmp_path, "G1 X40 RND=5\nY40\n")
    assert got == [("L", 35, 0), ("A", 40, 5, (35, 5), False), ("L", 40, 40)]


def test_rnd_on_a_right_turn_runs_clockwise(tmp_path):
    got = go(tmp_path, "G1 X40 RND=5\nY-40\n")
    assert got == [("L", 35, 0), ("A", 40, -5, (35, -5), True), ("L", 40, -40)]


def test_chf_is_the_chamfer_length_and_chr_its_leg(tmp_path):
    leg = 4 / (2 * math.cos(math.pi / 4))              # 90° turn: legs l / √2
    got = go(tmp_path, "G1 X40 CHF=4\nY40 CHR=3\nX0\n")
    assert got[0][:2] == ("L", pytest.approx(40 - leg)) and got[1] == ("L", 40, pytest.approx(leg))
    assert got[2] == ("L", 40, 37) and got[3] == ("L", 37, 40) and got[4] == ("L", 0, 40)
    assert math.hypot(got[1][1] - got[0][1], got[1][2] - got[0][2]) == pytest.approx(4)


def test_rnd_at_an_obtuse_corner_uses_the_half_angle(tmp_path):
    """A 60° turn: the arc starts ρ·tan 30° before the corner."""
    got = go(tmp_path, f"G1 X40 RND=6\nX{40 + 20 * math.cos(math.pi / 3)} Y{20 * math.sin(math.pi / 3)}\n")
    d = 6 * math.tan(math.pi / 6)
    assert got[0] == ("L", pytest.approx(40 - d), 0)
    end = got[1]
    assert end[0] == "A" and end[1:3] == pytest.approx((40 + d * 0.5, d * math.sqrt(3) / 2))
    assert end[3] == pytest.approx((40 - d, 6)) and end[4] is False


def test_rndm_rounds_every_corner_until_rndm_0(tmp_path):
    got = go(tmp_path, "RNDM=2\nG1 X40\nY40\nX0\nRNDM=0\nY0\nX10\n")
    arcs = [g for g in got if g[0] == "A"]
    # RNDM=2 was active for X0, so its end is rounded too; Y0's is not
    assert len(arcs) == 3 and got[-2:] == [("L", 0, 0), ("L", 10, 0)]


def test_a_rounding_is_compensated_as_an_arc_of_the_contour(tmp_path):
    """G42 outside the rounded corner: the tool runs the concentric arc ρ + r."""
    got = go(tmp_path, "G0 X-20 Y-20\nG1 G42 X0 Y0\nX40 RND=10\nY40\nG40 X60 Y60\n")
    assert got[1:4] == [("L", 0, -5), ("L", 30, -5), ("A", 45, 10, (30, 10), False)]


def test_a_chamfer_longer_than_its_elements_is_an_error(tmp_path):
    r = run(tmp_path, "G0 X0 Y0\nF100\nG1 X4 RND=10\nY40\nM30\n")
    f = error_of(r)
    assert (f.kind, f.line) == ("corner_insert", 3)


def test_rnd_between_a_line_and_an_arc_touches_both(tmp_path):
    """Line +x to (40, 0), then a CCW arc about (60, 0) (a right turn): the rounding circle's
    centre is where y = −5 meets the circle of radius 25 about (60, 0)."""
    cx = 60 - math.sqrt(600)
    touch = (60 - 20 * math.sqrt(600) / 25, -4.0)
    got = go(tmp_path, "G1 X40 RND=5\nG3 X60 Y-20 I20 J0\n")
    assert got[0] == ("L", pytest.approx(cx), 0)
    assert got[1][0] == "A" and got[1][1:3] == pytest.approx(touch) and got[1][4] is True
    assert got[1][3] == pytest.approx((cx, -5))
    assert got[2] == ("A", 60, -20, (60, 0), False)
    back = go(tmp_path, "G0 X60 Y-20\nG2 X40 Y0 I0 J20 RND=5\nG1 X0\n")   # the same corner, reversed
    assert back[1][1:3] == pytest.approx(touch) and back[1][3] == (60, 0)
    assert back[2][1:3] == pytest.approx((cx, 0)) and back[2][3] == pytest.approx((cx, -5))
    assert back[2][4] is False and back[3] == ("L", 0, 0)


def test_a_chamfer_next_to_an_arc_is_reported_unsupported(tmp_path):
    r = run(tmp_path, "G0 X0 Y0\nF100\nG1 X40 CHF=2\nG3 X40 Y20 I0 J10\nM30\n")
    f = error_of(r)
    assert (f.kind, f.line) == ("unsupported", 3)


def test_other_commands_keep_their_place_around_a_held_block(tmp_path):
    r = run(tmp_path, "G0 X0 Y0\nF100\nG1 X40 RND=5\nM8\nY40\nM30\n")
    kinds = [type(c).__name__ for c in r.commands]
    i = kinds.index("Coolant")
    assert kinds[i - 2:i + 2] == ["LinearFeed", "ArcFeed", "Coolant", "LinearFeed"]
    assert len(moves(r)) == 4


def test_frc_and_frcm_give_the_inserts_feed(tmp_path):
    r = run(tmp_path, "G0 X0 Y0\nF100\nG1 X40 RND=5 FRC=20\nY40 CHF=2\nFRCM=30\nX0 RND=1\nY0\nM30\n")
    feeds = [m.feed for m in moves(r)[1:]]
    # X40, its arc (FRC), Y40, its chamfer (the block's feed), X0, its arc (FRCM), Y0
    assert feeds == [100, 20, 100, 100, 100, 30, 100]


def _tangent(start, c):
    """Unit tangent of motion c at its start (start given) and at its end."""
    from vmach.canon import ArcFeed

    end = (c.axes["X"], c.axes["Y"])
    out = []
    for p in (start, end):
        if isinstance(c, ArcFeed):
            u = (p[0] - c.center[0], p[1] - c.center[1])
            t = (u[1], -u[0]) if c.clockwise else (-u[1], u[0])
        else:
            t = (end[0] - start[0], end[1] - start[1])
        n = math.hypot(*t)
        out.append((t[0] / n, t[1] / n))
    return out


@pytest.mark.parametrize("seed", range(40))
def test_rndm_leaves_no_corner_in_a_random_contour_of_lines_and_arcs(tmp_path, seed):
    """Every junction of a contour rounded with RNDM is tangent, and every insert has the
    programmed radius (random lines and arcs; a contour whose elements are too short for the
    rounding is corner_insert and skipped)."""
    import random

    from vmach.canon import ArcFeed

    rng = random.Random(seed)
    lines, x, y = ["G17 G90 G0 X0 Y0 Z0", "F100", "RNDM=1"], 0.0, 0.0
    for _ in range(rng.randint(2, 8)):
        if rng.random() < 0.5:
            x, y = rng.uniform(-50, 50), rng.uniform(-50, 50)
            lines.append(f"G1 X{x:.4f} Y{y:.4f}")
        else:
            i, j = rng.uniform(-30, 30), rng.uniform(-30, 30)
            a = math.atan2(-j, -i) + rng.uniform(-3, 3)
            x, y = x + i + math.hypot(i, j) * math.cos(a), y + j + math.hypot(i, j) * math.sin(a)
            lines.append(f"{rng.choice(['G2', 'G3'])} X{x:.6f} Y{y:.6f} I{i:.6f} J{j:.6f}")
    r = run(tmp_path, "\n".join(lines) + "\nM30\n")
    if not r.completed:                 # an element too short for the rounding
        assert error_of(r).kind == "corner_insert"
        return
    ms = moves(r)
    prev, before = (ms[0].axes["X"], ms[0].axes["Y"]), None
    for c in ms[1:]:
        t0, t1 = _tangent(prev, c)
        if before is not None:
            cross, dot = before[0] * t0[1] - before[1] * t0[0], before[0] * t0[0] + before[1] * t0[1]
            assert abs(cross) < 1e-6 and dot > 0
        before, prev = t1, (c.axes["X"], c.axes["Y"])
    inserts = [c for c in ms if isinstance(c, ArcFeed)
               and abs(math.hypot(c.axes["X"] - c.center[0], c.axes["Y"] - c.center[1]) - 1.0) < 1e-9]
    assert len(inserts) >= 1
