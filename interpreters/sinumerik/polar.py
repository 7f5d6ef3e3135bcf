"""Polar coordinates: the pole (G110 / G111 / G112) and moves by polar angle AP= and polar
radius RP= in the working plane (Programming Manual Fundamentals, "Polar coordinates").

Program coordinates, mm and degrees; AP is measured from the plane's first axis (X for G17,
Z for G18, Y for G19) toward its second.

- ``G111 X.. Y..`` puts the pole at that point of the workpiece coordinate system, ``G110``
  that far from the last programmed position, ``G112`` from the last pole; ``AP= RP=`` in the
  pole block give the offset in polar form instead. Without a pole the origin is the pole.
- ``G1 AP=.. RP=..`` moves to pole + RP·(cos AP, sin AP); a value left out is the current
  position's (``AP=45`` alone turns about the pole at the present radius), ``AP=IC(..)`` adds to
  the present angle. Other axes (Z) may move in the same block; the plane's own axes may not.
  ``G2/G3 AP= RP=`` turn about the pole.
"""

from __future__ import annotations

import math

from interpreters.sinumerik import blocks as b
from vmach.errors import ProgramError
from vmach.source import SourceRef

POLES = ("G110", "G111", "G112")


def plane_point(machine) -> tuple[float, float]:
    """The last programmed position in the plane, program coordinates (mm)."""
    g = machine.geometry
    p = machine.program_point()
    a, c = machine.plane_axes[:2]
    return (p[g.index(a)], p[g.index(c)])


def set_pole(machine, code: str, values: dict, src: SourceRef) -> None:
    """A pole block: ``values`` its plane-axis and AP/RP values as written."""
    scale = 25.4 if machine.inch else 1.0
    a, c = machine.plane_axes[:2]
    others = [k for k in values if k not in (a, c, "AP", "RP")]
    if others:
        raise ProgramError("syntax", f"{code}: give the pole in {a}/{c} or AP=/RP=, not {others[0]}", src)
    base = {"G111": (0.0, 0.0), "G110": plane_point(machine), "G112": pole(machine)}[code]
    if "AP" in values or "RP" in values:
        if a in values or c in values:
            raise ProgramError("syntax", f"{code}: the pole in {a}/{c} or in AP=/RP=, not both", src)
        ang, r = math.radians(values.get("AP", 0.0)), values.get("RP", 0.0) * scale
        machine.pole = (base[0] + r * math.cos(ang), base[1] + r * math.sin(ang))
    else:
        da, dc = values.get(a, 0.0) * scale, values.get(c, 0.0) * scale
        if machine.diameter and a == (machine.control.transverse or "X"):
            da /= 2.0
        if machine.diameter and c == (machine.control.transverse or "X"):
            dc /= 2.0
        machine.pole = (base[0] + da, base[1] + dc)


def pole(machine) -> tuple[float, float]:
    return machine.pole if machine.pole is not None else (0.0, 0.0)


def words(machine, polar: dict, axes, src: SourceRef) -> list:
    """The block's axis words with AP/RP turned into plane-axis words (absolute program
    values in the block's units)."""
    a, c = machine.plane_axes[:2]
    for word, _ in axes:
        if word.name in (a, c):
            raise ProgramError("syntax", f"{word.name} and AP=/RP= in one block: the end point in the "
                               "plane is given twice", src.at(word.col))
    scale = 25.4 if machine.inch else 1.0
    centre = pole(machine)
    here = plane_point(machine)
    dx, dy = here[0] - centre[0], here[1] - centre[1]
    ang = math.degrees(math.atan2(dy, dx)) if (dx or dy) else 0.0
    r = math.hypot(dx, dy)
    if "AP" in polar:
        value, mode = polar["AP"]
        ang = ang + value if mode == "IC" else value
    if "RP" in polar:
        value, mode = polar["RP"]
        r = r + value * scale if mode == "IC" else value * scale
        if r < 0:
            raise ProgramError("invalid_value", f"RP={value}: a negative polar radius", src)
    t = math.radians(ang)
    pa, pc = centre[0] + r * math.cos(t), centre[1] + r * math.sin(t)
    out = list(axes)
    for name, v in ((a, pa), (c, pc)):
        if machine.diameter and name == (machine.control.transverse or "X"):
            v *= 2.0                  # the word is read as a diameter
        out.append((b.Word(src.column, name, "axis", None, None, "AC"), v / scale))
    return out
