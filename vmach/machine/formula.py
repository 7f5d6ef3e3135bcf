"""Structure formulas (domain §1): ``WCBVXYZT`` → the links and joints of a kinematic chain.

A formula is read as a chain from the workpiece ``W`` through the fixed frame ``V`` (vertical) or
``H`` (horizontal) to the tool ``T``; ``W`` and ``T`` may be left out (the papers' ``C'VZXYB``).
Letters left of V/H move the workpiece, letters right of it
move the tool; X, Y, Z are prismatic joints along i, j, k; A, B, C revolute joints about i, j, k.
An axis letter may carry digits (``C1``). A prime (``C'``) marks a workpiece motion in the older
notation; in the compact form the position left of V/H already says so, and a primed letter
right of V/H is refused.

The chain is built outward from the base: the workpiece side in reverse (the letter next to V
sits on the base, ``W`` on the last one), the tool side in order (``T`` on the last one). Each
joint is named after its letter, drives the machine axis of that name, and its child link is the
lower-case letter (``b``, ``c``, ``x`` ...). A positive joint value turns or moves the *child*
link positively about/along its axis: on the workpiece side this moves the workpiece, so the tool
moves by the negative value relative to it (the ``Rot(k, −C) · Rot(j, −B)`` of domain §2).

``V`` and ``H`` both give the tool axis ``(0, 0, 1)`` in the last tool-side frame (Z is the spindle
axis by ISO 841 on either kind of machine); ``[dimensions.T] direction`` changes it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

LINEAR = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}
ROTARY = {"A": (1.0, 0.0, 0.0), "B": (0.0, 1.0, 0.0), "C": (0.0, 0.0, 1.0)}
_TOKEN = re.compile(r"([XYZABC])(\d*)('?)|([WVHT])")
#: the order in which a formula's axes are listed when the model has no ``[[axes]]``.
AXIS_ORDER = "XYZABC"


class FormulaError(ValueError):
    """A structure formula that cannot be read; ``str`` is the reason."""


@dataclass(frozen=True)
class FormulaJoint:
    """One joint a formula asks for (before dimensions are applied)."""

    token: str  # the axis name, e.g. "B" or "C1"
    kind: str  # "prismatic" or "revolute"
    axis: tuple[float, float, float]
    parent: str
    child: str
    side: str  # "work" or "tool"


@dataclass(frozen=True)
class FormulaChain:
    """What a formula builds: joints from the base outward, the links carrying W and T."""

    formula: str
    joints: tuple[FormulaJoint, ...]
    work_link: str
    tool_link: str
    frame: str  # "V" or "H"


def parse_formula(formula: str) -> FormulaChain:
    """Read ``formula``; raise :class:`FormulaError` with the reason if it is not valid."""
    text = formula.replace(" ", "")
    if not text:
        raise FormulaError("the formula is empty")
    tokens: list[tuple[str, bool]] = []
    pos = 0
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m:
            raise FormulaError(f"unexpected {text[pos]!r} at position {pos + 1}")
        if m.group(4):
            tokens.append((m.group(4), False))
        else:
            tokens.append((m.group(1) + m.group(2), bool(m.group(3))))
        pos = m.end()
    names = [t for t, _ in tokens]
    if names[0] != "W":  # the papers' short form leaves W and T out: C'VZXYB
        tokens.insert(0, ("W", False))
        names.insert(0, "W")
    if names[-1] != "T":
        tokens.append(("T", False))
        names.append("T")
    frames = [i for i, t in enumerate(names) if t in ("V", "H")]
    if len(frames) != 1:
        raise FormulaError("a formula has exactly one fixed frame, V or H")
    if names.count("W") != 1 or names.count("T") != 1:
        raise FormulaError("W and T appear once each, W first and T last")
    axes = [t for t in names if t not in ("W", "V", "H", "T")]
    dup = sorted({a for a in axes if axes.count(a) > 1})
    if dup:
        raise FormulaError(f"axis {dup[0]} appears twice")
    f = frames[0]
    for i, (tok, primed) in enumerate(tokens):
        if primed and i > f:
            raise FormulaError(
                f"primed {tok}' is a workpiece motion but stands right of {names[f]}"
            )
    work_side = [t for t, _ in tokens[1:f]][::-1]
    tool_side = [t for t, _ in tokens[f + 1 : -1]]
    joints: list[FormulaJoint] = []
    ends = {}
    for side, seq in (("work", work_side), ("tool", tool_side)):
        parent = "base"
        for tok in seq:
            letter = tok[0]
            kind = "prismatic" if letter in LINEAR else "revolute"
            axis = LINEAR.get(letter) or ROTARY[letter]
            child = tok.lower()
            joints.append(FormulaJoint(tok, kind, axis, parent, child, side))
            parent = child
        ends[side] = parent
    return FormulaChain(text, tuple(joints), ends["work"], ends["tool"], names[f])


def formula_axes(formula: str) -> tuple[str, ...]:
    """The axis names of a formula in X Y Z A B C order (then by name), e.g. X Y Z B C."""
    chain = parse_formula(formula)
    return tuple(sorted((j.token for j in chain.joints), key=lambda t: (AXIS_ORDER.index(t[0]), t)))
