"""A model file's ``[timing]`` table → :class:`vmach.machine.spec.TimingSpec`.

Schema (seconds unless stated; every key optional)::

    [timing]
    tool_change_s = 2.0
    spindle_start_s = 1.5
    spindle_stop_s = 1.0
    spindle_change_s = 0.5
    corner_overload = 1.2        # > 1 (1.0 would stop at every corner)
    ipo_cycle_s = 0.004
    [timing.cycles]
    C_AXIS_ON = 2.0

An unknown key is reported (a misspelt time would silently count as 0 s).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol

from vmach.machine.spec import TimingSpec


class Reader(Protocol):
    """What the timing table is read with: the model loader's reader
    (:class:`vmach.machine.loader.Reader`), named here by its shape so that this module does not
    import the loader that imports it."""

    raw: Mapping[str, Any]
    problems: list

    def table(self, value: Any, key: tuple, what: str) -> Mapping[str, Any]: ...

    def scalar(self, value: Any, key: tuple, what: str) -> float | None: ...

    def rate(self, value: Any, key: tuple, what: str) -> float | None: ...

    def err(self, kind: str, msg: str, key: tuple, fallback: tuple = ("formula",)) -> None: ...

TIMES = ("tool_change_s", "spindle_start_s", "spindle_stop_s", "spindle_change_s")


def read_timing(r: Reader) -> TimingSpec:
    """Read ``[timing]``; problems go to ``r.problems`` with their line."""
    if "timing" not in r.raw:
        return TimingSpec()
    t = r.table(r.raw["timing"], ("timing",), "timing")
    values: dict[str, float] = {}
    for key, value in t.items():
        where = ("timing", key)
        if key in TIMES:
            v = r.scalar(value, where, f"timing.{key}")
            if v is not None and v < 0:
                r.err("bad_value", f"timing.{key} must be >= 0 s", where)
            elif v is not None:
                values[key] = v
        elif key == "corner_overload":
            v = r.scalar(value, where, "timing.corner_overload")
            if v is not None and v < 1.0:
                r.err("bad_value", "timing.corner_overload must be >= 1", where)
            elif v is not None:
                values[key] = v
        elif key == "ipo_cycle_s":
            v = r.rate(value, where, "timing.ipo_cycle_s")
            if v is not None:
                values[key] = v
        elif key != "cycles":
            known = ", ".join((*TIMES, "corner_overload", "ipo_cycle_s", "cycles"))
            r.err("bad_value", f"timing.{key} is not a timing key (known: {known})", where)
    cycles: dict[str, float] = {}
    for name, value in r.table(t.get("cycles", {}), ("timing", "cycles"), "timing.cycles").items():
        where = ("timing", "cycles", name)
        v = r.scalar(value, where, f"timing.cycles.{name}")
        if v is not None and v < 0:
            r.err("bad_value", f"timing.cycles.{name} must be >= 0 s", where)
        elif v is not None:
            cycles[name] = v
    return TimingSpec(stated=True, cycles=cycles, **values)
