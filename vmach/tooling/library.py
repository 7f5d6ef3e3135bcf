"""Tool library files (``--tools FILE.toml``).

Format (every length in mm, angles in degrees)::

    [[tool]]
    name = "GLOD D40"          # as the program calls it: T="GLOD D40"
    number = 1                 # T1 (optional)
    type = "face"              # flat | face | ball | bull | chamfer | drill | probe
                               # (probe: a touch probe, diameter = its stylus ball's,
                               # cutting_length = the stylus; it removes no material)
                               # (turning | boring | grooving | threading: vmach.tooling.turning_toml;
                               # flywheel: vmach.tooling.flywheel)
    diameter = 40.0
    cutting_length = 5.5
    teeth = 4                  # flutes or inserts (optional)
    corner_radius = 0.8        # bull only
    point_angle = 150.0        # chamfer, drill: included cone angle
    tip_diameter = 0.0         # chamfer: flat at the tip
    shank = { diameter = 22.0, length = 40.0 }
    holder = { diameter = 63.0, length = 60.0 }
    [tool.d.1]                 # D1
    length = 0.0               # length offset
    radius = 20.0              # radius offset (optional; defaults to diameter/2)

Loading collects every problem, each at its file and line, into one
:class:`vmach.errors.ModelError`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from vmach.errors import ModelError
from vmach.findings import Finding, error
from vmach.machine.control import parse_toml, read_text
from vmach.machine.tomlpos import KeyLines
from vmach.tol import tol
from vmach.tooling.flywheel import flywheel_tool
from vmach.tooling.model import KINDS, Offset, Tool
from vmach.tooling.turning import TURNING_KINDS, TurningTool
from vmach.tooling.turning_toml import turning_tool

_KEYS = {
    "name", "number", "type", "diameter", "cutting_length", "teeth", "corner_radius",
    "point_angle", "tip_diameter", "shank", "holder", "d", "comment",
}
_REQUIRED = ("name", "type", "diameter", "cutting_length")


@dataclass(frozen=True)
class ToolLibrary:
    """Tools by name and number.

    tools : tuple of Tool (or TurningTool), in file order.
    path : str — the file it came from.
    """

    tools: tuple[Tool | TurningTool, ...] = ()
    path: str = "<tools>"
    _by_name: Mapping[str, Tool] = field(default_factory=dict, repr=False)
    _by_number: Mapping[int, Tool] = field(default_factory=dict, repr=False)

    @classmethod
    def of(cls, tools: Iterable[Tool], path: str = "<tools>") -> ToolLibrary:
        tools = tuple(tools)
        by_name = {t.name.upper(): t for t in tools}
        by_number = {t.number: t for t in tools if t.number is not None}
        return cls(tools, path, by_name, by_number)

    def lookup(self, tool: str | int) -> Tool | None:
        """The tool a program calls: a name (``"GLOD D40"``, case-insensitive) or a number
        (``1`` or ``"1"``, as :class:`vmach.canon.ToolChange` carries it). None if absent."""
        if isinstance(tool, int):
            return self._by_number.get(tool)
        text = str(tool).strip()
        found = self._by_name.get(text.upper())
        if found is None and text.isdigit():
            found = self._by_number.get(int(text))
        return found

    def radius(self, tool: str | int, d: int) -> float | None:
        """Radius (mm) of offset D``d`` of the tool a program calls, for tool radius
        compensation: the offset's radius, else half the diameter; a tool without offsets has
        D1. None when the tool or the offset is not in the library."""
        found = self.lookup(tool)
        if found is None:
            return None
        if not found.offsets:
            return found.diameter / 2.0 if d == 1 else None
        off = found.offsets.get(int(d))
        if off is None:
            return None
        return off.radius if off.radius is not None else found.diameter / 2.0

    def data(self, tool: str | int, d: int) -> dict[str, float | str] | None:
        """The control's tool data of offset D``d`` (Sinumerik ``$TC_DP``/``$TC_TP``): ``name``,
        ``type`` (a library kind), ``length`` and ``radius`` (mm), ``teeth``; a turning tool also its
        ``edge_position`` (SL 1..9). None when the tool
        or the offset is not in the library."""
        found = self.lookup(tool)
        radius = self.radius(tool, d)
        if found is None or radius is None:
            return None
        off = found.offsets.get(int(d))
        out = {"name": found.name, "type": found.kind, "length": off.length if off is not None else 0.0,
               "radius": radius, "teeth": found.teeth}
        if getattr(found, "edge_position", None) is not None:   # a turning tool: its cutting edge
            out["edge_position"] = found.edge_position            # position (SL 1..9)
        return out

    def __getitem__(self, tool: str | int) -> Tool:
        found = self.lookup(tool)
        if found is None:
            raise KeyError(tool)
        return found

    def __len__(self) -> int:
        return len(self.tools)

    def __contains__(self, tool: object) -> bool:
        return isinstance(tool, (str, int)) and self.lookup(tool) is not None


def load_tools(path: str | Path) -> ToolLibrary:
    """Read a tool library file; every problem is reported at once as ModelError."""
    text = read_text(path)
    return parse_tools(parse_toml(text, str(path)), KeyLines.scan(text, str(path)))


def parse_tools(data: Mapping[str, Any], lines: KeyLines) -> ToolLibrary:
    """Tools of a parsed library; ``lines`` locates keys for the problems."""
    problems: list[Finding] = []

    def bad(key: tuple, msg: str) -> None:
        problems.append(error("tool_library", msg, lines.find(key)))

    for key in data:
        if key != "tool":
            bad((key,), f"unknown top-level key {key!r} (tools are [[tool]] tables)")
    raw = data.get("tool", [])
    if not isinstance(raw, list):
        bad(("tool",), "'tool' must be an array of tables: write [[tool]]")
        raw = []
    tools: list[Tool] = []
    names: dict[str, int] = {}
    numbers: dict[int, int] = {}
    for i, entry in enumerate(raw):
        before = len(problems)
        tool = _one(entry, i, lines, bad)
        if tool is None or len(problems) > before:
            continue
        if tool.name.upper() in names:
            bad(("tool", i, "name"), f"tool {tool.name!r} is defined twice")
            continue
        if tool.number is not None and tool.number in numbers:
            bad(("tool", i, "number"), f"tool number {tool.number} is used twice")
            continue
        names[tool.name.upper()] = i
        if tool.number is not None:
            numbers[tool.number] = i
        tools.append(tool)
    if problems:
        raise ModelError(problems)
    return ToolLibrary.of(tools, lines.path)


def _num(entry: Mapping[str, Any], key: str, where: tuple, bad, default=None, positive=True):
    if key not in entry:
        return default
    v = entry[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        bad(where + (key,), f"{key} must be a number")
        return default
    if positive and v < tol.min_size:              # 1e-300 divides by zero in the polygons
        bad(where + (key,), f"{key} must be at least {tol.min_size:g}" if v > 0 else f"{key} must be > 0")
        return default
    if not positive and v < 0:
        bad(where + (key,), f"{key} must be >= 0")
        return default
    if abs(v) > tol.max_size:
        bad(where + (key,), f"{key} = {v:g} mm is larger than any machine ({tol.max_size:g} mm)")
        return default
    return float(v)


def _cylinder(entry: Mapping[str, Any], key: str, where: tuple, bad) -> tuple[float, float]:
    part = entry.get(key)
    if part is None:
        return 0.0, 0.0
    if not isinstance(part, Mapping):
        bad(where + (key,), f"{key} must be a table {{ diameter = .., length = .. }}")
        return 0.0, 0.0
    for k in part:
        if k not in ("diameter", "length"):
            bad(where + (key, k), f"{key}: unknown key {k!r}")
    d = _num(part, "diameter", where + (key,), bad, 0.0)
    length = _num(part, "length", where + (key,), bad, 0.0, positive=False)
    return d, length


def _one(entry: Any, i: int, lines: KeyLines, bad) -> Tool | None:
    where = ("tool", i)
    if not isinstance(entry, Mapping):
        bad(where, "each tool must be a table")
        return None
    if entry.get("type") in TURNING_KINDS:
        return turning_tool(entry, where, lines, bad, _num, _offsets)
    if entry.get("type") == "flywheel":       # polygonal turning (vmach.tooling.flywheel)
        return flywheel_tool(entry, where, lines, bad, _num, _offsets)
    for k in entry:
        if k not in _KEYS:
            bad(where + (k,), f"unknown key {k!r}")
    for k in _REQUIRED:
        if k not in entry:
            bad(where, f"tool {i + 1}: missing {k!r}")
    name = entry.get("name")
    if "name" in entry and (not isinstance(name, str) or not name.strip()):
        bad(where + ("name",), "name must be a non-empty string")
        name = None
    kind = entry.get("type")
    if "type" in entry and kind not in KINDS:
        known = ", ".join(KINDS + TURNING_KINDS + ("flywheel",))
        bad(where + ("type",), f"type must be one of {known}; got {kind!r}")
        kind = None
    number = entry.get("number")
    if number is not None and (isinstance(number, bool) or not isinstance(number, int) or number < 0):
        bad(where + ("number",), "number must be an integer >= 0")
        number = None
    dia = _num(entry, "diameter", where, bad)
    length = _num(entry, "cutting_length", where, bad)
    corner = _num(entry, "corner_radius", where, bad, 0.0, positive=False)
    point = _num(entry, "point_angle", where, bad, 118.0 if kind == "drill" else 90.0)
    tip = _num(entry, "tip_diameter", where, bad, 0.0, positive=False)
    teeth = entry.get("teeth", 0)
    if isinstance(teeth, bool) or not isinstance(teeth, int) or teeth < 0:
        bad(where + ("teeth",), "teeth must be an integer >= 0")
        teeth = 0
    shank = _cylinder(entry, "shank", where, bad)
    holder = _cylinder(entry, "holder", where, bad)
    if point is not None and not 0 < point < 180:
        bad(where + ("point_angle",), "point_angle must lie between 0 and 180 degrees")
    if kind == "bull":
        if "corner_radius" not in entry:
            bad(where, "a bull-nose tool needs corner_radius")
        elif dia is not None and corner is not None and not 0 < corner <= dia / 2:
            bad(where + ("corner_radius",), "corner_radius must be > 0 and <= diameter/2")
    if kind == "chamfer" and dia is not None and tip is not None and tip >= dia:
        bad(where + ("tip_diameter",), "tip_diameter must be smaller than diameter")
    if kind in ("ball", "probe") and dia is not None and length is not None and length < dia / 2:
        bad(where + ("cutting_length",), "a ball end mill's cutting_length must reach diameter/2")
    offsets = _offsets(entry.get("d", {}), where, bad)
    if None in (name, kind, dia, length, point, tip, corner):
        return None
    tool = Tool(
        name=name.strip(), kind=kind, diameter=dia, cutting_length=length, number=number,
        corner_radius=corner, point_angle=point, tip_diameter=tip, teeth=teeth,
        shank_diameter=shank[0], shank_length=shank[1],
        holder_diameter=holder[0], holder_length=holder[1],
        offsets=offsets, source=lines.find(where),
    )
    if kind in ("chamfer", "drill") and tool.cone_height() > length + 1e-9:
        bad(where + ("cutting_length",),
            f"cutting_length {length:g} is shorter than the cone ({tool.cone_height():.3f})")
    return tool


def _offsets(raw: Any, where: tuple, bad) -> dict[int, Offset]:
    out: dict[int, Offset] = {}
    if not isinstance(raw, Mapping):
        bad(where + ("d",), "d must be a table of D numbers: [tool.d.1]")
        return out
    for key, val in raw.items():
        if not str(key).isdigit() or int(key) < 1:
            bad(where + ("d", key), f"D number {key!r} must be an integer >= 1")
            continue
        if not isinstance(val, Mapping):
            bad(where + ("d", key), f"D{key} must be a table with length and radius")
            continue
        for k in val:
            if k not in ("length", "radius"):
                bad(where + ("d", key, k), f"D{key}: unknown key {k!r}")
        length = _num(val, "length", where + ("d", key), bad, 0.0, positive=False)
        radius = _num(val, "radius", where + ("d", key), bad, None, positive=False)
        out[int(key)] = Offset(length if length is not None else 0.0, radius)
    return out
