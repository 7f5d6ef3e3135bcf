"""Turning tools in a tool library file (:mod:`vmach.tooling.library`).

Format (lengths mm, angles degrees; see :mod:`vmach.tooling.turning` for the geometry)::

    [[tool]]
    name = "CNMG120408"
    number = 1
    type = "turning"             # turning | boring | grooving | threading
    shape = "C"                  # ISO shape letter (turning, boring)
    inscribed = 12.7             # inscribed circle IC (grooving/threading: insert length)
    thickness = 4.76
    nose_radius = 0.8
    clearance = 0.0              # the N of CNMG
    edge_position = 3            # cutting edge position SL 1..9
    lead_angle = 95.0            # holder's cutting edge angle κr
    holder = { width = 25.0, height = 25.0, length = 100.0 }
    bar = { diameter = 20.0, length = 150.0 }         # boring only
    width = 3.0                  # grooving: cutting width (corner_radius, depth)
    profile_angle = 60.0         # threading (pitch_min, pitch_max)
    [tool.d.1]
    length = 0.0                 # Sinumerik $TC_DP lengths are given per D as for milling tools
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from vmach.tooling.turning import EDGE_POSITIONS, SHAPES, TurningTool

KEYS = {
    "name", "number", "type", "shape", "inscribed", "thickness", "nose_radius", "clearance",
    "edge_position", "lead_angle", "holder", "bar", "width", "corner_radius", "depth",
    "profile_angle", "pitch_min", "pitch_max", "d", "comment",
}
_DEFAULT_SL = {"turning": 3, "boring": 2, "grooving": 3, "threading": 8}


def turning_tool(entry: Mapping[str, Any], where: tuple, lines, bad, num, offsets) -> TurningTool | None:
    """The :class:`TurningTool` of one ``[[tool]]`` entry, or None; problems go to ``bad(key,
    message)``. ``num`` and ``offsets`` are the library's number and D-table readers."""
    kind = entry["type"]
    for k in entry:
        if k not in KEYS:
            bad(where + (k,), f"unknown key {k!r} for a {kind} tool")
    name, number = name_number(entry, where, bad)
    if name is None:
        return None
    shape = entry.get("shape", "C")
    if kind in ("turning", "boring") and (not isinstance(shape, str) or shape not in SHAPES):
        bad(where + ("shape",), f"shape must be an ISO insert letter ({', '.join(SHAPES)}); got {shape!r}")
        return None
    sl = entry.get("edge_position", _DEFAULT_SL[kind])
    if isinstance(sl, bool) or not isinstance(sl, int | float) or sl not in EDGE_POSITIONS:
        bad(where + ("edge_position",), "edge_position must be an integer 1..9 (cutting edge position SL)")
        return None
    vals: dict[str, float] = {}
    defaults = {"inscribed": 12.7, "thickness": 4.76, "nose_radius": 0.8 if kind != "threading" else 0.05,
                "clearance": 0.0, "lead_angle": 95.0, "width": 0.0, "corner_radius": 0.0, "depth": 0.0,
                "profile_angle": 60.0, "pitch_min": 0.0, "pitch_max": 0.0}
    for k, d in defaults.items():
        v = num(entry, k, where, bad, d, positive=False)
        vals[k] = d if v is None else v
    if shape == "R" and kind in ("turning", "boring"):
        vals["nose_radius"] = vals["inscribed"] / 2.0
    if kind == "grooving" and vals["width"] <= 0:
        bad(where, "a grooving tool needs width > 0")
        return None
    if kind == "grooving" and not vals["corner_radius"] * 2 <= vals["width"]:
        bad(where + ("corner_radius",), "corner_radius must be at most width/2")
        return None
    if kind in ("turning", "boring") and shape != "R" and vals["nose_radius"] >= vals["inscribed"] / 2:
        bad(where + ("nose_radius",), "nose_radius must be smaller than inscribed/2")
        return None
    if not 0 < vals["profile_angle"] < 180 or not 0 < vals["lead_angle"] < 180:
        bad(where, "profile_angle and lead_angle must lie between 0 and 180 degrees")
        return None
    holder = _table(entry, "holder", ("width", "height", "length"), where, bad, num)
    bar = _table(entry, "bar", ("diameter", "length"), where, bad, num)
    if kind == "boring" and not bar.get("diameter"):
        bad(where, "a boring tool needs bar = { diameter = .., length = .. }")
        return None
    return TurningTool(
        name=name, kind=kind, number=number, shape=shape, inscribed=vals["inscribed"],
        thickness=vals["thickness"], nose_radius=vals["nose_radius"], clearance=vals["clearance"],
        edge_position=int(sl), lead_angle=vals["lead_angle"], width=vals["width"],
        corner_radius=vals["corner_radius"], depth=vals["depth"], profile_angle=vals["profile_angle"],
        pitch_min=vals["pitch_min"], pitch_max=vals["pitch_max"],
        holder_width=holder.get("width", 25.0), holder_height=holder.get("height", 25.0),
        holder_length=holder.get("length", 100.0 if kind != "boring" else 0.0),
        bar_diameter=bar.get("diameter", 0.0), bar_length=bar.get("length", 0.0),
        offsets=offsets(entry.get("d", {}), where, bad), source=lines.find(where))


def name_number(entry: Mapping[str, Any], where: tuple, bad) -> tuple[str | None, int | None]:
    """A tool entry's stripped name (None, told to ``bad``, when it is no non-empty string) and
    number (None when absent or not an integer >= 0, told)."""
    name = entry.get("name")
    if not isinstance(name, str) or not name.strip():
        bad(where + ("name",) if "name" in entry else where, "name must be a non-empty string")
        return None, None
    number = entry.get("number")
    if number is not None and (isinstance(number, bool) or not isinstance(number, int) or number < 0):
        bad(where + ("number",), "number must be an integer >= 0")
        number = None
    return name.strip(), number


def _table(entry, key: str, keys: tuple[str, ...], where: tuple, bad, num) -> dict[str, float]:
    part = entry.get(key)
    if part is None:
        return {}
    if not isinstance(part, Mapping):
        bad(where + (key,), f"{key} must be a table {{ {' = .., '.join(keys)} = .. }}")
        return {}
    out = {}
    for k in part:
        if k not in keys:
            bad(where + (key, k), f"{key}: unknown key {k!r}")
    for k in keys:
        v = num(part, k, where + (key,), bad, None, positive=False)
        if v is not None:
            out[k] = v
    return out
