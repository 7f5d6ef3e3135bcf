"""The other circle forms: CIP (through an intermediate point), CT (tangent to the path before
it), and AR= (opening angle with the end point or with the centre)."""

from __future__ import annotations

import pytest
from nc import error_of, moves, ok, run

from vmach.canon import ArcFeed


def arc(r):
    a = moves(r)[-1]
    assert isinstance(a, ArcFeed)
    return (round(a.axes["X"], 9), round(a.axes["Y"], 9)), tuple(round(c, 9) for c in a.center), a.clockwise


def test_cip_through_an_intermediate_point(tmp_path):
    r = ok(tmp_path, "G17 G90 G0 X10 Y0\nCIP X-10 Y0 I1=0 J1=10 F100\nM30\n")
    assert arc(r) == ((-10, 0), (0, 0), False)
    r = ok(tmp_path, "G17 G90 G0 X10 Y0\nCIP X-10 Y0 I1=0 J1=-10 F100\nM30\n")
    assert arc(r) == ((-10, 0), (0, 0), True)
    r = ok(tmp_path, "G17 G91 G0 X10 Y0\nCIP X-20 Y0 I1=-10 J1=10 F100\nM30\n")   # incremental
    assert arc(r) == ((-10, 0), (0, 0), False)


def test_ct_continues_tangent_to_the_line_before(tmp_path):
    r = ok(tmp_path, "G17 G90 G0 X0 Y0\nG1 X10 F100\nCT X20 Y10\nM30\n")
    assert arc(r) == ((20, 10), (10, 10), False)
    r = ok(tmp_path, "G17 G90 G0 X0 Y0\nG1 X10 F100\nCT X20 Y-10\nM30\n")
    assert arc(r) == ((20, -10), (10, -10), True)


def test_ct_after_an_arc_and_after_a_z_move(tmp_path):
    r = ok(tmp_path, "G17 G90 G0 X10 Y0\nG3 X0 Y10 I-10 J0 F100\nG1 Z-1\nCT X-10 Y20\nM30\n")
    # leaving (0, 10) toward −X: the circle through (−10, 20) has its centre at (0, 20)
    assert arc(r) == ((-10, 20), (0, 20), True)


@pytest.mark.parametrize("ar, centre, cw", [(90, (0, 10), False), (270, (10, 0), False)])
def test_ar_with_the_end_point(tmp_path, ar, centre, cw):
    r = ok(tmp_path, f"G17 G90 G0 X0 Y0\nG3 X10 Y10 AR={ar} F100\nM30\n")
    got = arc(r)
    assert got[0] == (10, 10) and got[1] == pytest.approx(centre) and got[2] is cw


def test_ar_with_the_centre_gives_the_end_point(tmp_path):
    r = ok(tmp_path, "G17 G90 G0 X10 Y0\nG2 I-10 J0 AR=90 F100\nM30\n")
    end, centre, cw = arc(r)
    assert end == pytest.approx((0, -10)) and centre == (0, 0) and cw is True
    assert moves(r)[-1].axes["Z"] == 0


@pytest.mark.parametrize("text, kind", [
    ("G17 G0 X10 Y0\nCIP X-10 Y0 I1=0 J1=0 F100\nM30\n", "arc_error"),        # on a line
    ("G17 G0 X10 Y0 Z0\nCIP X-10 Y0 Z5 I1=0 J1=10 F100\nM30\n", "unsupported"),  # in space
    ("G17 G0 X0 Y0\nCT X10 Y10 F100\nM30\n", "arc_error"),                     # nothing to be tangent to
    ("G17 G0 X0 Y0\nG1 X10 F100\nCT X20 Y0\nM30\n", "arc_error"),              # straight on
    ("G17 G0 X0 Y0\nG2 X10 Y0 AR=400 F100\nM30\n", "arc_error"),
])
def test_impossible_circles_are_errors(tmp_path, text, kind):
    f = error_of(run(tmp_path, text))
    assert f.kind == kind and f.line == text.count("\n") - 1
