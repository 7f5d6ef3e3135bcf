"""The feet a flat face's rim leaves between placed poses, and how many poses to add against them.

Where a flat end mill's or face mill's rim meets its side, the section across the rim shows
the tool as a quadrant: behind its face and inside its rim. Two placed poses whose corner
moves by du along the tool's axis and dv along the rim's outward normal, of the same sign —
the face advancing into the material while the rim draws back from it, or the reverse —
leave the right triangle between the two quadrants and the corner's path, of legs |du|, |dv|
and ``|du·dv| / √(du² + dv²)`` high (:func:`rim_feet`); m poses cut it m times lower. Near
the tool's laterals (the directions across its travel) a point of the material stays at the
rim while the tool passes, so nothing else of the pose takes it: the polygon shaft's
flank/shoulder corner, where the finishing cutter's saw-tooth Y reverses while its face
advances.

Most feet are cut again — by the next turn of a helix, by a later pass — so a step is parted
(:func:`parts`) only for feet whose right angle may lie in the stock, that the step's own
true tool sweeps, and that no sampled pose of another path, or of this path's other passes,
holds (:meth:`vmach.stock.sweeps.Coverage.recut`). Lengths mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vmach.stock import cusps
from vmach.stock.sweeps import by_axis, in_tool
from vmach.tooling.model import Tool
from vmach.tooling.solid import ToolSolid, lateral_angle, place

FOOT_BAND = 0.05   # mm: the rim's arc about each lateral whose feet are estimated
FOOT_SAMPLES = 9   # rim samples per lateral
CHECKS = 8         # parts of a step at whose poses a foot's right angle is looked for


@dataclass(frozen=True)
class Feet:
    """Feet at the rim's samples about its two laterals (:func:`rim_feet`): heights ``foot``
    (s, k) mm and the corners of each foot's triangle in the section across the rim midway,
    work frame (s, k, 3) each: ``a`` and ``b`` — the rim there at the two poses, on the
    surface the true sweep leaves — and ``apex``, the right angle, ``foot`` deep in the
    material the true sweep takes."""

    foot: np.ndarray
    a: np.ndarray
    b: np.ndarray
    apex: np.ndarray


def rim_feet(frames_a: np.ndarray, frames_b: np.ndarray, radius: float, segments: int) -> Feet:
    """Feet of a flat face's rim (``radius`` mm; the poses' polygons of ``segments`` turned
    for their laterals, :func:`vmach.tooling.solid.lateral_angle`) over steps from poses
    ``frames_a`` to ``frames_b`` (s, 3, 4), tool to work: the rim sampled over the arc within
    FOOT_BAND of each lateral's tangent line, FOOT_SAMPLES points each (k = 2·FOOT_SAMPLES).
    Each sample's travel over the step, in pose a's frame, gives du (along the axis) and dv
    (along the rim's outward normal); the travel along the rim itself is left out."""
    half = math.acos(max(1.0 - FOOT_BAND / radius, -1.0))
    alpha = lateral_angle(segments)
    fan = np.linspace(-half, half, FOOT_SAMPLES)
    phi = np.concatenate([alpha + fan, alpha + math.pi + fan])
    er = np.column_stack([np.cos(phi), np.sin(phi), np.zeros_like(phi)])           # (k, 3)
    pts = radius * er
    ra = frames_a[:, :, :3]
    wa, wb = place(pts, frames_a), place(pts, frames_b)                   # (s, k, 3) each
    d = np.einsum("sji,skj->ski", ra, wb - wa)                   # each sample's travel, a's frame
    du, dv = d[..., 2], np.einsum("ski,ki->sk", d, er)
    size = np.hypot(du, dv)
    foot = np.where(du * dv > 0.0, np.abs(du * dv) / np.where(size > 0, size, 1.0), 0.0)   # (size > 0 there)
    # the triangle in the section across the edge midway: the corners mid ∓ (du·axis +
    # dv·e_r)/2, the right angle where the later face meets the earlier rim (du > 0) or the
    # earlier face the later rim (du < 0)
    axis = ra[:, None, :, 2]                                               # (s, 1, 3)
    radial = np.einsum("sij,kj->ski", ra, er)                              # (s, k, 3)
    mid = 0.5 * (wa + wb)
    half_du, half_dv = 0.5 * du[..., None] * axis, 0.5 * dv[..., None] * radial
    apex = mid + np.sign(du)[..., None] * (half_du - half_dv)
    return Feet(foot, mid - half_du - half_dv, mid + half_du + half_dv, apex)


def parts(tool: Tool, ts: ToolSolid, fr: np.ndarray, idx: np.ndarray, cusp: float, chord: float, holds,
          cover, between) -> np.ndarray:
    """(s,) int: parts to cut the placed rotary steps ``idx`` (s,) of a path (frames ``fr``
    (n, 3, 4), turned as placed poses are) into so that the feet of ``tool``'s flat face
    (:func:`rim_feet`; none for a pointed tool) stay within ``cusp`` mm — counting only feet
    whose right angle may lie in the stock (``holds``: points (m, 3) -> (m,) bool), that the
    step's own true tool sweeps (at CHECKS poses within it, ``between`` as
    :meth:`vmach.stock.Stock.cut` takes it: off the lateral the section's triangle may lie in
    front of the surface the pass leaves) and that no sampled pose holds, ``chord`` inside its
    true tool (``cover``: the coverage index, :class:`vmach.stock.sweeps.Coverage` — its own
    pass's around the step, another path's, or this path's on another pass, its tip more than
    twice the tool's reach along the path away). The feet of the last pass over a surface are what is left."""
    out = np.ones(len(idx), int)
    radius = cusps.face_radius(tool)
    if radius <= 0.0 or len(idx) == 0:
        return out
    feet = rim_feet(fr[idx], fr[idx + 1], radius, ts.segments)
    step, sample = np.nonzero(feet.foot > cusp)
    if len(step):
        keep = holds(feet.apex[step, sample])
        step, sample = step[keep], sample[keep]
    if len(step):
        keep = _step_sweeps(tool, feet.apex[step, sample], idx[step], between)
        step, sample = step[keep], sample[keep]
    if len(step) == 0:
        return out
    apex = feet.apex[step, sample]
    # the rotation axis of each step (its tool axis turns about it): the axis the other
    # passes' crossings are looked for about
    om = np.cross(fr[idx[step], :, 2], fr[idx[step] + 1, :, 2])
    gap = 2.0 * (ts.length + ts.radius)
    taken = np.zeros(len(step), bool)
    for unit, grp in by_axis(om, np.linalg.norm(om, axis=1) > 1e-9):
        # held by this pass's own poses around the step (its curved rim), or another pass's
        taken[grp] = cover.recut(apex[grp], idx[step[grp]], unit, chord, gap, near=True)
        rest = grp[~taken[grp]]
        taken[rest] = cover.recut(apex[rest], idx[step[rest]], unit, chord, gap)
    step, sample = step[~taken], sample[~taken]
    m = np.ceil(feet.foot[step, sample] / cusp - 1e-9).astype(int)
    np.maximum.at(out, step, np.minimum(m, cusps.MOST))
    return out


def _step_sweeps(tool: Tool, points: np.ndarray, steps: np.ndarray, between) -> np.ndarray:
    """(p,) bool: points (p, 3) inside the true tool (:func:`vmach.stock.cusps.outline`) at
    one of the poses that part each one's step (``steps`` (p,)) into CHECKS."""
    uniq, inv = np.unique(steps, return_inverse=True)
    t, ax, _ = between(uniq, np.full(len(uniq), CHECKS))
    t = np.asarray(t, dtype=float).reshape(len(uniq), CHECKS - 1, 3)[inv]              # (p, k, 3)
    ax = np.asarray(ax, dtype=float).reshape(len(uniq), CHECKS - 1, 3)[inv]
    ax = ax / np.linalg.norm(ax, axis=2, keepdims=True)
    return in_tool(points[:, None, :] - t, ax, *cusps.outline(tool)).any(axis=1)
