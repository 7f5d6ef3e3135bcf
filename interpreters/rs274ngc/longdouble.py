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


def _machin_pi(bits: int) -> Fraction:
    """pi to ``bits`` bits (Machin's formula in integers; error below 2**-bits)."""
    guard = bits + 32
    one = 1 << guard

    def arctan_inv(n: int) -> int:
        total, term, k, n2 = 0, one // n, 1, n * n
        while term:
            total += term // k if k % 4 == 1 else -(term // k)
            term //= n2
            k += 2
        return total

    return Fraction(4 * (4 * arctan_inv(5) - arctan_inv(239)), one)


_PI_BITS = 1400  # enough to reduce any double-sized argument exactly to double precision
_PI_BIG = _machin_pi(_PI_BITS)
_PI = Fraction(round(_PI_BIG * (1 << 300)), 1 << 300)  # for ordinary arguments


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


def _reduce(a: Fraction, halves: int) -> tuple[int, Fraction]:
    """``a = k * (halves * pi / 2) + r`` with ``|r| <= halves * pi / 4``: (k, r)."""
    pi = _PI if abs(a) < (1 << 200) else _PI_BIG
    period = pi * halves / 2
    k = math.floor(a / period + Fraction(1, 2))
    return k, a - k * period


def sin_deg(x: float) -> float:
    """``sin((x * M_PIl) / 180.0)`` in long double, stored to double."""
    if not math.isfinite(x):
        return math.nan
    if x == 0.0:
        return x  # the sign of zero survives
    a = round_ld(round_ld(Fraction(x) * PI_L) / 180)
    k, q = _reduce(a, 1)
    sin, cos, one = _sin_cos(q)
    return (sin, cos, -sin, -cos)[k % 4] / one


def cos_deg(x: float) -> float:
    if not math.isfinite(x):
        return math.nan
    a = round_ld(round_ld(Fraction(x) * PI_L) / 180)
    k, q = _reduce(a, 1)
    sin, cos, one = _sin_cos(q)
    return (cos, -sin, -cos, sin)[k % 4] / one


def sin_ld(a: Fraction) -> Fraction:
    """``sinl(a)`` of a long double ``a`` (radians), rounded to long double."""
    k, r = _reduce(a, 1)
    sin, cos, one = _sin_cos(r)
    return round_ld(Fraction((sin, cos, -sin, -cos)[k % 4], one))


def tan_deg(x: float) -> float:
    if not math.isfinite(x):
        return math.nan
    if x == 0.0:
        return x
    a = round_ld(round_ld(Fraction(x) * PI_L) / 180)
    _, r = _reduce(a, 2)
    # tanl of the exact argument, with rationals well beyond double precision: in double,
    # TAN[45] would be 0.9999999999999999 and TAN[90] (about -4e19) far off
    if abs(r) <= Fraction(4, 5):
        sin, cos, _ = _sin_cos(r)
        return sin / cos
    pi = _PI if abs(a) < (1 << 200) else _PI_BIG
    sin, cos, _ = _sin_cos(pi / 2 - abs(r))  # tan(r) = cot(pi/2 - |r|), the complement exact
    if not sin:
        return math.inf
    t = cos / sin
    return t if r > 0 else -t


def _sin_cos(x: Fraction) -> tuple[int, int, int]:
    """sin(x) and cos(x) for |x| <= 1 in fixed point: (sin * one, cos * one, one), exact to
    well beyond double precision, even for a tiny x (Taylor series)."""
    bits = 256
    if x:
        bits += max(0, x.denominator.bit_length() - x.numerator.bit_length())
    xs = round(x * (1 << bits))
    sin = cos = 0
    term = 1 << bits  # x**n / n!
    n = 0
    while term:
        if n % 2 == 0:
            cos += term if n % 4 == 0 else -term
        else:
            sin += term if n % 4 == 1 else -term
        n += 1
        term = (term * xs >> bits) // n
    return sin, cos, 1 << bits


_PI_HALVES: dict[int, tuple[int, int]] = {}


def plus_pi_halves(x: float, k: int) -> float:
    """``x + k * M_PI_2l`` in long double, stored to double (``x`` finite).

    The same as ``float(round_ld(Fraction(x) + k * PI_2L))``, in integers: both terms are
    dyadic, so the sum is exact as an integer over a power of two; it is rounded to a 64-bit
    mantissa (ties to even), and the quotient to double by Python's correctly rounded
    integer division."""
    c = _PI_HALVES.get(k)
    if c is None:
        q = k * PI_2L
        c = _PI_HALVES[k] = (q.numerator, q.denominator.bit_length() - 1)
    cn, ce = c
    n, d = x.as_integer_ratio()
    e = d.bit_length() - 1
    big = max(e, ce)
    t = (n << (big - e)) + (cn << (big - ce))
    if t == 0:
        return 0.0
    negative = t < 0
    if negative:
        t = -t
    extra = t.bit_length() - 64
    if extra > 0:
        m = t >> extra
        rest = t - (m << extra)
        half = 1 << (extra - 1)
        if rest > half or (rest == half and m & 1):
            m += 1
        t = m << extra
    v = t / (1 << big)
    return -v if negative else v


def to_degrees(radians: float) -> float:
    """``(radians * 180.0) / M_PIl``: the product in double, the quotient in long double."""
    if radians == 0.0:
        return radians * 180.0  # keeps the sign of zero (-0.0 prints as -0.0000)
    return float(round_ld(Fraction(radians * 180.0) / PI_L))


def minus_half_pi(x: float) -> float:
    """``x - M_PI_2l`` stored to double."""
    return float(round_ld(Fraction(x) - PI_2L))


def plus_half_pi(x: float) -> float:
    return float(round_ld(Fraction(x) + PI_2L))
