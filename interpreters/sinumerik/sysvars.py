"""The catalogue of system variables (``sysvars.toml``, data, not code): what a ``$`` name is,
which indices it takes, its type, default and whether a program may write it.

Read once at import. :func:`lookup` is what the expression parser asks; the NCK state
(:mod:`interpreters.sinumerik.nck`) handles each *kind* of variable with one handler.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

KINDS = ("machine_data", "setting_data", "swivel", "program", "frame", "main_run", "plc", "tool")
TYPES = ("INT", "REAL", "BOOL", "STRING", "AXIS", "FRAME")
INDEX_KINDS = ("axis", "n", "comp", "any")     # any: an axis name if it is one, else as given
#: the variables whose type differs from their family's (``$TC_TP2`` is the tool's name)
TYPE_OF = {"$TC_TP2": "STRING"}


@dataclass(frozen=True, slots=True)
class SysVar:
    """One system variable.

    name : with ``$`` (``$MA_POS_LIMIT_PLUS``); kind : one of :data:`KINDS`; type : one of
    :data:`TYPES`; shapes : the index lists it takes, each a tuple of :data:`INDEX_KINDS`
    (``()`` = no index); default : value before anything is given or written; writable : a
    part program may assign it; md : machine/setting data number or None.
    """

    name: str
    kind: str
    type: str
    shapes: tuple[tuple[str, ...], ...]
    default: Any
    writable: bool
    md: int | None = None

    def shape(self, count: int) -> tuple[str, ...] | None:
        """The index list of ``count`` indices this variable takes, else None."""
        for s in self.shapes:
            if len(s) == count:
                return s
        return None

    def describe_shapes(self) -> str:
        return " or ".join(f"[{', '.join(s)}]" if s else "no index" for s in self.shapes)


def _default(typ: str, value: Any) -> Any:
    if value is None:
        return {"INT": 0, "REAL": 0.0, "BOOL": 0, "STRING": "", "AXIS": "", "FRAME": None}[typ]
    if typ == "REAL":
        return float(value)
    if typ in ("INT", "BOOL"):
        return int(value)
    return value


_DATA = tomllib.loads(Path(__file__).with_name("sysvars.toml").read_text("utf-8"))


def _load() -> dict[str, SysVar]:
    data = _DATA
    out: dict[str, SysVar] = {}
    for name, e in data.items():
        if not name.startswith("$"):
            continue
        kind, typ = e["kind"], e["type"]
        if kind not in KINDS or typ not in TYPES or e.get("access", "r") not in ("r", "rw"):
            raise ValueError(f"sysvars.toml: {name}: bad kind, type or access")
        shapes = tuple(tuple(p for p in s.split(",") if p) for s in e.get("index", [""]))
        if any(p not in INDEX_KINDS for s in shapes for p in s):
            raise ValueError(f"sysvars.toml: {name}: bad index kind")
        names = [name]
        if "range" in e:
            lo, hi = e["range"]
            names = [f"{name}{k}" for k in range(lo, hi + 1)]
        for n in names:
            t = TYPE_OF.get(n, typ)
            default = "" if t == "STRING" and typ != "STRING" else e.get("default")
            var = SysVar(n, kind, t, shapes, _default(t, default), e.get("access") == "rw", e.get("md"))
            if "range" in e:
                out.setdefault(n, var)      # a family: a name listed on its own wins
            else:
                out[n] = var
    return out


CATALOG: dict[str, SysVar] = _load()


def _groups() -> dict[int, tuple[str, ...]]:
    raw = _DATA["groups"]
    out = {int(k): tuple(v) for k, v in raw.items()}
    out[8] += tuple(f"G{n}" for n in range(505, 600))
    return out


#: G group number -> its codes in the control's order ($P_GG gives the 1-based position)
GROUPS: dict[int, tuple[str, ...]] = _groups()


#: machine and setting data vmach does not list: readable when the model gives them
GENERIC = re.compile(r"^\$(M[NCA]|S[NCA])_[A-Z0-9_]+$")
_ANY_INDEX = ((), ("any",), ("any", "any"), ("any", "any", "any"))


def lookup(name: str) -> SysVar | None:
    """The system variable ``name`` (upper case, with ``$``), or None when vmach has no such
    variable. Machine and setting data the catalogue does not list (``$MC_…``, ``$SA_…``) are
    known with no default (``default`` None): the model's ``[machine_data]`` must give them."""
    var = CATALOG.get(name)
    if var is None and GENERIC.match(name):
        kind = "setting_data" if name[1] == "S" else "machine_data"
        var = SysVar(name, kind, "REAL", _ANY_INDEX, None, kind == "setting_data")
    return var
