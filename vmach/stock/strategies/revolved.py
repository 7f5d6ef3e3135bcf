"""Revolved cutters: a turning tool's path while the workpiece turns.

A turning tool stands still while the main spindle turns the stock: what it removes is the
solid of revolution of its cross-section (:meth:`vmach.tooling.turning.TurningTool.section`)
swept in the X–Z half-plane. A straight step sweeps the convex section into the hull of its
two end placements (exact: a Minkowski sum), the pass is the union of its steps, and the union
revolved about the spindle axis is the cutter (:func:`vmach.stock.engine.revolved`).

Error bound: the section's nose arcs within the stock's chord (their points on the true
circles); the revolution a polygon of the blank's own segment count and phase, straddling the
true circle (vertex radius :func:`vmach.tooling.solid.straddle_radius`) — within half the
blank's chord of the true surface of revolution at the blank's radius, less inside it. Arcs of
the program come as their chords (``tol.chord``).

Poses ``rz`` are (n, 2) ``(r, z)`` mm: the tool's theoretical tip P's distance from the
spindle axis (signed: :func:`half_plane`) and its Z; what the section covers on the far side
of the axis is mirrored before the revolution.
"""

from __future__ import annotations

import numpy as np

from vmach.stock import engine
from vmach.stock.jobs import Cutter, Revolved, span
from vmach.stock.path import NOTHING, Bound, Claim, Free, Path
from vmach.stock.view import View
from vmach.tooling.solid import straddle_radius

#: steps per revolved cutter (one boolean each; a pass is cut in pieces of this many steps)
STEPS = 256

NAME = "revolved"
BOUND = Bound(over="blank_polygon", under="blank_polygon")
JOB = Revolved


def claim(path: Path, free: Free, view: View, cover) -> Claim:
    """A turning path (one with a ``section``) whole: its revolved jobs, one per STEPS steps."""
    if path.section is None:
        return NOTHING
    at = 0.0
    jobs = []
    for job in jobs_of(path.section, half_plane(path.tips), path.rows):
        jobs.append((at, job))
        at += STEPS
    return Claim(steps=np.ones(path.n - 1, bool), held=np.ones(path.n, bool), jobs=jobs)


def half_plane(tips: np.ndarray) -> np.ndarray:
    """(n, 2) ``(r, z)``: tips (n, 3) in the plane through the spindle axis that holds the
    tool — r signed, positive on the side of the path's point farthest from the axis — so
    that a step across the axis (a facing cut to X-1.6) stays straight."""
    xy = tips[:, :2]
    r = np.hypot(xy[:, 0], xy[:, 1])
    if len(r) == 0 or r.max() == 0:
        return np.column_stack([r, tips[:, 2]])
    u = xy[int(np.argmax(r))] / r.max()
    return np.column_stack([np.where(xy @ u < 0, -r, r), tips[:, 2]])


def jobs_of(section: np.ndarray, rz: np.ndarray, rows: np.ndarray | None) -> list[Revolved]:
    """The jobs of one turning path: the section (k, 2) at poses ``rz`` (n, 2), one job per
    STEPS steps (a lone pose: the section placed there). ``rows`` (n,) int or None."""
    rz = np.asarray(rz, dtype=float).reshape(-1, 2)
    if len(rz) == 0:
        return []
    if len(rz) == 1:
        return [Revolved([section + rz[0]], span(rows, 0, 0))]
    jobs = []
    for a in range(0, len(rz) - 1, STEPS):
        b = min(a + STEPS, len(rz) - 1)
        hulls = [np.concatenate([section + rz[i], section + rz[i + 1]]) for i in range(a, b)
                 if not np.allclose(rz[i], rz[i + 1], atol=1e-12) or i == a]
        jobs.append(Revolved(hulls, span(rows, a, b)))
    return jobs


def make(job: Revolved, maker) -> Cutter | None:
    """The cutter of one job within the stock's bounds (its (r, z) extent, one millimetre
    more: what lies outside removes nothing), a revolution of the maker's ``turn_segments``
    (:class:`vmach.stock.make.Maker`); None when it misses the stock."""
    bounds = np.asarray(maker.view.bounds, dtype=float)
    segments = maker.turn_segments
    lo, hi = bounds
    r_max = float(np.hypot(np.abs(bounds[:, 0]).max(), np.abs(bounds[:, 1]).max())) + 1.0
    keep = [h for h in job.hulls if np.abs(h[:, 0]).min() < r_max and h[:, 1].max() > lo[2] - 1.0
            and h[:, 1].min() < hi[2] + 1.0]
    if not keep:
        return None
    scale = straddle_radius(1.0, segments)
    solid = engine.revolved(keep, segments, (r_max, lo[2] - 1.0, hi[2] + 1.0), scale)
    if engine.is_empty(solid):
        return None
    return Cutter(solid, engine.bounds(solid), job.rows)
