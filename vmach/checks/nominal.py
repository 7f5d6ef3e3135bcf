"""Nominal parts made from a polygon profile: the design of a polygon-shaft end, as a mesh.

A polygon shaft's design is made, not drawn (domain.md §4): the DIN 32711 / 32712 profile
(:mod:`vmach.checks.polygon`) runs from the shaft's end face (Z = 0, the workpiece frame of the
fixture programs) to Z = −length, with a lead-in chamfer at the end (``angle`` from the axis
over ``chamfer_length`` along it: the flanks offset inward by ``(chamfer_length − |z|)·tan
angle`` — the envelope of ``h(α) − δ``, the profile's parallel curve) and a shoulder behind it:
a flat face at Z = −length out to a cylinder of ``shoulder_diameter`` that runs
``shoulder_length`` further. The profile is turned by ``phase`` about Z as
:meth:`Polygon.curve` turns it (the polygon-shaft programs, X = d1/2 − e1·sin 3C, make phase 30°).

    v, f = shaft_mesh(parse_profile("P3G:50"), ShaftDesign(length=40, chamfer=(15, 3),
                      shoulder=(60, 60), phase_deg=30))
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vmach.checks.polygon import Polygon
from vmach.errors import InputError

#: normal directions around the profile: a chord's sagitta ρ·(2π/n)²/8 stays under 0.1 µm
#: for ρ up to 40 mm
SEGMENTS = 1440


@dataclass(frozen=True)
class ShaftDesign:
    """The shaft end around a polygon profile, mm and degrees.

    length : polygon length from the end face (Z = 0) to the shoulder (Z = −length).
    chamfer : (angle from the axis, axial length) of the lead-in chamfer, or None.
    shoulder : (diameter, length) of the cylinder behind the shoulder face, or None (the
        polygon then ends in a flat face at Z = −length).
    phase_deg : turn of the profile about Z.
    """

    length: float
    chamfer: tuple[float, float] | None = None
    shoulder: tuple[float, float] | None = None
    phase_deg: float = 0.0


def parse_pair(text: str, what: str, sep: str = ":") -> tuple[float, float]:
    """``"15x3"`` / ``"60:60"`` → (15.0, 3.0); an InputError naming ``what`` otherwise."""
    parts = text.replace("×", sep).replace("x", sep).replace("X", sep).split(sep)
    try:
        a, b = (float(p) for p in parts)
    except ValueError:
        raise InputError(f"{what} {text!r}: expected two numbers, e.g. 15x3", kind="usage") from None
    if not (math.isfinite(a) and math.isfinite(b) and a > 0 and b > 0):
        raise InputError(f"{what} {text!r}: both numbers must be positive", kind="usage")
    return a, b


def shaft_mesh(profile: Polygon, design: ShaftDesign, segments: int = SEGMENTS
               ) -> tuple[np.ndarray, np.ndarray]:
    """The nominal shaft end as a closed, outward-oriented triangle mesh: vertices (n, 3)
    float, mm and faces (m, 3) int64."""
    length = design.length
    if not (math.isfinite(length) and length > 0):
        raise InputError("--length must be a positive length, mm", kind="usage")
    alpha = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    phase = math.radians(design.phase_deg)

    def ring(delta: float) -> np.ndarray:                       # the profile moved in by delta
        a = np.asarray(alpha)
        h, dh = profile.h(a) - delta, profile.dh(a)
        xy = np.stack([h * np.cos(a) - dh * np.sin(a), h * np.sin(a) + dh * np.cos(a)], axis=1)
        if profile.outer is not None:                            # P4C: the corners' circle
            r = np.hypot(xy[:, 0], xy[:, 1])
            xy *= np.minimum(1.0, (profile.outer - delta) / r)[:, None]
        c, s = math.cos(phase), math.sin(phase)
        return xy @ np.array([[c, s], [-s, c]])

    rings: list[tuple[float, np.ndarray]] = []
    if design.chamfer is not None:
        angle, axial = design.chamfer
        if not (0 < angle < 90 and axial < length):
            raise InputError(f"--chamfer {angle:g}x{axial:g}: the angle lies between 0 and 90°, "
                             f"the length under the polygon's {length:g} mm", kind="usage")
        rings.append((0.0, ring(axial * math.tan(math.radians(angle)))))
        rings.append((-axial, ring(0.0)))
    else:
        rings.append((0.0, ring(0.0)))
    rings.append((-length, ring(0.0)))
    if design.shoulder is not None:
        diameter, behind = design.shoulder
        outer = rings[-1][1]
        if diameter / 2 <= float(np.hypot(outer[:, 0], outer[:, 1]).max()):
            raise InputError(f"--shoulder {diameter:g}: the shoulder's diameter must exceed the "
                             f"profile's {profile.d2:g} mm", kind="usage")
        theta = np.arctan2(outer[:, 1], outer[:, 0])            # the circle at the ring's angles
        circle = diameter / 2 * np.stack([np.cos(theta), np.sin(theta)], axis=1)
        rings.append((-length, circle))
        rings.append((-length - behind, circle))
    return _stack(rings)


def _stack(rings: list[tuple[float, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """Closed mesh of rings (z, (n, 2) counter-clockwise) from the top down, joined by bands,
    capped by a fan at each end."""
    n = len(rings[0][1])
    verts = [np.column_stack([xy, np.full(n, z)]) for z, xy in rings]
    top, bottom = len(rings) * n, len(rings) * n + 1
    v = np.vstack(verts + [[0.0, 0.0, rings[0][0]], [0.0, 0.0, rings[-1][0]]])
    i = np.arange(n)
    j = (i + 1) % n
    faces = [np.column_stack([np.full(n, top), i, j])]             # the end face, seen from +Z
    for k in range(len(rings) - 1):
        a, b = k * n, (k + 1) * n
        faces.append(np.column_stack([a + i, b + i, b + j]))
        faces.append(np.column_stack([a + i, b + j, a + j]))
    last = (len(rings) - 1) * n
    faces.append(np.column_stack([np.full(n, bottom), last + j, last + i]))
    return v, np.vstack(faces).astype(np.int64)
