"""Limit and rate findings: vectorised, with source and move index, nothing clipped."""

from __future__ import annotations

import numpy as np
from machine.machine_helpers import model

from vmach.machine import axis_limit_findings, limit_mask, rate_findings
from vmach.source import SourceRef


def test_limit_mask_marks_exactly_the_values_outside():
    limits = np.array([[-1.0, 1.0], [np.nan, np.nan], [0.0, 5.0]])
    v = np.array([[-1.0, 1e9, 5.0], [1.0 + 1e-6, 0.0, -1e-6], [0.5, -1e9, 2.0]])
    assert limit_mask(v, limits).tolist() == [[False, False, False], [True, False, True],
                                              [False, False, False]]


def test_axis_limit_findings_carry_numbers_source_and_move():
    m = model("turnmill")
    q = m.q(n=4)
    q[1, m.axes.index("X")] = 331.5
    q[2, m.axes.index("Y")] = -70.0
    q[3, m.axes.index("C1")] = 1e6  # modulo axis: no travel limit
    src = [SourceRef("p.mpf", i + 10, 1, "") for i in range(4)]
    found = axis_limit_findings(m, q, sources=src, move_index=[100, 101, 102, 103])
    assert [(f.kind, f.line, f.move_index, f.data["axis"]) for f in found] == [
        ("axis_limit", 11, 101, "X"), ("axis_limit", 12, 102, "Y")]
    assert found[0].data == {"axis": "X", "value": 331.5, "min": -5.0, "max": 330.0}
    assert all(f.severity == "error" for f in found)
    assert q[1, 0] == 331.5  # the input is not clipped


def test_rate_findings_from_move_durations():
    m = model("s5d")
    a = m.q(n=3)
    b = a.copy()
    b[0, m.axes.index("X")] = 50.0  # 50 mm in 1 s = 3000 mm/min: exactly the maximum
    b[1, m.axes.index("X")] = 50.1  # just above
    b[2, m.axes.index("C")] = 240.0  # 240° in 1 s = 14400 °/min > 7200
    found = rate_findings(m, a, b, np.array([1.0, 1.0, 1.0]))
    assert [(f.kind, f.move_index, f.data["axis"]) for f in found] == [
        ("rate_limit", 1, "X"), ("rate_limit", 2, "C")]
    assert np.isclose(found[0].data["rate"], 3006.0) and found[0].data["max_rate"] == 3000.0
    assert np.isclose(found[1].data["rate"], 14400.0)
    assert rate_findings(m, a, b, np.array([2.0, 2.0, 2.0])) == []


def test_hybrid_drive_rates_and_limits_are_checked_too():
    m = model("h5d")
    a = m.q(n=1)
    b = m.q({"Z": 60.0})
    d0, _ = m.drive_values(a)
    d1, _ = m.drive_values(b)
    moved = abs(d1["p1"][0] - d0["p1"][0])
    seconds = moved / 6000.0 * 60.0 * 0.5  # twice the drive's maximum rate
    found = [f for f in rate_findings(m, a, b, [seconds]) if f.data["axis"] in ("p1", "p2")]
    assert {f.data["axis"] for f in found} == {"p1", "p2"}
    assert np.isclose(found[0].data["rate"], 12000.0)
