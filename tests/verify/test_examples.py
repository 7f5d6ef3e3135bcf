"""A bundled example verifies clean, or its findings are its documented point (issue 31)."""

from __future__ import annotations

from catalog import POLYGON_DIR

from vmach.verify import VerifyOptions, verify


def test_poly14_passes_its_profile_with_only_its_documented_rate_warning():
    """fixtures/polygon_shaft/vmach.toml: the flank only (z = -2 mm lay in the 3 mm chamfer: a
    0.27 mm 'deviation'); the chamfer asks C1 for more than its rate, a warning it documents."""
    report = verify(POLYGON_DIR / "POLY14.MPF", VerifyOptions(images=False))
    assert [(f.kind, f.severity) for f in report.findings] == [("rate_limit", "warning")]
    assert report.profile["pass"] is True and report.skipped == {}
    lo, hi = report.profile["tolerance_mm"]
    assert all(lo <= s["min_deviation_mm"] <= s["max_deviation_mm"] <= hi for s in report.profile["stations"])
