"""The standard cycles' parameter lists (``parameters.toml`` beside this module) and the
binding of a call's values to them.

A call gives its values in the list's order; a value left out (``POCKET3(10,0,2,,…)``) or
missing at the end takes the parameter's default. The classic list comes first; SINUMERIK
Operate's additions follow it, so one table reads both forms. Lengths are converted to mm
under G70/G700 by the expansion modules (they know which values are lengths).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

from vmach.errors import ProgramError
from vmach.source import SourceRef


@dataclass(frozen=True, slots=True)
class Parameter:
    """One parameter: ``name`` as the manual spells it, ``type`` "real", "int" or "string",
    its ``default`` (a string parameter's is "") and what it means; ``operate`` when
    SINUMERIK Operate added it."""

    name: str
    type: str
    default: float | str
    meaning: str
    operate: bool = False


@dataclass(frozen=True, slots=True)
class CycleSpec:
    """A cycle: its name, the expansion family, what it machines and its parameters."""

    name: str
    family: str
    meaning: str
    parameters: tuple[Parameter, ...]


@dataclass(frozen=True, slots=True)
class Call:
    """A call bound to its cycle's parameters.

    values : name (without a leading underscore, upper case) -> the value (float, ints as
        float; str for a "string" parameter); given : the names the call gave a value for.
    """

    spec: CycleSpec
    values: MappingProxyType
    given: frozenset

    def __getitem__(self, name: str) -> float:
        return self.values[name]

    def has(self, name: str) -> bool:
        return name in self.given


def load(path: Path | None = None) -> dict[str, CycleSpec]:
    """The cycles of a parameter file (``parameters.toml`` beside this module by default)."""
    path = path or Path(__file__).with_name("parameters.toml")
    raw = tomllib.loads(path.read_text(encoding="utf-8"))
    out = {}
    for name, t in raw.items():
        ps = [Parameter(n, ty, "" if ty == "string" else float(d), m) for n, ty, d, m in t["classic"]]
        ps += [Parameter(n, ty, "" if ty == "string" else float(d), m, True)
               for n, ty, d, m in t.get("operate", [])]
        out[name] = CycleSpec(name, t["family"], t["meaning"], tuple(ps))
    return out


#: every cycle vmach expands, by name
SPECS: dict[str, CycleSpec] = load()


def key(name: str) -> str:
    """The name a parameter is looked up by (``_RTP`` and ``RTP`` alike: ``RTP``)."""
    return name.lstrip("_").upper()


def bind(name: str, args, src: SourceRef, specs: dict[str, CycleSpec] | None = None) -> Call:
    """The call's values by parameter (left out: the default). More values than the cycle
    has parameters is ``call_arguments``; text or a truth value for a number ``type_error``;
    a fractional value for an "int" parameter ``cycle_parameter``. ``specs``: where the
    cycle is described (:data:`SPECS` by default)."""
    spec = (specs or SPECS)[name]
    ps = spec.parameters
    if len(args) > len(ps):
        raise ProgramError("call_arguments", f"{name} takes {len(ps)} parameters, got {len(args)}", src)
    values, given = {}, set()
    for i, p in enumerate(ps):
        v = args[i] if i < len(args) else None
        if v is None:
            values[key(p.name)] = p.default
            continue
        if p.type == "string":
            if not isinstance(v, str):
                raise ProgramError("type_error", f"{name}: {p.name} needs a string", src)
            values[key(p.name)] = v
            given.add(key(p.name))
            continue
        if isinstance(v, (str, bool)):
            raise ProgramError("type_error", f"{name}: {p.name} needs a number", src)
        v = float(v)
        if p.type == "int" and v != int(v):
            raise ProgramError("cycle_parameter", f"{name}: {p.name} must be a whole number, got {v:g}",
                               src, parameter=p.name, value=v)
        values[key(p.name)] = v
        given.add(key(p.name))
    return Call(spec, MappingProxyType(values), frozenset(given))
