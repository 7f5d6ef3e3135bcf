"""A turned shaft (#34's acceptance): facing, OD turning in steps, a chamfer, a radius and a
groove on the lathe; the cut part against the analytic solid of revolution — the envelope of
the inserts' nose circles along the programmed path of their theoretical tips — at stations
every 0.1 mm along Z."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vmach.motion.table import TRAVERSE
from vmach.verify import VerifyOptions, verify

ROOT = Path(__file__).resolve().parents[2]
SHAFT = ROOT / "fixtures" / "turning" / "SHAFT.MPF"
TOOLS = str(ROOT / "fixtures" / "tools" / "turning.toml")
STOCK = "cylinder:d=60,l=100,z=1"
#: the tools' cutting circles: centres relative to P (x, z) and their radius (fixtures/tools/turning.toml)
CIRCLES = {"CNMG120408": ([(0.8, 0.8)], 0.8),
           "GROOVE3": ([(0.2, 0.2 + k * 2.6 / 260) for k in range(261)], 0.2)}


def analytic_radius(tips_by_tool: dict, z: np.ndarray, blank: float = 30.0) -> np.ndarray:
    """(s,) the radius of the part at stations ``z`` (s,): the blank's, less every position of
    every cutting circle along each tool's path of P (polylines (n, 2) of (r, z), sampled so
    densely that the circles' envelope is exact to 1e-6 mm)."""
    out = np.full(len(z), blank)
    for name, paths in tips_by_tool.items():
        centres, rho = CIRCLES[name]
        for path in paths:
            seg = np.diff(path, axis=0)
            n = np.maximum(2, np.ceil(np.linalg.norm(seg, axis=1) / 0.002).astype(int))
            pts = np.concatenate([path[i] + np.linspace(0, 1, n[i])[:, None] * seg[i]
                                  for i in range(len(seg))])
            for c in centres:
                cx, cz = pts[:, 0] + c[0], pts[:, 1] + c[1]
                for i0 in range(0, len(z), 64):
                    dz = z[i0:i0 + 64, None] - cz[None, :]
                    lo = np.where(np.abs(dz) <= rho, cx[None, :] - np.sqrt(np.maximum(rho ** 2 - dz ** 2, 0)),
                                  np.inf)
                    out[i0:i0 + 64] = np.minimum(out[i0:i0 + 64], lo.min(axis=1))
    return out


def feed_paths(report) -> dict:
    """Tool name -> [polylines (n, 2) (r, z) of P] of its feed moves (rapids stay clear)."""
    t = report.table
    q0 = t.columns(report.model.axes, report.model.home, t.start)
    q1 = t.columns(report.model.axes, report.model.home, t.end)
    a, b = np.asarray(report.model.fk(q0).tip), np.asarray(report.model.fk(q1).tip)
    out: dict = {}
    for i in np.flatnonzero(t.kind != TRAVERSE):
        name = t.tools[int(t.tool[i])]
        ends = [[np.hypot(*a[i, :2]), a[i, 2]], [np.hypot(*b[i, :2]), b[i, 2]]]
        out.setdefault(name, []).append(np.array(ends))
    return out


def part_radius(stock, z: np.ndarray) -> np.ndarray:
    """(s,) the part's radius at stations z: the radius of the circle of its section's area."""
    out = []
    for zi in z:
        area = sum(0.5 * abs(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))
                   for p in stock.section(float(zi)))
        out.append(np.sqrt(area / np.pi))
    return np.array(out)


@pytest.fixture(scope="module", params=["lathe", "turnmill"])
def shaft(request):
    """The shaft (G96 S200 LIMS=3000), on the lathe and on the turn-mill's main spindle (whose
    live-tool spindle 2 stands still: no spindle_off_cut for turning moves)."""
    return verify(SHAFT, VerifyOptions(machine=request.param, tools=TOOLS, stock=STOCK, images=False))


def test_turned_shaft_verifies_without_findings(shaft):
    assert [f for f in shaft.findings if f.severity in ("error", "warning")] == []
    assert shaft.part is not None


def test_turned_shaft_matches_the_analytic_solid_of_revolution_within_5_microns(shaft):
    z = np.arange(-46.95, 0.0, 0.1)
    want = analytic_radius(feed_paths(shaft), z)
    got = part_radius(shaft.part, z)
    # the features are there: Ø56 behind, Ø50, the groove Ø44, the chamfer's start Ø40 + 2·0.05
    assert want[np.argmin(np.abs(z + 40))] == pytest.approx(28.0)
    assert want[np.argmin(np.abs(z + 22.5))] == pytest.approx(22.0)
    assert np.abs(got - want).max() < 0.005


def test_turned_shaft_cycle_time_follows_g96(shaft):
    notes = [n for n in shaft.timing.notes if n.startswith("G96")]
    assert len(notes) == 1
    # the finishing moves at Ø44 run at 1000·200/(π·44) rev/min: 0.25 mm/rev over 13 mm (N200, line 22)
    t = shaft.table
    row = int(np.flatnonzero((t.line == 22) & (t.kind != TRAVERSE))[0])
    from vmach.motion.timing import programmed_seconds
    n = 1000 * 200 / (np.pi * 44)
    assert programmed_seconds(t)[row] == pytest.approx(60 * 13 / (0.25 * n), rel=1e-9)
