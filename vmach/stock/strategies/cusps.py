"""Cusp poses: poses added inside the placed rotary steps where the tool would leave cusps
over the stock's ``cusp`` between a step's two poses — a curved side's
(:mod:`vmach.stock.cusps`), or, for a flat-faced prism told what other paths cut again (the
coverage index), its rim's feet (:mod:`vmach.stock.feet`).

Error bound: the added poses lie on the true motion (``between``), so they remove nothing the
tool does not; they bring the cusps within ``cusp`` (``tol.sweep_cusp``). An added pose is cut
as its fin (:func:`vmach.stock.cusps.fin_widths`), up to the height its cusps reach.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vmach.stock import cusps, feet, make
from vmach.stock.path import NOTHING, Bound, Claim, Free, Path, Poses
from vmach.stock.view import View
from vmach.tooling.model import Tool
from vmach.tooling.solid import ToolSolid, across, frames, spun


@dataclass(frozen=True)
class Added:
    """Poses added: frames (e, 3, 4), their places along the path ``at`` (e,) float (step +
    fraction), fin half-widths ``half`` (e,) mm and heights ``height`` (e,) mm along the axis;
    ``feet``: steps parted against the feet of a flat face's rim."""

    frames: np.ndarray
    at: np.ndarray
    half: np.ndarray
    height: np.ndarray
    feet: int = 0


NONE = Added(np.zeros((0, 3, 4)), np.zeros(0), np.zeros(0), np.zeros(0))

NAME = "cusps"
BOUND = Bound(under="side_cusps")


def claim(path: Path, free: Free, view: View, cover) -> Claim:
    """Poses added inside the free rotary steps of a path given the poses inside its steps
    (``between``) and its true tool, with the setting ``trim``; each cut as its fin, up to the
    height its cusps reach. It takes no step: the poses at the steps' ends are placed still."""
    s, tool = path.settings, path.true_tool
    if path.between is None or not s.trim or tool is None:
        return NOTHING
    add = added(tool, path.ts, path.pr, path.tips, path.frames, path.rotary & free.steps, path.between, view,
                cusp=s.cusp, chord=s.chord, cover=cover)
    counts = {"foot_steps": add.feet}
    if not len(add.frames):
        return Claim(counts=counts)
    counts["cusp_poses"] = len(add.frames)
    counts["cusp_fins"] = int(np.isfinite(make.fin_bucket(add.half, path.ts.radius)).sum())
    # an added pose lies on the step it parts: that step's row
    rows = (np.full((len(add.at), 2), -1) if path.rows is None
            else np.repeat(path.rows[np.floor(add.at).astype(int) + 1][:, None], 2, axis=1))
    return Claim(poses=Poses(add.at, add.frames, add.half, add.height, rows), counts=counts)


def added(tool: Tool, ts: ToolSolid, pr, tips: np.ndarray, fr: np.ndarray, steps: np.ndarray, between,
          view: View, *, cusp: float, chord: float, cover=None) -> Added:
    """The poses to add inside the placed rotary ``steps`` (n-1,) bool (``fr`` (n, 3, 4) the
    path's frames, as placed poses are turned; ``pr`` the tool as a prism or None;
    ``between``: the path's poses inside a step, :meth:`vmach.stock.Stock.cut`; ``cover``:
    the coverage index or None)."""
    # steps whose tool may reach the stock's bounds at all
    lo, hi = view.bounds
    reach = ts.length + ts.radius
    near = np.all((tips >= lo - reach) & (tips <= hi + reach), axis=1)
    idx = np.nonzero(steps & (near[:-1] | near[1:]))[0]
    sd = cusps.side(tool)
    if len(idx) == 0 or len(sd.points) == 0:
        return NONE
    c, over = cusps.step_cusps(sd, fr[idx], fr[idx + 1], view.holds, cusp, reach=True)
    height = np.full(len(idx), np.inf)
    if pr is None:
        keep = _not_recut(over, cover, chord)
        height = cusps.fin_height(over, len(idx), ts.length, keep)
    parts = cusps.substeps(c, cusp)
    n_feet = 0
    if cover is not None and pr is not None:
        more = feet.parts(tool, ts, fr, idx, cusp, chord, view.holds, cover, between)
        n_feet = int((more > 1).sum())
        parts = np.maximum(parts, more)
    need = parts > 1
    if not need.any():
        return Added(NONE.frames, NONE.at, NONE.half, NONE.height, n_feet)
    t, ax, at = between(idx[need], parts[need])
    unit = np.asarray(ax, dtype=float) / np.linalg.norm(ax, axis=1, keepdims=True)
    step = np.repeat(idx[need], parts[need] - 1)
    more = spun(frames(t, unit), across(unit, tips[step + 1] - tips[step]), ts.segments)
    height = np.repeat(height[need], parts[need] - 1)
    half = cusps.fin_widths(more, fr[step], fr[step + 1], cusps.fin_normal(ts.segments),
                            np.repeat(parts[need], parts[need] - 1), sd, view.holds,
                            cusps.face_radius(tool), height)
    return Added(more, np.asarray(at, dtype=float), half, height, n_feet)


def _not_recut(over: cusps.Over, cover, chord: float) -> np.ndarray | None:
    """(k,) bool: the samples over the cusp tolerance (``over``) that no other path cuts again
    — none of its sampled poses near them (:meth:`vmach.stock.sweeps.Coverage.at_poses`); None
    (all) without the coverage index. The added poses' fins need reach only those."""
    if cover is None or len(over.step) == 0:
        return None
    return ~cover.at_poses(over.point, over.cusp + chord)
