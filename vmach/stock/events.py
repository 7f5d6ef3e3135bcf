"""What happens to the stock at one move, for the verify checks.

* ``rapid_into_stock`` — a rapid (G0) that removes material: the stock's volume before and after
  the move differ by more than ``tol.removal_volume`` mm³; the removed chip's volume and centre
  are reported.
* ``holder_collision`` — the tool's non-cutting parts (shank, holder) overlap the stock *as it
  is after the move's own cut* by more than ``tol.removal_volume`` mm³ (parts are inscribed
  prisms 0.005 mm inside their cylinders: a body as wide as its cutter only touches).

Checking every move against the evolving stock would cost a boolean per move, so the checks are
screened in conservative steps: bounding boxes (:func:`cylinder_boxes`) pick the moves whose
rapid cutter or shank/holder could reach material at all; of those, the ones whose cylinders
lie wholly beyond one face plane of a convex blank (:func:`cylinders_beyond`, exact for a
cylinder) are dropped before any solid is made — a rapid only when it lies beyond by more than
the near-miss clearance; the solids left are met with the blank;
then, per chunk of moves, the parts are met with the stock as it is *before* the chunk (one
small boolean per solid: their union would cost more, they overlap). Material only ever
decreases, so a part that misses that stock misses it during the chunk; only a chunk with a
rapid or a part left is cut move by move and measured exactly
(:func:`vmach.stock.simulate.simulate`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vmach.stock import engine
from vmach.tooling.solid import frames, place


@dataclass(frozen=True)
class Part:
    """A non-cutting part of a tool: a cylinder from ``z0`` to ``z1`` mm above the tip."""

    name: str
    z0: float
    z1: float
    radius: float


def body_parts(tool) -> list[Part]:
    """Shank and holder of a :class:`vmach.tooling.model.Tool`: its stack without the cutter."""
    return [Part(*p) for p in tool.stack() if p[0] != "cutter"]


def cylinder_boxes(tips: np.ndarray, axes: np.ndarray, z0: float, z1: float, radius: float) -> np.ndarray:
    """Axis-aligned boxes (n, 2, 3) of a cylinder (axis from z0 to z1 above the tip, ``radius``)
    at poses ``tips``/``axes`` (n, 3): exact for a cylinder, mm."""
    a = axes / np.linalg.norm(axes, axis=1, keepdims=True)
    p0 = tips + z0 * a
    p1 = tips + z1 * a
    ext = radius * np.sqrt(np.clip(1.0 - a * a, 0.0, 1.0))
    lo = np.minimum(p0, p1) - ext
    hi = np.maximum(p0, p1) + ext
    return np.stack([lo, hi], axis=1)


def cylinders_beyond(planes: np.ndarray, tips: np.ndarray, axes: np.ndarray, z0: float, z1: float,
                     radius: float) -> np.ndarray:
    """(n, f) float, mm: how far a cylinder (axis from z0 to z1 above the tip, ``radius``) at
    each pose (tips, axes (n, 3)) lies beyond each plane (f, 4: unit normal, offset) — the least
    signed distance n·x − d over the cylinder, exact. A positive entry: that plane parts the
    cylinder (and the prism inscribed in it) from everything behind it."""
    a = axes / np.linalg.norm(axes, axis=1, keepdims=True)
    na = a @ planes[:, :3].T
    base = tips @ planes[:, :3].T - planes[:, 3]
    return base + np.minimum(z0 * na, z1 * na) - radius * np.sqrt(np.clip(1.0 - na * na, 0.0, 1.0))


def overlaps(boxes: np.ndarray, box: np.ndarray) -> np.ndarray:
    """(n,) bool: boxes (n, 2, 3) that meet ``box`` (2, 3)."""
    return np.all(boxes[:, 0] <= box[1], axis=1) & np.all(boxes[:, 1] >= box[0], axis=1)


def _ring(part: Part, chord: float) -> np.ndarray:
    """Points of a prism *inscribed* in the part's cylinder, its sides within ``chord`` mm of
    the circle: a holder exactly as wide as the cutter before it (a shell mill's body) then
    touches the cut surface without entering it."""
    segments = max(12, math.ceil(math.pi / math.acos(max(-1.0, 1.0 - chord / part.radius))))
    r = part.radius
    th = np.linspace(0, 2 * math.pi, segments, endpoint=False)
    c = np.column_stack([r * np.cos(th), r * np.sin(th)])
    return np.vstack([np.column_stack([c, np.full(segments, part.z0)]),
                      np.column_stack([c, np.full(segments, part.z1)])])


def part_solids(part: Part, tips: np.ndarray, axes: np.ndarray, chord: float = 0.005,
                planes: np.ndarray | None = None) -> list:
    """Solids the part occupies along a path of poses: the hull of consecutive poses when the
    axis does not turn (exact sweep), else the part placed at each pose of a turning step
    (each pose once: the prism made once and moved there). The part is an inscribed prism
    (``chord`` mm inside the true cylinder), so only overlaps deeper than ``chord`` can be
    reported. ``planes`` (f, 4): solids that lie wholly beyond one of them are left out (the
    face planes of a convex blank: those solids meet no stock cut from it)."""
    pts = _ring(part, chord)
    fr = frames(tips, axes)
    placed = place(pts, fr)
    a = axes / np.linalg.norm(axes, axis=1, keepdims=True)
    keep = np.ones(len(tips), bool)          # poses not beyond a plane
    if planes is not None:
        beyond = cylinders_beyond(planes, tips, a, part.z0, part.z1, part.radius)    # (n, f)
        keep = beyond.max(axis=1) <= 1e-6
    if len(tips) == 1:
        return [engine.hull(placed[0])] if keep[0] else []
    same = np.all(np.isclose(a[:-1], a[1:], rtol=0.0, atol=1e-12), axis=1)
    steps = same.copy()
    if planes is not None:
        steps &= np.minimum(beyond[:-1], beyond[1:]).max(axis=1) <= 1e-6
    out = [engine.hull(np.concatenate([placed[i], placed[i + 1]])) for i in np.nonzero(steps)[0]]
    turning = np.zeros(len(tips), bool)
    turning[:-1] |= ~same
    turning[1:] |= ~same
    turning &= keep
    if turning.any():
        prism = engine.hull(pts)
        out += [engine.transform(prism, fr[k]) for k in np.nonzero(turning)[0]]
    return out


def overlap_volume(solid, parts: list, centre: bool = True) -> tuple[float, np.ndarray | None]:
    """Volume (mm³) of ``solid`` inside the union of ``parts`` and the centre (of mass) of that
    overlap (None when ``centre`` is False: the volume alone is cheaper)."""
    if not parts:
        return 0.0, None
    inter = engine.intersect(solid, engine.union(parts))
    if engine.is_empty(inter):
        return 0.0, None
    return engine.volume(inter), engine.centroid(inter) if centre else None
