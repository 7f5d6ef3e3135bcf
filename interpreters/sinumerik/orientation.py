"""Three- to five-axis transformation TRAORI(n) … TRAFOOF and orientation programming
(Programming Manual Job Planning, "Three, four and five axis transformation (TRAORI)").

While TRAORI is on, X Y Z are the tool **tip** in the workpiece coordinate system (the tool
length is part of the transformation) and the tool's orientation is programmed

- as a direction vector ``A3= B3= C3=`` (from the tip toward the tool holder; its length is
  irrelevant; components not programmed in the block are zero);
- as angles ``A2= B2= C2=``: ORIEULER (default) turns a vector along Z first by A2 about Z,
  then by B2 about the new X (C2, the third Euler angle, does not change the vector); ORIRPY
  first by C2 about Z, then by B2 about the new Y, then by A2 about the new X; ORIRPY2 (the
  sequence Z, Y, X) by C2 about Z, B2 about Y, A2 about X, fixed axes; ORIVIRT1/2 by A2, B2, C2
  about the fixed axes the machine data $MC_ORIAX_TURN_TAB_1/2 names (default X, Y, Z);
- or by the rotary axes themselves (``B=30 C=90``).

With ORIWKS (default) a vector or angles are in the workpiece frame and turn with a rotating
frame; with ORIMKS they are in the basic coordinate system. ORIVECT/ORIPLANE (default: the
control's MD20150 start-up value here) turn the vector on the great circle between the block's
start and end orientation; ORIAXES moves the rotary axes linearly. A block without an
orientation keeps it. ORICONxx, ORICURVE and ORIPATH are ``unsupported``.

The interpreter cannot turn these into axis values (that needs the machine's inverse
kinematics, which ``interpreters/`` never see): it emits :class:`vmach.canon.OrientedMove` and
marks TRAORI/TRAFOOF with :class:`vmach.canon.Transformation`; ``vmach.machine.oriented``
solves them. After either marker the geometry and the two rotary axes are unknown to the
interpreter (``nan``, "where the machine is") until programmed absolutely; an incremental move
of an unknown axis is ``unsupported``.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

from interpreters.sinumerik import oripath, swivel, toolcarrier, tracyl, transmit
from vmach import canon
from vmach.errors import ProgramError
from vmach.findings import info
from vmach.source import SourceRef

#: the orientation words (parser kind "orient")
WORDS = ("A2", "B2", "C2", "A3", "B3", "C3")
#: the cone's axis (ORICONCW/CCW) and intermediate orientation (ORICONIO)
CONE_WORDS = ("A6", "B6", "C6", "A7", "B7", "C7")
#: G group 50 (angle definition), 51 (interpolation), 25 (reference)
DEFINITIONS = ("ORIEULER", "ORIRPY", "ORIRPY2", "ORIVIRT1", "ORIVIRT2")
#: the axes (1 X, 2 Y, 3 Z) the virtual orientation axes A2, B2, C2 turn about, in order, when
#: the model's machine data has no $MC_ORIAX_TURN_TAB_1/2 (MD21120/MD21130)
TURN_TAB = (1, 2, 3)
INTERPOLATION = {"ORIVECT": "vector", "ORIPLANE": "vector", "ORIAXES": "axes",
                 "ORICONCW": "cone_cw", "ORICONCCW": "cone_ccw", "ORICONIO": "cone_io",
                 "ORICONTO": "cone_to", "ORIPATH": "path", "ORIPATHS": "path"}


@dataclass(frozen=True)
class Traori:
    """The active TRAORI: its number and the two rotary axes it drives."""

    number: int
    rotaries: tuple[str, str]
    name: str = "TRAORI"


class Modes:
    """The orientation G groups' state (kept while TRAORI is off, as the control does)."""

    def __init__(self) -> None:
        self.definition = "ORIEULER"
        self.interpolation = "vector"
        self.workpiece = True          # ORIWKS
        self.lead = self.tilt = 0.0    # LEAD=, TILT= (oripath.py)


def set_mode(machine, name: str) -> None:
    """An orientation G code of groups 25, 50 and 51."""
    modes = machine.ori
    if name in ("ORIWKS", "ORIMKS"):
        modes.workpiece = name == "ORIWKS"
    elif name in INTERPOLATION:
        modes.interpolation = INTERPOLATION[name]
    else:
        modes.definition = name


def start(machine, name: str, args, src: SourceRef) -> list:
    """TRACYL(d), TRAORI(n) or CYCLE800(...) in a block: the commands that start it."""
    if name == "TRACYL":
        if machine.traori is not None:
            raise ProgramError("unsupported", "TRACYL while TRAORI or CYCLE800 is active is not "
                               "simulated (TRAFOOF first)", src)
        return [tracyl.activate(machine, args, src)]
    if name == "CYCLE800":
        return swivel.cycle800(machine, args, src, sys.modules[__name__])
    if name == "TRANSMIT":
        return [transmit.activate(machine, args, src)]
    return [activate(machine, args, src)]


def activate(machine, args, src: SourceRef, name: str = "TRAORI") -> canon.Transformation:
    """TRAORI or TRAORI(n) (or CYCLE800's start): the transformation marker; geometry and rotary
    axes become unknown."""
    if len(args) > 1:
        raise ProgramError("unsupported", "TRAORI with an orientation offset (parameters after n) is "
                           "not simulated", src)
    n = 1 if not args or args[0] is None else args[0]
    if isinstance(n, str) or n != int(n) or n < 1:
        raise ProgramError("invalid_value", f"TRAORI({n}): the transformation number is 1, 2, …", src)
    rot = tuple(a.name for a in machine.control.axes if a.kind == "rotary")
    if len(rot) != 2:
        raise ProgramError("unsupported", "TRAORI: the machine has not two rotary axes to orient the "
                           f"tool with (it has {len(rot)})", src)
    if machine.cutcom.engaged or machine.tracyl is not None or machine.traori is not None:
        raise ProgramError("unsupported", "TRAORI while tool radius compensation or another "
                           "transformation is active is not simulated (G40, TRAFOOF first)", src)
    machine.traori = Traori(int(n), rot, name)       # type: ignore[arg-type]
    forget(machine)
    return canon.Transformation(src, name=name, number=int(n))


def deactivate(machine, src: SourceRef) -> canon.Transformation:
    """TRAFOOF after TRAORI: the axes are machine axes again, at positions only the machine side
    knows."""
    forget(machine)
    machine.traori = None
    if getattr(machine, "swivel", None) is not None:     # TRAFOOF ends CYCLE800's too
        machine.frames.set_settable(*machine.swivel)
        machine.swivel = None
        machine.emit_frame(src)
    return canon.Transformation(src, name="TRAFOOF", number=0)


def code(machine, name: str, src: SourceRef) -> bool:
    """A code of the orientation groups (25, 50, 51), of the frame rotations of the tool carrier
    (53: toolcarrier.py) or of the transformation group (100:
    TRAORI or TRANSMIT alone, TRAFOOF); True for TRAFOOF (TRACYL's and TRANSMIT's end follows)."""
    if name in ("ORIWKS", "ORIMKS", *INTERPOLATION, *DEFINITIONS):
        set_mode(machine, name)
        said = any(f.kind == "orientation_simplified" for f in machine.notes)
        if name == "ORIPATHS" and not said:
            machine.notes.append(info("orientation_simplified", "ORIPATHS runs as ORIPATH: the "
                                      "smoothing of the orientation at the path's corners is not "
                                      "simulated", src, code=name))
        return False
    if name in toolcarrier.CODES:                    # G group 53: TOROT, PAROT …
        toolcarrier.code(machine, name, src)
        return False
    if name in ("TRAORI", "TRANSMIT"):
        machine.out.extend(start(machine, name, [], src))
        machine.placeholders = True
        return False
    if machine.traori is not None:
        if toolcarrier.active(machine):
            raise ProgramError("unsupported", "TRAFOOF while TCARR is active is not simulated "
                               "(TCARR=0 ends the tool carrier)", src)
        machine.out.append(deactivate(machine, src))
    return True


def carrier(machine, value, src: SourceRef) -> None:
    """``TCARR=n`` (toolcarrier.py)."""
    toolcarrier.select(machine, value, src, sys.modules[__name__])


def words(machine, v, src: SourceRef) -> bool:
    """Whether the block programs an orientation (``A3=`` …, left in ``v.interp``); an error
    without TRAORI."""
    found = [k for k in (*WORDS, *CONE_WORDS, *oripath.WORDS) if k in v.interp]
    if found and machine.traori is None:
        raise ProgramError("no_transformation", f"{', '.join(found)}: orientation programming needs "
                           "TRAORI", src)
    return bool(found)


def forget(machine) -> None:
    """The geometry and the transformation's rotary axes become unknown (``nan``)."""
    rot = machine.traori.rotaries
    pos = dict(machine.pos)
    for name in (*machine.geometry, *rot):
        pos[name] = math.nan
    machine.pos = pos
    machine.unknown = {*machine.geometry, *rot}


def check_known(machine, words, src: SourceRef) -> None:
    """An incremental word for an axis whose value only the machine side knows is refused."""
    for word, _ in words if machine.unknown else ():
        if word.name in machine.unknown:
            inc = word.mode == "IC" or (word.mode is None and not machine.absolute)
            if inc:
                raise ProgramError("unsupported", f"{word.name}: an incremental move right after "
                                   "TRAORI or TRAFOOF is not simulated (the position is the "
                                   "transformation's): program it absolutely first", src.at(word.col))


def learned(machine, words, new: dict, suppress: bool) -> None:
    """Axes with a known value again after a move (``new`` completed in place: a modulo axis
    programmed absolutely from an unknown position goes to the programmed value)."""
    for word, value in words if machine.unknown else ():
        name = word.name
        if name in machine.unknown and new.get(name) != new.get(name) and name not in machine.geometry:
            new[name] = float(value) + (0.0 if suppress else machine.frames.offset(name))
    machine.unknown = {n for n in machine.unknown if new.get(n) != new.get(n)}


def _turn(axis: int, deg: float, v):
    """v (3,) turned about the fixed axis 1 X, 2 Y or 3 Z by deg degrees."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    i, j = ((1, 2), (2, 0), (0, 1))[axis - 1]
    out = list(v)
    out[i], out[j] = c * v[i] - s * v[j], s * v[i] + c * v[j]
    return tuple(out)


def angles(machine, a: float, b: float, c: float) -> tuple[float, float, float]:
    """The tool vector of angles A2 B2 C2 (degrees) by the active definition (G group 50):
    ORIEULER Rz(A2)·Rx(B2)·e_z; ORIRPY (sequence X, Y, Z) Rz(C2)·Ry(B2)·Rx(A2)·e_z; ORIRPY2
    (sequence Z, Y, X) Rx(A2)·Ry(B2)·Rz(C2)·e_z; ORIVIRT1/2 A2, B2, C2 about the fixed axes
    $MC_ORIAX_TURN_TAB_1/2 names in order (default X, Y, Z)."""
    d = machine.ori.definition
    v = (0.0, 0.0, 1.0)
    if d == "ORIEULER":
        seq = ((3, c), (1, b), (3, a))
    elif d == "ORIRPY":
        seq = ((1, a), (2, b), (3, c))
    elif d == "ORIRPY2":
        seq = ((3, c), (2, b), (1, a))
    else:
        tab = machine.control.machine_data.get(f"$MC_ORIAX_TURN_TAB_{d[-1]}", TURN_TAB)
        if isinstance(tab, dict):
            tab = [tab[k] for k in sorted(tab)]
        tab = tuple(int(x) for x in tab)
        if len(tab) != 3 or not set(tab) <= {1, 2, 3}:
            tab = TURN_TAB
        seq = tuple(zip(tab, (a, b, c), strict=True))
    for axis, deg in seq:
        v = _turn(axis, deg, v)
    return v  # type: ignore[return-value]


def vector(machine, words: dict, src: SourceRef) -> tuple[float, float, float] | None:
    """The block's tool vector in the basic coordinate system from its orientation words
    ``{name: (value, mode)}``, or None."""
    if not words:
        return None
    three = [w for w in words if w.endswith("3")]
    if three and len(three) != len(words):
        raise ProgramError("syntax", "a block programs the orientation either as a vector (A3 B3 C3) or "
                           "as angles (A2 B2 C2), not both", src)
    val = {k: float(v[0]) for k, v in words.items()}
    if three:
        v = (val.get("A3", 0.0), val.get("B3", 0.0), val.get("C3", 0.0))
    else:
        v = angles(machine, *(val.get(k, 0.0) for k in ("A2", "B2", "C2")))
    if not math.hypot(*v) > 1e-12:
        raise ProgramError("invalid_value", "the programmed tool vector is zero", src)
    if machine.ori.workpiece and machine.frames.rotated:
        lin = machine.frames.lin
        v = tuple(sum(lin[i][j] * v[j] for j in range(3)) for i in range(3))
    return v  # type: ignore[return-value]


def _cone(machine, words: dict, orientation: dict, src: SourceRef):
    """The block's cone vector under ORICONCW/CCW (A6 B6 C6, the axis) or ORICONIO (A7 B7
    C7, the intermediate orientation), turned like a tool vector; None otherwise."""
    mode = machine.ori.interpolation
    if not mode.startswith("cone"):
        if words:
            raise ProgramError("syntax", f"{', '.join(words)}: a cone's vector needs ORICONCW, "
                               "ORICONCCW or ORICONIO", src)
        return None
    if not words and not orientation:                 # the orientation stays
        return None
    if mode == "cone_to":                             # tangential: the end orientation alone
        if words or not any(k.endswith("3") for k in orientation):
            raise ProgramError("unsupported", "ORICONTO: a block with the end orientation (A3 B3 C3) "
                               "alone is simulated", src)
        return None
    want = ("A7", "B7", "C7") if mode == "cone_io" else ("A6", "B6", "C6")
    wrong = [k for k in words if k not in want]
    if wrong or not words or not any(k.endswith("3") for k in orientation):
        raise ProgramError("unsupported", f"{mode.replace('cone_', 'ORICON').upper()}: a block "
                           f"with the end orientation (A3 B3 C3) and {' '.join(want)} is simulated; "
                           "the opening angle NUT, polynomials and other forms are not", src)
    v = tuple(float(words.get(k, (0.0, None))[0]) for k in want)
    if not math.hypot(*v) > 1e-12:
        raise ProgramError("invalid_value", "the cone's vector is zero", src)
    if machine.ori.workpiece and machine.frames.rotated:
        lin = machine.frames.lin
        v = tuple(sum(lin[i][j] * v[j] for j in range(3)) for i in range(3))
    return v


def frame_of(machine) -> tuple[float, ...]:
    """The active frame as OrientedMove.frame: origin (3), then the row-major linear part."""
    frames = machine.frames
    return (*(frames.off.get(n, 0.0) for n in machine.geometry), *frames.rotation_flat())


def move(machine, v, src: SourceRef, suppress: bool) -> bool:
    """A motion block under TRAORI: one OrientedMove (the block's values, see the module
    docstring), True. Right after TRAFOOF: incremental words of unknown axes are refused, and
    False (the move is an ordinary one)."""
    check_known(machine, v.axes, src)
    if machine.traori is None:
        return False
    words = {k: v.interp.pop(k) for k in WORDS if k in v.interp} if v.interp else {}
    cone = _cone(machine, {k: v.interp.pop(k) for k in CONE_WORDS if k in v.interp} if v.interp else {},
                 words, src)
    relative = oripath.take(machine, v, src)
    if machine.cutcom.engaged or machine.corners.holding or machine.corners.modal > 0:
        raise ProgramError("unsupported", "tool radius compensation, chamfers or roundings under TRAORI "
                           "are not simulated", src)
    rot = machine.traori.rotaries
    swivel.current(machine, src)                     # G54 … under CYCLE800: the swivel stays
    new = machine._targets(v, src, suppress) if v.axes else dict(machine.pos)
    learned(machine, v.axes, new, suppress)
    direct = any(w.name in rot for w, _ in v.axes)
    vec = vector(machine, words, src)
    if vec is not None and direct:
        raise ProgramError("syntax", "a block programs the orientation either by the rotary axes or by "
                           "a vector or angles, not both", src)
    axes = dict(new)
    for r in rot:
        if not any(w.name == r for w, _ in v.axes):
            axes[r] = math.nan
    carried = toolcarrier.active(machine) and not suppress
    if carried and vec is not None:
        raise ProgramError("unsupported", "an orientation vector or angles under TCARR without TRAORI "
                           "(program the rotary axes)", src)
    motion = machine.motion
    if motion in ("G1", "G2", "G3", "CIP", "CT") and machine.feed <= 0:
        raise ProgramError("zero_feed", "feed move with F0 (no feed programmed)", src)
    kw: dict = {}
    frames, g = machine.frames, machine.geometry
    if frames.rotated and not suppress and any(new[n] != new[n] for n in g):
        # the tip partly unknown under a rotated frame: the programmed program coordinates
        scale = 25.4 if machine.inch else 1.0
        prog = {w.name: float(val) * scale for w, val in v.axes if w.name in g}
        axes.update({n: prog.get(n, math.nan) for n in g})
        kw["frame"] = frame_of(machine)
    if motion in ("G0", "G1"):
        kind = "traverse" if motion == "G0" else "feed"
    else:
        if "frame" in kw:
            raise ProgramError("unsupported", "a circle as the first move after TRAORI, CYCLE800 or "
                               "TRAFOOF under a rotated frame (its start is only known to the machine)", src)
        tilted = (frames.rotated or carried) and not suppress   # the circle in the frame's plane
        arc, _ = machine.arc(v, src, new, suppress, in_program=tilted)
        axes = {k: (axes[k] if k in rot else arc.axes[k]) for k in axes}
        kind = "arc"
        kw = dict(plane=arc.plane, center=arc.center, clockwise=arc.clockwise, turns=arc.turns)
        if tilted:
            kw["frame"] = frame_of(machine)
    if not carried and vec is None and not direct:   # LEAD/TILT, ORIPATH: from the path
        arc = None
        if kind == "arc":
            lin = frames.lin if "frame" in kw else ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
            arc = (kw["plane"], kw["center"], tuple(axes[n] for n in g), kw["clockwise"], lin)
        vec = oripath.vector(machine, relative, tuple(machine.pos[n] for n in g),
                             tuple(new[n] for n in g), arc, src)
    elif relative and ("LEAD" in relative or "TILT" in relative):
        raise ProgramError("syntax", "a block programs the orientation either by LEAD/TILT or by the "
                           "rotary axes, a vector or angles, not both", src)
    if carried:                      # the program point through the frames and the table
        if kind != "arc":
            axes.update(zip(g, frames.to_program(tuple(new[n] for n in g)), strict=True))
        kw["frame"] = toolcarrier.frame(machine, new, src)
        kw["hold_axes"] = not any(w.name in g for w, _ in v.axes)
    machine.sink.append(canon.OrientedMove(src, motion=kind, axes=axes, vector=vec,
                                           interpolation=machine.ori.interpolation.replace(
                                               "path", "vector"), cone=cone,
                                           feed=0.0 if kind == "traverse" else machine.feed, **kw))
    if vec is not None:
        for r in rot:
            new[r] = math.nan
        machine.unknown |= set(rot)
    machine.pos = new
    return True
