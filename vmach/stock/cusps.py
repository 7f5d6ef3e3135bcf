"""Cusps between placed poses of a rotary step, and how many poses to add against them.

A rotary step cut by placing the tool at its two ends (:mod:`vmach.stock.sweep`) leaves the
material the tool sweeps between them and neither end reaches: where a curved side makes the
surface, a cusp between two imprints. Imprints ``s`` apart of a side of normal curvature
κ_t on a surface that is itself convex toward the tool with curvature κ_w leave

    c = ρ − √(ρ² − s²/4),   1/ρ = κ_t + κ_w          (≈ s²·(κ_t + κ_w) / 8; at most ρ)

— the sagitta of the relative circle of curvature over the chord s (two circles of
curvatures κ_t and κ_w touching: their gap at ±s/2). For a point of the tool's surface
that a step moves by ``d`` while the tool turns by δ:

- s is its travel across the side's straight generators (along the circumferential
  direction, for κ_t = cos(normal, radial)/r — a cylinder 1/R, a cone of half angle α at
  radius r cos α / r; and along the profile, for a ball's or a bull nose's arc: 1/its
  radius). Travel along a straight generator leaves no cusp.
- κ_w = δ / |d|: the point turns about the step's centre of rotation at that distance, and
  so does the surface it makes (the material lies around that centre: a shaft turning on
  its axis). On a flat face (κ_t = 0) this is the scallop ``r·δ²/8`` that the angle limit
  bounds (:func:`vmach.stock.sweep.scallop_bound`): end faces are not sampled.

The tip-step limit (``tol.sweep_step``) bounds s only at the tip. The chamfer mill of the
polygon-shaft program, 1 mm from its sharp tip (κ_t = cos 75° / 1 mm), left 0.031 mm at a
1 mm step; the Ø25 end mill's side at the shoulder, 26 mm from the axis, 0.016 mm.
:func:`step_cusps` takes each step's largest cusp over sample points of the side that may
lie in the material, and :func:`substeps` how many parts the step must be cut into so that
none exceeds ``tol.sweep_cusp``: a cusp shrinks with the square of the spacing,
``m = ⌈√(c / c_max)⌉``. The added poses are placed poses, which never cut more than the true
sweep, and each is cut as its *fin* (:func:`fin_widths`): the true tool within a slab through
its axis across its travel — all it removes beyond its neighbours but for its flat face's
scallop, at a fraction of the whole pose's cost in the booleans. Fan cutters' steps need none
(their hull fills the cusps, :mod:`vmach.stock.fan`), nor do translation runs (exact).

The same holds for a run's own placed poses between two rotary steps: beyond its neighbours
a pose adds only the lenses along the envelope and its face's share, so it too is cut as its
fin (widths over its two steps, :func:`fin_widths`) wherever its neighbours' fins are seen to
hold the rest of it (:func:`fins_cover`); a run's first and last poses stay whole.

Lengths mm, curvatures 1/mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vmach.tol import tol
from vmach.tooling.model import Tool
from vmach.tooling.solid import lateral_angle

AROUND = 32        # sample points around the axis per height
SPACING = 0.5      # mm between sample heights along the profile
MOST = 8           # parts a step is cut into at most
BLOCK = 200_000    # steps × sample points measured at a time (bounds the temporary arrays)
FIN_LEAST = 0.05   # mm: the narrowest fin
RIM = 0.1          # mm: a flat face's band along its rim that a fin holds whole


@dataclass(frozen=True)
class Side:
    """Sample points of a tool's side, tool frame (tip at the origin, axis +z).

    points : (p, 3) float, mm; around, along : (p, 3) float — unit tangents across the axis
    (circumferential) and along the profile (meridian); across, down : (p,) float, 1/mm — the
    side's normal curvature in those two directions (0 along a straight profile).
    """

    points: np.ndarray
    around: np.ndarray
    along: np.ndarray
    across: np.ndarray
    down: np.ndarray


_CACHE: dict[tuple, Side] = {}


def side(tool: Tool) -> Side:
    """The side of ``tool`` sampled (cached per tool geometry). End faces are left out: the
    scallop a flat face leaves is the angle limit's (:func:`vmach.stock.sweep.scallop_bound`,
    reported with the simulation)."""
    key = tool.geometry_key()
    if key in _CACHE:
        return _CACHE[key]
    prof = tool.profile(tol.tool_chord)
    arc_radius = {"ball": tool.radius, "bull": tool.corner_radius}.get(tool.kind, 0.0)
    ang = 2.0 * np.pi * (np.arange(AROUND) + 0.5) / AROUND
    cs = np.column_stack([np.cos(ang), np.sin(ang)])
    cols: list[list[np.ndarray]] = [[], [], [], [], []]
    for (z0, r0), (z1, r1) in zip(prof[:-1], prof[1:], strict=True):
        dz, dr = z1 - z0, r1 - r0
        length = math.hypot(dz, dr)
        if abs(dz) <= 1e-12 or length <= 1e-12:
            continue              # an end face (its scallop: the angle bound), or nothing
        t = np.linspace(0.0, 1.0, max(2, math.ceil(length / SPACING) + 1))
        z, r = z0 + dz * t, r0 + dr * t
        keep = r > 1e-9
        # the profile's outward normal in (z, r) is (-dr, dz)/length: its radial part over r
        # is the curvature across the axis (Meusnier)
        kc = abs(dz / length) / r[keep]
        km = 1.0 / arc_radius if arc_radius > 0 and abs(dr) > 1e-12 and abs(dz) > 1e-12 else 0.0
        for zi, ri, ki in zip(z[keep], r[keep], kc, strict=True):
            cols[0].append(np.column_stack([cs * ri, np.full(AROUND, zi)]))
            cols[1].append(np.column_stack([-cs[:, 1], cs[:, 0], np.zeros(AROUND)]))
            cols[2].append(np.column_stack([cs * (dr / length), np.full(AROUND, dz / length)]))
            cols[3].append(np.full(AROUND, ki))
            cols[4].append(np.full(AROUND, km))
    shapes = [(0, 3)] * 3 + [(0,)] * 2
    out = Side(*(np.concatenate(c) if c else np.zeros(s) for c, s in zip(cols, shapes, strict=True)))
    _CACHE[key] = out
    return out


def cusp_height(spacing: np.ndarray, kappa: np.ndarray) -> np.ndarray:
    """Cusp (mm) between imprints ``spacing`` apart, relative curvature ``kappa``: the
    sagitta of that circle over the chord, at most its radius (0 where kappa is 0)."""
    rho = 1.0 / np.maximum(kappa, 1e-12)
    sag = rho - np.sqrt(np.maximum(rho * rho - spacing * spacing / 4.0, 0.0))
    return np.where(kappa > 0, sag, 0.0)


def step_cusps(sd: Side, frames_a: np.ndarray, frames_b: np.ndarray, holds, least: float = 0.0,
               reach: bool = False):
    """(s,) mm: the largest cusp each step leaves between its two placed poses (frames
    (s, 3, 4) each, tool to work), over the side's sample points that may lie in the
    material at either end (``holds``: points (m, 3) -> (m,) bool, a superset of the stock).
    Cusps of ``least`` or less count as 0: only points over it are looked up. With ``reach``,
    (cusps, Over): those points over ``least`` that may lie in the material — where a pose
    between needs to reach (:func:`fin_height`)."""
    if len(sd.points) == 0 or len(frames_a) == 0:
        none = np.zeros(len(frames_a))
        return (none, Over.none()) if reach else none
    if len(frames_a) * len(sd.points) > BLOCK:
        k = max(1, BLOCK // len(sd.points))
        starts = range(0, len(frames_a), k)
        parts = [step_cusps(sd, frames_a[i : i + k], frames_b[i : i + k], holds, least, reach)
                 for i in starts]
        if not reach:
            return np.concatenate(parts)
        rows = [(o.step + i, o.height, o.point, o.cusp) for i, (_, o) in zip(starts, parts, strict=True)]
        return (np.concatenate([c for c, _ in parts]),
                Over(*(np.concatenate(x) for x in zip(*rows, strict=True))))
    rot, t = frames_a[:, :, :3], frames_a[:, :, 3]
    rel = np.matmul(rot.transpose(0, 2, 1), frames_b[:, :, :3])          # b in a's frame
    shift = np.einsum("sji,sj->si", rot, frames_b[:, :, 3] - t)
    # each point's travel over the step, in pose a's tool frame
    d = np.matmul(sd.points, (rel - np.eye(3)).transpose(0, 2, 1)) + shift[:, None, :]
    # the tool's turn over the step (radians), from the relative rotation's trace
    turn = np.arccos(np.clip((np.trace(rel, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0))
    travel = np.linalg.norm(d, axis=2)
    kw = turn[:, None] / np.maximum(travel, 1e-12)
    # the samples around lie 2π/AROUND apart: the largest travel across is at most 1/cos(π/AROUND)
    # of the largest sampled one
    across = np.abs(np.einsum("spi,pi->sp", d, sd.around)) / math.cos(math.pi / AROUND)
    down = np.abs(np.einsum("spi,pi->sp", d, sd.along))
    c = np.maximum(cusp_height(across, sd.across[None, :] + kw), cusp_height(down, sd.down[None, :] + kw))
    step, point = np.nonzero(c > least)
    out = np.zeros(len(frames_a))
    over = Over.none()
    if len(step):
        pa = np.einsum("kij,kj->ki", rot[step], sd.points[point]) + t[step]
        pb = pa + np.einsum("kij,kj->ki", rot[step], d[step, point])
        inside = holds(pa) | holds(pb)
        np.maximum.at(out, step, np.where(inside, c[step, point], 0.0))
        k = np.nonzero(inside)[0]
        over = Over(step[k], sd.points[point[k], 2], 0.5 * (pa[k] + pb[k]), c[step[k], point[k]])
    return (out, over) if reach else out


@dataclass(frozen=True)
class Over:
    """Side samples whose cusp is over the tolerance (:func:`step_cusps`): their step (k,)
    int, height along the axis from the tip (k,) mm, the point midway along its travel over
    the step (k, 3) mm, work frame, and the cusp (k,) mm."""

    step: np.ndarray
    height: np.ndarray
    point: np.ndarray
    cusp: np.ndarray

    @classmethod
    def none(cls) -> Over:
        return cls(np.zeros(0, int), np.zeros(0), np.zeros((0, 3)), np.zeros(0))


def fin_height(over: Over, steps: int, length: float, keep: np.ndarray | None = None) -> np.ndarray:
    """(steps,) mm: how far along the axis (from the tip) the fins of each step's added poses
    reach: from the greatest height of its samples over the tolerance (``over``; only those
    ``keep`` (k,) bool marks — e.g. not cut again by another pass), the next sample height up
    (SPACING along the profile), rounded up to steps of 2^(1/4) from SPACING so that poses
    share their fin pieces; inf (the whole length) where that reaches ``length``, the tool's
    cutting length. Above it every sampled cusp that counts is within the tolerance without
    the added poses: the pose's fin holds nothing there that its neighbours' imprints leave
    over it."""
    top = np.full(steps, -np.inf)
    k = np.ones(len(over.step), bool) if keep is None else np.asarray(keep, bool)
    np.maximum.at(top, over.step[k], over.height[k])
    h = np.maximum(top, 0.0) + SPACING
    step = np.ceil(4.0 * np.log2(h / SPACING) - 1e-9)
    out = SPACING * 2.0 ** (step / 4.0)
    return np.where(out < length, out, np.inf)


def substeps(cusps: np.ndarray, most: float = tol.sweep_cusp) -> np.ndarray:
    """(s,) int: parts to cut each step into so that its cusps (mm) stay within ``most``
    (cusps shrink with the square of the spacing), at most MOST."""
    m = np.ceil(np.sqrt(np.asarray(cusps, dtype=float) / most) - 1e-9)
    return np.clip(m, 1, MOST).astype(int)


def fin_normal(segments: int) -> np.ndarray:
    """(3,) unit normal, tool frame, of the plane through the axis that holds the lateral
    direction a placed pose's ``segments``-gon is turned to be exact toward
    (:func:`vmach.tooling.solid.lateral_angle`): the direction of travel across the axis,
    which a fin of the pose is narrow in."""
    alpha = lateral_angle(segments)
    return np.array([-math.sin(alpha), math.cos(alpha), 0.0])


def fin_widths(frames: np.ndarray, frames_a: np.ndarray, frames_b: np.ndarray, normal: np.ndarray,
               parts: np.ndarray, sd: Side, holds, face: float = 0.0, height=None) -> np.ndarray:
    """(e,) mm: half-widths of the fins that cut added poses (:func:`vmach.tooling.solid.fin_points`).

    An added pose (frames (e, 3, 4), tool to work) removes, beyond its neighbouring poses,
    the lenses its side leaves between imprints — along the envelope of the side, where its
    normal is perpendicular to the motion — and its flat face's scallop (which the angle limit
    bounds anyway). The fin keeps the pose within ``half`` of the plane through its axis
    normal to ``normal`` (tool frame) and holds those lenses when ``half`` covers, at every
    sampled height of the side (``sd``), the envelope's offset from that plane and half the
    spacing of the imprints there (the fin is the true tool's, exact toward the lateral:
    :func:`vmach.tooling.solid.fin_points`):

    - the step's motion (pose a to pose b, frames (e, 3, 4) each: the tip's travel and the
      axis's turn, no spin — a solid of revolution may spin freely) moves each point of the
      side by d; the envelope is where ``n·d`` changes sign around the axis (between two of
      the AROUND samples, the zero placed linearly; a cone's normal, nearly along its axis,
      puts it far from the meridian across the travel once the tool also moves along its
      axis);
    - imprints lie |d| / parts apart; a pose makes the envelope within half of that — the
      fin reaches the whole spacing, to its neighbours' meridians: a step's end poses are
      whole polygons, which reach the true radius φ* off their meridian, on one side.

    Only envelope points that may lie in the material count (``holds``: points (m, 3) ->
    (m,) bool), and with ``height`` (e,) mm (:func:`fin_height`) only those up to that height
    along the axis: the fin is cut there (:func:`vmach.tooling.solid.fin_points`). The sum,
    taken 25 % larger, plus ρ·(2π/AROUND)²/8 for the linear zero and
    0.05 mm, is the half-width; 0.05 mm where no envelope point counts. For a flat-faced tool
    (``face``: the face's radius, mm) at least the face's chord RIM from its rim: the face makes
    a flank's foot there over its whole chord. A fin lies inside the true tool at its pose: a
    narrower one than needed leaves cusps, never removes more."""
    e = len(frames)
    if e == 0 or len(sd.points) == 0:
        return np.full(e, FIN_LEAST)
    if e * len(sd.points) > BLOCK:
        k = max(1, BLOCK // len(sd.points))
        return np.concatenate([fin_widths(frames[i : i + k], frames_a[i : i + k], frames_b[i : i + k], normal,
                                          parts[i : i + k], sd, holds, face,
                                          None if height is None else height[i : i + k])
                               for i in range(0, e, k)])
    pts = sd.points                                                  # (P, 3): AROUND per height
    rho = np.hypot(pts[:, 0], pts[:, 1])
    radial = pts[:, :2] / rho[:, None]
    n_r, n_z = sd.along[:, 2], -np.einsum("pi,pi->p", sd.along[:, :2], radial)
    nrm = np.column_stack([radial * n_r[:, None], n_z])             # outward normals (P, 3)
    rot, t = frames[:, :, :3], frames[:, :, 3]
    mat, shift = _displacement(rot, t, frames_a, frames_b)
    # n·(M p + m) over the samples, without the (e, P, 3) displacements
    g = (np.einsum("pi,eij,pj->ep", nrm, mat, pts, optimize=True) + shift @ nrm.T).reshape(e, -1, AROUND)
    g1 = np.roll(g, -1, axis=2)
    step, ring, i = np.nonzero((g > 0) != (g1 > 0))                  # a zero after sample i
    out = np.zeros(e)
    if len(step):
        _lens_widths(out, g, g1, step, ring, i, pts, rho, rot, t, mat, shift, normal, parts, holds, height)
    if face > 0:       # the flat face's chord RIM from its rim, where it makes a flank's foot
        out = np.maximum(out, math.sqrt(2.0 * face * RIM))
    return 1.25 * out + FIN_LEAST


def _displacement(rot: np.ndarray, t: np.ndarray, frames_a: np.ndarray, frames_b: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """How a step (pose a to pose b, frames (e, 3, 4): the tip's travel and the axis's least
    turn, no spin) moves a point p of poses (rotations ``rot`` (e, 3, 3), tips ``t`` (e, 3)),
    in the pose's own frame: ``M p + m`` — (M (e, 3, 3), m (e, 3))."""
    e = len(rot)
    ua, ub = frames_a[:, :, 2], frames_b[:, :, 2]
    k = np.cross(ua, ub)
    c = np.einsum("ei,ei->e", ua, ub)
    kx = np.zeros((e, 3, 3))
    kx[:, 0, 1], kx[:, 0, 2], kx[:, 1, 2] = -k[:, 2], k[:, 1], -k[:, 0]
    kx -= kx.transpose(0, 2, 1)
    turn = kx + np.matmul(kx, kx) / (1.0 + c)[:, None, None]        # R_min - I (Rodrigues)
    rt = rot.transpose(0, 2, 1)
    mat = np.matmul(rt, np.matmul(turn, rot))                        # (e, 3, 3)
    shift = np.einsum("eij,ej->ei", rt, np.einsum("eij,ej->ei", turn, t - frames_a[:, :, 3])
                      + frames_b[:, :, 3] - frames_a[:, :, 3])
    return mat, shift


_OUTLINES: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}


def outline(tool: Tool) -> tuple[np.ndarray, np.ndarray]:
    """The true radius of ``tool`` along its axis: heights (k,) and radii (k,) mm, increasing
    heights, for ``np.interp`` over [0, the cutting length] (the largest radius where the
    profile steps at one height). Made once per tool shape (read-only arrays): a path cut in
    chunks asks for every chunk."""
    key = (tool.geometry_key(), tol.tool_chord)
    if key not in _OUTLINES:
        prof = tool.profile(tol.tool_chord)[:-1]               # the closing point on the axis
        zs = np.unique(prof[:, 0])
        rs = np.array([prof[prof[:, 0] == z, 1].max() for z in zs])
        zs.flags.writeable = False
        rs.flags.writeable = False
        _OUTLINES[key] = (zs, rs)
    return _OUTLINES[key]


def face_radius(tool: Tool) -> float:
    """Radius (mm) of the tool's flat end face (0 for a pointed tool)."""
    return float(outline(tool)[1][0])


def _lens_widths(out: np.ndarray, g, g1, step, ring, i, pts, rho, rot, t, mat, shift, normal, parts, holds,
                 height) -> None:
    """Into ``out`` (e,): per step, the largest envelope offset plus half the imprints' spacing
    over the envelope's zeros (``step``, ``ring``, ``i``: a zero of ``g`` after sample i) that
    may lie in the material (``holds``) and up to ``height``."""
    point = ring * AROUND + i
    inside = holds(np.einsum("kij,kj->ki", rot[step], pts[point]) + t[step])
    if height is not None:
        inside &= pts[point, 2] <= np.asarray(height, dtype=float)[step]
    step, ring, i, point = step[inside], ring[inside], i[inside], point[inside]
    g0, g1 = g[step, ring, i], g1[step, ring, i]
    base = np.arctan2(pts[point, 1], pts[point, 0])
    at = base + (2.0 * np.pi / AROUND) * g0 / (g0 - g1)          # the zero, linearly between
    nn = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    r = rho[point]
    offset = r * np.abs(np.cos(at) * nn[0] + np.sin(at) * nn[1])
    d = np.einsum("kij,kj->ki", mat[step], pts[point]) + shift[step]
    lens = np.linalg.norm(d, axis=1) / np.asarray(parts)[step]
    slack = r * (2.0 * np.pi / AROUND) ** 2 / 8.0
    np.maximum.at(out, step, offset + lens + slack)
