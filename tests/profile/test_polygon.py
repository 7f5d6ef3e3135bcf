"""DIN 32711 P3G / DIN 32712 P4C nominal profiles and ISO 286 limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vmach.checks.iso286 import it_value, limits
from vmach.checks.polygon import p3g, p3g_sizes, parse_profile
from vmach.errors import InputError


def test_size_table_is_the_domain_table():
    sizes = p3g_sizes()
    assert len(sizes) == 23
    assert sizes[50.0] == 1.8 and sizes[14.0] == 0.44 and sizes[100.0] == 4.5
    assert all(e < d / 16 for d, e in sizes.items())  # every size is convex


@pytest.mark.parametrize("d1", [14.0, 50.0, 100.0])
def test_p3g_sizes_width_and_area(d1):
    prof = p3g(d1)
    e1 = p3g_sizes()[d1]
    assert (prof.d2, prof.d3) == pytest.approx((d1 + 2 * e1, d1 - 2 * e1))
    xy = prof.curve(200_000)
    r = np.hypot(xy[:, 0], xy[:, 1])
    assert r.max() == pytest.approx(prof.d2 / 2, abs=1e-6)
    assert r.min() == pytest.approx(prof.d3 / 2, abs=1e-6)
    for ang in np.linspace(0, np.pi, 7):  # constant width d1 in every direction
        proj = xy @ np.array([math.cos(ang), math.sin(ang)])
        assert proj.max() - proj.min() == pytest.approx(d1, abs=1e-6)
    x, y = xy[:, 0], xy[:, 1]
    shoelace = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    assert prof.area == pytest.approx(math.pi * (d1 ** 2 / 4 - 4 * e1 ** 2))
    assert shoelace == pytest.approx(prof.area, rel=1e-7)


def test_signed_distance_is_the_normal_offset():
    prof = p3g(50.0)
    alpha = np.linspace(0, 2 * np.pi, 997)
    n = np.column_stack([np.cos(alpha), np.sin(alpha)])
    for s in (-0.3, -0.01, 0.0, 0.005, 0.2):
        pts = prof.envelope(alpha) + s * n
        assert np.allclose(prof.signed_distance(pts), s, atol=1e-10)
    phase = math.radians(17.0)
    c, sn = math.cos(phase), math.sin(phase)
    turned = prof.envelope(alpha) @ np.array([[c, sn], [-sn, c]])
    assert np.allclose(prof.signed_distance(turned, phase), 0.0, atol=1e-10)
    assert prof.signed_distance(np.zeros((1, 2)))[0] == pytest.approx(-prof.d3 / 2)


def test_p4c_flats_and_outer_circle():
    prof = parse_profile("P4C:35x30")
    assert (prof.d1, prof.d2_flats, prof.e, prof.d) == (35.0, 30.0, 5.0, 40.0)
    assert prof.e == pytest.approx(0.125 * prof.d)  # e = 0.125 d_m
    xy = prof.curve(3600)
    r = np.hypot(xy[:, 0], xy[:, 1])
    assert r.min() == pytest.approx(15.0, abs=1e-9) and r.max() == pytest.approx(17.5)
    corner = 17.5 * math.sqrt(0.5)
    d = prof.signed_distance(np.array([[15.0, 0.0], [16.0, 0.0], [0.0, 14.0], [corner, corner]]))
    assert d[:3] == pytest.approx([0.0, 1.0, -1.0], abs=1e-9)
    assert d[3] == pytest.approx(0.0, abs=1e-6)


@pytest.mark.parametrize("bad", ["P3G:51", "P5G:50", "P3G:50x40", "P4C:30", "P4C:30x35", "P3G:50/4", "",
                                 "P3G:1" + "0" * 155 + "/1", "P3G:1" + "0" * 400,
                                 "P4C:1" + "0" * 400 + "x1" + "0" * 155])
def test_bad_profile_specs(bad):
    with pytest.raises(InputError):
        parse_profile(bad)


@pytest.mark.parametrize(
    "fit, size, lower_um, upper_um",
    [  # ISO 286-2 table values
        ("g6", 50, -25, -9), ("g6", 60, -29, -10), ("g6", 25, -20, -7), ("g6", 100, -34, -12),
        ("g6", 14, -17, -6), ("k6", 50, 2, 18), ("k6", 60, 2, 21), ("k6", 14, 1, 12),
        ("h6", 50, -16, 0), ("H7", 50, 0, 25), ("H6", 80, 0, 19), ("f7", 50, -50, -25),
        ("m6", 50, 9, 25), ("n6", 50, 17, 33), ("js6", 50, -8, 8), ("G7", 30, 7, 28),
    ],
)
def test_iso286_limits_match_the_printed_tables(fit, size, lower_um, upper_um):
    lim = limits(fit, size)
    assert (round(lim.lower * 1000), round(lim.upper * 1000)) == (lower_um, upper_um)


def test_iso286_it_grades_and_rejections():
    # grades 5..10 as printed; above 100 µm the printed table is authoritative (iso286 docstring)
    assert [it_value(g, 50) for g in (5, 6, 7, 8, 9, 10)] == [11, 16, 25, 39, 62, 100]
    # printed IT6/IT7/IT8 for the steps 3-6 ... 80-120 mm; the formula with its rounding agrees
    # within 1 µm everywhere, and exactly for IT6 over the P3G sizes (10-120 mm)
    printed = {6: [8, 9, 11, 13, 16, 19, 22], 7: [12, 15, 18, 21, 25, 30, 35],
               8: [18, 22, 27, 33, 39, 46, 54]}
    sizes = [5, 8, 14, 25, 40, 60, 100]
    for grade, values in printed.items():
        got = [it_value(grade, s) for s in sizes]
        assert max(abs(a - b) for a, b in zip(got, values, strict=True)) <= 1
        if grade == 6:
            assert got[2:] == values[2:]
    assert it_value(6, 10) == 9 and it_value(6, 10.01) == 11  # over 10 up to 18
    for bad in ("x6", "g", "p6", "K7", "g30"):
        with pytest.raises(InputError):
            limits(bad, 50)
    with pytest.raises(InputError):
        limits("g6", 600)
