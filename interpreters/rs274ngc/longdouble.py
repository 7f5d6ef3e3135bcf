"""The x87 ``long double`` arithmetic LinuxCNC's degree functions happen to use.

LinuxCNC computes ``sin(x * M_PIl / 180.0)`` with ``M_PIl`` a long double, so the argument
and the C++ ``sin`` overload are long double: ``SIN[180]`` is about -5e-20, not +1.2e-16,
and ``25 * SIN[180]`` prints as ``-0.0000`` in its trace. To print the same numbers this
module reproduces those few operations exactly with rationals: products and quotients are
rounded to a 64-bit mantissa like the FPU does, the sine of the exact long double argument is
taken after an exact argument reduction, and the result is rounded to double.
"""

from __future__ import annotations

import math
from fractions import Fraction

#: M_PIl as an 80-bit long double (64-bit mantissa)
PI_L = Fraction(0xC90FDAA22168C235, 1 << 62)
PI_2L = PI_L / 2
_PI = Fraction(
    "3.14159265358979323846264338327950288419716939937510582097494459230781640628620899863"
)
_HALF_PI = _PI / 2


def round_ld(q: Fraction) -> Fraction:
    """Round to the nearest long double (64-bit mantissa, ties to even)."""
    if q == 0:
        return q
    sign = 1 if q > 0 else -1
    q = abs(q)
    e = q.numerator.bit_length() - q.denominator.bit_length()
    scale = Fraction(2) ** (63 - e)
    m = q * scale
    while m >= (1 << 64):
        scale /= 2
        m = q * scale
    while m < (1 << 63):
        scale *= 2
        m = q * scale
    whole = m.numerator // m.denominator
    rest = m - whole
    if rest > Fraction(1, 2) or (rest == Fraction(1, 2) and whole % 2):
        whole += 1
    return sign * Fraction(whole) / scale


def _reduce(a: Fraction, period: Fraction) -> tuple[int, float]:
    k = math.floor(a / period + Fraction(1, 2))
    return k, float(a - k * period)


def sin_deg(x: float) -> float:
    """``sin((x * M_PIl) / 180.0)`` in long double, stored to double."""
    if not math.isfinite(x):
        return math.nan
    a = round_ld(round_ld(Fraction(x) * PI_L) / 180)
    k, r = _reduce(a, _HALF_PI)
    return (math.sin(r), math.cos(r), -math.sin(r), -math.cos(r))[k % 4]


def cos_deg(x: float) -> float:
    if not math.isfinite(x):
        return math.nan
    a = round_ld(round_ld(Fraction(x) * PI_L) / 180)
    k, r = _reduce(a, _HALF_PI)
    return (math.cos(r), -math.sin(r), -math.cos(r), math.sin(r))[k % 4]


def tan_deg(x: float) -> float:
    if not math.isfinite(x):
        return math.nan
    a = round_ld(round_ld(Fraction(x) * PI_L) / 180)
    _, r = _reduce(a, _PI)
    return math.tan(r)


def to_degrees(radians: float) -> float:
    """``(radians * 180.0) / M_PIl`` in long double, stored to double."""
    return float(round_ld(round_ld(Fraction(radians) * 180) / PI_L))


def minus_half_pi(x: float) -> float:
    """``x - M_PI_2l`` stored to double."""
    return float(round_ld(Fraction(x) - PI_2L))


def plus_half_pi(x: float) -> float:
    return float(round_ld(Fraction(x) + PI_2L))
