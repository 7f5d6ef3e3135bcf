"""Translation runs: straight steps cut as exact hulls.

Error bound: none — the hull of a convex tool piece at both ends of a straight move is its
swept volume (a Minkowski sum), and a pose inside a run's hull adds nothing.
A run whose every step a strategy before (fans) took is left to it.
"""

from __future__ import annotations

import numpy as np

from vmach.stock.path import NOTHING, Bound, Claim, Free, Groups, Path
from vmach.stock.sweep import run_extremes
from vmach.stock.view import View

NAME = "runs"
BOUND = Bound()


def claim(path: Path, free: Free, view: View, cover) -> Claim:
    """The translation runs of a path (:func:`vmach.stock.sweep.plan`) not wholly taken
    before: their steps, the poses on them (with the setting ``trim``), one hull each."""
    s, tips = path.settings, path.tips
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
    if len(run) == 0:
        return Claim(steps=steps, held=held, counts=counts)
    made = Groups(run[:, 0].astype(float), [[run_extremes(tips, r)] for r in run],
                  np.array([path.row_span(a, b) for a, b in run], dtype=int))
    return Claim(steps=steps, held=held, groups=made, counts=counts)

