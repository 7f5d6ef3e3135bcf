"""Geometry the pictures and the HTML report's 3-D view both draw, computed with numpy: the
tool tip's path as segments, and the part's deviation per vertex. Kept apart from
``pictures`` (which draws through ``render``) so that ``scene`` (the HTML view's data) needs
neither."""

from __future__ import annotations

import math

import numpy as np

from vmach.motion.table import TRAVERSE, MoveTable


def toolpath_segments(
    table: MoveTable, model, step_deg: float = 2.0, region: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Tool-tip segments in the work frame: points (s, 2, 3) mm and kinds (s,) (0 rapid, 1 feed).

    Rows that turn a rotary axis are drawn as the curve the tip really follows (sampled every
    ``step_deg``). region (2, 3): keep only segments with both ends inside (the tool change
    trips to the turret position would shrink the part to a dot).
    """
    if len(table) == 0:
        return np.zeros((0, 2, 3)), np.zeros(0, int)
    d = np.abs(table.end - table.start)
    rot = d[:, table.rotary].max(axis=1) if table.rotary.any() else np.zeros(len(table))
    n = np.maximum(1, np.ceil(rot / step_deg)).astype(int)
    owner = np.repeat(np.arange(len(table)), n + 1)
    t = np.concatenate([np.linspace(0, 1, k + 1) for k in n])
    q = table.start[owner] + t[:, None] * (table.end - table.start)[owner]
    tips = model.fk(table.columns(model.axes, model.home, q)).tip
    first = np.r_[0, np.cumsum(n + 1)[:-1]]
    idx = np.concatenate([np.arange(f, f + k) for f, k in zip(first, n, strict=True)])
    seg = np.stack([tips[idx], tips[idx + 1]], axis=1)
    kinds = (table.kind[owner[idx]] != TRAVERSE).astype(int)
    if region is not None:
        inside = np.all((seg >= region[0]) & (seg <= region[1]), axis=(1, 2))
        seg, kinds = seg[inside], kinds[inside]
    return seg, kinds


def deviation_per_vertex(
    vertices: np.ndarray, profile, phase_deg: float, z_lo: float, z_hi: float
) -> np.ndarray:
    """Signed normal deviation (mm, > 0 material outside the nominal) of part vertices between
    z_lo and z_hi; NaN elsewhere."""
    out = np.full(len(vertices), np.nan)
    sel = (vertices[:, 2] >= z_lo) & (vertices[:, 2] <= z_hi)
    if sel.any():
        out[sel] = profile.signed_distance(vertices[sel, :2], math.radians(phase_deg))
    return out
