"""Where a key of a TOML file is written: key path -> (line, column).

``tomllib`` returns plain data without positions, so a model problem found after parsing is
located by scanning the text once: table headers (``[a.b]``, ``[[a]]`` with a running index per
array of tables, nested arrays of tables included) and ``key = value`` lines (dotted keys too).
Multi-line arrays and inline tables are skipped as values. A key path is a tuple of keys and
array indices, ``("joints", 2, "axis")``; :meth:`KeyLines.find` returns the place of the longest
prefix that is written in the file, so a *missing* key points at its table's header.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from vmach.source import SourceRef

_BARE = re.compile(r"[A-Za-z0-9_-]+")


def _split_key(text: str) -> list[str]:
    """Split a (possibly dotted, possibly quoted) key into its parts."""
    parts: list[str] = []
    i, n = 0, len(text)
    while i < n:
        ch = text[i]
        if ch in " \t.":
            i += 1
        elif ch in "\"'":
            j = text.find(ch, i + 1)
            j = n if j < 0 else j
            parts.append(text[i + 1 : j])
            i = j + 1
        else:
            m = _BARE.match(text, i)
            if not m:
                break
            parts.append(m.group(0))
            i = m.end()
    return parts


def _depth_change(line: str) -> int:
    """Net count of open brackets/braces outside strings and comments."""
    depth, quote = 0, ""
    i = 0
    while i < len(line):
        ch = line[i]
        if quote:
            if ch == "\\" and quote == '"':
                i += 1
            elif ch == quote:
                quote = ""
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            break
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        i += 1
    return depth


@dataclass(frozen=True)
class KeyLines:
    """Positions of the keys and headers of one TOML text."""

    path: str
    lines: tuple[str, ...]
    places: dict[tuple, tuple[int, int]]

    @classmethod
    def scan(cls, text: str, path: str = "<model>") -> KeyLines:
        lines = tuple(text.splitlines())
        places: dict[tuple, tuple[int, int]] = {}
        arrays: dict[tuple, int] = {}
        table: tuple = ()
        depth = 0
        for no, raw in enumerate(lines, start=1):
            if depth > 0:  # continuation of a multi-line value
                depth += _depth_change(raw)
                continue
            stripped = raw.strip()
            col = len(raw) - len(raw.lstrip()) + 1
            if not stripped or stripped.startswith("#"):
                continue
            if stripped.startswith("[["):
                end = stripped.find("]]")
                names = _split_key(stripped[2:end])
                table = cls._resolve(names, arrays, new_array=True)
                places.setdefault(table, (no, col))
                continue
            if stripped.startswith("["):
                end = stripped.find("]")
                names = _split_key(stripped[1:end])
                table = cls._resolve(names, arrays, new_array=False)
                places.setdefault(table, (no, col))
                continue
            eq = _find_eq(stripped)
            if eq < 0:
                continue
            key = tuple(_split_key(stripped[:eq]))
            if key:
                places.setdefault(table + key, (no, col))
            depth = _depth_change(stripped[eq + 1 :])
        return cls(path, lines, places)

    @staticmethod
    def _resolve(names: list[str], arrays: dict[tuple, int], new_array: bool) -> tuple:
        prefix: tuple = ()
        for i, name in enumerate(names):
            prefix = prefix + (name,)
            last = i == len(names) - 1
            if last and new_array:
                arrays[prefix] = arrays.get(prefix, 0) + 1
                prefix = prefix + (arrays[prefix] - 1,)
            elif prefix in arrays:
                prefix = prefix + (arrays[prefix] - 1,)
        return prefix

    def find(self, key: tuple) -> SourceRef:
        """SourceRef of ``key`` or of its longest written prefix (line 1 if none)."""
        k = tuple(key)
        while k:
            if k in self.places:
                line, col = self.places[k]
                return SourceRef(self.path, line, col, self.lines[line - 1])
            k = k[:-1]
        return SourceRef(self.path, 1, 1, self.lines[0] if self.lines else "")


def _find_eq(s: str) -> int:
    """Index of the ``=`` that separates a key from its value (outside quoted keys)."""
    quote = ""
    for i, ch in enumerate(s):
        if quote:
            if ch == quote:
                quote = ""
        elif ch in "\"'":
            quote = ch
        elif ch == "=":
            return i
        elif ch == "#":
            return -1
    return -1
