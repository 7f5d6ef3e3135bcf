"""CYCLE79 (multi-edge), CYCLE802 (arbitrary positions) and CYCLE60 (engraving): the moves
each call makes, worked out from the cycles' descriptions (interpreters/sinumerik/cycles/)."""

from __future__ import annotations

import math

import pytest
from nc import error_of, moves, run

from interpreters.sinumerik.cycles.engraving import GLYPHS
from vmach.canon import ArcFeed, LinearFeed, RunOptions, Traverse

R5 = RunOptions(tool_radius=lambda tool, d: 5.0 if d == 1 else 0.1)
HEAD = "T1 D1\nG17 G90 G0 X0 Y0 Z50\nS1000 M3 F300\n"


def err(tmp_path, call: str) -> tuple[str, int]:
    f = error_of(run(tmp_path, HEAD + call + "\nM30\n", options=R5))
    return f.kind, f.line


def go(tmp_path, call: str, line: int = 4):
    r = run(tmp_path, HEAD + call + "\nM30\n", options=R5)
    assert r.completed, [f.render() for f in r.findings]
    return [m for m in moves(r) if m.source.line == line]


def test_cycle79_hexagon_flats_a_tool_radius_out(tmp_path):
    """A hexagon 40 across flats, R2 corners, at (50, 40) from a Ø60 blank, 5 deep, finishing
    (VARI 2): the tool centre runs 20 + 5 from the centre on every flat, the corners are arcs
    of 2 + 5 about points on the corner directions."""
    ms = go(tmp_path, "CYCLE79(10, 0, 2, -5, 50, 40, 60, 0, 6, 40, 2, 0, 0, 0, 600, 200, 0, 2)")
    cut = [m for m in ms if isinstance(m, (LinearFeed, ArcFeed)) and m.axes["Z"] == -5]
    arcs = [m for m in cut if isinstance(m, ArcFeed)]
    assert len(arcs) == 6
    for m in arcs:
        assert math.dist(m.center, (50, 40)) == pytest.approx((20 - 2) / math.cos(math.pi / 6))
        assert math.dist((m.axes["X"], m.axes["Y"]), m.center) == pytest.approx(7)
    # every cut point lies at 25 from the centre along its nearest flat's normal
    for m in cut:
        x, y = m.axes["X"] - 50, m.axes["Y"] - 40
        if math.hypot(x, y) < 30:                       # not the infeed point outside
            best = max(x * math.cos(k * math.pi / 3) + y * math.sin(k * math.pi / 3) for k in range(6))
            assert best == pytest.approx(25)
    assert all(m.clockwise for m in arcs)               # climb outside: G2
    assert ms[-1].axes["Z"] == 10


def test_cycle79_edge_length_and_roughing_rings(tmp_path):
    """UMODE 1: a square of edge 30 (apothem 15) roughed from a Ø50 blank with FAL 0.5: the
    innermost ring 15 + 5 + 0.5 out, the outermost at least the blank's radius + 5."""
    ms = go(tmp_path, "CYCLE79(10, 0, 2, -3, 0, 0, 50, 0, 4, 30, 0, 0, 0.5, 0, 600, 200, 0, 1, 1)")
    xs = {}
    for m in ms:
        if "ring" in getattr(m.source, "phase", ""):
            xs.setdefault(m.source.phase, []).append(max(m.axes["X"], m.axes["Y"]))
    reach = sorted(round(max(v), 9) for v in xs.values())
    assert reach[0] == pytest.approx(20.5) and reach[-1] >= 25 + 5 - 1e-9


def test_cycle79_bad_parameters(tmp_path):
    assert err(tmp_path, "CYCLE79(10, 0, 2, -5, 0, 0, 60, 0, 2, 40)") == ("cycle_parameter", 4)
    # the blank smaller than the corners
    assert err(tmp_path, "CYCLE79(10, 0, 2, -5, 0, 0, 30, 0, 6, 40)") == ("cycle_parameter", 4)


def test_cycle802_drills_at_each_given_position(tmp_path):
    """MCALL CYCLE81 then CYCLE802 with three positions; position 2's Y is not given by the
    mask (digit 0) and keeps position 1's."""
    ms = go(tmp_path, "MCALL CYCLE81(10, 0, 2, -5)\nCYCLE802(111, 11, 10, 10, 20, 12, 30, 99)\nMCALL", line=5)
    bottoms = [(m.axes["X"], m.axes["Y"]) for m in ms if isinstance(m, LinearFeed) and m.axes["Z"] == -5]
    assert bottoms == [(10, 10), (20, 12), (30, 12)]
    assert {m.source.phase for m in ms if isinstance(m, LinearFeed)} == {"position 1/3", "position 2/3",
                                                                        "position 3/3"}


def test_cycle802_without_mcall_only_positions(tmp_path):
    ms = go(tmp_path, "CYCLE802(0, 0, 5, 6, , 7)")
    assert [(m.axes["X"], m.axes["Y"]) for m in ms] == [(5, 6), (5, 7)]
    assert all(isinstance(m, Traverse) for m in ms)


def test_cycle60_linear_text_follows_the_font(tmp_path):
    """'HI' 6 high at (10, 20), 0.2 deep: the font's cell scaled 1:1, the characters 2 apart
    (a third of the height)."""
    ms = go(tmp_path, 'CYCLE60("hi", 10, 0, 2, -0.2, 10, 20, 0, 6, 0, 100, 300, 0)')
    cut = [m for m in ms if isinstance(m, LinearFeed) and m.axes["Z"] == pytest.approx(-0.2)]
    pts = {(round(m.axes["X"], 9), round(m.axes["Y"], 9)) for m in cut}
    want = set()
    for k, ch in enumerate("HI"):
        for stroke in GLYPHS[ch]:
            want |= {(round(10 + k * 6 + u, 9), round(20 + v, 9)) for u, v in stroke}
    assert pts == want
    plunges = [m for m in cut if m.feed == 100]
    assert len(plunges) == len(GLYPHS["H"]) + len(GLYPHS["I"])
    assert max(m.axes["Z"] for m in ms if isinstance(m, Traverse)) == 50 and ms[-1].axes["Z"] == 10


def test_cycle60_centred_and_on_an_arc(tmp_path):
    """Centred (VARI 1) 'I' at (0, 0): its middle stroke at x = 0. On an arc of radius 30
    about (0, -30) (VARI 11, the reference point centred at the top): the strokes lie between
    radius 30 and 36 and symmetric about the Y axis."""
    ms = go(tmp_path, 'CYCLE60("I", 10, 0, 2, -0.2, 0, 0, 0, 6, 0, 100, 300, 1)')
    assert {round(m.axes["X"], 9) for m in ms if isinstance(m, LinearFeed) and m.feed == 100} >= {0}
    ms = go(tmp_path, 'CYCLE60("HOH", 10, 0, 2, -0.2, 0, 0, 0, 6, 0, 100, 300, 11, 0, -30)')
    cut = [m for m in ms if isinstance(m, LinearFeed)]
    radii = [math.hypot(m.axes["X"], m.axes["Y"] + 30) for m in cut]
    assert min(radii) >= 30 - 1e-9 and max(radii) <= math.hypot(36, 2) + 1e-9
    xs = {round(m.axes["X"], 6) + 0.0 for m in cut}
    assert xs == {-x + 0.0 for x in xs}


def test_cycle60_unknown_character_and_no_height(tmp_path):
    assert err(tmp_path, 'CYCLE60("A~", 10, 0, 2, -0.2, 0, 0, 0, 6)') == ("cycle_parameter", 4)
    assert err(tmp_path, 'CYCLE60("A", 10, 0, 2, -0.2, 0, 0, 0, 0)') == ("cycle_parameter", 4)
    assert err(tmp_path, 'CYCLE60(5, 10, 0, 2, -0.2, 0, 0, 0, 6)') == ("type_error", 4)


CONTOUR = "PROC CONT\nG1 X10 Y10\nX60 CHF=5\nY40\nG3 X50 Y50 CR=10\nG1 X10\nY10\nM17\n"


def test_cycle72_compensates_the_contour_with_the_allowance(tmp_path):
    """The subprogram's rectangle run counter-clockwise with G41 (the tool inside it), Ø10,
    FAL 0.5: the walls 5.5 inside, the R10 corner an arc of 4.5 about (50, 40), the chamfer
    offset too; two levels of 2.9 down to −6 + FALD 0.2; the approach 10 before the start."""
    call = 'CYCLE72("CONT", 10, 0, 2, -6, 3, 0.5, 0.2, 500, 100, 111, 41, 1, 10, 800, 1, 10)'
    r = run(tmp_path, HEAD + call + "\nM30\n", options=R5, CONT_DOT_SPF=CONTOUR)
    assert r.completed, [f.render() for f in r.findings]
    ms = [m for m in moves(r) if m.source.line == 4]
    cut = [m for m in ms if isinstance(m, (LinearFeed, ArcFeed)) and m.source.phase == "roughing depth 1/2"]
    xs, ys = [m.axes["X"] for m in cut], [m.axes["Y"] for m in cut]
    assert min(xs) == pytest.approx(10) and max(xs) == pytest.approx(54.5)   # from the approach
    assert min(ys[1:]) == pytest.approx(10) and max(ys) == pytest.approx(44.5)
    arc = [m for m in cut if isinstance(m, ArcFeed)]
    assert len(arc) == 1 and arc[0].center == pytest.approx((50, 40))
    assert math.dist((arc[0].axes["X"], arc[0].axes["Y"]), arc[0].center) == pytest.approx(4.5)
    infeeds = [m for m in ms if isinstance(m, LinearFeed) and "infeed" in m.source.phase]
    assert {round(m.axes["Z"], 9) for m in infeeds} == {-5.8, -2.9}
    assert (ms[0].axes["X"], ms[0].axes["Y"]) == (0, 10)                     # 10 before (10, 10)


def test_cycle72_section_of_the_program_incremental_and_on_the_centre_line(tmp_path):
    ms = go(tmp_path, 'CYCLE72("PA:PE", 10, 0, 2, -1, 0, 0, 0, 500, 100, 2, 40, 1, 0, 800, 1, 0)\n'
            "M30\nPA: G1 X5 Y5\nG91 X10\nG2 X10 Y0 I5 J0\nPE: Y-7")
    cut = [(round(m.axes["X"], 9), round(m.axes["Y"], 9)) for m in ms
           if isinstance(m, (LinearFeed, ArcFeed)) and m.source.phase == "finishing"]
    assert cut == [(5, 5), (15, 5), (25, 5), (25, -2)]


def test_cycle72_bad_contours(tmp_path):
    assert err(tmp_path, 'CYCLE72("NOPE", 10, 0, 2, -1)') == ("cycle_parameter", 4)
    assert err(tmp_path, 'CYCLE72("A:B", 10, 0, 2, -1)\nM30\nA: G1 X=R1 Y0\nB: X5') == ("cycle_parameter", 4)
