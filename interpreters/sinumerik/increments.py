"""Incremental moves after a frame change: setting data SD42440 ``$SC_FRAME_OFFSET_INCR_PROG``.

With 1 (the control's default) an axis's increment counts from its point as programmed under
the frame it was reached in, so a changed offset is traversed too (``X1``, ``TRANS X100``,
``X=IC(1)`` ends at machine 102); with 0 only the programmed distance (ends at 2).
``Machine.stale`` maps each axis not programmed since the last frame change to that frame.
"""

from __future__ import annotations

import copy

from vmach.canon import ControlSpec

NAME = "$SC_FRAME_OFFSET_INCR_PROG"


def traverses_offset(control: ControlSpec) -> bool:
    """SD42440 from the model's machine data (default 1)."""
    return bool((getattr(control, "machine_data", None) or {}).get(NAME, 1))


def frame_changes(machine) -> None:
    """Call before the frame changes: each axis keeps the frame its position was reached under."""
    if machine.incr_offset:
        before = copy.copy(machine.frames)
        machine.stale = {n: machine.stale.get(n, before) for n in machine.names}
