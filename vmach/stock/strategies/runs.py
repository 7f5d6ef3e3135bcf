"""Translation runs: straight steps cut as exact hulls.

Error bound: none — the hull of a convex tool piece at both ends of a straight move is its
swept volume (a Minkowski sum), and a pose inside a run's hull adds nothing. A run along the
tool's own axis with the stock in front of the tool's back (a retract, an approach) removes
only what the tool at its inner pose removes, so it is cut as that pose. Runs that stack along
the axis (:func:`vmach.stock.sweep.stacked_runs`) are cut as one hull, their union.
"""

from __future__ import annotations

import numpy as np

from vmach.stock.events import cylinder_boxes
from vmach.stock.sweep import axial_runs, run_extremes
from vmach.stock.view import View
from vmach.tooling.solid import ToolSolid


def within(runs: np.ndarray, outer: np.ndarray) -> np.ndarray:
    """(r,) bool: which runs [first, last] (r, 2) lie wholly within one of the ``outer`` runs
    (f, 2) (every step of the run is one of its steps)."""
    if len(runs) == 0 or len(outer) == 0:
        return np.zeros(len(runs), bool)
    k = np.searchsorted(outer[:, 0], runs[:, 0], side="right") - 1   # outer runs are in order
    ok = k >= 0
    kk = np.maximum(k, 0)
    return ok & (outer[kk, 0] <= runs[:, 0]) & (runs[:, 1] <= outer[kk, 1])


def outside(poses: np.ndarray, runs: np.ndarray) -> np.ndarray:
    """Placed poses (m,) int not on one of the runs [first, last] (r, 2): the run's hull (the
    tool swept along its segment, same axis) already contains the tool at every pose of it."""
    if len(runs) == 0 or len(poses) == 0:
        return poses
    covered = np.zeros(int(max(poses.max(), runs.max())) + 1, bool)
    for a, b in runs:
        covered[a : b + 1] = True
    return poses[~covered[poses]]


def claim_axial(ts: ToolSolid, tips: np.ndarray, unit: np.ndarray, runs: np.ndarray, poses: np.ndarray,
                fan_runs: np.ndarray, view: View) -> tuple[np.ndarray, np.ndarray, int]:
    """(runs, placed poses, runs claimed) with the translation runs along the tool's own axis
    whose inner pose has the stock in front of its back (:func:`vmach.stock.sweep.axial_runs`,
    :meth:`vmach.stock.view.View.behind` over the Z range of the run's two ends) replaced by
    the tool placed at that pose, unless a run or fan of the path holds that pose already."""
    axial, inner = axial_runs(tips, unit, runs)
    if not axial.any():
        return runs, poses, 0
    idx = np.nonzero(axial)[0]
    ends = np.array([run_extremes(tips, r) for r in runs[idx]], dtype=int)
    b0 = cylinder_boxes(tips[ends[:, 0]], unit[ends[:, 0]], 0.0, ts.length, ts.radius)
    b1 = cylinder_boxes(tips[ends[:, 1]], unit[ends[:, 1]], 0.0, ts.length, ts.radius)
    zlo = np.minimum(b0[:, 0, 2], b1[:, 0, 2])
    zhi = np.maximum(b0[:, 1, 2], b1[:, 1, 2])
    gone = idx[view.behind(tips[inner[idx]], unit[inner[idx]], ts, zlo, zhi)]
    if len(gone) == 0:
        return runs, poses, 0
    keep = np.ones(len(runs), bool)
    keep[gone] = False
    runs = runs[keep]
    placed = outside(outside(np.unique(inner[gone]), runs), fan_runs)
    return runs, np.unique(np.r_[poses, placed]).astype(int), len(gone)
