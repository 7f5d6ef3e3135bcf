"""Macros: ``DEFINE <name> AS <text>`` (Programming Manual Job planning, "Macro technique").

A macro stands for the NC text after ``AS``; wherever its name stands as a word of a block, the
control reads the text instead (``DEFINE RETRACT AS G0 SUPA Z0 D0`` … ``N20 RETRACT``). Macros
come from the macro definition files (``_N_SMAC_DEF``, ``_N_MMAC_DEF``, ``_N_UMAC_DEF``, read by
``definitions.py`` from the program's directory) and from ``DEFINE`` lines of the program
itself, which count from their line on. A name is an identifier, a G, M or H function
(``DEFINE M6 AS L6``); the text is read once (a macro inside a macro is not expanded again) and
strings and comments are left alone. vmach reports positions in the expanded block as if the
macro's text stood where its name does.
"""

from __future__ import annotations

import re

#: ``[N10] DEFINE NAME AS text``
_DEFINE = re.compile(r"^\s*(?:N\d+\s+)?DEFINE\s+([A-Z_$][A-Z0-9_]*)\s+AS\s+(.*?)\s*$", re.IGNORECASE)
#: a word of a block, or a string (left alone)
_WORD = re.compile(r'"[^"]*"|[A-Za-z_][A-Za-z0-9_]*')


def definition(code: str) -> tuple[str, str] | None:
    """``(NAME, text)`` when ``code`` (a block without its comment) defines a macro."""
    m = _DEFINE.match(code)
    return (m.group(1).upper(), m.group(2)) if m else None


def expand(code: str, table: dict[str, str]) -> str:
    """``code`` with every word that names a macro of ``table`` replaced by its text."""
    if not table:
        return code

    def sub(m: re.Match) -> str:
        w = m.group(0)
        return w if w[0] == '"' else table.get(w.upper(), w)

    return _WORD.sub(sub, code)
