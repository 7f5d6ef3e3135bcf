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


CODES, WORDS = _load()
ACCEPTED_WORDS = frozenset(WORDS["accepted"])
STATEMENTS = frozenset(WORDS["statements"])
PROC_ATTRIBUTES = frozenset(WORDS["proc_attributes"])
TYPES = frozenset(WORDS["types"])
UNSUPPORTED_WORDS = frozenset(WORDS["unsupported"])
