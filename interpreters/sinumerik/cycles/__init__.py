"""Siemens standard milling, boring and tapping cycles expanded into canonical moves as the
control executes them: face milling (CYCLE71, CYCLE61), pockets (POCKET3, POCKET4), spigots
(CYCLE76, CYCLE77), slots (LONGHOLE, SLOT1, SLOT2), boring and reaming (CYCLE85–CYCLE89),
tapping (CYCLE84, CYCLE840).

The parameter lists are data (``parameters.toml``: the classic lists of the 840D "Cycles"
manual and what SINUMERIK Operate appends); each family is one module. Every move a call
makes carries the calling block's :class:`~vmach.source.SourceRef` with the cycle's phase
(``roughing depth 2/3 ring 4/6``), so a finding names the call and the part of the cycle.

The door: :data:`NAMES` (what this package expands), :data:`MODAL` (what ``MCALL`` may call:
the cycles that work at the current position), :func:`run` and :func:`modal`.
"""

from __future__ import annotations

from interpreters.sinumerik.cycles import (
    boring,
    contour,
    engraving,
    facing,
    measuring,
    pockets,
    positions,
    slots,
    spigots,
)
from interpreters.sinumerik.cycles.common import Context
from interpreters.sinumerik.cycles.parameters import SPECS, bind
from interpreters.sinumerik.cycles.path import TooMany
from interpreters.sinumerik.drilling import drill
from vmach.errors import ProgramError
from vmach.source import SourceRef

_EXPAND = {
    "CYCLE71": facing.face, "CYCLE61": facing.face,
    "POCKET3": pockets.rectangular, "POCKET4": pockets.circular,
    "CYCLE76": spigots.rectangular, "CYCLE77": spigots.circular, "CYCLE79": spigots.polygon,
    "LONGHOLE": slots.longhole, "SLOT1": slots.slot1, "SLOT2": slots.slot2,
    "CYCLE84": boring.tap, "CYCLE840": boring.tap,
    "CYCLE85": boring.bore, "CYCLE86": boring.bore, "CYCLE87": boring.bore,
    "CYCLE88": boring.bore, "CYCLE89": boring.bore,
    "CYCLE60": engraving.engrave, "CYCLE72": contour.mill,
    "CYCLE976": measuring.measure, "CYCLE977": measuring.measure, "CYCLE978": measuring.measure,
    "CYCLE979": measuring.measure, "CYCLE998": measuring.measure,
    "CYCLE802": lambda ctx: positions.positions(ctx, modal),
}
if set(_EXPAND) != set(SPECS):
    raise ImportError("parameters.toml and the expansion modules name different cycles")

#: every cycle this package expands
NAMES = frozenset(_EXPAND)
#: the cycles ``MCALL`` may call modally (they work at the current position)
MODAL = frozenset(n for n, spec in SPECS.items() if spec.family == "boring")


def run(machine, name: str, args, src: SourceRef) -> None:
    """Expand the call ``name(args)`` at the machine's current state into its moves."""
    try:
        _EXPAND[name](Context(machine, bind(name, args, src), src))
    except TooMany as e:
        raise ProgramError("cycle_parameter", f"{name}: {e}", src) from None


def modal(machine, src: SourceRef) -> None:
    """Run the cycle ``MCALL`` made modal (``machine.mcall``) at the current position."""
    name, args = machine.mcall
    (run if name in MODAL else drill)(machine, name, args, src)
