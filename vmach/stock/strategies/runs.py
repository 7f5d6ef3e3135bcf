"""Translation runs: straight steps cut as exact hulls.

Error bound: none — the hull of a convex tool piece at both ends of a straight move is its
swept volume (a Minkowski sum), and a pose inside a run's hull adds nothing. A run along the
tool's own axis with the stock in front of the tool's back (a retract, an approach) removes
only what the tool at its inner pose removes, so it is cut as that pose.
A run whose every step a strategy before (fans) took is left to it.
"""

from __future__ import annotations

import numpy as np

from vmach.stock.events import cylinder_boxes
from vmach.stock.path import NOTHING, Bound, Claim, Free, Groups, Path
from vmach.stock.sweep import axial_runs, run_extremes
from vmach.stock.view import View
from vmach.tooling.solid import ToolSolid

NAME = "runs"
BOUND = Bound()


def claim(path: Path, free: Free, view: View, cover) -> Claim:
    """The translation runs of a path (:func:`vmach.stock.sweep.plan`) not wholly taken
    before: their steps, the poses on them (with the setting ``trim``), one hull each; an axial
    run with the stock in front of its back is cut as its inner pose (``axial``: placed,
    unless a run or fan holds it)."""
    s, tips, unit = path.settings, path.tips, path.unit
    run = path.sweep.runs
    if len(run) == 0:
        return NOTHING
    taken = np.r_[0, np.cumsum(~free.steps)]
    run = run[taken[run[:, 1]] - taken[run[:, 0]] < run[:, 1] - run[:, 0]]
    steps = np.zeros(path.n - 1, bool)
    held = np.zeros(path.n, bool)
    for a, b in run:
        steps[a:b] = True
        held[a : b + 1] = s.trim
    steps &= free.steps
    counts = {"covered": int((held & free.place).sum()) * len(path.ts.pieces)}
    place = np.zeros(0, int)
    if s.trim and len(run) and s.on("axial"):
        by_fans = np.zeros(path.n, bool)                      # poses a strategy before holds
        by_fans[:-1] |= ~free.steps
        by_fans[1:] |= ~free.steps
        run, place, counts["axial_runs"] = claim_axial(path.ts, tips, unit, run, by_fans, view)
    if len(run) == 0:
        return Claim(steps=steps, held=held, place=place, counts=counts)
    made = Groups(run[:, 0].astype(float), [[run_extremes(tips, r)] for r in run],
                  np.array([path.row_span(a, b) for a, b in run], dtype=int))
    return Claim(steps=steps, held=held, place=place, groups=made, counts=counts)


def outside(poses: np.ndarray, runs: np.ndarray) -> np.ndarray:
    """Placed poses (m,) int not on one of the runs [first, last] (r, 2): the run's hull (the
    tool swept along its segment, same axis) already contains the tool at every pose of it."""
    if len(runs) == 0 or len(poses) == 0:
        return poses
    covered = np.zeros(int(max(poses.max(), runs.max())) + 1, bool)
    for a, b in runs:
        covered[a : b + 1] = True
    return poses[~covered[poses]]


def claim_axial(ts: ToolSolid, tips: np.ndarray, unit: np.ndarray, runs: np.ndarray, held: np.ndarray,
                view: View) -> tuple[np.ndarray, np.ndarray, int]:
    """(runs, poses to place (k,) int, runs claimed) with the translation runs along the
    tool's own axis whose inner pose has the stock in front of its back
    (:func:`vmach.stock.sweep.axial_runs`, :meth:`vmach.stock.view.View.behind` over the Z
    range of the run's two ends) replaced by the tool placed at that pose, unless a run left
    or a pose ``held`` (n,) bool holds it already."""
    none = np.zeros(0, int)
    axial, inner = axial_runs(tips, unit, runs)
    if not axial.any():
        return runs, none, 0
    idx = np.nonzero(axial)[0]
    ends = np.array([run_extremes(tips, r) for r in runs[idx]], dtype=int)
    b0 = cylinder_boxes(tips[ends[:, 0]], unit[ends[:, 0]], 0.0, ts.length, ts.radius)
    b1 = cylinder_boxes(tips[ends[:, 1]], unit[ends[:, 1]], 0.0, ts.length, ts.radius)
    zlo = np.minimum(b0[:, 0, 2], b1[:, 0, 2])
    zhi = np.maximum(b0[:, 1, 2], b1[:, 1, 2])
    gone = idx[view.behind(tips[inner[idx]], unit[inner[idx]], ts, zlo, zhi)]
    if len(gone) == 0:
        return runs, none, 0
    keep = np.ones(len(runs), bool)
    keep[gone] = False
    runs = runs[keep]
    placed = outside(np.unique(inner[gone]), runs)
    return runs, placed[~held[placed]].astype(int), len(gone)
