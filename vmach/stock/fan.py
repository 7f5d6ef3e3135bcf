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
(10 % larger for what lies between samples), and :class:`vmach.stock.Stock` shortens a fan
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
- the face's rim does not leave a foot the hull would take (:func:`rim_standoff`), or the
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

from vmach.stock.halfplanes import face_lines, polygon
from vmach.stock.sweeps import by_axis
from vmach.tol import tol

#: M's face planes are moved this far outward (mm): the cutter is ε smaller than H \ M, so the
#: faces of H that lie in a sampled face plane (the first and last pose) are never nearly
#: coplanar with M's.
EPS = 1e-6
PARALLEL = 1e-6   # rotation axes agreeing to this (unit vectors), axes perpendicular to ω
#: The bridge is measured at samples of the side's surface; between samples it can be a
#: little larger (up to 6 % on the helix tests), so the measure is taken 10 % larger.
SAMPLING_MARGIN = 1.1
#: A rim band is covered by another pose's face only where that face reaches this far (mm)
#: beyond the tip along the face line: the stretch of the chain a rim must cut lies within
#: about 1 mm of its tip on the polygon shaft (the program's Y approximates the contact point).
RIM_REACH = 1.5


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

def _exit(p: np.ndarray, d: np.ndarray, planes: np.ndarray, limit: float) -> np.ndarray:
    """Distance along unit directions d (m, 3) from points p (m, 3) to where the rays leave
    the convex region {x : n·x <= c} (planes (f, 4)), clipped to [0, limit]. A ray that
    starts outside and enters later gets its exit distance (the segment then covers the
    inside part, and more)."""
    if len(p) > 1024:
        return np.concatenate([_exit(p[i : i + 1024], d[i : i + 1024], planes, limit)
                               for i in range(0, len(p), 1024)])
    nd = d @ planes[:, :3].T                                   # (m, f)
    slack = planes[:, 3][None, :] - p @ planes[:, :3].T        # (m, f)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(nd > 1e-15, slack / nd, np.inf)
    return np.clip(t.min(axis=1), 0.0, limit)


def may_fan(rotary: np.ndarray) -> bool:
    """Whether a path's steps (``rotary`` (n-1,) bool: those that turn the axis) can hold a
    fan run at all: two steps or more, one of them rotary (:func:`plan_fans` makes none
    otherwise, and callers need not prepare its arguments)."""
    rotary = np.asarray(rotary, bool)
    return len(rotary) >= 2 and bool(rotary.any())


def plan_fans(tips: np.ndarray, axes: np.ndarray, rotary: np.ndarray, tool: Prism, *,
              max_angle: float = tol.fan_angle, slides: np.ndarray | None = None,
              clear: np.ndarray | None = None, rim: float = tol.fan_overcut,
              stock_box: np.ndarray | None = None, others=None) -> FanPlan:
    """Candidate fan runs of a path: maximal stretches of rotary steps — and, where
    ``slides`` (n-1,) bool allows, of steps that keep the axis and move the tool perpendicular
    to the rotation axis in between (a facing pass that indexes the workpiece and moves the
    tool in turn) — that meet the conditions of the module docstring, each turning the axis
    by at most ``max_angle`` and holding at least two rotary steps. Poses joined by slides
    share an axis; their lowest face is the one the chain is judged by (M lies below it; the
    others' faces are parallel and above, and the slide between them is a translation, whose
    hull is its exact sweep). The twist is not judged here: the cutter of a run is measured
    once made and the run cut shorter where it bridges too much (:class:`vmach.stock.Stock`).

    tips, axes : (n, 3) float — poses (work frame, unit axes). rotary : (n-1,) bool — steps
    that turn the axis. tool : the prism. clear : (n,) bool — poses whose far end (the
    prism's back face) lies beyond the stock (:func:`back_clear`); only steps between two
    such poses join a run. rim : mm — the most the face chain may lie below the path of the
    faces' rims (:func:`rim_standoff`), unless the path cuts the rim's band anyway or the
    band lies beyond ``stock_box`` (2, 3), the stock's bounds. Steps not in a run are left to
    placed poses and translation hulls. others : groups of points (g, k, 3), omega -> (g,)
    bool — whether other paths' true tools sweep every point of a group
    (:mod:`vmach.stock.sweeps`): a rim band they sweep above ``rim`` is taken anyway.
    """
    tips = np.asarray(tips, dtype=float)
    a = np.asarray(axes, dtype=float)
    n = len(tips)
    if not may_fan(rotary):
        return NO_FANS
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
    scale = max(1.0, float(np.abs(tips).max()))
    r = tool.radius
    # a step is a fan candidate when it turns, both axes are perpendicular to its rotation
    # axis, and the crease of the two (lowest) face lines lies inside both faces
    ok = turn & (np.abs(s_fwd) <= r) & (np.abs(s_back) <= r)
    ok &= np.abs(np.einsum("ij,ij->i", a[:-1], w)) <= PARALLEL
    ok &= np.abs(np.einsum("ij,ij->i", a[1:], w)) <= PARALLEL
    band = _rim_band(s_fwd, s_back, turn, r)
    near = np.minimum(rim_standoff(tips, a, angle), band) <= rim
    if not near.all():
        near |= _rims_covered(tips, a, w, turn, band, rim, r, ~near,
                              tool.inner, stock_box, others)
    ok &= near
    slide &= near
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
                    and s_back[last] <= s_fwd[j] + 1e-9):
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
    if not runs:
        return NO_FANS
    ru = np.asarray(runs, dtype=int)
    return FanPlan(ru, w[ru[:, 0]])


def rim_standoff(tips: np.ndarray, axes: np.ndarray, angle: np.ndarray, reach: int = 2) -> np.ndarray:
    """(n-1,) mm: for each step, how far the path of the face's rim stands off the face chain.

    A face is a disc: toward its rim along omega it narrows to the point tip ± R·omega, whose
    projection along omega is the tip. Near the rim the tool reaches the chain of face lines
    only where the tips' path runs along it; where a tip lies beyond its own stretch of the
    chain (the tool centre ahead of or behind the contact: a Y that only approximates the
    profile) or above it (the higher pose of a slide), the material between the chain and the
    path is left by the true tool in a thin band at the rim — and would be taken by H minus M,
    which cuts to the chain at every height. Measured as the largest ``n_j·x − h_j`` over the
    face planes j of the poses within ``reach`` of each step, at both tips x and the chord's
    midpoint, the latter raised by the arc's sagitta ``(c/2)·tan(δ/4)`` (a rotating tip runs on
    an arc outside its chord)."""
    n = len(tips)
    h = np.einsum("ij,ij->i", tips, axes)
    mid = 0.5 * (tips[:-1] + tips[1:])
    sag = 0.5 * np.linalg.norm(tips[1:] - tips[:-1], axis=1) * np.tan(np.radians(angle) / 4.0)
    out = np.zeros(n - 1)
    for off in range(-reach, reach + 2):
        j = np.clip(np.arange(n - 1) + off, 0, n - 1)
        for x, extra in ((tips[:-1], 0.0), (tips[1:], 0.0), (mid, sag)):
            out = np.maximum(out, np.einsum("ij,ij->i", x, axes[j]) - h[j] + extra)
    return out


def _rim_band(s_fwd: np.ndarray, s_back: np.ndarray, turn: np.ndarray, radius: float) -> np.ndarray:
    """(n-1,) mm: the height of the band at a face's rim in which its disc is too narrow to
    reach the ends of its stretch of the face chain. The stretch runs from crease to crease,
    at most S = max(|s_fwd|, |s_back|) from the tip; the disc is at least that wide up to
    ``R − √(R² − S²)`` from its rim. A step without a turn (a slide) takes the larger band of
    the turns on either side of it. Whatever the rim leaves lies within this band, so it is
    also a bound of the error the rim can make."""
    big = np.minimum(np.maximum(np.abs(s_fwd), np.abs(s_back)), radius)   # no crease: the radius
    band = radius - np.sqrt(radius**2 - big**2)
    prev, nxt = _turns_around(turn)
    left = np.where(prev >= 0, band[np.maximum(prev, 0)], radius)
    right = np.where(nxt < len(band), band[np.minimum(nxt, len(band) - 1)], radius)
    return np.where(turn, band, np.maximum(left, right))


def _turns_around(turn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each step (turn (m,) bool), the last turning step at or before it (-1: none) and
    the first at or after it (m: none)."""
    idx = np.arange(len(turn))
    prev = np.maximum.accumulate(np.where(turn, idx, -1))
    nxt = np.minimum.accumulate(np.where(turn, idx, len(turn))[::-1])[::-1]
    return prev, nxt


def _rims_covered(tips: np.ndarray, axes: np.ndarray, w: np.ndarray, turn: np.ndarray, band: np.ndarray,
                  rim: float, radius: float, which: np.ndarray, inner: float,
                  box: np.ndarray | None = None, others=None) -> np.ndarray:
    """(n-1,) bool: of the steps ``which``, those whose rim bands the path cuts anyway, or
    that lie beyond the stock's bounding ``box`` (2, 3) along omega (the tool's inscribed
    radius ``inner`` from the tip: the least the true rim reaches), or that the true tools of
    other paths sweep (``others``: groups of points (g, k, 3), omega -> (g,) bool,
    :meth:`vmach.stock.sweeps.Sweeps.others`) above the height ``rim`` that a band may have
    anyway — points of the face chain across the band's stretch (``RIM_SAMPLES``) at heights
    from ``rim`` to the band's, just on the tool's side of the face.

    Whatever a fan takes in the band at a face's rim (:func:`rim_standoff`) is taken by the
    true motion too if the path passes the same place again with the face at full width
    there: another pose, its axis within 1° and its face plane within ``rim`` of the tip,
    lying along omega beyond the band, and wide enough at the band's level
    (``sqrt(2Rd − d²)`` for a pose d away) to reach ``RIM_REACH`` beyond the tip. A finishing
    helix's next turn, 2 mm lower, does that for every turn but the last (whose lower rims
    stay to be judged) and its previous turn for every turn but the first (upper rims). Both
    rims of both poses of a step must be covered."""
    n = len(tips)
    steps = np.nonzero(which)[0]
    if len(steps) == 0:
        return np.zeros(n - 1, bool)
    # each step's omega: its own, or a neighbouring turn's (a slide); each pose takes the
    # omega and the (larger) band of the steps it belongs to
    prev, nxt = _turns_around(turn)
    src = np.where(turn, np.arange(n - 1), np.where(prev >= 0, prev, np.minimum(nxt, n - 2)))
    pose_om = w[src[np.minimum(np.arange(n), n - 2)]]
    pose_band = np.maximum(np.r_[band[:1], band], np.r_[band, band[-1:]])
    h = np.einsum("ij,ij->i", tips, axes)
    qs = np.unique(np.r_[steps, steps + 1])
    # other poses turned alike: axes within 1 degree (in blocks: problems × poses)
    cos1 = np.cos(np.radians(1.0))
    pairs = [np.nonzero(axes[qs[b : b + 256]] @ axes.T >= cos1) for b in range(0, len(qs), 256)]
    q = np.concatenate([qs[b + r] for b, (r, _) in zip(range(0, len(qs), 256), pairs, strict=True)])
    j = np.concatenate([c for _, c in pairs])
    om = pose_om[q]
    keep = np.abs(np.einsum("ij,ij->i", axes[j], tips[q]) - h[j]) <= rim   # face plane near the tip
    d = np.einsum("ij,ij->i", tips[q] - tips[j], om)                   # > 0: the other pose is lower
    side = np.abs(np.einsum("ij,ij->i", tips[j] - tips[q], np.cross(om, axes[q])))  # along the face line
    # at the level of q's rim, a pose d lower (or higher) is sqrt(2Rd - d²) wide
    width = np.sqrt(np.maximum(2 * radius * np.abs(d) - d * d, 0.0))
    cover = keep & (np.abs(d) >= pose_band[q] + 1e-3) & (side <= width - RIM_REACH)
    lower = np.zeros(n, bool)
    upper = np.zeros(n, bool)
    lower[q[cover & (d > 0)]] = True
    upper[q[cover & (d < 0)]] = True
    if box is not None:
        # a rim whose whole band lies beyond the stock along omega leaves its foot in the air
        # (the first turns of a helix that starts above the end face); the true rim is at
        # least the polygon's inscribed radius out
        box = np.asarray(box, dtype=float)
        reach = np.einsum("ij,ij->i", tips, pose_om)
        top = np.maximum(box[0] * pose_om, box[1] * pose_om).sum(axis=1)
        bottom = np.minimum(box[0] * pose_om, box[1] * pose_om).sum(axis=1)
        upper |= reach + inner - pose_band >= top
        lower |= reach - inner + pose_band <= bottom
    if others is not None:
        for sign, done in ((-1.0, lower), (1.0, upper)):
            need = qs[~done[qs] & np.any(pose_om[qs], axis=1) & (pose_band[qs] > rim)]
            if len(need):
                # from the true rim: halfway between the straddling polygon's vertices and its
                # inscribed circle
                done[need] = _swept_by_others(tips, axes, need, pose_om[need], sign, pose_band[need],
                                              rim, 0.5 * (radius + inner), others)
    both = lower & upper & np.any(pose_om, axis=1)
    out = np.zeros(n - 1, bool)
    out[steps] = both[steps] & both[steps + 1]
    return out


#: points across (along the face line) and up (heights) of a rim's band tried against other
#: paths' sweeps (:func:`_rims_covered`)
RIM_SAMPLES = (3, 2)


def _swept_by_others(tips: np.ndarray, axes: np.ndarray, which: np.ndarray, om: np.ndarray, sign: float,
                     band: np.ndarray, rim: float, radius: float, others) -> np.ndarray:
    """(w,) bool: of the poses ``which`` (w,) of a path (tips, unit axes (n, 3)), each with its
    omega (w, 3) and its rim's band (heights (w,) mm), those whose rim toward ``sign``·omega
    has the band swept above ``rim`` by other paths' true tools (``others``). The band lies on
    the face chain — what a fan cuts to, the lowest of the face planes of the poses within
    two of it — across its stretch (as wide as the disc is at the band's top) at heights from
    ``rim`` to the band's above the true rim (``radius``): those points, 0.001 mm above the
    chain, are asked as one group (``others``: groups (g, k, 3), omega -> (g,) bool, every
    point swept; :meth:`vmach.stock.sweeps.Sweeps.holds_all`), the middle one first."""
    across, up = RIM_SAMPLES
    t, a = tips[which], axes[which]
    half = np.sqrt(np.maximum(2.0 * radius * band - band * band, 0.0))             # (w,)
    line = np.cross(om, a)
    u = np.linspace(0.0, 1.0, up)[None, :] * (band - rim)[:, None] + rim              # (w, up)
    s = np.linspace(-1.0, 1.0, across)[None, :] * half[:, None]                        # (w, across)
    pts = (t + sign * radius * om)[:, None, None] - sign * u[:, None, :, None] * om[:, None, None] \
        + s[:, :, None, None] * line[:, None, None]                                   # (w, across, up, 3)
    # down to the chain: the lowest face plane of the poses around (n·x <= h below each)
    h = np.einsum("ij,ij->i", tips, axes)
    depth = np.zeros(pts.shape[:3])
    for off in range(-2, 3):
        j = np.clip(which + off, 0, len(tips) - 1)
        depth = np.maximum(depth, np.einsum("wabi,wi->wab", pts, axes[j]) - h[j][:, None, None])
    pts = pts - (depth - 1e-3)[..., None] * a[:, None, None]
    # the middle sample first: others' groups are looked for by their first point
    mid = across // 2 * up + up // 2
    flat = pts.reshape(len(which), -1, 3)
    flat = np.concatenate([flat[:, mid : mid + 1], np.delete(flat, mid, axis=1)], axis=1)
    out = np.zeros(len(which), bool)
    for o, grp in by_axis(om):
        out[grp] = others(flat[grp], o)
    return out


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


@dataclass(frozen=True)
class SideLines:
    """The tool's side lines at ±omega for every pose of a path (see :func:`side_samples`):
    starts p, ends q (2, n, 3) — from the face to where the cutter ends; inside (2, n) —
    length of each line inside the blank; axes (n, 3); omega (3,)."""

    p: np.ndarray
    q: np.ndarray
    inside: np.ndarray
    axes: np.ndarray
    omega: np.ndarray


def side_lines(frames_: np.ndarray, omega: np.ndarray, tool: Prism, reach: np.ndarray,
               blank: np.ndarray) -> SideLines:
    """Side lines of every pose (frames (n, 3, 4), tool to work): the prism's edges along the
    axis that lie furthest toward +omega and toward -omega — from the polygon's vertex on the
    face, so on the tool's surface whatever the polygon's turn about its axis — to where the
    cutter ends (``reach`` (n, 2, 3): the box each pose's cutter is trimmed to); ``blank``
    (g, 4) — the planes of the blank's hull."""
    rot, tips = frames_[:, :, :3], frames_[:, :, 3]
    axes = rot[:, :, 2]
    local = np.einsum("nji,j->ni", rot, omega)                      # omega in each tool frame
    score = local[:, :2] @ tool.ring[:, :2].T                       # (n, s)
    p = []
    for pick in (np.argmax(score, axis=1), np.argmin(score, axis=1)):
        p.append(np.einsum("nij,nj->ni", rot, tool.ring[pick]) + tips)
    p = np.stack(p)
    q = np.stack([pk + axes * _exit_box(pk, axes, reach, tool.length)[:, None] for pk in p])
    inside = np.stack([_exit(pk, axes, blank, tool.length) for pk in p])
    return SideLines(p, q, inside, axes, omega)


def _exit_box(p: np.ndarray, d: np.ndarray, boxes: np.ndarray, limit: float) -> np.ndarray:
    """Distance along unit directions d (m, 3) from points p (m, 3) to where the rays leave
    their boxes (m, 2, 3), clipped to [0, limit]."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(d > 1e-15, (boxes[:, 1] - p) / d, np.where(d < -1e-15, (boxes[:, 0] - p) / d, np.inf))
    return np.clip(t.min(axis=1), 0.0, limit)


def side_samples(lines: SideLines, i: int, j: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The surfaces the tool's side sweeps at its ±omega extremes over poses i..j, sampled.

    The side's extreme lines of consecutive poses span a ruled surface — the floor or ceiling
    the side cuts. The lines run from the face to where the cutter ends (its trim box); the
    surface is sampled on the part of the lines inside the blank (overcut elsewhere removes
    nothing), at 7 points along each line, denser toward where it leaves the blank (the hull
    bridges most far out) and with one close to the face (the bridge grows from nothing there;
    see :func:`covered`), and 3 across each step. The true sweep between two poses lies
    beyond the interpolated surface (the side is curved across), so the samples are at or
    inside it.

    Returns, for each of the two sides that moves along omega: (line end points (2m, 3),
    samples (3, m-1, 7, 3) — across each step, step, along the lines —, outward direction
    (3,) — away from the tool)."""
    out = []
    s = np.array([0.0, 0.02, 0.25, 0.5, 0.75, 0.9, 1.0])
    t = np.array([0.0, 0.5, 1.0])[:, None, None, None]
    ax = lines.axes[i : j + 1]
    for side, sign in enumerate((1.0, -1.0)):
        p, q = lines.p[side, i : j + 1], lines.q[side, i : j + 1]
        ends = np.concatenate([p, q])
        if np.ptp(ends @ lines.omega) <= 1e-9:
            continue        # a planar floor: the hull is exact there
        along = p[:, None, :] + ax[:, None, :] * (lines.inside[side, i : j + 1, None] * s)[..., None]
        out.append((ends, along[:-1][None] * (1 - t) + along[1:][None] * t, sign * lines.omega))
    return out


def reaches(planes: np.ndarray, samples: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """(k,) mm: for each sample (k, 3), how far the convex solid {x : n·x <= c} (planes
    (f, 4)) reaches beyond it along ``direction`` (0 when the sample is not inside), times
    SAMPLING_MARGIN."""
    toward = planes[:, :3] @ direction
    slack = planes[:, 3][None, :] - samples @ planes[:, :3].T
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where(toward[None, :] > 1e-12, slack / toward[None, :], np.inf)
    reach = lam.min(axis=1)
    inside = (slack >= -1e-9).all(axis=1) & np.isfinite(reach)
    return SAMPLING_MARGIN * np.where(inside, reach, 0.0)


def covered(grid: np.ndarray, need: np.ndarray, reach: float, direction: np.ndarray, tips: np.ndarray,
            axes: np.ndarray, tool: Prism, behind: float = 0.0) -> np.ndarray:
    """(a, m, s) bool: the samples ``grid`` (a, m, s, 3) of a sampled surface (:func:`side_samples`)
    around which whatever lies within ``reach`` mm of the surface along ``direction`` (3,) is
    cut anyway by the tool at one of the poses ``tips``, ``axes`` (c, 3; unit axes) — asked
    only for the samples ``need`` (a, m, s) bool.

    The surface between samples is made of patches (a bilinear patch lies in the hull of its
    four corners, so what lies within ``reach`` of it along ``direction`` lies in the hull of
    those corners and the same moved by ``reach``). A patch is covered when those eight
    points lie within the cylinder inscribed in the prism's polygon at one and the same pose —
    so inside the true tool and its polygon both, at a place the path's motion takes. A sample
    is covered when every patch around it is. What a fan takes there beyond its own run's
    sweep is taken by those poses anyway, by the true tool and by the simulated one alike.

    ``behind`` (mm): the cylinders reach that far behind their poses' faces as well. What a
    patch holds there the pose does not cut, but it lies within ``behind`` of what it does:
    a cutter that takes it removes no more than that beyond the true sweep (near its face, a
    helix's next turn stands a little behind or ahead of the face chain where this turn's face
    meets it, the chains of the two differing by their sampling)."""
    out = np.zeros(need.shape, bool)
    if not need.any() or len(tips) == 0 or min(need.shape[0], need.shape[2]) < 2:
        return out
    # patches (a-1, m, s-1) around a needed sample
    want = need[:-1, :, :-1] | need[1:, :, :-1] | need[:-1, :, 1:] | need[1:, :, 1:]
    idx = np.nonzero(want)
    a, k, b = idx
    corners = np.stack([grid[a, k, b], grid[a + 1, k, b], grid[a, k, b + 1], grid[a + 1, k, b + 1]], axis=1)
    corners = np.concatenate([corners, corners + reach * np.asarray(direction, dtype=float)], axis=1)
    inner = tool.inner
    length = tool.length + behind
    tips = tips - behind * axes
    # a pose holds a patch when its eight points are inside: surely when the patch's bounding
    # ball is, possibly when the ball meets the cylinder (tested point by point)
    flat = corners.reshape(-1, 3)
    centre = 0.5 * (flat.min(axis=0) + flat.max(axis=0))
    rho = float(np.linalg.norm(flat - centre, axis=1).max())
    near = _ball_in_cylinder(centre[None], np.array([rho]), tips, axes, length, inner)[1][0]
    tp, ax = tips[near], axes[near]
    patch = np.zeros(want.shape, bool)
    if len(tp):
        mid = corners.mean(axis=1)
        sure, maybe = _ball_in_cylinder(mid, np.linalg.norm(corners - mid[:, None], axis=2).max(axis=1),
                                        tp, ax, length, inner)
        ok = sure.any(axis=1)
        pi_, pj = np.nonzero(maybe & ~ok[:, None])
        d = corners[pi_] - tp[pj][:, None]                                  # (q, 8, 3)
        z = np.einsum("qki,qi->qk", d, ax[pj])
        radial = np.linalg.norm(d - z[..., None] * ax[pj][:, None], axis=2)
        ok[pi_[((z >= 0.0) & (z <= length) & (radial <= inner)).all(axis=1)]] = True
        patch[idx] = ok
    # a sample is covered when every patch around it is (those off the grid do not count)
    full = np.ones((need.shape[0] + 1, need.shape[1], need.shape[2] + 1), bool)
    full[1:-1, :, 1:-1] = patch
    around = full[:-1, :, :-1] & full[1:, :, :-1] & full[:-1, :, 1:] & full[1:, :, 1:]
    return around & need


def _ball_in_cylinder(centres: np.ndarray, radii: np.ndarray, tips: np.ndarray, axes: np.ndarray,
                      length: float, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """(inside, meets), each (k, c) bool: whether the ball (centres (k, 3), radii (k,)) lies
    inside, or may meet, the cylinder of the pose (tips, unit axes (c, 3); ``length``,
    ``radius``, from the tip along the axis)."""
    z = centres @ axes.T - np.einsum("ci,ci->c", tips, axes)[None]          # (k, c)
    cc = np.einsum("ki,ki->k", centres, centres)[:, None]
    tt = np.einsum("ci,ci->c", tips, tips)[None]
    radial2 = np.maximum(cc - 2.0 * centres @ tips.T + tt - z * z, 0.0)    # |centre - tip|² - z²
    r = radii[:, None]
    inside = (z >= r) & (z <= length - r) & (radial2 <= np.maximum(radius - r, 0.0) ** 2) & (radius >= r)
    meets = (z >= -r) & (z <= length + r) & (radial2 <= (radius + r) ** 2)
    return inside, meets


def hull_planes(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Face planes (f, 4) ``n·x <= c`` of a convex triangle mesh (outward faces)."""
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    n = np.cross(b - a, c - a)
    length = np.linalg.norm(n, axis=1)
    good = length > 1e-14
    n = n[good] / length[good][:, None]
    return np.column_stack([n, np.einsum("ij,ij->i", n, a[good])])


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


def _basis(omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Orthonormal u, v with u × v = omega."""
    u = np.cross(omega, [1.0, 0.0, 0.0])
    if np.linalg.norm(u) < 0.5:
        u = np.cross(omega, [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    return u, np.cross(omega, u)


def material_points(tips: np.ndarray, axes: np.ndarray, omega: np.ndarray, around: np.ndarray,
                    margin: float = 1.0, eps: float = EPS) -> np.ndarray | None:
    """Vertices (k, 3) of M — the material below every face plane of a run, moved out by
    ``eps`` — within a box ``margin`` around the points ``around`` (m, 3) (the hull's), so
    that H \\ M is the fan cutter. All face planes contain omega, so M is a prism along it:
    the face lines cut a convex polygon out of a rectangle in the plane perpendicular to
    omega (:func:`vmach.stock.halfplanes.polygon`). None if empty."""
    u, v = _basis(omega)
    pu, pv, pw = around @ u, around @ v, around @ omega
    lo, hi = np.array([pu.min(), pv.min()]) - margin, np.array([pu.max(), pv.max()]) + margin
    lines = face_lines(tips, axes, u, v)
    lines[:, 2] += eps
    p = polygon(lines, lo, hi)
    if len(p) < 3 or np.ptp(p[:, 0]) * np.ptp(p[:, 1]) <= 0.0:
        return None
    base = p[:, :1] * u + p[:, 1:] * v
    w0, w1 = pw.min() - margin, pw.max() + margin
    return np.vstack([base + w0 * omega, base + w1 * omega])
