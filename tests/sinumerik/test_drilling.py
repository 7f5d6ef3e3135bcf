"""Standard drilling cycles CYCLE81/82/83 and MCALL: the moves each makes, worked out from the
cycle manual's description, and the errors of bad parameters."""

from __future__ import annotations

import pytest
from nc import check, error_of, moves, ok, run

from vmach.canon import Dwell, LinearFeed, Traverse


def strokes(result, axis="Z"):
    """(G0|G1, value along the axis, feed) of every move after the first two (setup)."""
    out = []
    for m in moves(result)[1:]:
        kind = "G1" if isinstance(m, LinearFeed) else "G0"
        out.append((kind, round(m.axes[axis], 9), getattr(m, "feed", None)))
    return out


HEAD = "G17 G90 G0 X5 Y6 Z50\nF120\n"


def test_cycle81_approaches_drills_and_retracts(tmp_path):
    r = ok(tmp_path, HEAD + "CYCLE81(10, 0, 2, -15)\nM30\n")
    assert strokes(r) == [("G0", 2, None), ("G1", -15, 120), ("G0", 10, None)]
    assert all((m.axes["X"], m.axes["Y"]) == (5, 6) and m.source.line == 3 for m in moves(r)[1:])


def test_dpr_is_relative_to_the_reference_plane_and_wins_over_dp(tmp_path):
    r = ok(tmp_path, HEAD + "CYCLE81(10, -2, 1, -50, 8)\nM30\n")
    assert strokes(r) == [("G0", -1, None), ("G1", -10, 120), ("G0", 10, None)]


def test_mcall_drills_after_every_positioning_block_until_mcall_alone(tmp_path):
    r = ok(tmp_path, HEAD + "MCALL CYCLE82(10, 0, 2, , 8, 0.5)\nX20\nY20\nMCALL\nX40\nM30\n")
    ms = moves(r)
    holes = [(m.axes["X"], m.axes["Y"]) for m in ms if isinstance(m, LinearFeed)]
    assert holes == [(20, 6), (20, 20)]
    assert [c.seconds for c in r.commands if isinstance(c, Dwell)] == [0.5, 0.5]
    assert ms[-1].axes["X"] == 40 and ms[-1].axes["Z"] == 10 and isinstance(ms[-1], Traverse)


def test_cycle83_swarf_removal_strokes_with_degression(tmp_path):
    """First stroke 8 mm (FDPR) at F·FRF, then 8 − 3 = 5, then DAM = 3 (5 − 3 is not above 3),
    the last cut short at DP; back to RFP + SDIS between strokes and down again to 0.6 mm above
    the last depth."""
    r = ok(tmp_path, HEAD + "CYCLE83(10, 0, 2, -20, , , 8, 3, 0, 0, 0.5, 1)\nM30\n")
    assert strokes(r) == [
        ("G0", 2, None), ("G1", -8, 60),
        ("G0", 2, None), ("G0", -7.4, None), ("G1", -13, 120),
        ("G0", 2, None), ("G0", -12.4, None), ("G1", -16, 120),
        ("G0", 2, None), ("G0", -15.4, None), ("G1", -19, 120),
        ("G0", 2, None), ("G0", -18.4, None), ("G1", -20, 120),
        ("G0", 10, None)]


def test_cycle83_chip_breaking_backs_off_one_millimetre(tmp_path):
    r = ok(tmp_path, HEAD + "CYCLE83(10, 0, 2, -12, , -5, , 0, 0, 0, 1, 0)\nM30\n")
    assert strokes(r) == [("G0", 2, None), ("G1", -5, 120), ("G0", -4, None), ("G1", -10, 120),
                          ("G0", -9, None), ("G1", -12, 120), ("G0", 10, None)]


def test_the_cycle_drills_along_the_planes_normal(tmp_path):
    r = ok(tmp_path, "G19 G90 G0 X50 Y6 Z5\nF100\nCYCLE81(40, 30, 1, 20)\nM30\n")
    assert strokes(r, "X") == [("G0", 31, None), ("G1", 20, 100), ("G0", 40, None)]


@pytest.mark.parametrize("call, kind", [
    ("CYCLE81(10, 0, 2, 5)", "cycle_parameter"),          # depth above the reference plane
    ("CYCLE81(10, 0, 2)", "cycle_parameter"),             # no depth
    ("CYCLE81(10, 0, 2, -5, 0, 1, 0, 0, 0, 1)", "call_arguments"),   # Operate's list has 9
    ('CYCLE81(10, 0, "A", -5)', "type_error"),
])
def test_bad_cycle_parameters_are_errors_at_the_call(tmp_path, call, kind):
    f = error_of(run(tmp_path, HEAD + call + "\nM30\n"))
    assert (f.kind, f.line) == (kind, 3)


def test_mcall_of_anything_but_a_drilling_cycle_is_unsupported(tmp_path):
    found = check(tmp_path, "MCALL L10\nX1\nM30\n")
    assert [(f.kind, f.line) for f in found] == [("unsupported", 1)]
    assert check(tmp_path, "MCALL CYCLE81(10, 0, 2, -5)\nX1\nMCALL\nM30\n") == []


def test_holes2_drills_a_bolt_circle_with_the_modal_cycle(tmp_path):
    import math

    r = ok(tmp_path, HEAD + "MCALL CYCLE81(10, 0, 2, -5)\nHOLES2(20, 30, 15, 90, , 4)\nMCALL\nM30\n")
    feeds = [m for m in moves(r) if isinstance(m, LinearFeed)]
    got = [(round(m.axes["X"], 9), round(m.axes["Y"], 9)) for m in feeds]
    want = [(round(20 + 15 * math.cos(math.radians(a)), 9), round(30 + 15 * math.sin(math.radians(a)), 9))
            for a in (90, 180, 270, 360)]
    assert got == want and all(m.axes["Z"] == -5 for m in feeds)


def test_holes1_drills_a_row_from_its_nearer_end(tmp_path):
    r = ok(tmp_path, "G17 G90 G0 X100 Y0 Z50\nF120\nMCALL CYCLE82(10, 0, 2, -5, , 1)\n"
           "HOLES1(0, 0, 0, 10, 20, 3)\nMCALL\nM30\n")
    xs = [m.axes["X"] for m in moves(r) if isinstance(m, LinearFeed)]
    assert xs == [50, 30, 10]            # X100 is nearer the row's last hole
    assert len([c for c in r.commands if isinstance(c, Dwell)]) == 3


def test_a_pattern_of_no_holes_is_an_error(tmp_path):
    f = error_of(run(tmp_path, HEAD + "HOLES2(0, 0, 10, 0, 0, 0)\nM30\n"))
    assert (f.kind, f.line) == ("cycle_parameter", 3)
