"""Flywheel (multi-insert) cutters for polygonal turning.

A flywheel cutter carries ``inserts`` equal inserts on a circle: each insert's tip lies at the
**cutting radius** ``radius`` from the cutter's axis, the inserts ``360°/inserts`` apart. In
polygonal turning the cutter's axis stands parallel to the workpiece's, on the tool spindle,
and the tool spindle is coupled to the main spindle at a ratio (Sinumerik ``COUPDEF``/
``COUPON``): what the work loses is the region the inserts sweep relative to the turning work
(:mod:`vmach.stock.strategies.polygonal`).

Conventions (lengths mm, angles degrees):

- The tool's **point P** — what the control moves along the programmed X/Z — is insert tip
  circle's point nearest the workpiece axis, at the cutters' front (−Z) end: so X (a radius) is
  the closest approach of the tips to the work axis, the cutter's centre lies ``radius``
  beyond P along machine +X, and the inserts' cutting edges run ``width`` from P toward +Z.
- An insert's section in the plane across the cutter's axis (:meth:`FlywheelTool.insert_section`)
  is the corner of an ISO insert (``shape``: corner angle ε of :data:`vmach.tooling.turning.SHAPES`,
  or ``R`` round) of ``nose_radius``, pointing radially outward, symmetric about its radial
  line, reaching ``inscribed`` back toward the axis. Real polygon inserts are asymmetric (rake
  face radial, relief behind); near the flank only the tip's arc cuts, which this keeps exact.
- ``counter``: the holder's gearing turns the cutter against the work for a positive coupling
  ratio (default false: the same way round, the usual set-up, which gives the polygon shapes of
  domain §6).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from vmach.source import SourceRef
from vmach.tooling.model import Offset
from vmach.tooling.turning import SHAPES, hull2
from vmach.tooling.turning_toml import name_number

KEYS = {"name", "number", "type", "inserts", "radius", "shape", "inscribed", "nose_radius", "width",
        "body_diameter", "counter", "d", "comment"}


@dataclass(frozen=True)
class FlywheelTool:
    """A multi-insert flywheel cutter (module docstring for the conventions).

    inserts : int >= 1. radius : float, mm — cutting radius (axis to insert tip).
    shape : ISO letter of the inserts' corner (``SHAPES``). inscribed : mm, how far the insert
    reaches back from its tip. nose_radius : mm. width : mm, the cutting edges' length along
    the cutter's axis. body_diameter : mm, the cutter body's (hub's) diameter (at most the
    insert's back). counter : bool (module docstring). name, number, offsets, source : as
    :class:`vmach.tooling.model.Tool`.
    """

    name: str
    inserts: int
    radius: float
    number: int | None = None
    shape: str = "T"
    inscribed: float = 6.0
    nose_radius: float = 0.2
    width: float = 10.0
    body_diameter: float = 0.0
    counter: bool = False
    offsets: Mapping[int, Offset] = field(default_factory=dict)
    source: SourceRef | None = None

    polygon = True      # cuts polygons when its spindle is coupled to the main spindle
    kind = "flywheel"

    @property
    def teeth(self) -> int:
        return self.inserts

    @property
    def diameter(self) -> float:
        return 2.0 * self.radius

    @property
    def cutting_length(self) -> float:
        return self.width

    def length(self, d: int | None) -> float:
        if not d:
            return 0.0
        off = self.offsets.get(int(d))
        return off.length if off else 0.0

    def stack(self) -> list[tuple[str, float, float, float]]:
        """A cylinder along the tool direction (+X from P) that holds the cutter for the checks
        that only know cylinders: the cutter disc (2·radius across, ``width`` thick, its axis
        along Z) lies within a cylinder of length 2·radius and radius max(radius, width)
        about the line through P and the cutter's centre (an envelope, not the shape)."""
        return [("cutter", 0.0, 2.0 * self.radius, max(self.radius, self.width, 0.1))]

    def geometry_key(self) -> tuple:
        return ("flywheel", self.inserts, self.radius, self.shape, self.inscribed, self.nose_radius,
                self.width, self.counter)

    def reach(self) -> float:
        """mm: the farthest any point of an insert lies from the cutter's axis (its tip)."""
        return self.radius

    def insert_section(self, chord: float = 0.001) -> np.ndarray:
        """(m, 2) float: one insert's convex section across the cutter's axis, ``(u, v)`` mm in
        the cutter's frame — its axis at the origin, the tip at ``(radius, 0)`` — the nose arc's
        points on the true circle with chords within ``chord``, counter-clockwise."""
        eps_deg, corners = SHAPES[self.shape]
        rn, back = self.nose_radius, self.inscribed
        centre = np.array([self.radius - rn, 0.0])
        if corners == 0:                                  # round insert: a circle of nose_radius
            return hull2(centre + _arc(rn, -math.pi, math.pi, chord))
        half = math.radians(eps_deg) / 2.0
        spread = math.pi / 2.0 - half                     # the nose arc's half angle
        pts = [centre + _arc(rn, -spread, spread, chord)]
        # the two edges, tangent to the nose, running back toward the axis
        for s in (-1.0, 1.0):
            t = centre + rn * np.array([math.cos(s * spread), math.sin(s * spread)])
            d = np.array([-math.cos(half), s * math.sin(half)])
            pts.append((t + back * d)[None])
        return hull2(np.concatenate(pts))


def _arc(r: float, a0: float, a1: float, chord: float) -> np.ndarray:
    """(n, 2) points at radius r from angle a0 to a1 (rad), chords' sag within ``chord``, the
    middle angle among them."""
    if r <= 0:
        return np.zeros((1, 2))
    step = 2.0 * math.acos(max(-1.0, 1.0 - chord / r))
    n = max(3, math.ceil((a1 - a0) / max(step, 1e-6)) + 1)
    n += 1 - n % 2                  # odd: the arc's middle (the insert's tip) is a vertex
    a = np.linspace(a0, a1, n)
    return r * np.column_stack([np.cos(a), np.sin(a)])


def flywheel_tool(entry: Mapping, where: tuple, lines, bad, num, offsets) -> FlywheelTool | None:
    """The :class:`FlywheelTool` of one ``[[tool]]`` entry of ``type = "flywheel"``, or None;
    problems go to ``bad(key, message)`` (``num``, ``offsets``: the library's readers)."""
    for k in entry:
        if k not in KEYS:
            bad(where + (k,), f"unknown key {k!r} for a flywheel tool")
    name, number = name_number(entry, where, bad)
    if name is None:
        return None
    inserts = entry.get("inserts")
    if isinstance(inserts, bool) or not isinstance(inserts, int) or not 1 <= inserts <= 24:
        bad(where + ("inserts",), "inserts must be an integer 1..24 (the flywheel's insert count)")
        return None
    shape = entry.get("shape", "T")
    if not isinstance(shape, str) or shape not in SHAPES:
        bad(where + ("shape",), f"shape must be an ISO insert letter ({', '.join(SHAPES)}); got {shape!r}")
        return None
    counter = entry.get("counter", False)
    if not isinstance(counter, bool):
        bad(where + ("counter",), "counter must be true or false")
        return None
    vals = {}
    for k, d in {"radius": None, "inscribed": 6.0, "nose_radius": 0.2, "width": 10.0,
                 "body_diameter": 0.0}.items():
        v = num(entry, k, where, bad, d, positive=k in ("radius", "inscribed", "width"))
        if v is None:
            if d is None:
                bad(where, "a flywheel tool needs its cutting radius: radius = ..")
            return None
        vals[k] = float(v)
    if vals["nose_radius"] < 0 or vals["nose_radius"] >= vals["inscribed"] / 2.0:
        bad(where + ("nose_radius",), "nose_radius must lie in [0, inscribed/2)")
        return None
    if vals["inscribed"] >= vals["radius"]:
        bad(where + ("inscribed",), "inscribed must be smaller than radius (the insert lies on the cutter)")
        return None
    if vals["body_diameter"] / 2.0 > vals["radius"] - vals["inscribed"] + 1e-9:
        bad(where + ("body_diameter",), "the body must lie inside the inserts (body_diameter/2 <= "
                                        "radius - inscribed)")
        return None
    return FlywheelTool(name=name, inserts=int(inserts), radius=vals["radius"], number=number,
                        shape=shape, inscribed=vals["inscribed"], nose_radius=vals["nose_radius"],
                        width=vals["width"], body_diameter=vals["body_diameter"], counter=counter,
                        offsets=offsets(entry.get("d", {}), where, bad), source=lines.find(where))


__all__ = ["FlywheelTool", "flywheel_tool"]
