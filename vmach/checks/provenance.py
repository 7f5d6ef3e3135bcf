"""Which moves' tools pass through a set of points: the program lines behind a region.

The tool of every row of the move table is placed as the stock simulation places it — the
machine axes interpolated linearly along the row and run through the model's forward
kinematics (``model.fk(q)``: tip and axis in the workpiece frame) — at samples no farther apart
than :data:`STEP` mm of tip travel and :data:`TURN` degrees of any rotary axis, and each sample
is the tool's cutting part revolved about its axis (``Tool.profile``: radius as a function of
height from the tip). A point is *touched* by a row when it lies inside one of the row's tool
samples or within ``slack`` mm of one. This reads only the move table, the kinematics and the
tool library, never the stock's own records, so it does not depend on how the stock was cut.

    touch = touching_rows(table, model, library, points_per_region, slack=0.05)
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

#: mm of tip travel and degrees of rotation between tool samples along a row
STEP = 0.5
TURN = 1.0


@dataclass(frozen=True)
class Touch:
    """The rows whose tools touch a region's points.

    rows : (r,) int, ascending — move-table rows. hits : (r,) int — points each touches.
    first : int or None — the row touching the region's first point (its deepest), else the
        row with the most hits. touching : False when no row touches and ``rows`` are the
        nearest ones instead (within ``near`` mm). distance : (r,) float, mm — each row's
        closest approach to the points (<= slack when touching).
    """

    rows: np.ndarray
    hits: np.ndarray
    first: int | None
    touching: bool
    distance: np.ndarray


def _radius_function(tool) -> tuple[np.ndarray, np.ndarray]:
    """(z (p,), r (p,)) increasing in z: the cutting part's radius at height z from the tip."""
    prof = np.asarray(tool.profile(chord=0.005), dtype=float)[:-1]   # without the closing point
    z, r = prof[:, 0], prof[:, 1]
    keep = np.r_[z[1:] != z[:-1], True]                                  # at a step: the outer r
    return z[keep], r[keep]


def _outside(points: np.ndarray, tips: np.ndarray, axes: np.ndarray, zr, length: float
             ) -> np.ndarray:
    """How far points (k, 3) lie outside the tool samples at tips (k, 3) along unit axes
    (k, 3), pair by pair: (k,) mm, <= 0 inside (an estimate outside the tool: the larger of
    the radial and the axial excess, never more than the true distance)."""
    rel = points - tips
    u = np.einsum("kj,kj->k", rel, axes)
    rho = np.sqrt(np.maximum(np.einsum("kj,kj->k", rel, rel) - u * u, 0.0))
    radius = np.interp(np.clip(u, 0.0, length), zr[0], zr[1])
    return np.maximum(np.maximum(rho - radius, -u), u - length)


def touching_rows(table, model, library, regions: list[np.ndarray], slack=0.05,
                  near: float = 5.0) -> list[Touch]:
    """For each array of points (k, 3) mm in ``regions``, the rows whose tools touch them
    (see the module docstring). ``library``: the tool library (``lookup(name)``); ``slack``:
    mm, one for all regions or a sequence of one per region."""
    slacks = np.broadcast_to(np.asarray(slack, dtype=float), (len(regions),))
    n = len(table)
    empty = Touch(np.zeros(0, int), np.zeros(0, int), None, False, np.zeros(0))
    if n == 0 or library is None or not regions:
        return [empty for _ in regions]
    axes = tuple(model.axes)
    q0 = table.columns(axes, model.home, table.start)
    q1 = table.columns(axes, model.home, table.end)
    rotary = np.array([table.rotary[table.axes.index(a)] if a in table.axes else False for a in axes])
    tools = {}
    for i, name in enumerate(table.tools):
        t = library.lookup(name)
        if t is not None:
            tools[i] = t
    tool_of = np.asarray(table.tool)
    rows = np.flatnonzero(np.isin(tool_of, list(tools)))
    if not len(rows):
        return [empty for _ in regions]
    a, b = model.fk(q0[rows]), model.fk(q1[rows])
    travel = np.linalg.norm(np.asarray(b.tip) - np.asarray(a.tip), axis=1)
    turn = np.abs(q1[rows][:, rotary] - q0[rows][:, rotary]).max(axis=1) if rotary.any() else 0 * travel
    count = np.maximum(1, np.maximum(np.ceil(travel / STEP), np.ceil(turn / TURN))).astype(int) + 1
    row_of = np.repeat(rows, count)
    first = np.r_[0, np.cumsum(count)[:-1]]
    t = (np.arange(count.sum()) - np.repeat(first, count)) / np.repeat(count - 1, count)
    q = q0[row_of] + (q1[row_of] - q0[row_of]) * t[:, None]
    pose = model.fk(q)
    tips = np.asarray(pose.tip, dtype=float)
    ax = np.asarray(pose.axis, dtype=float)
    ax = ax / np.linalg.norm(ax, axis=1, keepdims=True)
    tool_at = tool_of[row_of]
    # each sample's box: tip and the top of its cutting part, grown by its radius
    length = np.array([tools[int(i)].cutting_length for i in tool_at])
    radius = np.array([tools[int(i)].radius for i in tool_at])
    top = tips + ax * length[:, None]
    lo = np.minimum(tips, top) - radius[:, None]
    hi = np.maximum(tips, top) + radius[:, None]
    # a ball about each sample's cutting part holds it: its centre and radius
    centre = tips + ax * (length / 2)[:, None]
    ball = np.hypot(radius, length / 2)
    out = []
    for pts, sl in zip(regions, slacks, strict=True):
        pts = np.asarray(pts, dtype=float).reshape(-1, 3)
        out.append(_touch(pts, tips, ax, lo, hi, centre, ball, row_of, tool_at, tools, float(sl), near))
    return out


def _approach(pts, tree, cand, tips, ax, centre, ball, tool_at, tools, slack, reach):
    """For samples ``cand`` (c,): the closest approach of each to the points (c,) mm (inf when
    none lies within ``reach`` of its ball), the points it touches (c,) int, and whether it
    touches the first point (c,) bool. Only the (sample, point) pairs within reach of the
    sample's ball are measured (a k-d tree of the points)."""
    best = np.full(len(cand), np.inf)
    hits = np.zeros(len(cand), dtype=int)
    first_hit = np.zeros(len(cand), dtype=bool)
    if tree is None or not len(cand):
        return best, hits, first_hit
    near = tree.query_ball_point(centre[cand], ball[cand] + reach)
    count = np.fromiter((len(x) for x in near), dtype=np.int64, count=len(cand))
    if not count.sum():
        return best, hits, first_hit
    si = np.repeat(np.arange(len(cand)), count)                    # sample of each pair
    pi = np.fromiter(itertools.chain.from_iterable(near), dtype=np.int64, count=int(count.sum()))
    e = np.empty(len(si))
    for ti in np.unique(tool_at[cand[si]]):
        tool = tools[int(ti)]
        m = tool_at[cand[si]] == ti
        j = cand[si[m]]
        e[m] = _outside(pts[pi[m]], tips[j], ax[j], _radius_function(tool), tool.cutting_length)
    np.minimum.at(best, si, e)
    np.add.at(hits, si, e <= slack)
    first_hit[si[(pi == 0) & (e <= slack)]] = True
    return best, hits, first_hit


def _touch(pts, tips, ax, lo, hi, centre, ball, row_of, tool_at, tools, slack, near) -> Touch:
    box_lo, box_hi = pts.min(axis=0) - near, pts.max(axis=0) + near
    cand = np.flatnonzero(np.all((lo <= box_hi) & (hi >= box_lo), axis=1))
    tree = cKDTree(pts) if len(pts) else None
    best = hits = first_hit = np.zeros(0)
    for reach in (slack, near):          # the touching samples; failing those, the nearest
        best, hits, first_hit = _approach(pts, tree, cand, tips, ax, centre, ball, tool_at, tools,
                                          slack, reach)
        if (best <= slack).any():
            break
    rows_c = row_of[cand]
    if not len(rows_c) or not np.isfinite(best).any():
        return Touch(np.zeros(0, int), np.zeros(0, int), None, False, np.zeros(0))
    touching = bool((best <= slack).any())
    pick = best <= slack if touching else best <= best[np.isfinite(best)].min() + min(near, max(slack, 0.5))
    rows, inv = np.unique(rows_c[pick], return_inverse=True)
    row_hits = np.zeros(len(rows), dtype=int)
    np.maximum.at(row_hits, inv, hits[pick])
    dist = np.full(len(rows), np.inf)
    np.minimum.at(dist, inv, best[pick])
    deepest = rows_c[pick & first_hit]
    main = int(deepest[0]) if len(deepest) else int(rows[np.argmax(row_hits)]) if touching else \
        int(rows[np.argmin(dist)])
    if not math.isfinite(float(dist.min())):
        return Touch(np.zeros(0, int), np.zeros(0, int), None, False, np.zeros(0))
    return Touch(rows, row_hits, main, touching, dist)
