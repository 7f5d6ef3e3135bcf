"""The orientable tool carrier TCARR and the frames it lends: TOROT, TOFRAME, PAROT (Programming
Manual Job Planning, "Orientable toolholders"; Function Manual K2, "TCARR and PAROT").

``TCARR=1`` selects swivel data record 1 — the model's own, derived from its chain
(``$TC_CARR7…12`` axis vectors, reversed for an axis that turns the part, ``$TC_CARR23`` the
kinematic type T/P/M, ``$TC_CARR35/36`` the axis names: vmach/machine/machdata.py). From then
on the rotary axes are programmed directly (``G0 B30 C45``) and the control keeps the tool
length along the turned tool and the workpiece zero on the turned table: the program's X Y Z
(after the frames) are **machine-parallel**, and the tool tip on the part is

    tip_part = off + R_tableᵀ · lin · p

with ``p`` the program point, ``off`` and ``lin`` the frames' translation and linear part,
``R_table`` the rotation the table axes give the part (identity on a head machine, T). A block
that programs only rotary axes turns them with the linear axes holding still (the tip moves
with the part, as on the machine without TRAORI).

- ``PAROT`` puts the table's rotation ``R_table`` into the programmable frame's rotation: the
  workpiece coordinate system turns with the part, so X Y Z are on the part again (P and M).
- ``TOROT`` / ``TOFRAME`` put the tool's rotation ``R_tool`` there: Z along the turned tool
  (T and M; on a table machine the tool does not turn: identity). TOFRAME is TOROT here (SD42980
  $SC_TOFRAME_MODE 2000, "as for swivelling").
- ``PAROTOF`` / ``TOROTOF`` take the rotation out again; ``TCARR=0`` ends the tool carrier
  (positions become "where the machine is", as after TRAFOOF).

The rotations come from the rotary positions programmed at the time (an unknown position is
``unsupported``). Records other than 1, TCOABS/TCOFR and TOROTX… are not simulated.
"""

from __future__ import annotations

from interpreters.sinumerik.frames import IDENTITY, matmul
from interpreters.sinumerik.swivel import _carr, rotations, transpose
from vmach.errors import ProgramError
from vmach.source import SourceRef

#: G group 53 codes simulated here
CODES = ("TOROT", "TOFRAME", "PAROT", "TOROTOF", "PAROTOF")


def active(machine) -> bool:
    return machine.traori is not None and machine.traori.name == "TCARR"


def select(machine, value, src: SourceRef, orientation) -> None:
    """``TCARR=n``; ``orientation`` gives activate/deactivate (orientation.py)."""
    if isinstance(value, str) or value != int(value):
        raise ProgramError("type_error", "TCARR=n needs the number of a swivel data record", src)
    n = int(value)
    if n == 0:
        if active(machine):
            if machine.frames.rot != IDENTITY and getattr(machine, "carrier_frame", None):
                _rotate(machine, None, src)
            machine.out.append(orientation.deactivate(machine, src))
        return
    if n != 1:
        raise ProgramError("unsupported", f"TCARR={n}: vmach has swivel data record 1 only (the "
                           "machine's own)", src)
    if not any(float(_carr(machine, k) or 0.0) for k in (7, 8, 9)):
        raise ProgramError("unsupported", "TCARR: the machine has no swivel data ($TC_CARR7…12) for "
                           "its rotary axes", src)
    if active(machine):
        return
    pos, unknown = dict(machine.pos), set(machine.unknown)
    machine.out.append(orientation.activate(machine, [], src, name="TCARR"))
    machine.pos, machine.unknown = pos, unknown        # the program's positions stay known


def code(machine, name: str, src: SourceRef) -> None:
    """TOROT, TOFRAME, PAROT and their OFF codes (G group 53)."""
    if name in ("TOROTOF", "PAROTOF"):
        if getattr(machine, "carrier_frame", None):
            _rotate(machine, None, src)
        return
    if not active(machine):
        raise ProgramError("unsupported", f"{name} without an orientable tool carrier (TCARR=1) is "
                           "not simulated", src)
    tool, table = rotations(machine, machine.pos, src)
    _rotate(machine, table if name == "PAROT" else tool, src)
    machine.carrier_frame = name


def _rotate(machine, m, src: SourceRef) -> None:
    machine.frames.rot = IDENTITY if m is None else m
    machine.frames.refresh()
    machine.carrier_frame = None
    machine.emit_frame(src)


def frame(machine, new: dict, src: SourceRef) -> tuple[float, ...]:
    """OrientedMove.frame of a block under TCARR ending at ``new`` (rotary values there):
    origin ``off``, linear ``R_tableᵀ · lin``."""
    _, table = rotations(machine, new, src)
    frames = machine.frames
    lin = matmul(transpose(table), frames.lin)
    return (*(frames.off.get(n, 0.0) for n in machine.geometry), *(v for row in lin for v in row))
