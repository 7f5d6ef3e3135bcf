"""Turned, then milled, on one stock (#34's acceptance): the size-50 P3G shaft from Ø60 bar —
faced and turned to d2 = 53.6 with the CNMG 120408 at G96, then POLY50's milling — verifies
with the profile check as POLY50 does."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vmach.stock import engine
from vmach.verify import VerifyOptions, verify

ROOT = Path(__file__).resolve().parents[2]
TURNED = ROOT / "fixtures" / "polygon_shaft" / "TURNED50.MPF"


@pytest.fixture(scope="module")
def turned():
    return verify(TURNED, VerifyOptions(images=False))


def test_turned_then_milled_polygon_passes_its_profile_without_findings(turned):
    assert [(f.kind, f.severity) for f in turned.findings if f.severity != "info"] == []
    assert turned.profile["pass"] is True and turned.skipped == {}
    lo, hi = turned.profile["tolerance_mm"]
    assert all(lo <= s["min_deviation_mm"] <= s["max_deviation_mm"] <= hi for s in turned.profile["stations"])


def test_the_milling_sits_on_the_turned_diameter_and_face(turned):
    part = turned.part
    # behind the polygon (z -40) the turned Ø53.6 runs to z -45; the bar's Ø60 after it
    for z, r in ((-42.5, 26.8), (-47.0, 30.0)):
        area = sum(0.5 * abs(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))
                   for p in part.section(z))
        assert np.sqrt(area / np.pi) == pytest.approx(r, abs=0.002)
    assert engine.bounds(part.solid)[1, 2] == pytest.approx(0.0, abs=1e-6)   # faced at Z0 (blank top Z1)
    assert "CNMG120408" in turned.timing.per_tool and "GLOD D25" in turned.timing.per_tool
