"""ISO 286-1 limits for a nominal size and a tolerance class (``g6``, ``k6``, ``H7`` ...).

Computed from the standard's formulas, not copied tables:

- Diameter step: the size D lies in a step (D_a, D_b] of 0, 3, 6, 10, 18, 30, 50, 80, 120, 180,
  250, 315, 400, 500 mm; the formulas use the geometric mean D = √(D_a·D_b) (√(1·3) for the
  first step).
- Standard tolerance factor ``i = 0.45·∛D + 0.001·D`` (µm, D in mm, D ≤ 500 mm).
- Standard tolerance ``IT5..IT18 = 7, 10, 16, 25, 40, 64, 100, 160, 250, 400, 640, 1000,
  1600, 2500 × i`` (µm).
- Fundamental deviation of shafts (µm; es upper, ei lower):
  f: es = −5.5·D^0.41;  g: es = −2.5·D^0.34;  h: es = 0;  js: ±IT/2;
  k: ei = +0.6·∛D for grades 4 to 7, 0 otherwise;  m: ei = +(IT7 − IT6);  n: ei = +5·D^0.34.
  The other limit is the first ∓ IT of the grade.
- Holes F, G, H: EI = −es of the shaft of the same letter (F, G) or 0 (H), ES = EI + IT; JS ±IT/2.
- Rounding (applied to IT values and fundamental deviations, µm): to 1 µm up to 100 µm, then
  to 5 µm up to 200 µm, to 10 µm up to 1000 µm, to 50 µm above. This reproduces the printed
  IT6 values and the g6, k6, h6, m6, n6, f7, H7 limits of the P3G sizes (14–100 mm) exactly; a
  few other printed values differ by 1 µm (IT7 10–18 mm: formula 17, table 18; IT6 3–6 mm:
  7, table 8) or,
  above 100 µm, by one rounding step. The standard's printed tables remain authoritative.

Letters whose formulas need the standard's tabulated corrections (a–e, j, p–zc, holes K–ZC)
are not offered: asking for them is an :class:`~vmach.errors.InputError`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from vmach.errors import InputError

STEPS = (0, 3, 6, 10, 18, 30, 50, 80, 120, 180, 250, 315, 400, 500)
IT_FACTORS = {5: 7, 6: 10, 7: 16, 8: 25, 9: 40, 10: 64, 11: 100, 12: 160, 13: 250, 14: 400,
              15: 640, 16: 1000, 17: 1600, 18: 2500}
SHAFTS = ("f", "g", "h", "js", "k", "m", "n")
HOLES = ("F", "G", "H", "JS")


@dataclass(frozen=True)
class Limits:
    """Limit deviations of a size, mm: ``lower`` ≤ actual − nominal ≤ ``upper``."""

    fit: str
    size: float
    lower: float
    upper: float
    it: float


def _round(um: float) -> float:
    a = abs(um)
    if a <= 100:
        q = 1
    elif a <= 200:
        q = 5
    elif a <= 1000:
        q = 10
    else:
        q = 50
    return math.copysign(math.floor(a / q + 0.5) * q, um)


def mean_size(size: float) -> float:
    """Geometric mean D of the diameter step holding ``size`` (mm)."""
    if not 0 < size <= STEPS[-1]:
        raise InputError(f"ISO 286: size {size:g} mm outside 0..500 mm", kind="fit")
    for a, b in zip(STEPS[:-1], STEPS[1:], strict=True):
        if size <= b:
            return math.sqrt((a or 1) * b)
    raise AssertionError  # pragma: no cover


def it_value(grade: int, size: float) -> float:
    """Standard tolerance IT``grade`` for ``size``, µm (rounded)."""
    if grade not in IT_FACTORS:
        raise InputError(f"ISO 286: IT{grade} not supported (IT5..IT18)", kind="fit")
    D = mean_size(size)
    i = 0.45 * D ** (1 / 3) + 0.001 * D
    return _round(IT_FACTORS[grade] * i)


def limits(fit: str, size: float) -> Limits:
    """Limit deviations of ``size`` (mm) for tolerance class ``fit`` (``g6``, ``H7``...)."""
    m = re.fullmatch(r"\s*([A-Za-z]{1,2})(\d{1,2})\s*", fit or "")
    if not m:
        raise InputError(f"fit {fit!r}: expected a letter and a grade, e.g. g6", kind="fit")
    letter, grade = m.group(1), int(m.group(2))
    it = it_value(grade, size)
    D = mean_size(size)
    if letter in SHAFTS:
        if letter == "js":
            return Limits(fit, size, -it / 2000, it / 2000, it / 1000)
        if letter in ("f", "g", "h"):
            es = {"f": -_round(5.5 * D ** 0.41), "g": -_round(2.5 * D ** 0.34), "h": 0.0}[letter]
            return Limits(fit, size, (es - it) / 1000, es / 1000, it / 1000)
        if letter == "k":
            ei = _round(0.6 * D ** (1 / 3)) if 4 <= grade <= 7 else 0.0
        elif letter == "m":
            ei = it_value(7, size) - it_value(6, size)
        else:  # n
            ei = _round(5 * D ** 0.34)
        return Limits(fit, size, ei / 1000, (ei + it) / 1000, it / 1000)
    if letter in HOLES:
        if letter == "JS":
            return Limits(fit, size, -it / 2000, it / 2000, it / 1000)
        ei = {"F": _round(5.5 * D ** 0.41), "G": _round(2.5 * D ** 0.34), "H": 0.0}[letter]
        return Limits(fit, size, ei / 1000, (ei + it) / 1000, it / 1000)
    raise InputError(
        f"fit {fit!r}: tolerance class not supported (shafts {', '.join(SHAFTS)}; holes "
        f"{', '.join(HOLES)})", kind="fit")
