"""Nominal polygon profiles: DIN 32711-1 P3G and DIN 32712 P4C (domain.md §5), vectorised.

Both are envelopes of lines with the support function ``h(α) = d/2 − e·cos(n·α)`` (n lobes),
α being the direction of the outward normal:

    x(α) = h(α)·cos α − h'(α)·sin α,   y(α) = h(α)·sin α + h'(α)·cos α,   h'(α) = n·e·sin(n·α)

- **P3G** (n = 3): d = d1, e = e1 from the size table (``data/din32711.csv``); constant width
  d1; d2 = d1 + 2·e1 circumscribed, d3 = d1 − 2·e1 inscribed; radius of curvature
  ρ = d1/2 + 8·e1·cos 3α (convex while e1 < d1/16); area π·(d1²/4 − 4·e1²).
- **P4C** (n = 4), designation ``P4C d1×d2/e``: d2 the width across the flats, e the
  eccentricity (``e = 0.125·d_m`` with d_m = d2 + 2·e, so e = d2/6 unless given), and the
  circle of diameter d1 truncating the corners: the part is the intersection of the half-planes
  ``x·n(α) ≤ h(α)`` with that circle.

Signed distance of points to the nominal profile (:meth:`Polygon.signed_distance`): for a convex
body K, ``dist(x, ∂K) = max over unit u of (x·u − h_K(u))`` with sign (> 0 outside), inside as
well as outside. The maximum over α is found on a grid and polished by Newton steps on
``d/dα (x·n(α) − h(α)) = 0``. Exact for P3G; for P4C exact inside and along the flats and arcs
(the max of the two convex constraints), a lower bound only outside near the flat-to-arc
corners.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from vmach.errors import InputError
from vmach.tol import tol

DATA = Path(__file__).parent / "data"


@lru_cache(maxsize=1)
def p3g_sizes() -> dict[float, float]:
    """DIN 32711 size table: d1 -> e1 (mm), read from ``data/din32711.csv``."""
    out: dict[float, float] = {}
    with open(DATA / "din32711.csv", encoding="utf-8") as fh:
        rows = csv.DictReader(line for line in fh if not line.startswith("#"))
        for row in rows:
            out[float(row["d1"])] = float(row["e1"])
    return out


@dataclass(frozen=True)
class Polygon:
    """A polygon profile.

    kind : ``"P3G"`` or ``"P4C"``. lobes : 3 or 4.
    d : float, mm — mean diameter of the support function (d1 for P3G, d_m for P4C).
    e : float, mm — eccentricity.
    d1 : float, mm — nominal size (P3G) / truncating outer diameter (P4C).
    outer : float or None, mm — radius of the truncating circle (P4C).
    """

    kind: str
    lobes: int
    d: float
    e: float
    d1: float
    outer: float | None = None
    d2_flats: float | None = None

    # --- sizes ---------------------------------------------------------------------------
    @property
    def e1(self) -> float:
        return self.e

    @property
    def d2(self) -> float:
        """Circumscribed diameter (P3G: d1 + 2e1; P4C: d1, the truncating circle)."""
        return self.d1 + 2 * self.e if self.outer is None else 2 * self.outer

    @property
    def d3(self) -> float:
        """Inscribed diameter (P3G: d1 − 2e1; P4C: across the flats, d2)."""
        return self.d - 2 * self.e

    @property
    def area(self) -> float:
        """Cross-section area, mm² (closed form for P3G, numerical for P4C)."""
        if self.outer is None:
            return math.pi * (self.d ** 2 / 4 - (self.lobes ** 2 - 1) * self.e ** 2 / 2)
        xy = self.curve(20000)
        x, y = xy[:, 0], xy[:, 1]
        return 0.5 * float(np.abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))

    @property
    def name(self) -> str:
        if self.kind == "P3G":
            return f"P3G {self.d1:g}"
        return f"P4C {self.d1:g}x{self.d2_flats:g}/{self.e:g}"

    # --- support function and curve ------------------------------------------------------
    def h(self, alpha: np.ndarray) -> np.ndarray:
        """Support function h(α), mm; alpha (...) radians."""
        return self.d / 2 - self.e * np.cos(self.lobes * np.asarray(alpha))

    def dh(self, alpha: np.ndarray) -> np.ndarray:
        return self.lobes * self.e * np.sin(self.lobes * np.asarray(alpha))

    def d2h(self, alpha: np.ndarray) -> np.ndarray:
        return self.lobes ** 2 * self.e * np.cos(self.lobes * np.asarray(alpha))

    def envelope(self, alpha: np.ndarray) -> np.ndarray:
        """Envelope points (..., 2) mm for normal directions alpha (radians)."""
        a = np.asarray(alpha, dtype=float)
        h, dh = self.h(a), self.dh(a)
        c, s = np.cos(a), np.sin(a)
        return np.stack([h * c - dh * s, h * s + dh * c], axis=-1)

    def curve(self, n: int = 3600, phase: float = 0.0) -> np.ndarray:
        """Closed nominal contour, (n, 2) float mm, counter-clockwise, turned by ``phase``
        radians. P3G: the envelope at n equally spaced normal directions. P4C: the radial
        function min(outer, half-plane body) at n polar angles."""
        if self.outer is None:
            xy = self.envelope(np.linspace(0, 2 * np.pi, n, endpoint=False))
        else:
            theta = np.linspace(0, 2 * np.pi, n, endpoint=False)
            a = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
            cosd = np.cos(theta[:, None] - a[None, :])
            with np.errstate(divide="ignore"):
                r = np.where(cosd > 1e-9, self.h(a)[None, :] / np.where(cosd > 1e-9, cosd, 1), np.inf)
            rad = np.minimum(r.min(axis=1), self.outer)
            xy = np.column_stack([rad * np.cos(theta), rad * np.sin(theta)])
        if phase:
            c, s = math.cos(phase), math.sin(phase)
            xy = xy @ np.array([[c, s], [-s, c]])
        return xy

    # --- deviation -----------------------------------------------------------------------
    def signed_distance(self, points: np.ndarray, phase: float = 0.0, grid: int = 720,
                        newton: int = 4) -> np.ndarray:
        """Signed normal distance of points from the nominal profile turned by ``phase``.

        points : (n, 2) float, mm. Returns (n,) float, mm: > 0 outside (material beyond the
        nominal profile), < 0 inside (a gouge).
        """
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        c, s = math.cos(phase), math.sin(phase)
        x = p[:, 0] * c + p[:, 1] * s           # rotate by -phase
        y = -p[:, 0] * s + p[:, 1] * c
        a = np.linspace(0, 2 * np.pi, grid, endpoint=False)
        f = x[:, None] * np.cos(a) + y[:, None] * np.sin(a) - self.h(a)[None, :]
        al = a[np.argmax(f, axis=1)]
        for _ in range(newton):
            ca, sa = np.cos(al), np.sin(al)
            g1 = -x * sa + y * ca - self.dh(al)
            g2 = -x * ca - y * sa - self.d2h(al)
            step = np.where(g2 < -1e-12, g1 / np.where(g2 < -1e-12, g2, -1.0), 0.0)
            al = al - np.clip(step, -0.05, 0.05)
        dist = x * np.cos(al) + y * np.sin(al) - self.h(al)
        dist = np.maximum(dist, f.max(axis=1))  # Newton never worse than the grid
        if self.outer is not None:
            dist = np.maximum(dist, np.hypot(x, y) - self.outer)
        return dist


def p3g(d1: float, e1: float | None = None) -> Polygon:
    """A P3G profile; ``e1`` from the size table when not given."""
    if e1 is None:
        table = p3g_sizes()
        if float(d1) not in table:
            sizes = ", ".join(f"{k:g}" for k in table)
            raise InputError(f"P3G {d1:g} is not a DIN 32711 size ({sizes}); give e1 as P3G:{d1:g}/e1",
                             kind="profile_spec")
        e1 = table[float(d1)]
    if not 0 < e1 < d1 / 16:
        raise InputError(f"P3G {d1:g}: e1 = {e1:g} must lie between 0 and d1/16 (convex profile)",
                         kind="profile_spec")
    return Polygon("P3G", 3, float(d1), float(e1), float(d1))


def p4c(d1: float, d2: float, e: float | None = None) -> Polygon:
    """A P4C profile ``d1×d2/e`` (e = d2/6, i.e. 0.125·d_m, when not given)."""
    if e is None:
        e = d2 / 6.0
    if not (0 < d2 < d1 and e > 0):
        raise InputError(f"P4C {d1:g}x{d2:g}/{e:g}: need 0 < d2 < d1 and e > 0", kind="profile_spec")
    return Polygon("P4C", 4, float(d2 + 2 * e), float(e), float(d1), outer=d1 / 2.0,
                   d2_flats=float(d2))


_SPEC = re.compile(
    r"^\s*(P3G|P4C)\s*[: ]\s*(?P<a>[0-9.]+)\s*(?:[xX×]\s*(?P<b>[0-9.]+))?\s*(?:/\s*(?P<e>[0-9.]+))?\s*$",
    re.IGNORECASE,
)


def parse_profile(spec: str) -> Polygon:
    """``P3G:50``, ``P3G 50``, ``P3G:50/1.8``, ``P4C:35x30``, ``P4C:35x30/5``."""
    m = _SPEC.match(spec or "")
    if not m:
        raise InputError(f"profile {spec!r}: expected P3G:<d1>[/<e1>] or P4C:<d1>x<d2>[/<e>]",
                         kind="profile_spec")
    kind = m.group(1).upper()
    try:
        a = float(m.group("a"))
        b = float(m.group("b")) if m.group("b") else None
        e = float(m.group("e")) if m.group("e") else None
    except ValueError:
        raise InputError(f"profile {spec!r}: bad number", kind="profile_spec") from None
    if not all(math.isfinite(v) and v <= tol.max_size for v in (a, b, e) if v is not None):
        raise InputError(f"profile {spec!r}: sizes must be finite and at most {tol.max_size:g} mm",
                         kind="profile_spec")
    if kind == "P3G":
        if b is not None:
            raise InputError(f"profile {spec!r}: P3G takes one size (d1)", kind="profile_spec")
        return p3g(a, e)
    if b is None:
        raise InputError(f"profile {spec!r}: P4C needs d1xd2", kind="profile_spec")
    return p4c(a, b, e)
