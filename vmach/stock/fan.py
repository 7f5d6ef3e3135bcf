"""Fan cutters: one solid for a run of rotary steps of a flat-faced tool.

A rotary path is otherwise cut by placing the tool at every sampled pose (:mod:`vmach.stock.sweep`):
exact but slow, because the booleans pay for every placed copy crossing its neighbours, and the
side of the tool leaves cusps between copies. Where the motion allows it, a run of poses
``a..b`` is cut instead by one *fan cutter*

    F = H \\ M,   H = hull(tool at poses a..b) ∩ trim box,   M = ∩_k {x : x·n_k <= h_k + ε}

with ``n_k`` the tool axis and ``h_k = tip_k·n_k`` the plane of the tool's flat end face at
pose k: ``M`` is the material below every sampled face plane, ``F`` the part of the hull above
at least one of them.

**Why it is right.** The hull of two rotated copies of a flat-faced tool overcuts in a wedge
*below* the faces (about R·sin(δ/2) deep, :func:`vmach.stock.sweep.hull_overcut`); removing
``M`` takes exactly that wedge away, so the surface the faces make is the tangent polygon of the
sampled face planes — the same surface placed poses make, with the same scallop bound
(:func:`vmach.stock.sweep.scallop_bound`). Above the face chain, between consecutive poses, the
hull fills what the tool's body and side sweep between the samples (placed poses leave that
as cusps). The hull exceeds the true swept volume only where the motion twists: when the tool
also moves along the rotation axis ω, the lines of the tool's side at its ±ω extremes sweep a
helicoid-like ruled surface (the floor or ceiling the side cuts), and the hull bridges it —
the more, the longer the run and the further the lines reach. No closed form held for long
runs, so every made fan is *measured*: :func:`side_samples` samples that ruled surface inside
the blank, :func:`reaches` takes the distance from it to the hull's boundary along ±ω
(10 % larger for what lies between samples), and :mod:`vmach.stock.make_fans` shortens a fan
until that is within ``tol.fan_overcut``. This is the only place vmach may remove more than
the true sweep, and by no more than that — except where the path's own motion cuts the
bridged place anyway: a finishing helix passes every place again one turn lower (and higher),
the tool's disc at full width there, so the bridge of every turn but the last (first) lies in
the next (previous) turn's tool. :func:`covered` tells which samples' surroundings, with the
bridge above them, lie inside the cylinder inscribed in one pose of the path; those do not
count, and the stock in the end is the one the true motion leaves (to the same bound).

**When it applies** (checked per run, else the poses are placed as before):

- the tool is a single convex prism with its end face at z = 0 (flat end mill, face mill);
- the axis turns about one fixed direction ω (to 1e-6) and stays perpendicular to it, over
  at least two steps (a single step always turns about some direction: the tilted axis of
  a cone would pass);
- the face chain is convex and made by the faces themselves: along each face line (in the
  plane perpendicular to ω) the creases with its neighbours come in order, and lie inside
  that pose's face. A concave chain (the tool inside a bore, a rotation that reverses) fails
  this, because there the hull would bridge material no pose reaches;
- the run turns the axis by at most ``tol.fan_angle``;
- the whole blank lies behind every pose's back face (:func:`back_clear`: behind, nothing
  like M takes away the notches the hull fills between neighbouring back faces);
- the face's rim does not leave a foot the hull would take (:func:`vmach.stock.fan_rims.rim_standoff`), or the
  path cuts that place again with the face at full width (another turn of a helix), or the
  foot would lie beyond the stock along ω (a helix's first turns above the end face).

A run may hold *slides* between its turns — steps that keep the axis and move the tool
perpendicular to ω (a facing pass that indexes the workpiece, then moves); poses joined by
slides are judged by their lowest face, and a slide's hull is its exact sweep.

Lengths mm, angles degrees unless named otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull

from vmach.stock import fan_rims
from vmach.tol import tol

PARALLEL = 1e-6   # rotation axes agreeing to this (unit vectors), axes perpendicular to ω


@dataclass(frozen=True)
class Prism:
    """A tool piece that is a right prism on the tool axis: end face at z = 0.

    radius : float, mm — largest radius of its polygon (>= the true radius); length : float, mm;
    ring : (s, 3) float — the polygon's vertices on the end face (tool frame); inner : float, mm
    — the radius of the cylinder inscribed in it (the least distance of the polygon's edges
    from the axis).
    """

    radius: float
    length: float
    ring: np.ndarray
    inner: float


def prism(piece: np.ndarray) -> Prism | None:
    """The piece (k, 3) as a :class:`Prism` — every point on one of two end faces, the same
    convex polygon on both — or None if it is not one (a cone, a ball...). Points on the axis
    (the centres of the end faces) are allowed."""
    p = np.asarray(piece, dtype=float)
    z = p[:, 2]
    r = np.hypot(p[:, 0], p[:, 1])
    top = float(z.max())
    scale = max(1.0, float(r.max()), top)
    ring = r > 1e-9 * scale
    if abs(float(z.min())) > 1e-9 * scale or top <= 0 or not ring.any():
        return None
    low, high = np.abs(z) <= 1e-9 * scale, np.abs(z - top) <= 1e-9 * scale
    if not np.all(low | high):
        return None
    front, back = p[ring & low, :2], p[ring & high, :2]
    if len(front) != len(back) or len(front) < 3:
        return None
    fo, bo = np.lexsort(front.T[::-1]), np.lexsort(back.T[::-1])
    if not np.allclose(front[fo], back[bo], rtol=0.0, atol=1e-9 * scale):
        return None
    # the inscribed radius: the least offset of the polygon's edge lines (n·x + c <= 0 inside)
    inner = float(-ConvexHull(front).equations[:, 2].max())
    return Prism(float(r.max()), top, p[ring & low], inner)


@dataclass(frozen=True)
class FanPlan:
    """runs : (f, 2) int — [first, last] pose of each candidate fan run; omega : (f, 3)
    float — its rotation axis."""

    runs: np.ndarray
    omega: np.ndarray


NO_FANS = FanPlan(np.zeros((0, 2), int), np.zeros((0, 3)))


def may_fan(rotary: np.ndarray) -> bool:
    """Whether a path's steps (``rotary`` (n-1,) bool: those that turn the axis) can hold a
    fan run at all: two steps or more, one of them rotary (:func:`plan_fans` makes none
    otherwise, and callers need not prepare its arguments)."""
    rotary = np.asarray(rotary, bool)
    return len(rotary) >= 2 and bool(rotary.any())


def plan_fans(tips: np.ndarray, axes: np.ndarray, rotary: np.ndarray, tool: Prism, *,
              max_angle: float = tol.fan_angle, slides: np.ndarray | None = None,
              clear: np.ndarray | None = None, rim: float = tol.fan_overcut,
              stock_box: np.ndarray | None = None, cover=None) -> FanPlan:
    """Candidate fan runs of a path: maximal stretches of rotary steps — and, where
    ``slides`` (n-1,) bool allows, of steps that keep the axis and move the tool perpendicular
    to the rotation axis in between (a facing pass that indexes the workpiece and moves the
    tool in turn) — that meet the conditions of the module docstring, each turning the axis
    by at most ``max_angle`` and holding at least two rotary steps. Poses joined by slides
    share an axis; their lowest face is the one the chain is judged by (M lies below it; the
    others' faces are parallel and above, and the slide between them is a translation, whose
    hull is its exact sweep). The twist is not judged here: the cutter of a run is measured
    once made and the run cut shorter where it bridges too much (:mod:`vmach.stock.make_fans`).

    tips, axes : (n, 3) float — poses (work frame, unit axes). rotary : (n-1,) bool — steps
    that turn the axis. tool : the prism. clear : (n,) bool — poses whose far end (the
    prism's back face) lies beyond the stock (:func:`back_clear`); only steps between two
    such poses join a run. rim : mm — the most the face chain may lie below the path of the
    faces' rims (:func:`vmach.stock.fan_rims.rim_standoff`), unless the path cuts the rim's
    band anyway or the band lies beyond ``stock_box`` (2, 3), the stock's bounds. Steps not in
    a run are left to placed poses and translation hulls. cover : the coverage index
    (:class:`vmach.stock.sweeps.Coverage`) or None: a rim band other paths' true tools sweep
    above ``rim`` is taken anyway.
    """
    tips = np.asarray(tips, dtype=float)
    a = np.asarray(axes, dtype=float)
    if not may_fan(rotary):
        return NO_FANS
    st = _steps(tips, a, rotary, tool, slides, clear, rim, stock_box, cover)
    runs = _runs(st, tips, a, max_angle)
    if not runs:
        return NO_FANS
    ru = np.asarray(runs, dtype=int)
    return FanPlan(ru, st.w[ru[:, 0]])


@dataclass(frozen=True)
class _Steps:
    """Per step (n-1,) of a path: ok — a fan candidate; slide — a slide a run may hold; w (n-1, 3)
    — the unit rotation axis; angle — the turn, degrees; s_fwd, s_back — the creases of its two
    faces' lines (:func:`_creases`)."""

    ok: np.ndarray
    slide: np.ndarray
    w: np.ndarray
    angle: np.ndarray
    s_fwd: np.ndarray
    s_back: np.ndarray


def _steps(tips: np.ndarray, a: np.ndarray, rotary, tool: Prism, slides, clear, rim: float, stock_box,
           cover) -> _Steps:
    """Which steps may join a fan run (the arguments of :func:`plan_fans`)."""
    n = len(tips)
    cross = np.cross(a[:-1], a[1:])
    sin = np.linalg.norm(cross, axis=1)
    angle = np.degrees(np.arctan2(sin, np.einsum("ij,ij->i", a[:-1], a[1:])))
    ends = np.ones(n, bool) if clear is None else np.asarray(clear, bool)
    both = ends[:-1] & ends[1:]
    turn = np.asarray(rotary, bool) & (sin > 1e-12) & both
    slide = np.zeros(n - 1, bool) if slides is None else np.asarray(slides, bool)
    slide = slide & (sin <= 1e-12) & both & ~turn
    w = np.zeros_like(cross)
    w[turn] = cross[turn] / sin[turn][:, None]
    # groups of poses joined by slides; each group's face is its lowest (smallest tip·axis)
    group = np.r_[0, np.cumsum(~slide)]
    h = np.einsum("ij,ij->i", tips, a)
    order = np.lexsort((h, group))
    first = np.r_[True, group[order][1:] != group[order][:-1]]
    rep = np.empty(group[-1] + 1, int)
    rep[group[order][first]] = order[first]
    lo, hi = rep[group[:-1]], rep[group[1:]]                 # a step's two groups' faces
    s_fwd, s_back = _creases(tips[lo], a[lo], tips[hi], a[hi], w)
    r = tool.radius
    # a step is a fan candidate when it turns, both axes are perpendicular to its rotation
    # axis, and the crease of the two (lowest) face lines lies inside both faces
    ok = turn & (np.abs(s_fwd) <= r) & (np.abs(s_back) <= r)
    ok &= np.abs(np.einsum("ij,ij->i", a[:-1], w)) <= PARALLEL
    ok &= np.abs(np.einsum("ij,ij->i", a[1:], w)) <= PARALLEL
    band = fan_rims.rim_band(s_fwd, s_back, turn, r)
    near = np.minimum(fan_rims.rim_standoff(tips, a, angle), band) <= rim
    if not near.all():
        near |= fan_rims.rims_covered(tips, a, w, turn, band, rim, r, ~near, tool.inner, stock_box, cover)
    return _Steps(ok & near, slide & near, w, angle, s_fwd, s_back)


def _runs(st: _Steps, tips: np.ndarray, a: np.ndarray, max_angle: float) -> list[tuple[int, int]]:
    """The maximal runs [first, last] of candidate steps (and slides between them) about one
    rotation axis, turning by at most ``max_angle`` with the creases in order (a convex chain),
    holding at least two rotary steps."""
    n = len(tips)
    ok, slide, w, angle = st.ok, st.slide, st.w, st.angle
    scale = max(1.0, float(np.abs(tips).max()))
    move = tips[1:] - tips[:-1]
    runs: list[tuple[int, int]] = []
    i = 0
    while i < n - 1:
        if not ok[i]:
            i += 1
            continue
        omega = w[i]
        total = float(angle[i])
        turns, last = 1, i                                  # last: the run's last rotary step
        j = i + 1
        while j < n - 1:
            if slide[j]:
                if abs(float(move[j] @ omega)) > 1e-9 * scale or abs(float(a[j] @ omega)) > PARALLEL:
                    break
                j += 1
                continue
            # same rotation axis, and on the shared (lowest) face line the crease with the
            # group before comes before the crease with the group after
            if not (ok[j] and np.linalg.norm(w[j] - omega) <= PARALLEL and total + angle[j] <= max_angle
                    and st.s_back[last] <= st.s_fwd[j] + 1e-9):
                break
            total += float(angle[j])
            turns, last = turns + 1, j
            j += 1
        if turns < 2:
            # a run needs two rotary steps: only then do its axes span the plane it turns in,
            # and has it a face between two creases whose order tells a convex chain
            i = last + 1
            continue
        runs.append((i, j))
        i = j
    return runs


def back_clear(tips: np.ndarray, axes: np.ndarray, tool: Prism, solid: np.ndarray) -> np.ndarray:
    """(n,) bool: poses (tips, unit axes (n, 3)) whose prism has the whole of ``solid`` (its
    vertices (v, 3): the blank, which holds the stock) behind its back face, ``tool.length``
    behind the tip (only that is used: a ToolSolid serves as well).

    Why fans need it: the tools of a run stand side by side like the faces of a fan; seen
    from behind, their back faces meet in notches (two neighbouring back faces cross at a
    small angle), and the hull fills those notches, where no pose reaches. In front, M takes
    the like wedges below the faces away; behind, nothing would — so a run is fanned only
    where the notches lie outside the material (a long end mill on a shaft; a face mill
    whose back face is beyond the blank)."""
    reach = np.einsum("ij,ij->i", tips, axes) + tool.length
    support = (axes @ np.asarray(solid, dtype=float).T).max(axis=1)
    return support <= reach


def _creases(tips0: np.ndarray, axes0: np.ndarray, tips1: np.ndarray, axes1: np.ndarray,
             w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each step from face 0 to face 1 (tips, axes (m, 3)): where the two face lines cross
    (in the plane perpendicular to the step's rotation axis w), as offsets along line 0 from
    tip 0 (s_fwd) and along line 1 from tip 1 (s_back), in the direction of travel t = w × n.

    Line 0 is {tip0 + s·t0}; it meets plane 1 where (tip0 + s·t0)·n1 = h1, and t0·n1 = sin δ
    (t1·n0 = −sin δ). Steps without a turn get +inf."""
    t0 = np.cross(w, axes0)
    t1 = np.cross(w, axes1)
    h0 = np.einsum("ij,ij->i", tips0, axes0)
    h1 = np.einsum("ij,ij->i", tips1, axes1)
    d0 = np.einsum("ij,ij->i", t0, axes1)
    d1 = np.einsum("ij,ij->i", t1, axes0)
    with np.errstate(divide="ignore", invalid="ignore"):
        s_fwd = np.where(d0 > 1e-15, (h1 - np.einsum("ij,ij->i", tips0, axes1)) / d0, np.inf)
        s_back = np.where(d1 < -1e-15, (h0 - np.einsum("ij,ij->i", tips1, axes0)) / d1, np.inf)
    return s_fwd, s_back


