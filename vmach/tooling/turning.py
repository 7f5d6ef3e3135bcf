"""Turning tools: ISO inserts in holders, grooving and threading inserts, boring bars.

A turning tool does not turn: the workpiece does. What it cuts is its **cross-section** in the
X–Z half-plane through the spindle axis (:meth:`TurningTool.section`), swept along the path and
revolved about the spindle (:mod:`vmach.stock.strategies.revolved`). Coordinates of a section
are ``(x, z)`` mm relative to the tool's **theoretical tip P** — the point the control moves
along the programmed contour without tool nose radius compensation: x radial (outward +), z
along the spindle (toward the tailstock +).

The cutting edge position (Sinumerik ``$TC_DP2`` "SL", LinuxCNC's orientation, ISO's
imaginary tool nose number) says where P lies from the nose centre S, with X up and Z to the
right (a lathe whose tool sits behind the turning centre, as Siemens draws it)::

    SL 1: P = S + (+r, +r)    SL 5: P = S + (0, +r)     SL 9: P = S
    SL 2: P = S + (+r, -r)    SL 6: P = S + (+r, 0)
    SL 3: P = S + (-r, -r)    SL 7: P = S + (0, -r)
    SL 4: P = S + (-r, +r)    SL 8: P = S + (-r, 0)

(entries ``(dx, dz)``, r the nose radius). SL 3 is the external turning tool cutting toward the
chuck (−Z) and facing toward the centre (−X); SL 2 the boring bar; SL 8 a threading or
grooving insert plunging toward the centre.

Kinds (lengths mm, angles degrees):

=============  ==============================================================================
``turning``    ISO insert ``shape`` (C D V K: rhombic 80/55/35/55°, S square, T triangle,
               W trigon 80°, R round) of inscribed circle ``inscribed``, ``nose_radius``,
               in a holder of cutting edge angle ``lead_angle`` (κr, default 95°)
``boring``     the same insert on a boring bar (``bar`` diameter and length along −Z)
``grooving``   a rectangular insert of cutting ``width``, ``corner_radius`` at both cutting
               corners, plunging depth ``depth``; P is the corner toward −Z (SL 3) unless told
``threading``  a V insert of ``profile_angle`` (60 metric) with ``nose_radius``, pitches
               ``pitch_min``–``pitch_max``; P at the tip (SL 8)
=============  ==============================================================================
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from vmach.source import SourceRef
from vmach.tooling.model import Offset

TURNING_KINDS = ("turning", "boring", "grooving", "threading")

#: ISO 1832 shape letter -> (corner angle ε in degrees, corners of the insert; 0 = round)
SHAPES: dict[str, tuple[float, int]] = {
    "C": (80.0, 4), "D": (55.0, 4), "V": (35.0, 4), "K": (55.0, 4), "E": (75.0, 4), "M": (86.0, 4),
    "S": (90.0, 4), "T": (60.0, 3), "W": (80.0, 3), "R": (0.0, 0),
}

#: cutting edge position -> where P lies from the nose centre S, in units of the nose radius (dx, dz)
EDGE_POSITIONS: dict[int, tuple[float, float]] = {
    1: (1.0, 1.0), 2: (1.0, -1.0), 3: (-1.0, -1.0), 4: (-1.0, 1.0),
    5: (0.0, 1.0), 6: (1.0, 0.0), 7: (0.0, -1.0), 8: (-1.0, 0.0), 9: (0.0, 0.0),
}

_SECTIONS: dict[tuple, np.ndarray] = {}     # cross-sections by geometry and chord


@dataclass(frozen=True)
class TurningTool:
    """A turning tool: an insert in a holder, fixed on the turret while the workpiece turns.

    name, number, offsets, source : as :class:`vmach.tooling.model.Tool`.
    kind : one of :data:`TURNING_KINDS`.
    shape : ISO shape letter (``turning``, ``boring``), :data:`SHAPES`.
    inscribed : float, mm — the insert's inscribed circle (IC); for ``grooving``/``threading``
        the insert's length from its tip into the holder.
    thickness : float, mm. nose_radius : float, mm (0: sharp). clearance : float, degrees.
    edge_position : int, 1..9 — the cutting edge position (module docstring).
    lead_angle : float, degrees — the holder's cutting edge angle κr (``turning``, ``boring``).
    width, corner_radius, depth : ``grooving`` insert's cutting width, corner radii, depth, mm.
    profile_angle, pitch_min, pitch_max : ``threading`` insert, degrees and mm.
    holder_width, holder_height, holder_length : the holder's shank section (Z × Y) and length
        behind the insert along +X (external tools), mm.
    bar_diameter, bar_length : a boring bar along +Z behind the insert, mm.
    """

    name: str
    kind: str
    number: int | None = None
    shape: str = "C"
    inscribed: float = 12.7
    thickness: float = 4.76
    nose_radius: float = 0.8
    clearance: float = 0.0
    edge_position: int = 3
    lead_angle: float = 95.0
    width: float = 0.0
    corner_radius: float = 0.0
    depth: float = 0.0
    profile_angle: float = 60.0
    pitch_min: float = 0.0
    pitch_max: float = 0.0
    holder_width: float = 25.0
    holder_height: float = 25.0
    holder_length: float = 100.0
    bar_diameter: float = 0.0
    bar_length: float = 0.0
    offsets: Mapping[int, Offset] = field(default_factory=dict)
    source: SourceRef | None = None

    turning = True    # the workpiece turns, not the tool (milling tools have no such attribute)
    teeth = 1

    # what the milling side reads of any tool ---------------------------------------------------
    @property
    def radius(self) -> float:
        """mm: the nose radius — the radius tool nose radius compensation offsets by."""
        return self.nose_radius if self.kind != "grooving" else self.corner_radius

    @property
    def diameter(self) -> float:
        return 2.0 * self.radius

    @property
    def cutting_length(self) -> float:
        """mm: how far the insert reaches from P into the holder (its section's extent)."""
        sec = self.section()
        return float(np.ptp(sec[:, 0]) + np.ptp(sec[:, 1]))

    def stack(self) -> list[tuple[str, float, float, float]]:
        """A coarse cylinder model along the tool axis (radial, +X from the tip) for the checks
        that only know cylinders (fixtures, machine parts): the insert as a rod of its half
        thickness as far as it reaches, then the holder's shank (round of its section's
        half diagonal). The stock meets the true cross-section instead
        (:mod:`vmach.stock.strategies.revolved`)."""
        reach = float(np.ptp(self.section()[:, 0]))
        out = [("cutter", 0.0, reach, max(self.thickness / 2.0, self.radius, 0.1))]
        if self.holder_length > 0:
            out.append(("holder", reach, reach + self.holder_length,
                        math.hypot(self.holder_width, self.holder_height) / 2.0))
        return out

    def length(self, d: int | None) -> float:
        if not d:
            return 0.0
        off = self.offsets.get(int(d))
        return off.length if off else 0.0

    def geometry_key(self) -> tuple:
        return (self.kind, self.shape, self.inscribed, self.nose_radius, self.edge_position,
                self.lead_angle, self.width, self.corner_radius, self.depth, self.profile_angle)

    # the cross-section ---------------------------------------------------------------------------
    def nose_centre(self) -> np.ndarray:
        """(2,) the nose (or cutting corner) centre S relative to P, (x, z) mm."""
        dx, dz = EDGE_POSITIONS[self.edge_position]
        return -np.array([dx, dz]) * self.radius

    def section(self, chord: float = 0.001) -> np.ndarray:
        """(m, 2) float: the insert's convex cross-section in the X–Z plane, ``(x, z)`` mm
        from P, counter-clockwise, its rounded corners within ``chord`` of their arcs."""
        key = (self.geometry_key(), float(chord))
        if key not in _SECTIONS:
            _SECTIONS[key] = _section(self, float(chord))
            _SECTIONS[key].flags.writeable = False
        return _SECTIONS[key]

    def holder_section(self) -> np.ndarray:
        """(4, 2) float: the holder's (or boring bar's) rectangle in the X–Z plane behind the
        insert, ``(x, z)`` mm from P, counter-clockwise: an external holder's shank beyond the
        insert along +X, flush with it on P's side in Z (as a PCLNR holder carries its insert
        at its corner); a boring bar along +Z from the insert."""
        sec = self.section()
        if self.kind == "boring" and self.bar_diameter > 0:
            # the bar runs along +Z behind the insert, its axis at the insert's middle in X
            xm = float(sec[:, 0].mean())
            z0 = float(sec[:, 1].max())
            h = self.bar_diameter / 2.0
            return np.array([[xm - h, z0], [xm + h, z0], [xm + h, z0 + self.bar_length],
                             [xm - h, z0 + self.bar_length]])
        x0 = float(sec[:, 0].max())
        dz = EDGE_POSITIONS[self.edge_position][1]
        w = self.holder_width
        z0 = (float(sec[:, 1].min()) if dz < 0 else float(sec[:, 1].max()) - w if dz > 0
              else float(sec[:, 1].mean()) - w / 2.0)       # flush with the insert on P's side
        return np.array([[x0, z0], [x0 + self.holder_length, z0], [x0 + self.holder_length, z0 + w],
                         [x0, z0 + w]])


def _sharp(tool: TurningTool) -> np.ndarray:
    """(k, 2) the insert's sharp polygon in the canonical pose (cutting corner pointing into
    the −X/−Z quadrant of SL 3, or toward −X for SL 5..9 and grooving/threading), sharp
    cutting corner at the origin, counter-clockwise."""
    if tool.kind == "grooving":
        w, d = tool.width, max(tool.depth, tool.width)
        return np.array([[0.0, -w / 2.0], [d, -w / 2.0], [d, w / 2.0], [0.0, w / 2.0]])
    if tool.kind == "threading":
        half = math.radians(tool.profile_angle) / 2.0
        h = max(tool.inscribed, 1.0)
        return np.array([[0.0, 0.0], [h, h * math.tan(half)], [h, -h * math.tan(half)]])
    eps_deg, corners = SHAPES[tool.shape]
    if corners == 0:
        return np.zeros((1, 2))
    eps = math.radians(eps_deg)
    if corners == 4:
        side = tool.inscribed / math.sin(eps)
        n = 2
    else:
        side = tool.inscribed * math.sqrt(3.0)
        n = 1
    if EDGE_POSITIONS[tool.edge_position][0] != 0 and EDGE_POSITIONS[tool.edge_position][1] != 0:
        a1 = math.radians(tool.lead_angle - 90.0)       # main edge from the corner, from +X toward +Z
    else:
        a1 = -eps / 2.0                                 # symmetric about X, the corner toward −X
    e1 = np.array([math.cos(a1), math.sin(a1)])
    e2 = np.array([math.cos(a1 + eps), math.sin(a1 + eps)])
    if n == 2:
        pts = [np.zeros(2), side * e1, side * (e1 + e2), side * e2]
    else:
        pts = [np.zeros(2), side * e1, side * e2]
    return np.array(pts)


def _arc_points(centre: np.ndarray, r: float, chord: float) -> np.ndarray:
    """(n, 2) points on the circle about ``centre`` of radius r, n a multiple of 4 from angle 0
    (so the extremes in ±x and ±z are among them), chords within ``chord``."""
    step = 2.0 * math.acos(max(-1.0, 1.0 - chord / r))
    n = 4 * max(2, math.ceil(2.0 * math.pi / max(step, 1e-6) / 4.0))
    ang = np.arange(n) * (2.0 * math.pi / n)
    return centre + r * np.column_stack([np.cos(ang), np.sin(ang)])


def hull2(points: np.ndarray) -> np.ndarray:
    """(h, 2) the convex hull of 2-D ``points`` (n, 2), counter-clockwise (monotone chain)."""
    pts = np.unique(np.round(np.asarray(points, dtype=float), 12), axis=0)
    if len(pts) < 3:
        return pts

    def chain(seq):
        out: list = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 1e-15:
                out.pop()
            out.append(p)
        return out

    lower, upper = chain(pts), chain(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _corner_centre(poly: np.ndarray, i: int, r: float) -> np.ndarray:
    """The centre of radius r tangent to both edges at corner i of a convex polygon (k, 2)."""
    p, a, b = poly[i], poly[i - 1], poly[(i + 1) % len(poly)]
    u, v = (a - p) / np.linalg.norm(a - p), (b - p) / np.linalg.norm(b - p)
    half = math.acos(float(np.clip(u @ v, -1.0, 1.0))) / 2.0
    bis = (u + v) / np.linalg.norm(u + v)
    return p + bis * r / math.sin(half)


def _rounded(poly: np.ndarray, r: float, corners: list[int], chord: float) -> tuple[np.ndarray, list]:
    """A convex polygon (k, 2) with ``corners`` rounded to radius r (arcs' points on the true
    circles, chords within ``chord``): (hull, the corners' centres)."""
    if r <= 0:
        return poly, [poly[i] for i in corners]
    centres = [_corner_centre(poly, i, r) for i in corners]
    keep = [poly[i] for i in range(len(poly)) if i not in corners]
    pts = np.concatenate([np.reshape(keep, (-1, 2))] + [_arc_points(c, r, chord) for c in centres])
    return hull2(pts), centres


def _section(tool: TurningTool, chord: float) -> np.ndarray:
    r = tool.radius
    if tool.kind in ("turning", "boring") and SHAPES[tool.shape][1] == 0:      # round insert
        return _placed(tool, _arc_points(np.zeros(2), r, chord), np.zeros(2), r)
    sharp = _sharp(tool)
    if tool.kind == "grooving":
        cut = [i for i in range(len(sharp)) if abs(sharp[i, 0]) < 1e-12]
        poly, centres = _rounded(sharp, r, cut, chord)
        centre = min(centres, key=lambda c: c[1])            # the −Z cutting corner's
        return _placed(tool, poly, np.asarray(centre), r)
    poly, centres = _rounded(sharp, r, [0], chord)
    return _placed(tool, poly, np.asarray(centres[0]), r)


def _placed(tool: TurningTool, poly: np.ndarray, centre: np.ndarray, r: float) -> np.ndarray:
    """The canonical polygon (cutting corner centre ``centre``) turned into the tool's edge
    position and moved so that P is the origin, counter-clockwise."""
    dx, dz = EDGE_POSITIONS[tool.edge_position]
    if dx != 0 and dz != 0:            # SL 1..4: the canonical SL 3 mirrored
        m = np.array([-dx, -dz])
        poly, centre = poly * m, centre * m
    elif (dx, dz) != (0.0, 0.0):
        # SL 5..8: the canonical insert points toward −X; turned to point along (dx, dz)
        ang = math.atan2(dz, dx) - math.pi
        c, s = math.cos(ang), math.sin(ang)
        rot = np.array([[c, -s], [s, c]])
        poly, centre = poly @ rot.T, rot @ centre
    return hull2(poly - (centre + np.array([dx, dz]) * r))


__all__ = ["EDGE_POSITIONS", "SHAPES", "TURNING_KINDS", "TurningTool", "hull2"]
