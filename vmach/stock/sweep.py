"""Swept volumes from pose sequences, and the error bounds of the sweep vmach uses.

A *path* is a sequence of tool poses (tip, unit axis) in the workpiece frame; consecutive poses
are joined by motion. The tool is a solid of revolution, so a pose is fully given by tip and axis.

How each step i → i+1 is swept (:func:`plan`):

- **Translation** (the axis turns by less than ``tol.hull_angle``): the convex hull of each
  convex tool piece at both poses. For a pure translation this *is* the swept volume
  (Minkowski sum of a convex piece and a segment), so the step is exact. Runs of collinear
  translation steps are coalesced into one hull.
- **Rotation** (the axis turns): the tool is placed at both poses and nothing in between — no
  hull. The hull of the two end poses would overcut by about R·sin(δ/2) (R the tool radius, δ
  the rotation; :func:`hull_overcut`), 0.19 mm for R = 12.5 mm at 1.713°, whereas placed poses
  are each inside the true swept volume, so the sweep can only *leave* material, never remove
  too much. What it leaves are scallops between neighbouring poses, bounded by
  :func:`scallop_bound`: ``r·(sec(δ/2) − 1) + (r·δ)²·κ/8`` for a surface generated at distance r
  from the rotation axis by a tool face of normal curvature κ (κ = 0 for the flat end face of a
  face mill, 1/R for the cylindrical side, cos ψ / ρ on a cone). The caller samples rotary moves
  densely enough (``tol.sweep_angle``, ``tol.sweep_step``) for the bound it needs; tests prove
  the bound on closed-form cuts. Where a run of rotary steps of a flat-faced tool allows it,
  :class:`vmach.stock.Stock` cuts the run as one fan cutter instead (:mod:`vmach.stock.fan`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vmach.tol import tol

#: tips closer than this to the line of a translation run count as collinear, mm
COLLINEAR = 1e-6


@dataclass(frozen=True)
class SweepPlan:
    """How a path is cut.

    poses : (m,) int — indices of poses where the tool solid is placed on its own.
    runs : (r, 2) int — [first, last] pose index of each coalesced translation run; the run is
        cut as the hull of the tool at its poses (all collinear, so first and last suffice
        once the extreme points along the line are taken).
    angles : (n-1,) float, degrees — rotation of the tool axis per step.
    """

    poses: np.ndarray
    runs: np.ndarray
    angles: np.ndarray

    @property
    def count(self) -> int:
        return len(self.poses) + len(self.runs)


def axis_angles(axes: np.ndarray) -> np.ndarray:
    """Angle between consecutive tool axes: axes (n, 3) → (n-1,) float, degrees."""
    a = np.asarray(axes, dtype=float)
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    if len(a) < 2:
        return np.zeros(0)
    cross = np.linalg.norm(np.cross(a[:-1], a[1:]), axis=1)
    dot = np.einsum("ij,ij->i", a[:-1], a[1:])
    return np.degrees(np.arctan2(cross, dot))


def plan(tips: np.ndarray, axes: np.ndarray, hull_angle: float = tol.hull_angle) -> SweepPlan:
    """Decide, per step of a path, between an exact translation hull and placed poses.

    tips : (n, 3) float, mm. axes : (n, 3) float, unit (tip toward holder).
    """
    tips = np.asarray(tips, dtype=float).reshape(-1, 3)
    n = len(tips)
    if n == 0:
        return SweepPlan(np.zeros(0, int), np.zeros((0, 2), int), np.zeros(0))
    ang = axis_angles(axes)
    moved = np.linalg.norm(np.diff(tips, axis=0), axis=1) > COLLINEAR if n > 1 else np.zeros(0, bool)
    trans = (ang <= hull_angle) & moved
    rot = ang > hull_angle
    runs: list[tuple[int, int]] = []
    i = 0
    while i < n - 1:
        if not trans[i]:
            i += 1
            continue
        j = i + 1
        d = tips[j] - tips[i]
        d /= np.linalg.norm(d)
        while j < n - 1 and trans[j] and _on_line(tips[j + 1], tips[i], d):
            j += 1
        runs.append((i, j))
        i = j
    placed = np.zeros(n, bool)
    placed[:-1] |= rot
    placed[1:] |= rot
    # a pose neither in a run nor rotated (a path of one pose, or steps that do not move)
    in_run = np.zeros(n, bool)
    for a, b in runs:
        in_run[a : b + 1] = True
    placed |= ~in_run & ~placed
    # drop repeated identical poses
    idx = np.nonzero(placed)[0]
    if len(idx) > 1:
        same = np.r_[False, (np.linalg.norm(np.diff(tips[idx], axis=0), axis=1) <= COLLINEAR)
                     & (axis_angles(np.asarray(axes, float)[idx]) <= hull_angle)]
        idx = idx[~same]
    return SweepPlan(idx, np.asarray(runs, dtype=int).reshape(-1, 2), ang)


def _on_line(p: np.ndarray, origin: np.ndarray, direction: np.ndarray) -> bool:
    v = p - origin
    return float(np.linalg.norm(v - np.dot(v, direction) * direction)) <= COLLINEAR


def run_extremes(tips: np.ndarray, run: tuple[int, int]) -> tuple[int, int]:
    """Indices of the two extreme tips along a collinear run (the run may reverse)."""
    a, b = int(run[0]), int(run[1])
    seg = tips[a : b + 1]
    d = seg[-1] - seg[0]
    if np.linalg.norm(d) <= COLLINEAR:
        d = seg[np.argmax(np.linalg.norm(seg - seg[0], axis=1))] - seg[0]
    t = (seg - seg[0]) @ d
    return a + int(np.argmin(t)), a + int(np.argmax(t))


def axial_runs(tips: np.ndarray, axes: np.ndarray, runs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Translation runs (r, 2) along the tool's own axis — the tool only moves in or out along
    itself (an approach to a cut, a retract from it) — and the pose at each one's inner end
    (the smaller tip·axis, where the tool's end is deepest): ((r,) bool, (r,) int).

    Such a run's hull is the tool at its inner pose and what its cross-section sweeps behind
    that pose's back face (a tool's radius never shrinks from its tip toward its back, so the
    tool moved out along itself stays within the tool there and the cylinder behind it)."""
    if len(runs) == 0:
        return np.zeros(0, bool), np.zeros(0, int)
    ends = np.array([run_extremes(tips, r) for r in runs], dtype=int)
    a = np.asarray(axes, dtype=float)[ends[:, 0]]
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    d = tips[ends[:, 1]] - tips[ends[:, 0]]
    length = np.linalg.norm(d, axis=1)
    along = np.einsum("ij,ij->i", d, a)
    axial = np.linalg.norm(d - along[:, None] * a, axis=1) <= COLLINEAR * np.maximum(1.0, length)
    inner = np.where(along >= 0.0, ends[:, 0], ends[:, 1])
    return axial, inner


# --------------------------------------------------------------------------------------------
# Error bounds (docs/stock.md, "Error budget")
# --------------------------------------------------------------------------------------------


def scallop_bound(r: float | np.ndarray, delta_deg: float | np.ndarray,
                  kappa: float | np.ndarray = 0.0) -> np.ndarray:
    """Largest material left between two placed poses of a rotary step, mm.

    r : distance of the generated surface point from the rotation axis, mm.
    delta_deg : rotation between the poses, degrees.
    kappa : normal curvature of the generating tool surface in the direction of motion, 1/mm
        (0 for a flat face).

    A flat face turned by δ about an axis at distance r leaves the tangent polygon of the
    circle of radius r: its corners stand ``r·(sec(δ/2) − 1)`` proud (exact). A curved tool
    surface adds the classical scallop of two arcs of curvature κ a chord ``r·δ`` apart,
    ``(r·δ)²·κ/8`` (second order).
    """
    d = np.radians(np.asarray(delta_deg, dtype=float))
    r = np.asarray(r, dtype=float)
    return r * (1.0 / np.cos(d / 2.0) - 1.0) + (r * d) ** 2 * np.asarray(kappa) / 8.0


def hull_overcut(radius: float, r: float, delta_deg: float) -> float:
    """Depth by which the convex hull of a flat-faced tool of ``radius`` at two poses turned by
    δ about an axis at distance ``r`` from its face cuts below the true swept surface, mm:
    ``r − √(r² + R²)·cos(atan(R/r) + δ/2)`` (≈ R·sin(δ/2))."""
    d = math.radians(delta_deg)
    rho = math.hypot(r, radius)
    return r - rho * math.cos(math.atan2(radius, r) + d / 2.0)


def rotary_substeps(delta_deg: np.ndarray, tip_travel: np.ndarray,
                    angle: float = tol.sweep_angle, step: float = tol.sweep_step) -> np.ndarray:
    """Sub-steps per move so that each keeps within ``angle`` degrees and ``step`` mm of tip
    travel; moves without rotation need one. delta_deg, tip_travel : (n,) → (n,) int >= 1."""
    delta = np.abs(np.asarray(delta_deg, dtype=float))
    travel = np.asarray(tip_travel, dtype=float)
    k = np.maximum(np.ceil(delta / angle), np.ceil(travel / step))
    k = np.where(delta > 0, np.maximum(k, 1), 1)
    # beyond any table vmach builds (callers refuse such moves): no int overflow
    return np.minimum(np.nan_to_num(k, nan=1.0, posinf=2.0**62), 2.0**62).astype(np.int64)
