"""Fans and columns: runs of rotary steps of a flat-faced prism cut as one solid each.

Error bound: a fan (:mod:`vmach.stock.fan`) or column (:mod:`vmach.stock.column`) removes at
most ``tol.fan_overcut`` beyond the true sweep — measured on every cutter made, which is made
shorter (or left to fans, or to placed poses) until it holds — and leaves what placed poses at
its samples leave (the face chain's scallops). It exists because placed poses of a rotary
path are most of the booleans' work: a fan replaces a dozen poses, a column a fan per turn.
It runs before the translation runs: a fan run takes the slides between its rotary steps too.
"""

from __future__ import annotations

import numpy as np

from vmach.stock.column import plan_columns
from vmach.stock.fan import may_fan, plan_fans
from vmach.stock.jobs import ColumnJob, Fan
from vmach.stock.path import NOTHING, Bound, Claim, Free, Path
from vmach.stock.view import View

NAME = "fans"
BOUND = Bound(over="fan_overcut", under="face_scallop")


def claim(path: Path, free: Free, view: View, cover) -> Claim:
    """The fan runs and columns over the free rotary steps of a path and the straight slides
    between them; none unless the tool is one flat-faced prism (:func:`vmach.stock.fan.plan_fans`,
    ``cover``: the coverage index or None). Columns only with the setting ``columns`` (and not
    switched off). A run's end poses are turned for its own steps, not for the move beyond."""
    s, pr, tips, unit = path.settings, path.pr, path.tips, path.unit
    rotary = path.rotary & free.steps
    if pr is None or not s.fans or not may_fan(rotary):
        return NOTHING                                      # (before the back test, which costs)
    fans = plan_fans(tips, unit, rotary, pr, slides=~path.rotary & free.steps,
                     clear=view.back_clear(tips, unit, pr), stock_box=view.bounds, cover=cover)
    if not len(fans.runs):
        return NOTHING
    cols, left = [], fans
    if s.columns and s.on("columns"):
        ts = path.ts
        cp = plan_columns(tips, unit, fans, radius=ts.radius, inner=ts.radius * np.cos(np.pi / ts.segments),
                          overcut=s.fan_overcut)
        cols, left = cp.columns, cp.fans
    a, b = fans.runs[:, 0], fans.runs[:, 1]
    path.turn_for(np.r_[a, b], np.r_[tips[a + 1] - tips[a], tips[b] - tips[b - 1]])
    steps = np.zeros(path.n - 1, bool)
    held = np.zeros(path.n, bool)
    for first, last in fans.runs:
        steps[first:last] = True
        held[first : last + 1] = True
    fr, whole = path.frames, (tips, unit)
    jobs = [(float(c.cells[0, 0]), ColumnJob(c, tips, unit, fr, whole,
                                             path.row_span(int(c.cells.min()), int(c.cells.max()))))
            for c in cols]
    jobs += [(float(f0), Fan(tips[f0 : f1 + 1], unit[f0 : f1 + 1], left.omega[k], fr[f0 : f1 + 1], whole,
                             path.row_span(f0, f1))) for k, (f0, f1) in enumerate(left.runs)]
    return Claim(steps=steps, held=held, jobs=jobs)
