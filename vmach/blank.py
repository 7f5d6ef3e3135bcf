"""The blank a program declares itself: Sinumerik ``WORKPIECE(...)`` → a ``--stock`` spec.

SINUMERIK Operate writes the blank into the program header, e.g. for turning
``WORKPIECE(,"",,"CYLINDER",192,0,-100,-80,60)``: argument 4 the form, then a bit mask, ZA (the
blank's top, mm), ZI (its bottom: absolute when below ZA, else a length), ZB (the machining
limit, unused here) and the form's sizes — for ``CYLINDER`` the outer diameter XA, for
``PIPE`` XA and the inner diameter XI (a pipe is simulated as a full cylinder and said so),
for ``BOX``/``RECTANGLE`` the corners X0, Y0, X1, Y1 (milling). The argument layout is taken
from programs the control writes; unknown forms are reported, never guessed.
"""

from __future__ import annotations

from collections.abc import Sequence

from vmach import canon
from vmach.errors import InputError


def _num(args: Sequence, i: int, what: str, src) -> float:
    if i >= len(args) or not isinstance(args[i], (int, float)) or isinstance(args[i], bool):
        raise InputError(
            f"WORKPIECE: argument {i + 1} ({what}) must be a number", kind="workpiece", source=src
        )
    return float(args[i])


def stock_from_program(commands: Sequence[canon.Command]) -> tuple[str, list[str]] | None:
    """The stock spec of the first WORKPIECE(...) in the stream, and notes; None without one."""
    call = next((c for c in commands if isinstance(c, canon.CycleCall) and c.name == "WORKPIECE"), None)
    if call is None:
        return None
    args, src, notes = list(call.args), call.source, []
    form = str(args[3]).upper() if len(args) > 3 and isinstance(args[3], str) else ""
    za = _num(args, 5, "ZA", src)
    zi = _num(args, 6, "ZI", src)
    bottom = zi if zi < za else za - zi
    length = za - bottom
    if length <= 0:
        raise InputError("WORKPIECE: the blank has no length (ZI)", kind="workpiece", source=src)
    if form in ("CYLINDER", "PIPE"):
        d = _num(args, 8, "XA", src)
        if form == "PIPE":
            notes.append("WORKPIECE PIPE simulated as a full cylinder (no bore)")
        return f"cylinder:d={d:g},l={length:g},z={za:g}", notes
    if form in ("BOX", "RECTANGLE"):
        x0, y0, x1, y1 = (
            _num(args, i, n, src) for i, n in zip(range(8, 12), ("X0", "Y0", "X1", "Y1"), strict=True)
        )
        return (
            f"box:xmin={min(x0, x1):g},xmax={max(x0, x1):g},ymin={min(y0, y1):g},ymax={max(y0, y1):g},"
            f"zmin={bottom:g},zmax={za:g}",
            notes,
        )
    raise InputError(
        f"WORKPIECE: blank form {form or args[3:4]!r} is not simulated (CYLINDER, PIPE, BOX)",
        kind="workpiece",
        source=src,
    )
