"""Turning on SINUMERIK: thread cutting G33/G34/G35 (:mod:`.threads`) and the standard
turning cycles — grooves CYCLE93, undercuts CYCLE94/CYCLE96, threads CYCLE97 — expanded into
canonical moves that carry the calling block, as the control executes them.

The door: :data:`NAMES` (the cycles this package expands) and :func:`run`.
"""

from __future__ import annotations

from pathlib import Path

from interpreters.sinumerik.cycles.common import Context
from interpreters.sinumerik.cycles.parameters import bind, load
from interpreters.sinumerik.cycles.path import TooMany
from interpreters.sinumerik.turning.thread_cycle import cycle97
from vmach.errors import ProgramError
from vmach.source import SourceRef

#: the turning cycles' parameter lists (``parameters.toml`` beside this module)
SPECS = load(Path(__file__).with_name("parameters.toml"))
_EXPAND = {"CYCLE97": cycle97}
if set(_EXPAND) != set(SPECS):
    raise ImportError("turning/parameters.toml and the expansion modules name different cycles")

#: every turning cycle this package expands
NAMES = frozenset(_EXPAND)


def run(machine, name: str, args, src: SourceRef) -> None:
    """Expand the call ``name(args)`` at the machine's current state into its moves."""
    try:
        _EXPAND[name](Context(machine, bind(name, args, src, SPECS), src))
    except TooMany as e:
        raise ProgramError("cycle_parameter", f"{name}: {e}", src) from None
