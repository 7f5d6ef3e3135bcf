"""Canonical machining commands: the only contract between ``interpreters/`` and ``vmach/``.

The idea is LinuxCNC's ``canon.hh``: an interpreter reads a program and emits a stream of
simple commands; nothing downstream ever sees G-code text, and an interpreter never sees meshes
or kinematic chains. It asks the machine questions only through :class:`ControlSpec`.

Contracts every interpreter keeps:

- Units: lengths in mm, angles in degrees, time in seconds, feed in mm/min (``per_minute``),
  mm per spindle revolution (``per_rev``) or 1/min (``inverse_time``) as the last
  :class:`FeedMode` says. Inch programs are converted before they get here.
- Motion targets (``axes``) are **machine-axis values** after every work offset and frame
  (G54, TRANS, ROT, G92 ...) has been applied, for *every* axis the control knows, named as the
  machine model names them (``X Y Z C1`` on the turn-mill, ``X Y Z B C`` on the five-axis).
  Linear targets are the programmed tool tip; tool-length compensation is applied downstream by
  the kinematics, because its direction depends on the chain.
- The transverse axis of a lathe (``X`` with DIAMON) is always a **radius**.
- Under a kinematic transformation the machine side solves (Sinumerik TRAORI, CYCLE800) motion
  is :class:`OrientedMove` (tip and tool vector in the workpiece frame) between
  :class:`Transformation` marks, and axes only the machine knows are ``nan``;
  ``vmach.machine.oriented.resolve`` turns such a stream into plain motions.
- Modulo rotary axes are **unwrapped**: the value carries direction and amount of travel
  (from 350, ``ACP(10)`` gives 370; then ``ACN(350)`` gives 350).
- Every command carries the :class:`SourceRef` of the block that caused it.
- State commands (:class:`Spindle`, :class:`Coolant`, :class:`FeedMode` ...) carry the state
  *after* the change, so a consumer only keeps the last one of each kind.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

from vmach.errors import ProgramError
from vmach.source import SourceRef
from vmach.tol import tol

# --------------------------------------------------------------------------------------------
# What the machine tells an interpreter (canon.hh's query functions, as data)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class AxisSpec:
    """One programmable machine axis.

    name : str
        Name as programmed (``X``, ``C1``).
    kind : str
        ``"linear"`` (mm) or ``"rotary"`` (degrees).
    modulo : float or None
        360 for a modulo rotary axis (endless turning, ACP/ACN/DC), else None.
    home : float
        Position at program start (mm or degrees).
    g90_mode : str
        How a plain absolute target moves a modulo axis: ``"ac"`` (Sinumerik default,
        MD30455 bit 2 = 0: toward larger or smaller modulo value) or ``"dc"`` (shortest path).
    """

    name: str
    kind: str = "linear"
    modulo: float | None = None
    home: float = 0.0
    g90_mode: str = "ac"


@dataclass(frozen=True, slots=True)
class ControlSpec:
    """What an interpreter may know of the machine.

    axes : tuple of AxisSpec
        The programmable axes, in the machine model's order.
    geometry : tuple of str
        The three geometry axes (first, second, third) that planes, frames and arcs use.
    transverse : str or None
        The lathe's transverse axis that DIAMON/DIAMOF apply to.
    cycles : frozenset of str
        Maker's cycles and procedures callable by name (``C_AXIS_ON``).
    gcodes : frozenset of str
        Machine-specific G codes (``G971``).
    strict_axes : bool
        True when the axis list is authoritative (from ``--machine``): any other axis word is
        an error. False: any axis letter the program uses is accepted as a plain axis.
    zero_offsets : mapping
        ``{"G54": {"X": 0.0, ...}, ...}`` settable zero offsets in mm/degrees (default zero).
    spindles : tuple of int
        Spindle numbers the machine has.
    master_spindle : int
        Spindle that plain ``S``/``M3`` address at program start.
    dialect : str or None
        The machine's control language (``"sinumerik"``, ``"rs274ngc"``): it reads programs
        whose extension does not say (``.nc``); None: not declared.
    definitions : tuple of str
        Files of global user data (GUD definition files) the control has besides those found by
        their standard names (``_N_SGUD_DEF`` …), by name relative to the program's directory:
        read from there only (a name leading outside is refused), from the model's
        ``[control] definitions`` and the setup file's ``definitions``.
    machine_data : mapping
        The control's data a program may read, by name with ``$`` (``"$MA_POS_LIMIT_PLUS"``):
        machine and setting data, swivel data (``$TC_CARR``), PLC and I/O start values. A value
        is a number or string; an indexed datum is a mapping from index (an int, an axis name,
        or a tuple of them) to its value. Lengths mm, angles degrees, rates mm/min or deg/min.
    """

    axes: tuple[AxisSpec, ...] = ()
    geometry: tuple[str, str, str] = ("X", "Y", "Z")
    transverse: str | None = None
    cycles: frozenset[str] = frozenset()
    gcodes: frozenset[str] = frozenset()
    strict_axes: bool = False
    zero_offsets: Mapping[str, Mapping[str, float]] = field(default_factory=dict)
    spindles: tuple[int, ...] = (1,)
    master_spindle: int = 1
    dialect: str | None = None
    machine_data: Mapping[str, Any] = field(default_factory=dict)
    definitions: tuple[str, ...] = ()

    def axis(self, name: str) -> AxisSpec | None:
        for a in self.axes:
            if a.name == name:
                return a
        return None


DEFAULT_CONTROL = ControlSpec(
    axes=(AxisSpec("X"), AxisSpec("Y"), AxisSpec("Z")),
    strict_axes=False,
)


# --------------------------------------------------------------------------------------------
# Commands
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Command:
    """Base of every canonical command."""

    source: SourceRef
    kind: ClassVar[str] = "command"

    def fields(self) -> dict[str, Any]:
        """The command's own fields for JSON (without kind and source)."""
        return {}

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "kind": self.kind,
            "file": self.source.path,
            "line": self.source.line,
        }
        out.update(self.fields())
        return out


@dataclass(frozen=True, slots=True)
class Traverse(Command):
    """Rapid positioning (G0) to ``axes`` (every axis, machine values)."""

    axes: Mapping[str, float] = field(default_factory=dict)
    kind: ClassVar[str] = "traverse"

    def fields(self) -> dict[str, Any]:
        return {"axes": dict(self.axes), "feed": None}


@dataclass(frozen=True, slots=True)
class LinearFeed(Command):
    """Straight feed move (G1) to ``axes`` at ``feed`` (units per the last FeedMode)."""

    axes: Mapping[str, float] = field(default_factory=dict)
    feed: float = 0.0
    kind: ClassVar[str] = "feed"

    def fields(self) -> dict[str, Any]:
        return {"axes": dict(self.axes), "feed": self.feed}


@dataclass(frozen=True, slots=True)
class ProbeMove(LinearFeed):
    """A measuring move of a touch probe toward ``axes`` at ``feed``: the probe stops where
    its stylus touches the part. The interpreter cannot know where that is (the control would
    measure); it sends the whole measuring path, and verify stops the move at the contact on
    the simulated stock (:mod:`vmach.checks.probing`). ``required``: no contact within the
    path is an error (``probe_no_contact``), as a measuring cycle's alarm or G38.2/G38.4 are.
    Every consumer that does not know probing sees a :class:`LinearFeed`."""

    required: bool = True
    kind: ClassVar[str] = "probe"

    def fields(self) -> dict[str, Any]:
        return {"axes": dict(self.axes), "feed": self.feed, "required": self.required}


@dataclass(frozen=True, slots=True)
class ArcFeed(Command):
    """Circular or helical feed move (G2/G3).

    axes : end point, every axis (machine values).
    plane : tuple (first, second, normal) axis names of the arc plane, e.g. ("Z", "X", "Y").
    center : (2,) float, mm — centre in the plane's first and second axis (machine values).
    clockwise : looking from the positive normal axis down on the plane.
    turns : extra full turns (0 for an arc of less than one turn).
    """

    axes: Mapping[str, float] = field(default_factory=dict)
    plane: tuple[str, str, str] = ("X", "Y", "Z")
    center: tuple[float, float] = (0.0, 0.0)
    clockwise: bool = True
    turns: int = 0
    feed: float = 0.0
    kind: ClassVar[str] = "arc"

    def fields(self) -> dict[str, Any]:
        return {
            "axes": dict(self.axes),
            "feed": self.feed,
            "plane": list(self.plane),
            "center": list(self.center),
            "clockwise": self.clockwise,
            "turns": self.turns,
        }


MOTIONS = (Traverse, LinearFeed, ArcFeed)


@dataclass(frozen=True, slots=True)
class Transformation(Command):
    """A kinematic transformation the *machine side* carries out switched on or off.

    name : ``"TRAORI"`` (the five-axis orientation transformation), ``"CYCLE800"`` (a swivelled
        working plane: the same contract, the orientation fixed by the swivel) or ``"TRAFOOF"``
        (off; also ``CYCLE800()``).
    number : the transformation's number (``TRAORI(2)``), 1 by default.

    Between ``TRAORI`` and ``TRAFOOF`` an interpreter emits :class:`OrientedMove` instead of
    the motions of :data:`MOTIONS`; it cannot know the axis values there (they need the machine's
    inverse kinematics), so after either marker every axis the transformation drives (the
    geometry axes and the two rotary axes) is **unknown to the interpreter** until the program
    positions it absolutely: such a value is ``nan`` in the motions that follow, meaning "where
    the machine is now", and a consumer resolves it (``vmach.machine.oriented.resolve``). An
    interpreter refuses an incremental move of an unknown axis.
    """

    name: str = "TRAORI"
    number: int = 1
    kind: ClassVar[str] = "transformation"

    def fields(self) -> dict[str, Any]:
        return {"name": self.name, "number": self.number}


@dataclass(frozen=True, slots=True)
class OrientedMove(Command):
    """A motion block under the orientation transformation (TRAORI): the programmed pose in
    the **workpiece frame** (the machine model's ``work`` frame, the control's basic coordinate
    system: every frame already applied), not axis values.

    motion : ``"traverse"``, ``"feed"`` or ``"arc"`` (the tool tip's path: a line, or the arc
        given by ``plane``/``center``/``clockwise``/``turns`` as in :class:`ArcFeed`).
    axes : every axis the interpreter knows: the geometry axes are the tool **tip** (mm,
        workpiece frame; ``nan``: where it is now); a rotary axis the transformation drives is
        the value programmed directly in this block (degrees), or ``nan`` when the orientation
        decides it; other axes are machine values as in any motion.
    vector : (3,) the programmed tool direction (from the tip toward the spindle, workpiece
        frame, not necessarily unit), or None: from rotary axes programmed directly (``axes``),
        or — with neither — the orientation stays as it is.
    interpolation : ``"axes"`` (ORIAXES: the rotary axes move linearly between the end
        orientations) or ``"vector"`` (ORIVECT/ORIPLANE: the vector turns on the great circle
        between them); either way the tip moves on its programmed path.
    frame : None, or 12 numbers (origin x y z, then a row-major 3x3 linear part) when the
        block leaves a geometry axis where it is under a rotated frame, is a circle in a plane
        the frame tilts (``plane``/``center`` then in program coordinates too), comes from a
        cycle under CYCLE800 or TRAORI, or runs under TCARR: then the geometry values in
        ``axes`` are **program coordinates** (``nan`` where the tip stays), and the workpiece
        point is ``origin + linear · program``.
    prefer : None, or (rotary axis name, +1 or −1): of the two solutions take the one with the
        higher (+1) or lower (−1) value of that axis when both are inside the travel
        (CYCLE800's direction); None: the transformation's own rule.
    hold_axes : the linear axes keep their values while the rotary axes turn (CYCLE800's
        swivelling without tool follow-up: the tip moves with the part); ``motion`` traverse.
    cone : None, or (3,) for ``interpolation`` ``"cone_cw"``/``"cone_ccw"`` (ORICONCW/CCW:
        the vector turns about this cone axis clockwise/counter-clockwise as seen against it,
        its angle to the axis going linearly from the start's to the end's) or ``"cone_io"``
        (ORICONIO: the intermediate orientation the cone passes through), workpiece frame.

    The consumer samples the block within ``tol.angle_step`` of orientation and ``tol.chord``
    of path, solves each sample with the model's inverse kinematics and emits
    :class:`LinearFeed` (:class:`Traverse` for G0) rows of axis values right after this command,
    which stays in the stream as the record of what was programmed.
    """

    motion: str = "feed"
    axes: Mapping[str, float] = field(default_factory=dict)
    vector: tuple[float, float, float] | None = None
    interpolation: str = "vector"
    feed: float = 0.0
    plane: tuple[str, str, str] = ("X", "Y", "Z")
    center: tuple[float, float] = (0.0, 0.0)
    clockwise: bool = True
    turns: int = 0
    frame: tuple[float, ...] | None = None
    prefer: tuple[str, int] | None = None
    hold_axes: bool = False
    cone: tuple[float, float, float] | None = None
    kind: ClassVar[str] = "oriented_move"

    def fields(self) -> dict[str, Any]:
        out: dict[str, Any] = {"motion": self.motion, "axes": dict(self.axes),
                               "vector": list(self.vector) if self.vector is not None else None,
                               "interpolation": self.interpolation, "feed": self.feed}
        if self.motion == "arc":
            out.update(plane=list(self.plane), center=list(self.center), clockwise=self.clockwise,
                       turns=self.turns)
        if self.cone is not None:
            out["cone"] = list(self.cone)
        return out


@dataclass(frozen=True, slots=True)
class Dwell(Command):
    """Dwell (G4): ``seconds``, or ``revolutions`` of the master spindle."""

    seconds: float | None = None
    revolutions: float | None = None
    kind: ClassVar[str] = "dwell"

    def fields(self) -> dict[str, Any]:
        return {"seconds": self.seconds, "revolutions": self.revolutions}


@dataclass(frozen=True, slots=True)
class ToolChange(Command):
    """Tool change: ``tool`` is the name (``"GLOD D40"``) or the number as text (``"1"``)."""

    tool: str = ""
    number: int | None = None
    offset: int | None = None
    kind: ClassVar[str] = "tool_change"

    def fields(self) -> dict[str, Any]:
        return {"tool": self.tool, "number": self.number, "offset": self.offset}


@dataclass(frozen=True, slots=True)
class ToolOffset(Command):
    """Activate tool offset (edge) ``offset`` (Sinumerik D, RS274 H); 0 switches it off."""

    offset: int = 0
    kind: ClassVar[str] = "tool_offset"

    def fields(self) -> dict[str, Any]:
        return {"offset": self.offset}


@dataclass(frozen=True, slots=True)
class Spindle(Command):
    """State of spindle ``spindle`` after a change: speed (rev/min) and direction.

    direction : ``"cw"``, ``"ccw"`` or ``"stop"``.
    """

    spindle: int = 1
    speed: float = 0.0
    direction: str = "stop"
    kind: ClassVar[str] = "spindle"

    def fields(self) -> dict[str, Any]:
        return {"spindle": self.spindle, "speed": self.speed, "direction": self.direction}


@dataclass(frozen=True, slots=True)
class MasterSpindle(Command):
    """The spindle that plain S and M3/M4/M5 now address (Sinumerik SETMS)."""

    spindle: int = 1
    kind: ClassVar[str] = "master_spindle"

    def fields(self) -> dict[str, Any]:
        return {"spindle": self.spindle}


@dataclass(frozen=True, slots=True)
class Coolant(Command):
    """Coolant state: ``"mist"``, ``"flood"``, ``"mist+flood"`` or ``"off"``."""

    mode: str = "off"
    kind: ClassVar[str] = "coolant"

    def fields(self) -> dict[str, Any]:
        return {"mode": self.mode}


@dataclass(frozen=True, slots=True)
class SurfaceSpeed(Command):
    """Constant cutting speed (Sinumerik G96 S… LIMS=…, RS274/NGC G96 D… S…) on, or off (G97).

    spindle : the spindle whose speed follows the transverse axis (the master spindle).
    speed : m/min (feet/min converted), 0 when off. limit : rev/min, the speed's upper bound
        (LIMS, the D word), 0 for none. axis : the transverse axis whose radius sets the
        speed, n = 1000·speed / (2π·r) (the radius in mm, canonical X is a radius).
    """

    spindle: int = 1
    speed: float = 0.0
    limit: float = 0.0
    axis: str = "X"
    kind: ClassVar[str] = "surface_speed"

    def fields(self) -> dict[str, Any]:
        return {"spindle": self.spindle, "speed": self.speed, "limit": self.limit, "axis": self.axis}


@dataclass(frozen=True, slots=True)
class SpindleCoupling(Command):
    """A spindle coupled to another at a ratio (Sinumerik synchronous spindle ``COUPDEF``/
    ``COUPON``/``COUPOF``), or uncoupled: what polygonal turning needs.

    following, leading : spindle numbers (the following spindle FS, the leading spindle LS).
    ratio : FS turns per LS turn (COUPDEF's numerator over its denominator; negative: FS turns
        the other way). active : the coupling holds from here on (False: ended).
    offset : degrees, FS's angle when LS is at 0 (position couplings; None: not given, taken as
        0, or not fixed: a velocity coupling). mode : ``"DV"`` setpoint, ``"AV"`` actual value
        (both position couplings) or ``"VV"`` velocity coupling.
    """

    following: int = 2
    leading: int = 1
    ratio: float = 1.0
    active: bool = True
    offset: float | None = None
    mode: str = "DV"
    kind: ClassVar[str] = "spindle_coupling"

    def fields(self) -> dict[str, Any]:
        return {"following": self.following, "leading": self.leading, "ratio": self.ratio,
                "active": self.active, "offset": self.offset, "mode": self.mode}


@dataclass(frozen=True, slots=True)
class FeedMode(Command):
    """Feed interpretation: ``"per_minute"``, ``"per_rev"`` or ``"inverse_time"``."""

    mode: str = "per_minute"
    kind: ClassVar[str] = "feed_mode"

    def fields(self) -> dict[str, Any]:
        return {"mode": self.mode}


@dataclass(frozen=True, slots=True)
class PathMode(Command):
    """How motion blocks join: ``"exact"`` (exact stop, G60: the axes stop at every block end)
    or ``"continuous"`` (continuous path, G64 and the rounding modes G641...: the path speed is
    only lowered at corners).

    Emitted when the mode changes. Before the first PathMode a consumer assumes
    ``"continuous"`` (G64, the interpreters' start-up state). A block-wise exact stop (G9 on
    Sinumerik) under continuous mode is emitted as ``"exact"`` before that block's motion and
    ``"continuous"`` after it.
    """

    mode: str = "continuous"
    kind: ClassVar[str] = "path_mode"

    def fields(self) -> dict[str, Any]:
        return {"mode": self.mode}


@dataclass(frozen=True, slots=True)
class PathTolerance(Command):
    """The contour tolerance the control keeps from here on (Sinumerik ``CYCLE832(tol, …)``):
    ``tolerance`` mm (0: the control's own again); ``setting`` what else the call said
    (``"_FINISH"`` …), as written. It moves nothing; vmach writes the transformed blocks it
    approximates (TRAORI, CYCLE800) within it."""

    tolerance: float = 0.0
    setting: tuple[Any, ...] = ()
    kind: ClassVar[str] = "path_tolerance"

    def fields(self) -> dict[str, Any]:
        return {"tolerance": self.tolerance, "setting": list(self.setting)}


@dataclass(frozen=True, slots=True)
class PlaneSelect(Command):
    """Working plane as (first, second, normal) axis names: G17 XY, G18 ZX, G19 YZ."""

    plane: tuple[str, str, str] = ("X", "Y", "Z")
    kind: ClassVar[str] = "plane"

    def fields(self) -> dict[str, Any]:
        return {"plane": list(self.plane)}


@dataclass(frozen=True, slots=True)
class SetFrame(Command):
    """The active coordinate frame changed (informational; targets are already resolved).

    origin : program zero in machine values, per axis.
    rotation : (9,) float — row-major 3x3 linear part for the geometry axes (a rotation, or with
        Sinumerik's SCALE / MIRROR a scaled or mirrored one).
    """

    origin: Mapping[str, float] = field(default_factory=dict)
    rotation: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    kind: ClassVar[str] = "frame"

    def fields(self) -> dict[str, Any]:
        return {"origin": dict(self.origin), "rotation": list(self.rotation)}


@dataclass(frozen=True, slots=True)
class CycleCall(Command):
    """A machine-declared cycle or machine-specific G code (``C_AXIS_ON``, ``G971``)."""

    name: str = ""
    args: tuple[Any, ...] = ()
    kind: ClassVar[str] = "cycle"

    def fields(self) -> dict[str, Any]:
        return {"name": self.name, "args": list(self.args)}


@dataclass(frozen=True, slots=True)
class Message(Command):
    """Operator message (Sinumerik MSG, RS274 (MSG,...))."""

    text: str = ""
    kind: ClassVar[str] = "message"

    def fields(self) -> dict[str, Any]:
        return {"text": self.text}


@dataclass(frozen=True, slots=True)
class SetVariable(Command):
    """A program wrote a control variable that leaves the NC (PLC data ``$A_DBB``, outputs
    ``$A_OUT``, synchronised-action markers): recorded, no effect on geometry.

    name : str — as written, with its index (``$A_OUT[3]``); value : number or string.
    """

    name: str = ""
    value: Any = 0
    kind: ClassVar[str] = "set_variable"

    def fields(self) -> dict[str, Any]:
        return {"name": self.name, "value": self.value}


@dataclass(frozen=True, slots=True)
class Comment(Command):
    """A comment the interpreter passes on (RS274 ``( ... )``)."""

    text: str = ""
    kind: ClassVar[str] = "comment"

    def fields(self) -> dict[str, Any]:
        return {"text": self.text}


@dataclass(frozen=True, slots=True)
class Pause(Command):
    """Program stop M0, or optional stop M1 (``optional=True``)."""

    optional: bool = False
    kind: ClassVar[str] = "pause"

    def fields(self) -> dict[str, Any]:
        return {"optional": self.optional}


@dataclass(frozen=True, slots=True)
class ProgramEnd(Command):
    """End of the main program (M30, M2)."""

    code: str = "M30"
    kind: ClassVar[str] = "program_end"

    def fields(self) -> dict[str, Any]:
        return {"code": self.code}


# --------------------------------------------------------------------------------------------
# Trace formats
# --------------------------------------------------------------------------------------------


def _num(v: float) -> str:
    return f"{v:.4f}"


def format_text(cmd: Command, index: int) -> str:
    """One human-readable trace line: counter, kind, fields, ``; file:line``."""
    f = cmd.fields()
    parts: list[str] = []
    for key, val in f.items():
        if key == "axes":
            parts.append(" ".join(f"{k}={_num(v)}" for k, v in val.items()))
        elif val is None:
            continue
        elif isinstance(val, float):
            parts.append(f"{key}={_num(val)}")
        elif isinstance(val, dict):
            parts.append(f"{key}=" + ",".join(f"{k}:{_num(v)}" for k, v in val.items()))
        elif isinstance(val, list):
            parts.append(f"{key}=" + ",".join(_num(x) if isinstance(x, float) else str(x) for x in val))
        elif isinstance(val, str):
            parts.append(f"{key}={json.dumps(val, ensure_ascii=False)}")
        else:
            parts.append(f"{key}={val}")
    body = " ".join(parts)
    return f"{index:6d} {cmd.kind:<14s} {body}  ; {cmd.source.path}:{cmd.source.line}"


def format_json(cmd: Command) -> str:
    """One JSON Lines record (a ``nan`` — an axis only the machine knows — is ``null``)."""
    return dumps(cmd.to_json())


def dumps(record: dict) -> str:
    """``record`` as strict JSON: ``nan`` written as ``null``."""
    try:
        return json.dumps(record, ensure_ascii=False, allow_nan=False)
    except ValueError:
        return json.dumps(_no_nan(record), ensure_ascii=False)


def _no_nan(v):
    if isinstance(v, float):
        return None if v != v else v
    if isinstance(v, dict):
        return {k: _no_nan(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_no_nan(x) for x in v]
    return v


# --------------------------------------------------------------------------------------------
# What an interpreter returns
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class RunOptions:
    """Knobs every interpreter honours.

    max_blocks : blocks executed before the run stops with ``block_limit`` (infinite loops).
    max_call_depth : nested subprogram calls before ``call_depth``.
    tool_radius : ``(tool, D number) -> radius`` (mm, or None for an offset the tool lacks),
        for tool radius compensation (G41/G42); the tool as :class:`ToolChange` names it
        (``"GLOD D40"``, ``"1"``). None when no tool library was given.
    tool_data : ``(tool, D number) -> {"length": mm, "radius": mm, "type": int, "teeth": int}``
        (None for an offset the tool lacks), for the control's tool data (``$TC_DP``); None
        when no tool library was given.
    dialect_options : settings only one dialect understands, by name (RS274/NGC:
        ``tool_table``, ``ini``, ``var_file``, ``var_file_update``, ``continue_after_error``);
        a dialect ignores the names it does not know.
    """

    max_blocks: int = tol.max_blocks
    max_call_depth: int = 16
    tool_radius: Callable[[str, int], float | None] | None = None
    tool_data: Callable[[str, int], Mapping[str, float] | None] | None = None
    dialect_options: Mapping[str, Any] = field(default_factory=dict)


class CommandList(list):
    """The canonical commands of one run, held to ``limit`` (``tol.max_commands``; each costs
    about 0.35 kB): one more is a ``resource_limit`` ProgramError at its own place, so that a
    loop that moves (``G81 ... L1000000000``) stops long before it fills the memory."""

    def __init__(self, limit: int | None = None):
        super().__init__()
        self.limit = tol.max_commands if limit is None else limit

    def append(self, cmd: Command) -> None:
        if len(self) >= self.limit:
            raise ProgramError("resource_limit", f"the program makes more than {self.limit:,} "
                               "canonical commands (vmach's limit, vmach/tol.py max_commands; "
                               "verify the program in parts)", cmd.source, limit=self.limit)
        super().append(cmd)

    def extend(self, cmds) -> None:
        for c in cmds:
            self.append(c)


@dataclass(slots=True)
class RunResult:
    """Outcome of interpreting a program.

    commands : the canonical stream, in execution order.
    findings : warnings met while running, and the error that stopped the run if any.
    completed : False when an error stopped the run before its end.
    blocks : number of blocks executed (all files).
    """

    commands: list[Command]
    findings: list[Any]
    completed: bool
    blocks: int = 0
