"""Language facts loaded once from ``language.toml`` (data, not code)."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True, slots=True)
class Code:
    """A G code or G-group keyword (``G1``, ``DIAMON``, ``TRAFOOF``).

    status : "codes" (simulated), "accepted" (no modelled effect) or "unsupported".
    """

    name: str
    group: int
    group_name: str
    modal: bool
    status: str


def _load() -> tuple[dict[str, Code], dict[str, list[str]]]:
    data = tomllib.loads((Path(__file__).with_name("language.toml")).read_text("utf-8"))
    codes: dict[str, Code] = {}
    for g in data["group"]:
        names = {status: list(g.get(status, ())) for status in ("codes", "accepted", "unsupported")}
        if g["name"] == "settable_offset":
            names["codes"] += [f"G{n}" for n in range(505, 600)]
        for status, lst in names.items():
            for name in lst:
                codes[name] = Code(name, g["number"], g["name"], g["modal"], status)
    return codes, data["words"]


@dataclass(frozen=True, slots=True)
class Command:
    """A predefined command that is not a G-group code (``commands.toml``).

    kind : "keyword", "procedure", "value", "axis_value", "position", "alarm",
        "setting_cycle" or "cycle" (one handler each in ``commands.py``)
    effect : what it does on the control (for the ``no_effect`` info and the docs)
    """

    name: str
    kind: str
    effect: str


def _load_commands() -> dict[str, Command]:
    data = tomllib.loads((Path(__file__).with_name("commands.toml")).read_text("utf-8"))
    out: dict[str, Command] = {}
    for entry in data["command"]:
        for name in entry["names"]:
            if name in out:
                raise ValueError(f"commands.toml: {name} is listed twice")
            out[name] = Command(name, entry["kind"], entry["effect"])
    return out


CODES, WORDS = _load()
COMMANDS = _load_commands()
ACCEPTED_WORDS = frozenset(n for n, c in COMMANDS.items() if c.kind == "keyword")
STATEMENTS = frozenset(WORDS["statements"])
PROC_ATTRIBUTES = frozenset(WORDS["proc_attributes"])
TYPES = frozenset(WORDS["types"])
UNSUPPORTED_WORDS = frozenset(WORDS["unsupported"])
UNSUPPORTED_FUNCTIONS = frozenset(WORDS["unsupported_functions"])
