"""Fans and columns: runs of rotary steps of a flat-faced prism cut as one solid each.

Error bound: a fan (:mod:`vmach.stock.fan`) or column (:mod:`vmach.stock.column`) removes at
most ``tol.fan_overcut`` beyond the true sweep — measured on every cutter made, which is made
shorter (or left to fans, or to placed poses) until it holds — and leaves what placed poses at
its samples leave (the face chain's scallops). It exists because placed poses of a rotary
path are most of the booleans' work: a fan replaces a dozen poses, a column a fan per turn.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vmach.stock.column import Column, plan_columns
from vmach.stock.fan import NO_FANS, FanPlan, may_fan, plan_fans
from vmach.stock.view import View
from vmach.tooling.solid import ToolSolid


@dataclass(frozen=True)
class Claim:
    """fans : the fan runs left to fans; columns : the columns; runs : (f, 2) every fan run as
    first claimed (the steps fans and columns hold together)."""

    fans: FanPlan = NO_FANS
    columns: list[Column] = field(default_factory=list)
    runs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), int))


def claim(ts: ToolSolid, pr, tips: np.ndarray, unit: np.ndarray, rotary: np.ndarray, view: View, *,
          columns: bool, overcut: float, others=None) -> Claim:
    """The fan runs and columns over the ``rotary`` steps (n-1,) bool of a path (tips, unit
    axes (n, 3)) and the straight slides between them; none unless the tool is one flat-faced
    prism ``pr`` (:func:`vmach.stock.fan.plan_fans`; ``others``: what other paths' true tools
    sweep, :meth:`vmach.stock.sweeps.Sweeps.others`)."""
    if pr is None or not may_fan(rotary):
        return Claim()                     # (before the back test, which costs)
    fans = plan_fans(tips, unit, rotary, pr, slides=~rotary, clear=view.back_clear(tips, unit, pr),
                     stock_box=view.bounds, others=others)
    if not len(fans.runs):
        return Claim(fans, [], fans.runs)
    cols: list[Column] = []
    left = fans
    if columns:
        cp = plan_columns(tips, unit, fans, radius=ts.radius, inner=ts.radius * np.cos(np.pi / ts.segments),
                          overcut=overcut)
        cols, left = cp.columns, cp.fans
    return Claim(left, cols, fans.runs)
