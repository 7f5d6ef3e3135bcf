"""Cutting tools as profiles: radius as a function of height along the tool axis.

OpenCAMLib describes a cutter by its profile; so does vmach. A :class:`Tool` gives the half
section of its cutting part as a polyline ``(z, r)`` — ``z`` along the tool axis from the tip
(z = 0) toward the holder, ``r`` the radius — and the solid is that polyline revolved about the
axis (:mod:`vmach.tooling.solid`). Shank and holder are plain cylinders behind the cutting part;
stock removal uses the cutting part only, the verify stage checks shank and holder for contact.

Kinds and their parameters (lengths mm, angles degrees):

============  =============================================================================
``flat``      flat end mill: ``diameter``; flat end face, cylindrical side
``face``      face/shell mill with ``inserts``: like ``flat``; ``cutting_length`` is the
              largest depth of cut (insert edge length)
``ball``      ball end mill: hemispherical end of radius ``diameter``/2
``bull``      bull-nose (torus) end mill: ``corner_radius``
``chamfer``   chamfer mill: cone of included ``point_angle`` from a tip of ``tip_diameter``
              up to ``diameter``, then cylindrical
``drill``     twist drill: cone of included ``point_angle`` (118° usual), then cylindrical
============  =============================================================================
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from vmach.source import SourceRef

KINDS = ("flat", "face", "ball", "bull", "chamfer", "drill", "probe")


@dataclass(frozen=True, slots=True)
class Offset:
    """One tool offset (Sinumerik D number): geometry length and radius, wear included, mm."""

    length: float = 0.0
    radius: float | None = None


@dataclass(frozen=True)
class Tool:
    """A cutter with its shank and holder.

    name : str
        Name as the program calls it (``T="GLOD D40"``).
    number : int or None
        Tool number (``T1``).
    kind : str
        One of :data:`KINDS`.
    diameter : float, mm
        Cutting diameter.
    cutting_length : float, mm
        Length of the cutting part from the tip.
    corner_radius : float, mm
        ``bull`` only.
    point_angle : float, degrees
        ``chamfer`` and ``drill``: included angle of the cone (90 for a 45° chamfer mill).
    tip_diameter : float, mm
        ``chamfer``: diameter of the flat at the tip.
    teeth : int
        Flutes or inserts.
    shank_diameter, shank_length : float, mm
        Cylinder behind the cutting part (0 length: none).
    holder_diameter, holder_length : float, mm
        Cylinder behind the shank.
    offsets : mapping int -> Offset
        D numbers.
    source : SourceRef or None
        Where the tool is defined.
    """

    name: str
    kind: str
    diameter: float
    cutting_length: float
    number: int | None = None
    corner_radius: float = 0.0
    point_angle: float = 180.0
    tip_diameter: float = 0.0
    teeth: int = 0
    shank_diameter: float = 0.0
    shank_length: float = 0.0
    holder_diameter: float = 0.0
    holder_length: float = 0.0
    offsets: Mapping[int, Offset] = field(default_factory=dict)
    source: SourceRef | None = None

    @property
    def radius(self) -> float:
        return self.diameter / 2.0

    def profile(self, chord: float = 0.002) -> np.ndarray:
        """Half section of the cutting part.

        Returns
        -------
        (m, 2) float, mm
            ``(z, r)`` from the tip on the axis (r = 0) around to the top on the axis, arcs
            broken into segments whose sagitta is at most ``chord``.
        """
        R, L = self.radius, self.cutting_length
        pts: list[tuple[float, float]] = [(0.0, 0.0)]
        if self.kind in ("flat", "face"):
            pts.append((0.0, R))
        elif self.kind in ("ball", "probe"):     # a touch probe: its stylus ball
            for a in _arc_angles(R, math.pi / 2, chord)[1:]:
                pts.append((R - R * math.cos(a), R * math.sin(a)))
        elif self.kind == "bull":
            rc = self.corner_radius
            pts.append((0.0, R - rc))
            for a in _arc_angles(rc, math.pi / 2, chord)[1:]:
                pts.append((rc - rc * math.cos(a), R - rc + rc * math.sin(a)))
        elif self.kind in ("chamfer", "drill"):
            half = math.radians(self.point_angle) / 2.0
            r0 = self.tip_diameter / 2.0 if self.kind == "chamfer" else 0.0
            if r0 > 0:
                pts.append((0.0, r0))
            pts.append(((R - r0) / math.tan(half), R))
        else:  # pragma: no cover - the loader rejects other kinds
            raise ValueError(f"unknown tool kind {self.kind!r}")
        if pts[-1][0] < L:
            pts.append((L, R))
        pts.append((max(L, pts[-1][0]), 0.0))
        return np.asarray(pts, dtype=float)

    def geometry_key(self) -> tuple:
        """Hashable key of everything that shapes the cutting part (for caches)."""
        return (self.kind, self.diameter, self.cutting_length, self.corner_radius,
                self.point_angle, self.tip_diameter)

    def cone_height(self) -> float:
        """Axial length of the non-cylindrical end (0 for flat and face mills), mm."""
        prof = self.profile()
        full = np.nonzero(np.isclose(prof[:, 1], self.radius))[0]
        return float(prof[full[0], 0]) if len(full) else self.cutting_length

    def stack(self) -> list[tuple[str, float, float, float]]:
        """The tool as cylinders along its axis from the tip: ``(part, z0, z1, radius)`` mm for
        the cutting part, the shank and the holder (parts of zero size left out)."""
        out = [("cutter", 0.0, self.cutting_length, self.radius)]
        z = self.cutting_length
        for part, d, length in (("shank", self.shank_diameter, self.shank_length),
                                ("holder", self.holder_diameter, self.holder_length)):
            if length > 0 and d > 0:
                out.append((part, z, z + length, d / 2.0))
                z += length
        return out

    def length(self, d: int | None) -> float:
        """Length offset of edge ``d`` (0 when the edge is not defined or ``d`` is None/0)."""
        if not d:
            return 0.0
        off = self.offsets.get(int(d))
        return off.length if off else 0.0


def _arc_angles(radius: float, sweep: float, chord: float) -> np.ndarray:
    """Angles 0..sweep with segment sagitta <= chord on a circle of ``radius``."""
    if radius <= 0:
        return np.array([0.0, sweep])
    step = 2.0 * math.acos(max(-1.0, 1.0 - chord / radius))
    n = max(2, math.ceil(sweep / max(step, 1e-6)))
    return np.linspace(0.0, sweep, n + 1)
