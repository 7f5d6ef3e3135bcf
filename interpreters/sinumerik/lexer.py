"""Tokens of one Sinumerik block (one line).

Identifiers are upper-cased (the NC language is case-insensitive); string literals keep their
case. An identifier made of an address letter and digits (``X10``, ``G0``, ``R85``, ``C1``) is a
single token; the parser splits it. A decimal part written right after it (``X10.5``) is glued
on, so ``X10.5`` is one token ``X10.5``.

Words need no separator (the NCK's rule, see :func:`split_words`): ``G0G90X0Y0`` is read as
``G0 G90 X0 Y0`` and ``N10G1X=R1`` as ``N10 G1 X=R1``, while a name (two letters or ``_``
first: ``GOTOF``, ``CYCLE81``, ``DEPTH``, ``CR``) is never split.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass

from vmach.errors import ProgramError
from vmach.source import SourceRef

NUM, STR, IDENT, OP, END = "num", "str", "ident", "op", "end"


@dataclass(frozen=True, slots=True)
class Token:
    kind: str
    text: str  # upper-cased for identifiers; the literal text for strings (without quotes)
    col: int  # 1-based column in the line
    value: float | int | str | None = None


_TOKEN = re.compile(
    r"""
    (?P<ws>[ \t\f\v\r]+)
  | (?P<num>(?:\d+\.\d*|\.\d+|\d+)(?:EX[+-]?\d+)?)
  | (?P<hex>'H[0-9A-F]+')
  | (?P<bin>'B[01]+')
  | (?P<str>"[^"]*")
  | (?P<ident>[A-Z_$][A-Z0-9_$]*(?:\.\d*)?)
  | (?P<op>==|<>|<=|>=|<<|[<>=+\-*/()\[\],:])
    """,
    re.VERBOSE | re.IGNORECASE,
)

_ADDR_DECIMAL = re.compile(r"^[A-Z]+(?:\d+\.\d*|\.\d+)$")
#: an address word at the start of an identifier: one letter and its number (``G0``, ``X10.5``)
_ADDRESS_WORD = re.compile(r"[A-Z](?:\d+(?:\.\d*)?|\.\d+)")


def split_words(ident: str, is_name: Callable[[str], bool] | None = None) -> list[str]:
    """The words of an identifier written without separators, as the NCK reads them.

    A name the control knows is one word: a keyword, a G code, a defined variable, a
    subprogram, a cycle or an axis of the machine (``is_name`` tells; ``P3G_SHAFT`` when that
    program exists). Otherwise one letter followed by a digit is an address and its number
    (names a program defines start with two letters or an underscore), so the identifier is
    read as a chain of address words, each a letter and its number, until what is left is a
    known name or does not start with a letter and a digit: ``G0G90X0Y0`` → ``G0 G90 X0 Y0``,
    ``T1D1M6`` → ``T1 D1 M6``, ``G1X`` → ``G1 X`` (its value follows: ``G1X=R1``),
    ``X10CYCLE81`` → ``X10 CYCLE81``, ``G0C1`` → ``G0 C1`` (axis C1 when ``=`` follows).
    """
    if not _address_at(ident, 0) or (is_name is not None and is_name(ident)):
        return [ident]
    words: list[str] = []
    pos = 0
    while _address_at(ident, pos) and not (words and is_name is not None and is_name(ident[pos:])):
        m = _ADDRESS_WORD.match(ident, pos)
        words.append(m.group())  # type: ignore[union-attr]
        pos = m.end()  # type: ignore[union-attr]
    if pos < len(ident):
        words.append(ident[pos:])
    return words


def _address_at(ident: str, pos: int) -> bool:
    """Whether an address word (a letter and its number) starts at ``pos``."""
    if len(ident) - pos < 2 or not ident[pos].isalpha():
        return False
    c = ident[pos + 1]
    return c.isdigit() or (c == "." and pos + 2 < len(ident) and ident[pos + 2].isdigit())


def number(text: str) -> float | int:
    """The value of a decimal literal (``12``, ``1.5``, ``1.5EX3``). Raises OverflowError
    when it is not a finite double (so is an integer of more than 308 digits)."""
    t = text.upper()
    if "EX" in t:
        mant, exp = t.split("EX")
        if len(exp.lstrip("+-0")) > 4:
            raise OverflowError(text)
        value = float(mant) * 10.0 ** int(exp)
    elif "." in t:
        value = float(t)
    elif len(t.lstrip("+-0")) > 308:
        raise OverflowError(text)
    else:
        return int(t)
    if not math.isfinite(value):
        raise OverflowError(text)
    return value


def tokenize(text: str, source: SourceRef, is_name: Callable[[str], bool] | None = None) -> list[Token]:
    """Tokens of ``text`` (a block without its ``;`` comment), ending with an END token;
    ``is_name`` tells the names that :func:`split_words` keeps whole.

    Raises ProgramError(kind="syntax") at the first character that starts no token.
    """
    out: list[Token] = []
    pos = 0
    n = len(text)
    match = _TOKEN.match
    while pos < n:
        m = match(text, pos)
        if m is None:
            raise ProgramError("syntax", f"unexpected character {text[pos]!r}", source.at(pos + 1))
        kind = m.lastgroup
        tok = m.group()
        col = pos + 1
        pos = m.end()
        if kind == "ws":
            continue
        if kind == "num":
            try:
                value = number(tok)
            except OverflowError:
                raise ProgramError("syntax", f"number {tok} is out of range", source.at(col)) from None
            out.append(Token(NUM, tok, col, value))
        elif kind in ("hex", "bin"):
            value = int(tok[2:-1], 16 if kind == "hex" else 2)
            if value.bit_length() > 64:
                raise ProgramError("syntax", f"constant {tok} is out of range", source.at(col))
            out.append(Token(NUM, tok, col, value))
        elif kind == "str":
            out.append(Token(STR, tok[1:-1], col, tok[1:-1]))
        elif kind == "ident":
            up = tok.upper()
            if len(up) > 2 and up[1] <= "9" and up[0] != "$" and not _ADDRESS_WORD.fullmatch(up):
                words = split_words(up, is_name)  # words without separators: all but the last
                for w in words[:-1]:              # are address words
                    out.append(Token(IDENT, w, col))
                    col += len(w)
                up = words[-1]
            if "." in up and not _ADDR_DECIMAL.match(up):
                # "NAME." is not an address with a decimal part: give the dot back
                cut = up.index(".")
                pos = pos - (len(up) - cut)
                up = up[:cut]
                if pos < n and text[pos] == ".":
                    raise ProgramError("syntax", "unexpected '.'", source.at(pos + 1))
            out.append(Token(IDENT, up, col))
        else:
            out.append(Token(OP, tok, col))
    out.append(Token(END, "", n + 1))
    return out


def split_comment(line: str) -> tuple[str, str]:
    """Split a line at the first ``;`` that is not inside a string: (code, comment)."""
    if ";" not in line:
        return line, ""
    in_str = False
    for i, ch in enumerate(line):
        if ch == '"':
            in_str = not in_str
        elif ch == ";" and not in_str:
            return line[:i], line[i + 1 :]
    return line, ""
