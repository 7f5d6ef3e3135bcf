"""The interpreter's model of the machine: settings, parameters and the tool table.

Units follow LinuxCNC: positions and offsets the interpreter keeps are in *program* units
(mm after G21, inch after G20); numbered parameters holding offsets and the tool table are in
*user* units, which for LinuxCNC's standalone ``rs274`` (its simulated machine) are inches.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from interpreters.rs274ngc.diag import NgcError

MM_PER_INCH = 25.4
NUM_PARAMETERS = 5602  # #1 .. #5601
#: The simulated machine of ``rs274`` works in inches (saicanon GET_EXTERNAL_LENGTH_UNITS):
#: parameters holding lengths and the tool table use them.
EXTERNAL_LENGTH_UNITS = 0.03937007874016



@dataclass
class Tool:
    """One tool table entry (user units: inch)."""

    number: int
    pocket: int
    offset: list[float] = field(default_factory=lambda: [0.0] * 9)  # x y z a b c u v w
    diameter: float = 0.0
    frontangle: float = 0.0
    backangle: float = 0.0
    orientation: int = 0


class ToolTable:
    """Tools by number, in the order of the table file (that order is CHANGE_TOOL's index).

    Entry 0 is the spindle: a copy of the tool loaded by the last tool change (M6). As in
    LinuxCNC's standalone interpreter, M61 changes the tool number but not that copy.
    """

    def __init__(self, tools: list[Tool]):
        self.tools = tools
        self.spindle = Tool(0, 0)

    def load(self, index: int) -> None:
        """CHANGE_TOOL(index): copy the entry into the spindle (index 0 leaves it)."""
        if index > 0:
            t = self.tools[index - 1]
            self.spindle = Tool(t.number, t.pocket, list(t.offset), t.diameter,
                                t.frontangle, t.backangle, t.orientation)

    def index(self, number: int) -> int | None:
        """Index of tool ``number`` (0 for T0), None when it is not in the table."""
        if number == 0:
            return 0
        for i, t in enumerate(self.tools, start=1):
            if t.number == number:
                return i
        return None

    def entry(self, index: int) -> Tool:
        if index == 0:
            return self.spindle
        return self.tools[index - 1]


class OpenToolTable(ToolTable):
    """The table when vmach's own tool library decides which tools exist (``vmach verify``
    and ``run --tools``): every tool number is found, in a pocket of its own number, so that
    a T the library lacks is vmach's ``unknown_tool`` finding rather than a stop."""

    def __init__(self) -> None:
        super().__init__([])

    def index(self, number: int) -> int | None:
        found = super().index(number)
        if found is None:
            self.tools.append(Tool(number, number))
            found = len(self.tools)
        return found


#: ``rs274`` without ``-t`` knows three tools (LinuxCNC 2.9 standalone default table).
DEFAULT_TOOLS = (
    Tool(1, 1, [0.0, 0.0, 0.511, 0, 0, 0, 0, 0, 0], 0.125),
    Tool(2, 2, [0.0, 0.0, 0.1, 0, 0, 0, 0, 0, 0], 0.0625),
    Tool(3, 3, [0.0, 0.0, 1.273, 0, 0, 0, 0, 0, 0], 0.201),
)


def default_tool_table() -> ToolTable:
    return ToolTable([Tool(t.number, t.pocket, list(t.offset), t.diameter) for t in DEFAULT_TOOLS])


_INT_PREFIX = re.compile(r"\s*[+-]?\d+")
_FLOAT_PREFIX = re.compile(r"\s*[+-]?(?:\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?|inf|nan)",
                           re.IGNORECASE)


def read_tool_table(path: str | Path, notes: list[str] | None = None) -> ToolTable:
    """A LinuxCNC 2.9 tool table (``T1 P1 Z0.5 D0.25 ;comment``), values in inches.

    Read as LinuxCNC's tool data loader reads it: words are separated by blanks, numbers are
    read like C's ``sscanf`` (the longest numeric prefix), a line with a word it cannot read
    is skipped with the note rs274 prints (appended to ``notes``), a line without P keeps its
    place in the table but cannot be found by its tool number.
    """
    try:
        text = Path(path).read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise NgcError("unreadable", path=str(path), reason=exc.strerror or str(exc)) from None
    tools: list[Tool] = []
    for raw in text.splitlines(keepends=True):
        body = raw.split(";", 1)[0]
        tokens = [t for t in body.split(" ") if t and t != "\n"]
        if not [t for t in tokens if t.strip()]:
            continue
        t = Tool(-1, -1)
        valid = True
        pocket = None
        for tok in tokens:
            key, val = tok[0].upper(), tok[1:]
            m = (_INT_PREFIX if key in "TPQ" else _FLOAT_PREFIX).match(val)
            if key not in "TPDXYZABCUVWIJQ" or m is None:
                valid = False
                continue
            v = m.group()
            if key == "T":
                t.number = int(v)
            elif key == "P":
                pocket = int(v)
            elif key == "Q":
                t.orientation = int(v)
            elif key == "D":
                t.diameter = float(v)
            elif key == "I":
                t.frontangle = float(v)
            elif key == "J":
                t.backangle = float(v)
            else:
                t.offset["XYZABCUVW".index(key)] = float(v)
        if not valid:
            if notes is not None:
                line = raw if raw.endswith("\n") else raw + "\n"
                notes.append(f"File: {path} Unrecognized line skipped:")
                notes.append("    " + line.rstrip("\n"))
            continue
        if pocket is None:
            t.number = -1  # LinuxCNC keeps the entry's place but not its tool number
        t.pocket = pocket if pocket is not None else -1
        tools.append(t)
    return ToolTable(tools)


class Settings:
    """Modal state (LinuxCNC ``setup_struct``), positions in program units."""

    def __init__(self) -> None:
        # current position in the active coordinate system; a b c in degrees
        self.pos = [0.0] * 6
        self.origin = [0.0] * 6  # active G54..G59.3 offset
        self.origin_index = 1
        self.axis_offset = [0.0] * 6  # G92
        self.rotation = 0.0  # XY rotation of the active system, degrees
        self.tool_offset = [0.0] * 6
        self.metric = True
        self.plane = 170
        self.incremental = False
        self.ijk_absolute = False
        self.feed_mode = 0  # 0 per minute, 1 inverse time, 2 per revolution
        self.feed = 0.0
        self.speed = 0.0
        self.spindle = "stop"
        self.motion = 800
        self.retract_r = True
        self.cycle = {"r": 0.0, "cc": 0.0, "p": 0.0, "q": 0.0, "l": 1}
        self.cycle_il: float | None = None
        self.mist = False
        self.flood = False
        self.feed_override = True
        self.speed_override = True
        self.control = "continuous"
        self.tolerance = 0.0
        self.naivecam = 0.0
        # rs274's simulated machine starts with pocket 1 "loaded" (saicanon _active_slot = 1)
        # but nothing in the spindle entry, and tool 0 prepared
        self.current_pocket = 1
        self.selected_pocket = 0
        self.selected_tool = 0
        self.t_seen = False
        self.toolchange_flag = False
        self.offset_h = 0
        # cutter radius compensation (comp.py): side 0 off, 1 left, 2 right; the radius in
        # program units; the programmed point (x y z) the compensated moves start from
        self.comp_side = 0
        self.comp_radius = 0.0
        self.comp_orientation = 0
        self.comp_first = True
        self.comp_program = [0.0, 0.0, 0.0]
        self.arc_not_allowed = False

    def u2p(self, u: float) -> float:
        """USER_TO_PROGRAM_LEN: user units (rs274: inch) to program units, as LinuxCNC
        computes it (through GET_EXTERNAL_LENGTH_UNITS, so the floats round the same)."""
        mm = u / EXTERNAL_LENGTH_UNITS
        return mm if self.metric else mm / MM_PER_INCH

    def p2u(self, p: float) -> float:
        """PROGRAM_TO_USER_LEN: program units to user units."""
        return (p if self.metric else p * MM_PER_INCH) * EXTERNAL_LENGTH_UNITS


class Params:
    """Numbered parameters and the named ones (locals per call level, globals ``#<_x>``)."""

    def __init__(self) -> None:
        self.num = [0.0] * NUM_PARAMETERS
        self.num[5220] = 1.0
        self.num[5599] = 1.0
        self.globals: dict[str, float] = {}
        self.locals: list[dict[str, float]] = [{}]

    def store_named(self, name: str, value: float) -> None:
        if name.startswith("_"):
            self.globals[name] = value
        else:
            self.locals[-1][name] = value


_D2R = math.pi / 180.0


def rotate(x: float, y: float, degrees: float) -> tuple[float, float]:
    """Rotate (x, y) about the origin by ``degrees`` (LinuxCNC Interp::rotate).

    Computed even for 0 degrees, as LinuxCNC does: ``-0.0`` may become ``0.0`` on the way,
    which shows in the trace as ``0.0000`` instead of ``-0.0000``.
    """
    t = degrees * _D2R
    c, s = math.cos(t), math.sin(t)
    return x * c - y * s, x * s + y * c
