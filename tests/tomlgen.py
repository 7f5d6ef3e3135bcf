"""Writing TOML back from parsed data, for tests that mutate models, tool libraries and setup
files value by value (tests/test_fuzz_inputs.py). Only what ``tomllib`` returns is handled:
tables, arrays, arrays of tables, strings, integers, floats, booleans, dates and times."""

from __future__ import annotations

import datetime as dt
import json
import math
from collections.abc import Iterator
from typing import Any

#: one value of each TOML type, and the awkward ones of each (what a typo or an attacker writes)
EVERY_TYPE: tuple[Any, ...] = (
    {}, {"a": 1}, [], [1, "a"], [[1, 2], [3]], [{"x": 1}],
    0, -1, 1, 2**63 - 1, -(2**63),
    0.0, -0.0, 1e-300, 1e300, math.inf, -math.inf, math.nan,
    True, False,
    "", "x", "sinumerik", "é\u0000", "a" * 300,
    dt.date(1979, 5, 27), dt.time(7, 32), dt.datetime(1979, 5, 27, 7, 32),
)


def value(v: Any) -> str:
    """``v`` as an inline TOML value."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, dt.date | dt.time):
        return v.isoformat()
    if isinstance(v, list):
        return "[" + ", ".join(value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{key(k)} = {value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def key(k: str) -> str:
    return k if k and all(c.isalnum() or c in "_-" for c in k) else json.dumps(k)


def dumps(data: dict) -> str:
    """A TOML document for ``data``: scalars and inline arrays first, then sub-tables and arrays
    of tables, as a person writes a model."""
    out: list[str] = []
    _table(data, (), out)
    return "\n".join(out) + "\n"


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def _table(data: dict, path: tuple, out: list[str]) -> None:
    for k, v in data.items():
        if not isinstance(v, dict) and not _is_table_array(v):
            out.append(f"{key(k)} = {value(v)}")
    for k, v in data.items():
        sub = (*path, key(k))
        if isinstance(v, dict):
            out.append(f"\n[{'.'.join(sub)}]")
            _table(v, sub, out)
        elif _is_table_array(v):
            for item in v:
                out.append(f"\n[[{'.'.join(sub)}]]")
                _table(item, sub, out)


def leaves(data: Any, path: tuple = ()) -> Iterator[tuple]:
    """The path of every value in ``data`` (keys and list indices), tables' own paths too."""
    if path:
        yield path
    if isinstance(data, dict):
        for k, v in data.items():
            yield from leaves(v, (*path, k))
    elif isinstance(data, list):
        for i, v in enumerate(data):
            yield from leaves(v, (*path, i))


def replaced(data: Any, path: tuple, new: Any) -> Any:
    """A copy of ``data`` with the value at ``path`` replaced by ``new``."""
    if not path:
        return new
    head, rest = path[0], path[1:]
    if isinstance(data, dict):
        return {k: (replaced(v, rest, new) if k == head else v) for k, v in data.items()}
    return [replaced(v, rest, new) if i == head else v for i, v in enumerate(data)]
