"""Profile conformance: synthetic sections, and parts cut with manifold3d from exact
support-function poses (issue 4 acceptance)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.stock.conftest import turnmill
from vmach.checks.polygon import p3g
from vmach.checks.profile import check_profile, densify, golden_min, stations
from vmach.errors import InputError
from vmach.stock import Stock
from vmach.tooling import Tool

FACE = Tool("face 40", "face", 40.0, 5.5, teeth=4)


def turned(points: np.ndarray, deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return points @ np.array([[c, s], [-s, c]])


def test_synthetic_section_finds_phase_and_offset():
    prof = p3g(50.0)
    alpha = np.linspace(0, 2 * np.pi, 7200, endpoint=False)  # chords sag < 4e-6 mm
    n = np.column_stack([np.cos(alpha), np.sin(alpha)])
    contour = turned(prof.envelope(alpha) + 0.003 * n, 137.0)   # 137 = 17 + 120
    res = check_profile(lambda z: [contour], prof, [-20.0, -10.0], fit="g6")
    assert res.phase_deg == pytest.approx(17.0, abs=1e-3)
    assert res.max == pytest.approx(0.003, abs=2e-5) and res.min == pytest.approx(0.003, abs=2e-5)
    data = res.to_json()
    assert list(data)[:7] == ["type", "d1", "e1", "stations", "max_abs_deviation_mm",
                              "rms_deviation_mm", "tolerance_mm"]
    assert data["type"] == "P3G" and data["d1"] == 50.0 and data["e1"] == 1.8
    assert data["tolerance_mm"] == [-0.0125, -0.0045]  # g6 on d1 = 50: -25..-9 µm, halved
    assert data["pass"] is False and len(data["stations"]) == 2
    assert {"z", "max_deviation_mm", "min_deviation_mm"} <= set(data["stations"][0])
    fixed = check_profile(lambda z: [contour], prof, [-20.0], phase_deg=0.0)
    assert fixed.phase_deg == 0.0 and fixed.max > 0.1  # wrong phase: large deviations


def test_missing_section_is_reported_not_passed():
    res = check_profile(lambda z: [], p3g(50.0), [-5.0], fit="js7")
    assert res.stations[0].found is False and res.passed is False
    assert res.to_json()["stations"][0]["max_deviation_mm"] is None


def facet_deviation(prof, alpha: np.ndarray, h: np.ndarray) -> float:
    """Largest distance of the corners of the tangent polygon (lines x·n(a) = h) from the
    nominal curve, by brute force against 400k curve points (independent of the check)."""
    n0 = np.column_stack([np.cos(alpha), np.sin(alpha)])
    n1 = np.roll(n0, -1, axis=0)
    h1 = np.roll(h, -1)
    det = n0[:, 0] * n1[:, 1] - n0[:, 1] * n1[:, 0]
    corners = np.column_stack([(h * n1[:, 1] - h1 * n0[:, 1]) / det,
                               (n0[:, 0] * h1 - n1[:, 0] * h) / det])
    curve = prof.curve(400_000)
    best = np.empty(len(corners))
    for i in range(0, len(corners), 16):
        d = np.linalg.norm(corners[i:i + 16, None, :] - curve[None, :, :], axis=2)
        best[i:i + 16] = d.min(axis=1)
    return float(best.max())


def support_cut(step_deg: float, deep: dict[int, float] | None = None):
    """Cut a P3G-50 with a face mill whose face sits at X = h(C) (domain §5) every step."""
    prof = p3g(50.0)
    c = np.arange(0.0, 360.0, step_deg)
    alpha = np.radians(c)
    h = prof.h(alpha)
    for k, dh in (deep or {}).items():
        h[k] -= dh
    tips, axes = turnmill(h, 0.0, -20.0, c)
    stock = Stock.from_spec("cylinder:d=56,l=40", chord=0.01)
    stock.cut(FACE, np.vstack([tips, tips[:1]]), np.vstack([axes, axes[:1]]))
    return prof, alpha, h, stock


def test_support_function_cut_deviates_by_exactly_the_faceting():
    step = 1.5
    prof, alpha, h, stock = support_cut(step)
    facets = facet_deviation(prof, alpha, h)
    # the corners of tangents 1.5 deg apart stand about rho*(sec(0.75 deg) - 1) proud
    rho = prof.d1 / 2 + 8 * prof.e1
    assert facets == pytest.approx(rho * (1 / math.cos(math.radians(step / 2)) - 1), rel=0.02)
    res = check_profile(stock.section, prof, stations("-35:-5", 4), fit="js7")
    assert res.phase_deg == pytest.approx(0.0, abs=0.01) or res.phase_deg == pytest.approx(120.0, abs=0.01)
    assert res.max == pytest.approx(facets, abs=2e-4)
    assert res.min >= -2e-5
    assert res.tolerance == pytest.approx((-0.00625, 0.00625))  # js7 on 50: ±12.5 µm, halved
    assert res.passed


def test_a_flank_cut_005_too_deep_fails_with_that_deviation():
    step = 1.5
    k = int(round(40 / step))  # the flank around 40 deg
    prof, alpha, h, stock = support_cut(step, {k - 1: 0.05, k: 0.05, k + 1: 0.05})
    res = check_profile(stock.section, prof, stations("-35:-5", 3), fit="js7", phase_deg=0.0)
    assert res.min == pytest.approx(-0.05, abs=2e-4)
    assert res.passed is False
    assert res.to_json()["max_abs_deviation_mm"] == pytest.approx(0.05, abs=2e-4)


def test_stations_and_densify():
    assert stations("-35:-5", 7).tolist() == [-35, -30, -25, -20, -15, -10, -5]
    assert stations("-5:-35", step=10).tolist() == [-35, -25, -15, -5]
    assert stations("-35:-5", 1).tolist() == [-20]
    for bad in ("-35", "a:b", "1:2:3", "nan:1", "-inf:0", "-1e400:0"):
        with pytest.raises(InputError):
            stations(bad)
    # found by fuzzing: a NaN range reached the report as null deviations (a traceback in the
    # summary), a huge count ran for many minutes, an infinite one raised OverflowError
    for spec, count, step in (("-35:-5", 100_000, None), ("-35:-5", 0, None), ("-1e300:1e300", None, 1e-9),
                              ("-35:-5", None, 0.001)):
        with pytest.raises(InputError) as exc:
            stations(spec, count, step)
        assert exc.value.kind == "profile_spec"
    assert len(stations("-35:-5", None, 0.05)) == 601 and len(stations("-35:-5", 1000)) == 1000
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    d = densify(square, 0.1)
    gaps = np.linalg.norm(np.diff(np.vstack([d, d[:1]]), axis=0), axis=1)
    assert len(d) == 40 and np.all(gaps <= 0.1 + 1e-12)


@pytest.mark.parametrize("where", [0.3137, -0.999, 0.99995])
def test_golden_min_finds_the_minimum_within_its_tolerance(where):
    calls = []

    def f(x):
        calls.append(x)
        return (x - where) ** 2 + 0.1 * (x - where) ** 4

    got = golden_min(f, -1.0, 1.0, 1e-6)
    assert abs(got - where) <= 1e-6
    assert len(calls) <= 2 + math.ceil(math.log(2.0 / 1e-6) / math.log(1.0 / 0.618))
    # the minimum at an end of the bracket: the search runs to that end
    assert golden_min(lambda x: x, 2.0, 3.0, 1e-6) == pytest.approx(2.0, abs=1e-6)
