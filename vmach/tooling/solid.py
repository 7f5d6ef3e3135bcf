"""Tool solids: profiles revolved once, split into convex pieces, cached.

A revolved profile is convex exactly when its half section, closed along the axis, is a convex
polygon. Cutting profiles of the kinds in :mod:`vmach.tooling.model` always are; a profile that
is not (a neck, a tool with a smaller shank included) is cut at its reflex vertices into stacked
pieces, each convex, so that a translation sweep can use one convex hull per piece.

Polygonisation: a circle of radius r becomes an n-gon whose vertices lie at
``r_v = 2r / (1 + cos(π/n))``, so the polygon straddles the circle and deviates from it by at
most ``r_v·(1 − cos(π/n)) / 2`` either way; ``n`` is the smallest count that keeps this within
the chord tolerance at the largest radius (:func:`segments_for`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vmach.tol import tol
from vmach.tooling.model import Tool


def segments_for(radius: float, chord: float = tol.tool_chord, minimum: int = 12) -> int:
    """Smallest polygon count whose straddling polygon stays within ``chord`` of the circle."""
    if radius <= 0:
        return minimum
    c = max(-1.0, 1.0 - 2.0 * chord / radius)
    return max(minimum, math.ceil(math.pi / math.acos(c)))


def polygon_deviation(radius: float, segments: int) -> float:
    """Largest radial deviation (mm) of the straddling ``segments``-gon from the circle."""
    c = math.cos(math.pi / segments)
    return radius * (1.0 - c) / (1.0 + c)


def straddle_radius(radius: float, segments: int) -> float:
    """Vertex radius of the straddling polygon."""
    return 2.0 * radius / (1.0 + math.cos(math.pi / segments))


@dataclass(frozen=True)
class ToolSolid:
    """Polygonised cutting part of one tool in the tool frame (tip at the origin, axis +z).

    pieces : tuple of (k, 3) float arrays, mm — vertices of each convex piece (its hull is the
        piece).
    segments : int — polygon count.
    deviation : float, mm — largest deviation of the polygonised side from the true surface.
    radius : float, mm — largest radius; length : float, mm — axial length.
    """

    pieces: tuple[np.ndarray, ...]
    segments: int
    deviation: float
    radius: float
    length: float

    @property
    def points(self) -> np.ndarray:
        """All piece vertices (k, 3) float, mm."""
        return np.concatenate(self.pieces)


def convex_runs(profile: np.ndarray) -> list[np.ndarray]:
    """Split a half-section ``profile`` (m, 2) ``(z, r)`` into runs that revolve to convex
    solids, cutting at reflex vertices with planes perpendicular to the axis."""
    pts = profile
    cuts: list[float] = []
    # walk the open outline (tip -> top); a right turn (seen with z to the right, r up) is reflex
    for i in range(1, len(pts) - 1):
        a, b, c = pts[i - 1], pts[i], pts[i + 1]
        cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
        if cross > 1e-12 and pts[i, 1] > 0:
            cuts.append(float(pts[i, 0]))
    if not cuts:
        return [profile]
    levels = sorted({float(profile[0, 0]), *cuts, float(profile[-1, 0])})
    runs = []
    for z0, z1 in zip(levels[:-1], levels[1:], strict=True):
        zs = np.unique(np.concatenate([[z0, z1], profile[(profile[:, 0] > z0) & (profile[:, 0] < z1), 0]]))
        r = np.array([radius_at(profile, z) for z in zs])
        runs.append(np.column_stack([zs, r]))
    return runs


def radius_at(profile: np.ndarray, z: float) -> float:
    """Largest radius of the profile at height z (0 outside)."""
    best = 0.0
    for (z0, r0), (z1, r1) in zip(profile[:-1], profile[1:], strict=True):
        lo, hi = min(z0, z1), max(z0, z1)
        if lo - 1e-12 <= z <= hi + 1e-12:
            if abs(z1 - z0) < 1e-12:
                best = max(best, r0, r1)
            else:
                best = max(best, r0 + (r1 - r0) * (z - z0) / (z1 - z0))
    return best


def ring_points(run: np.ndarray, segments: int) -> np.ndarray:
    """Vertices of a revolved run (k, 2) ``(z, r)``: one ring per point with r > 0, one axis
    point where r = 0. Returns (p, 3) float, mm."""
    ang = 2.0 * np.pi * (np.arange(segments) + 0.5) / segments
    cs = np.column_stack([np.cos(ang), np.sin(ang)])
    out = []
    for z, r in run:
        if r <= 1e-12:
            out.append(np.array([[0.0, 0.0, z]]))
        else:
            rv = straddle_radius(r, segments)
            out.append(np.column_stack([cs * rv, np.full(segments, z)]))
    return np.concatenate(out)


_CACHE: dict[tuple, ToolSolid] = {}


def _solid(tool: Tool, chord: float, segments: int | None) -> ToolSolid:
    key = (tool.geometry_key(), chord, segments)
    if key in _CACHE:
        return _CACHE[key]
    n = segments or segments_for(tool.radius, chord)
    prof = tool.profile(chord)
    pieces = tuple(ring_points(run, n) for run in convex_runs(prof))
    out = ToolSolid(pieces, n, polygon_deviation(tool.radius, n), tool.radius,
                    float(prof[:, 0].max()))
    _CACHE[key] = out
    return out


def tool_solid(tool: Tool, chord: float = tol.tool_chord, segments: int | None = None) -> ToolSolid:
    """The cached polygonised cutting part of ``tool`` (revolved once per tool and tolerance)."""
    return _solid(tool, float(chord), segments)


def frames(tips: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """Tool-to-work transforms for poses.

    tips : (n, 3) float, mm — tool tip in the work frame.
    axes : (n, 3) float — tool axis (tip toward holder), normalised here.
    Returns (n, 3, 4) float: rotation taking +z to the axis (the shortest rotation; the turn
    about the axis is irrelevant for a solid of revolution) and the tip as translation.
    """
    tips = np.asarray(tips, dtype=float).reshape(-1, 3)
    a = np.asarray(axes, dtype=float).reshape(-1, 3)
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    n = len(a)
    # Rodrigues for z -> a; the antipodal case (a = -z) turns about x.
    x, y, z = a[:, 0], a[:, 1], a[:, 2]
    k = 1.0 / (1.0 + np.where(z > -1 + 1e-12, z, 1.0))
    rot = np.empty((n, 3, 3))
    rot[:, 0, 0] = 1 - x * x * k
    rot[:, 0, 1] = -x * y * k
    rot[:, 0, 2] = x
    rot[:, 1, 0] = -x * y * k
    rot[:, 1, 1] = 1 - y * y * k
    rot[:, 1, 2] = y
    rot[:, 2, 0] = -x
    rot[:, 2, 1] = -y
    rot[:, 2, 2] = z
    flip = z <= -1 + 1e-12
    rot[flip] = np.diag([1.0, -1.0, -1.0])
    out = np.empty((n, 3, 4))
    out[:, :, :3] = rot
    out[:, :, 3] = tips
    return out


def place(points: np.ndarray, frames_: np.ndarray) -> np.ndarray:
    """Points (k, 3) of the tool frame placed by frames (n, 3, 4): returns (n, k, 3)."""
    return np.einsum("nij,kj->nki", frames_[:, :, :3], points) + frames_[:, None, :, 3]
