"""Tool solids: profiles revolved once, split into convex pieces, cached.

A revolved profile is convex exactly when its half section, closed along the axis, is a convex
polygon. Cutting profiles of the kinds in :mod:`vmach.tooling.model` always are; a profile that
is not (a neck, a tool with a smaller shank included) is cut at its reflex vertices into stacked
pieces, each convex, so that a translation sweep can use one convex hull per piece.

Polygonisation: a circle of radius r becomes an n-gon whose vertices lie at
``r_v = 2r / (1 + cos(π/n))``, so the polygon straddles the circle and deviates from it by at
most ``r_v·(1 − cos(π/n)) / 2`` either way; ``n`` is the smallest count that keeps this within
the chord tolerance at the largest radius (:func:`segments_for`), rounded up to a multiple of 4.

Phase: a solid of revolution may turn freely about its axis; its polygon may not. The
polygon's support toward a direction at angle φ from a vertex is ``r_v·cos φ``, which equals
the true radius at ``φ* = arccos((1 + cos(π/n)) / 2)`` (:func:`exact_phase`). :func:`spun`
turns each pose so that a vertex lies φ* from the *lateral* direction of its motion (the tool
axis × the travel): then the walls, floors and shoulders the side sweeps as it travels lie
exactly where the true tool puts them — on both sides, and (n a multiple of 4) also at the
front and back. Other directions keep the ±deviation above.

Arcs (``tool_solid(..., arcs=True)``, the ``fine`` preset): exact *at* the lateral is first
order only — a degree off it the polygon is up to its deviation inside or outside the circle,
and where a flat face's rim makes the foot of a flank at a side-made shoulder (the rim narrows
to the shoulder there), the vertex φ* off the lateral cut 0.0093 mm below the true rim on the
polygon shaft. So a flat or face mill's rings may be arcs of the true circle over ±``RIM_ARC``
about both laterals, from the tangent points of the polygon's vertices kept around them
(:func:`lateral_arcs`): never outside the circle there, within ``RIM_SAG`` inside it, the ring
convex and the piece still a right prism (fans and columns take it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vmach.tol import tol
from vmach.tooling.model import Tool

#: Half-angle (degrees) of the arcs of the true circle that a prism tool's rings (a flat or
#: face mill: the face's rim and the side) take about ±lateral with ``arcs`` (:func:`ring_points`),
#: and their sag (mm). A flat face's rim makes the flank's foot where a side-made surface meets
#: it (the flank/shoulder corner); the straddling polygon's vertex φ* from the lateral lies
#: ``polygon_deviation`` beyond the true rim there, and its flat edges cut what the round rim
#: leaves. ±5° holds the Ø25 rim's band 0.05 mm high (the foot the program leaves) and the
#: laterals' tilt near the shoulder (0.5–1.7°); 0.002 mm left the part as 0.001 did
#: (+0.0063 / +0.0057 mm at the corner line) with 5 % fewer triangles, 0.004 did not (+0.0066,
#: 13 points over 0.005): docs/stock.md.
RIM_ARC = 5.0
RIM_SAG = 0.002


def segments_for(radius: float, chord: float = tol.tool_chord, minimum: int = 12) -> int:
    """Smallest polygon count, a multiple of 4, whose straddling polygon stays within
    ``chord`` of the circle (a multiple of 4: :func:`spun` makes four directions exact)."""
    if radius <= 0:
        return minimum
    c = max(-1.0, 1.0 - 2.0 * chord / radius)
    n = max(minimum, math.ceil(math.pi / math.acos(c)))
    return -(-n // 4) * 4


def exact_phase(segments: int) -> float:
    """Angle (radians) from a vertex of the straddling ``segments``-gon toward which its
    support is the true radius: ``cos φ* = r / r_v = (1 + cos(π/n)) / 2``."""
    return math.acos((1.0 + math.cos(math.pi / segments)) / 2.0)


def lateral_angle(segments: int) -> float:
    """Angle (radians) from the tool frame's x axis at which :func:`spun` puts the side a
    pose is turned for: ``π/n − φ*`` (vertex 0 of :func:`ring_points` lies at π/n, and the
    side φ* from a vertex)."""
    return math.pi / segments - exact_phase(segments)


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


def ring_points(run: np.ndarray, segments: int, arc: float = 0.0, sag: float = RIM_SAG) -> np.ndarray:
    """Vertices of a revolved run (k, 2) ``(z, r)``: one ring per point with r > 0, one axis
    point where r = 0. Returns (p, 3) float, mm.

    arc : half-angle (radians) about the two lateral directions that :func:`spun` turns a pose
        for (``±`` :func:`lateral_angle`) over which the ring is an arc of the true circle
        (:func:`lateral_arcs`): the straddling polygon's vertices within ``arc + φ*`` of them
        give way to it."""
    ang = 2.0 * np.pi * (np.arange(segments) + 0.5) / segments
    keep = np.ones(segments, bool)
    if arc > 0:
        keep = _off_laterals(ang, segments) >= arc + exact_phase(segments) - 1e-9
    cs = np.column_stack([np.cos(ang[keep]), np.sin(ang[keep])])
    out = []
    for z, r in run:
        if r <= 1e-12:
            out.append(np.array([[0.0, 0.0, z]]))
            continue
        rv = straddle_radius(r, segments)
        out.append(np.column_stack([cs * rv, np.full(len(cs), z)]))
        if arc > 0:
            a = lateral_arcs(r, segments, arc, sag)
            out.append(np.column_stack([r * np.cos(a), r * np.sin(a), np.full(len(a), z)]))
    return np.concatenate(out)


def _off_laterals(ang: np.ndarray, segments: int) -> np.ndarray:
    """Angular distance (radians) of tool-frame angles ``ang`` from the nearer of the two
    lateral directions (``lateral_angle`` and the opposite one)."""
    d = np.mod(np.asarray(ang, dtype=float) - lateral_angle(segments), np.pi)
    return np.minimum(d, np.pi - d)


def lateral_arcs(r: float, segments: int, arc: float, sag: float = RIM_SAG) -> np.ndarray:
    """Angles (radians, tool frame) of the points of a circle of radius r (mm) that replace
    the straddling ``segments``-gon's vertices within ``arc + φ*`` of the two lateral
    directions (φ*: :func:`exact_phase`): the arc from the tangent point of the last vertex
    kept on one side to that of the first kept on the other — a vertex's tangents touch the
    circle φ* from it, so the ring stays convex, never deviates more than the polygon does,
    and is the arc over at least ``±arc`` — its points at most ``2·acos(1 − sag/r)`` apart
    (inscribed chords within ``sag`` mm of the circle), one exactly at each lateral."""
    step = 2.0 * math.acos(max(-1.0, 1.0 - sag / r))
    pitch = 2.0 * math.pi / segments
    phi = exact_phase(segments)
    out = []
    for lat in (lateral_angle(segments), lateral_angle(segments) + math.pi):
        # the kept vertices (k + 0.5)·pitch around this lateral: the last below
        # lat - arc - φ* and the first above lat + arc + φ*
        lo = (math.floor((lat - arc - phi + 1e-9) / pitch - 0.5) + 0.5) * pitch
        hi = (math.ceil((lat + arc + phi - 1e-9) / pitch - 0.5) + 0.5) * pitch
        a, b = lo + phi, hi - phi
        below = np.linspace(a, lat, max(1, math.ceil((lat - a) / step)) + 1)
        above = np.linspace(lat, b, max(1, math.ceil((b - lat) / step)) + 1)
        out.append(np.unique(np.concatenate([below, above])))
    return np.concatenate(out)


def fin_points(piece: np.ndarray, segments: int, half: float, sag: float = 0.002,
               height: float = math.inf) -> np.ndarray:
    """Points (q, 3), tool frame, whose hull is the *true* tool of a polygonised piece (its
    vertices (p, 3) from :func:`ring_points` with ``segments``) within the slab
    ``|x·m| <= half`` mm about the plane through the axis and the lateral direction that
    :func:`spun` turns a pose for (π/n − φ* from the x axis; m across it). On rings of the
    true surface (radius ``r_v·(1 + cos(π/n))/2``) of the piece: points of the circle at most
    ``2·acos(1 − sag/r)`` apart (an inscribed polygon within ``sag`` of it) over the arcs
    inside the slab about ±lateral, one exactly at each and at the slab's planes; between two
    rings of different radius (a cone), where the slab's planes cut the surface in curves,
    their points on rings 1.4 apart in radius from ``half`` (the whole ring there). The hull
    lies inside the true tool (never beyond it: a cone is ruled, its rings' hull is itself)
    and reaches the true radius toward ±lateral. With a finite ``height`` (mm from the tip
    along the axis), only the part of it up to that height: the rings above it left out and
    a whole ring (its arcs too) put at that height on the piece's surface."""
    alpha = lateral_angle(segments)
    pts = np.asarray(piece, dtype=float)
    scale = 1.0 / straddle_radius(1.0, segments)                  # r_v -> the true radius
    given = [(float(z), scale * float(np.hypot(*pts[pts[:, 2] == z, :2].T).max()))
             for z in np.unique(pts[:, 2])]
    rings = [(z, r, True) for z, r in given]           # (z, r, whole arc) — and between:
    for (z0, r0), (z1, r1) in zip(given[:-1], given[1:], strict=True):
        if z0 < height < z1:                           # the top of a fin cut to a height
            rings.append((height, r0 + (r1 - r0) * (height - z0) / (z1 - z0), True))
        lo, hi = sorted((r0, r1))
        if hi - lo <= 1e-9 or half >= hi:
            continue
        # the slab's planes cut the cone between in curves: their points on rings 1.4 apart
        # (and the whole ring where the slab takes in all of it)
        r = max(lo, half)
        while r < hi:
            rings.append((z0 + (z1 - z0) * (r - r0) / (r1 - r0), r, r <= half))
            r *= 1.4
    out = []
    for z, r, arc in rings:
        if z > height:
            continue
        if r <= 1e-12:
            out.append(np.array([[0.0, 0.0, z]]))
            continue
        step = 2.0 * math.acos(max(-1.0, 1.0 - sag / r))
        if half >= r:
            k = 2 * max(4, math.ceil(math.pi / step))                # even: one at ±lateral
            ang = alpha + 2.0 * math.pi * np.arange(k) / k
        else:
            beta = math.asin(half / r)
            # odd: one at the lateral; between the piece's rings only the slab's two planes
            k = 2 * max(1, math.ceil(beta / step)) + 1 if arc else 2
            side = np.linspace(-beta, beta, k)
            ang = np.concatenate([alpha + side, alpha + math.pi + side])
        out.append(np.column_stack([r * np.cos(ang), r * np.sin(ang), np.full(len(ang), z)]))
    return np.concatenate(out) if out else np.zeros((0, 3))


def _is_prism(run: np.ndarray) -> bool:
    """Is the revolved run (k, 2) ``(z, r)`` a cylinder with flat ends (a flat or face mill):
    every point off the axis at one radius, on two heights?"""
    off = run[run[:, 1] > 1e-12]
    return (len(off) >= 2 and float(np.ptp(off[:, 1])) <= 1e-12 * max(1.0, float(off[:, 1].max()))
            and len(np.unique(off[:, 0])) == 2 and len(np.unique(run[:, 0])) == 2)


_CACHE: dict[tuple, ToolSolid] = {}


def _solid(tool: Tool, chord: float, segments: int | None, arcs: bool) -> ToolSolid:
    key = (tool.geometry_key(), chord, segments, arcs)
    if key in _CACHE:
        return _CACHE[key]
    n = segments or segments_for(tool.radius, chord)
    prof = tool.profile(chord)
    # a prism's rings take arcs about the laterals where they are finer than its polygon
    arc = math.radians(RIM_ARC) if arcs and polygon_deviation(tool.radius, n) > RIM_SAG else 0.0
    pieces = tuple(ring_points(run, n, arc if _is_prism(run) else 0.0) for run in convex_runs(prof))
    out = ToolSolid(pieces, n, polygon_deviation(tool.radius, n), tool.radius,
                    float(prof[:, 0].max()))
    _CACHE[key] = out
    return out


def tool_solid(tool: Tool, chord: float = tol.tool_chord, segments: int | None = None,
               arcs: bool = False) -> ToolSolid:
    """The cached polygonised cutting part of ``tool`` (revolved once per tool and tolerance);
    with ``arcs``, a flat or face mill's rings are round about the laterals
    (:func:`ring_points`, ``RIM_ARC``) where its polygon deviates more than ``RIM_SAG``."""
    return _solid(tool, float(chord), segments, bool(arcs))


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


def lateral(tips: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """Lateral directions (n, 3) of the poses of a path (:func:`across`), with the travel at
    pose i taken from pose i-1 to pose i+1 (one-sided at the ends); where the tip does not
    move, the travel of the axis."""
    tips = np.asarray(tips, dtype=float).reshape(-1, 3)
    a = np.asarray(axes, dtype=float).reshape(-1, 3)
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    if len(tips) < 2:
        return np.zeros_like(tips)
    idx = np.arange(len(tips))
    nxt, prv = np.minimum(idx + 1, len(tips) - 1), np.maximum(idx - 1, 0)
    d = tips[nxt] - tips[prv]
    still = np.linalg.norm(d, axis=1) <= 1e-9
    d[still] = (a[nxt] - a[prv])[still]
    return across(a, d)


def across(axes: np.ndarray, travel: np.ndarray) -> np.ndarray:
    """Unit ``axis × travel`` (n, 3) for unit axes and travel vectors (n, 3): the direction
    across the travel in which the tool's side makes its walls. Zero where the travel is
    nil or along the axis (a plunge: no side is preferred)."""
    out = np.cross(axes, travel)
    length = np.linalg.norm(out, axis=1)
    good = length > 1e-9 * np.maximum(np.linalg.norm(travel, axis=1), 1e-12)
    out[good] /= length[good][:, None]
    out[~good] = 0.0
    return out


def spun(frames_: np.ndarray, side: np.ndarray, segments: int) -> np.ndarray:
    """Frames (n, 3, 4) turned about their own tool axis so that the polygon of a
    :func:`ring_points` solid reaches exactly the true radius toward ±side (n, 3) (unit,
    perpendicular to the axis; a row of zeros: the work Z across the axis, or X for a tool
    along Z) and, ``segments`` a multiple of 4, toward the two directions perpendicular to it
    (:func:`exact_phase`)."""
    rot = frames_[:, :, :3]
    side = np.array(side, dtype=float).reshape(-1, 3)
    none = ~np.any(side, axis=1)
    if none.any():
        # no travel across the axis (a plunge, a move along the axis): the work frame's Z
        # (X for a tool along Z) across the axis — the floors and shoulders of a turn-mill,
        # the walls of a mill
        ax = rot[none, :, 2]
        ref = np.where(np.abs(ax[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
        ref = ref - np.einsum("ij,ij->i", ref, ax)[:, None] * ax
        side[none] = ref / np.linalg.norm(ref, axis=1, keepdims=True)
    local = np.einsum("nji,nj->ni", rot, side)                 # side in each tool frame
    psi = np.arctan2(local[:, 1], local[:, 0])
    # turn the frame so that the side lies at lateral_angle (vertex 0 then lies φ* from it)
    beta = np.where(np.hypot(local[:, 0], local[:, 1]) > 1e-9, psi - lateral_angle(segments), 0.0)
    c, s = np.cos(beta), np.sin(beta)
    turn = np.zeros((len(beta), 3, 3))
    turn[:, 0, 0], turn[:, 0, 1], turn[:, 1, 0], turn[:, 1, 1], turn[:, 2, 2] = c, -s, s, c, 1.0
    out = np.array(frames_, dtype=float, copy=True)
    out[:, :, :3] = rot @ turn
    return out


def place(points: np.ndarray, frames_: np.ndarray) -> np.ndarray:
    """Points (k, 3) of the tool frame placed by frames (n, 3, 4): returns (n, k, 3).
    (A batched product: numpy's einsum, which has no BLAS path for it, took 25× as long.)"""
    turned = np.matmul(frames_[:, :, :3], np.asarray(points, dtype=float).T).transpose(0, 2, 1)
    return turned + frames_[:, None, :, 3]
