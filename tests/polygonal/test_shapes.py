"""The four shape families of polygonal turning (domain §6), from geometry alone (#34).

A flywheel cutter (n inserts, cutting radius R) coupled to the main spindle at tool:work = k
cuts, seen from the work, along P(α) = A e^{iα} − R e^{i(1−k)α} (A = X + R, the cutter's centre
distance): 2:1 an ellipse of semi-axes X and A + R (slightly convex flats, two per insert), 1:1
a circle of radius A about a point R off the axis (strongly convex, one flat per insert), 3:1 a
curve whose flat bends away from the axis while 4R > A (concave). Each test cuts a bar with
:meth:`vmach.stock.Stock.polygon`, slices the part and measures its section
(:mod:`vmach.checks.flats`): the number of flats, the flanks' bulge (sign and value) against
the same measure of the analytic curve, and the section's radius against the curve's."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vmach.checks.flats import flanks, radius_profile
from vmach.stock import Stock
from vmach.stock.strategies.polygonal import SAG, Coupling
from vmach.tooling.flywheel import FlywheelTool


def sharp(n: int, radius: float = 25.0) -> FlywheelTool:
    """A flywheel whose inserts end in sharp tips (so that the cut flank is the tip's curve)."""
    return FlywheelTool(name=f"FW{n}", inserts=n, radius=radius, shape="T", inscribed=8.0, nose_radius=0.0,
                        width=10.0)


def cut(tool: FlywheelTool, k: float, x: float, bar: float = 32.0) -> np.ndarray:
    stock = Stock.from_spec(f"cylinder:d={bar},l=40")
    assert stock.polygon(tool, Coupling(k), np.array([[x, 0, 2], [x, 0, -25]]), np.array([0, 1])) == 1
    sec = stock.section(-12.0)
    assert len(sec) == 1                    # one piece: no island left between the inserts' paths
    return sec[0]


def curve_radius(k: float, x: float, radius: float, phi: np.ndarray) -> np.ndarray:
    """r(φ) of insert 0's tip curve P(α) = A e^{iα} − R e^{i(1−k)α} about its flat at φ = 0
    (where the curve's direction from the axis turns monotonically with α)."""
    a = x + radius
    alpha = np.linspace(-math.pi / 2, math.pi / 2, 200001)
    p = a * np.exp(1j * alpha) - radius * np.exp(1j * (1 - k) * alpha)
    th = np.unwrap(np.angle(p))
    mid = len(alpha) // 2
    d = np.diff(th)
    lo = mid - np.argmax(d[:mid][::-1] <= 0) if (d[:mid] <= 0).any() else 0
    hi = mid + np.argmax(d[mid:] <= 0) if (d[mid:] <= 0).any() else len(th) - 1
    assert th[lo] < phi.min() and th[hi] > phi.max()
    return np.interp(phi, th[lo:hi + 1], np.abs(p)[lo:hi + 1])


def chord_bulge(phi: np.ndarray, r: np.ndarray) -> float:
    """Signed largest deviation (outward +) of the curve r(φ) from its chord between φ[0], φ[-1]."""
    pts = np.column_stack([r * np.cos(phi), r * np.sin(phi)])
    a, b = pts[0], pts[-1]
    d = b - a
    n = np.array([d[1], -d[0]]) / np.linalg.norm(d)
    if n @ (a + b) < 0:
        n = -n
    dev = (pts - a) @ n
    return float(dev[np.argmax(np.abs(dev))])


FAMILIES = [
    # k, inserts, X, flats, shape
    (2, 2, 11.0, 4, "convex"),        # near-square, slight convexity
    (2, 3, 12.0, 6, "convex"),        # hexagon
    (1, 3, 10.0, 3, "strong"),        # strong convexity
    (3, 2, 12.0, 6, "concave"),       # concavity
    (4, 2, 13.0, 8, "concave"),       # and above
]


@pytest.mark.parametrize("k, n, x, flats, shape", FAMILIES)
def test_the_shape_families_come_from_the_relative_motion(k, n, x, flats, shape):
    tool = sharp(n)
    contour = cut(tool, k, x)
    fl = flanks(contour)
    assert len(fl) == flats
    across = 2.0 * x
    for f in fl:
        assert f.radius == pytest.approx(x, abs=2 * SAG)            # the flat's middle at X
        if shape == "convex":
            assert 0.0 < f.bulge < 0.01 * across                       # slight
        elif shape == "strong":
            assert f.bulge > 0.05 * across
        else:
            assert f.bulge < 0.0
    # every flank alike (the inserts' phases are evenly spread)
    assert np.ptp([f.bulge for f in fl]) < 2 * SAG
    # and each the analytic curve's: the same window about the flat, the same bulge
    half = math.radians(180.0 / flats) * 0.8           # flanks() measures the middle 80% between corners
    phi = np.linspace(-half, half, 2001)
    want = chord_bulge(phi, curve_radius(k, x, tool.radius, phi))
    assert fl[0].bulge == pytest.approx(want, abs=3 * SAG)


@pytest.mark.parametrize("k, n, x", [(2, 3, 12.0), (1, 3, 10.0), (3, 2, 12.0)])
def test_the_section_follows_the_tip_curve_within_the_stated_tolerance(k, n, x):
    # COUPON's offset 0: insert 0 points at the work's axis when the main spindle is at 0, so
    # its flat's middle lies on the work's +X
    tool = sharp(n)
    contour = cut(tool, k, x)
    th, r = radius_profile(contour)
    sel = np.abs(th) < math.radians(180.0 / len(flanks(contour))) * 0.6
    want = curve_radius(k, x, tool.radius, th[sel])
    assert np.max(np.abs(r[sel] - want)) < 2 * SAG


def test_the_nose_radius_rounds_the_tip_curve_and_keeps_the_flat_at_x():
    tool = FlywheelTool(name="FW", inserts=3, radius=25.0, shape="T", inscribed=8.0, nose_radius=0.8,
                        width=10.0)
    fl = flanks(cut(tool, 2, 12.0))
    assert len(fl) == 6 and all(f.radius == pytest.approx(12.0, abs=2 * SAG) for f in fl)


def test_a_counter_rotating_holder_is_the_negative_ratio():
    # against the work at 2:1 the tip runs through A e^{iα} − R e^{3iα}, not the ellipse
    def area(k, counter):
        tool = FlywheelTool(name="FW", inserts=2, radius=25.0, shape="T", inscribed=8.0, nose_radius=0.0,
                            width=10.0, counter=counter)
        c = cut(tool, k, 12.0)
        return 0.5 * abs(np.sum(c[:, 0] * np.roll(c[:, 1], -1) - np.roll(c[:, 0], -1) * c[:, 1]))

    assert area(2, True) == pytest.approx(area(-2, False), abs=1e-6)
    assert abs(area(2, True) - area(2, False)) > 1.0


def test_the_cut_reaches_from_p_along_the_feed_plus_the_edges_width():
    stock = Stock.from_spec("cylinder:d=32,l=40")
    stock.polygon(sharp(3), Coupling(2), np.array([[12.0, 0, -25], [12.0, 0, -30]]))   # edges 10 mm
    for z, flats in ((-30.5, 0), (-29.5, 6), (-15.5, 6), (-14.5, 0)):
        sec = stock.section(z)
        assert len(sec) == 1 and len(flanks(sec[0])) == flats
        if not flats:
            assert np.hypot(*sec[0].T).min() == pytest.approx(16.0, abs=0.01)     # the bar
