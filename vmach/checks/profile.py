"""Conformance of a simulated part to a DIN 32711 / DIN 32712 polygon profile.

The part is sliced at Z stations; each section's contour (the one around the work axis) is
sampled densely along its edges, and the signed normal distance of every sample from the
nominal profile is measured (> 0 material outside the nominal profile, < 0 a gouge). The
profile is turned about the axis by the phase that minimises the RMS deviation over all
stations together (or by a given phase). Per station and overall: max, min, RMS. The check
passes when every deviation lies in the band of the ISO 286 tolerance class of d1
(:mod:`vmach.checks.iso286`), halved because a deviation of the diameter by δ moves each flank
by δ/2: ``tolerance_mm = [ei/2, es/2]``.

    result = check_profile(sections, parse_profile("P3G:50"), zs, fit="g6")
    result.to_json()   # the "profile" object of report.json
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from vmach.checks.iso286 import limits
from vmach.checks.polygon import Polygon
from vmach.errors import InputError

#: spacing of the samples along section edges, mm (the deviation is convex along an edge, so
#: its maximum sits at a vertex; the spacing bounds how much of a gouge's minimum is missed)
SAMPLE_SPACING = 0.02


@dataclass(frozen=True)
class Station:
    """Deviation of one section, mm (``points`` samples; ``found`` False when the part has no
    material around the axis at this Z)."""

    z: float
    max: float
    min: float
    rms: float
    points: int
    found: bool = True


@dataclass(frozen=True)
class ProfileResult:
    """Outcome of a profile check (mm, degrees)."""

    profile: Polygon
    stations: tuple[Station, ...]
    phase_deg: float
    fit: str
    tolerance: tuple[float, float]

    @property
    def max(self) -> float:
        return max((s.max for s in self.stations if s.found), default=math.nan)

    @property
    def min(self) -> float:
        return min((s.min for s in self.stations if s.found), default=math.nan)

    @property
    def max_abs(self) -> float:
        return max(abs(self.max), abs(self.min)) if self.stations else math.nan

    @property
    def rms(self) -> float:
        found = [s for s in self.stations if s.found]
        n = sum(s.points for s in found)
        return math.sqrt(sum(s.rms ** 2 * s.points for s in found) / n) if n else math.nan

    @property
    def passed(self) -> bool:
        lo, hi = self.tolerance
        return bool(self.stations) and all(
            s.found and s.min >= lo - 1e-12 and s.max <= hi + 1e-12 for s in self.stations)

    def to_json(self) -> dict:
        """The ``"profile"`` object of report.json."""
        return {
            "type": self.profile.kind,
            "d1": self.profile.d1,
            "e1": self.profile.e,
            "stations": [
                {"z": round(s.z, 6), "max_deviation_mm": _r(s.max), "min_deviation_mm": _r(s.min),
                 "rms_deviation_mm": _r(s.rms), "found": s.found}
                for s in self.stations
            ],
            "max_abs_deviation_mm": _r(self.max_abs),
            "rms_deviation_mm": _r(self.rms),
            "tolerance_mm": [round(self.tolerance[0], 6), round(self.tolerance[1], 6)],
            "fit": self.fit,
            "phase_deg": round(self.phase_deg, 4),
            "pass": self.passed,
        }


def _r(v: float) -> float | None:
    return None if not math.isfinite(v) else round(float(v), 6)


#: most Z stations one profile check takes (each is a section of the part and a fit)
MAX_STATIONS = 1000


def stations(spec: str, count: int | None = None, step: float | None = None) -> np.ndarray:
    """Z stations from ``"z0:z1"`` (both included): ``count`` equally spaced, or every
    ``step`` mm; at most ``MAX_STATIONS``. Returns (n,) float, mm."""
    try:
        a, b = (float(t) for t in spec.split(":"))
    except ValueError:
        raise InputError(f"profile z range {spec!r}: expected z0:z1, e.g. -35:-5",
                         kind="profile_spec") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise InputError(f"profile z range {spec!r}: z0 and z1 must be finite numbers", kind="profile_spec")
    lo, hi = min(a, b), max(a, b)
    if step is not None:
        if step <= 0:
            raise InputError("profile z step must be > 0", kind="profile_spec")
        if not (hi - lo) / step < MAX_STATIONS:
            raise InputError(f"profile z range {spec!r} every {step:g} mm: more than {MAX_STATIONS} "
                             "stations", kind="profile_spec")
        n = int(math.floor((hi - lo) / step + 1e-9)) + 1
        return lo + step * np.arange(n)
    n = 7 if count is None else count
    if not 1 <= n <= MAX_STATIONS:
        raise InputError(f"profile station count must be 1 to {MAX_STATIONS}", kind="profile_spec")
    return np.array([(lo + hi) / 2]) if n == 1 else np.linspace(lo, hi, n)


def axis_contour(polygons: Sequence[np.ndarray]) -> np.ndarray | None:
    """The outer contour that encloses the work axis (x = y = 0), else the largest one."""
    best, best_area = None, 0.0
    for p in polygons:
        if len(p) < 3:
            continue
        area = 0.5 * float(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))
        if area <= 0:
            continue  # a hole
        if _contains(p, 0.0, 0.0):
            return p
        if area > best_area:
            best, best_area = p, area
    return best


def _contains(p: np.ndarray, x: float, y: float) -> bool:
    xi, yi = p[:, 0], p[:, 1]
    xj, yj = np.roll(xi, 1), np.roll(yi, 1)
    cross = ((yi > y) != (yj > y)) & (x < (xj - xi) * (y - yi) / np.where(yj != yi, yj - yi, 1) + xi)
    return bool(cross.sum() % 2)


def densify(contour: np.ndarray, spacing: float = SAMPLE_SPACING) -> np.ndarray:
    """Closed contour (k, 2) sampled along its edges at most ``spacing`` apart, vertices kept."""
    a = contour
    b = np.roll(contour, -1, axis=0)
    n = np.maximum(1, np.ceil(np.linalg.norm(b - a, axis=1) / spacing).astype(int))
    idx = np.repeat(np.arange(len(a)), n)
    t = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)
    t = t / np.repeat(n, n)
    return a[idx] + (b[idx] - a[idx]) * t[:, None]


def best_phase(profile: Polygon, samples: Sequence[np.ndarray]) -> float:
    """Phase (radians) turning the nominal profile to the least RMS deviation of ``samples``."""
    found = [s for s in samples if len(s)]
    if not found:
        return 0.0
    pts = np.concatenate(found)
    sub = pts[:: max(1, len(pts) // 1000)]
    fine = pts[:: max(1, len(pts) // 5000)]
    period = 2 * math.pi / profile.lobes
    grid = np.linspace(0, period, 90, endpoint=False)
    cost = [float(np.mean(profile.signed_distance(sub, ph, grid=180, newton=2) ** 2)) for ph in grid]
    k = int(np.argmin(cost))
    step = grid[1] - grid[0]
    best = golden_min(lambda ph: float(np.mean(profile.signed_distance(fine, ph, grid=360) ** 2)),
                      grid[k] - step, grid[k] + step, 1e-6)
    return best % period


GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


def golden_min(f: Callable[[float], float], a: float, b: float, xtol: float) -> float:
    """The minimum of ``f`` on [a, b] to within ``xtol`` (golden-section search: one new value
    per step, the bracket shrinks by 0.618; for a function with one minimum in the bracket).
    (scipy's minimize_scalar would do, but importing scipy.optimize costs a CLI run 0.8 s.)"""
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = f(c), f(d)
    while b - a > xtol:
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = f(d)
    return c if fc <= fd else d


def check_profile(section: Callable[[float], Sequence[np.ndarray]], profile: Polygon,
                  zs: Sequence[float], fit: str = "g6", phase_deg: float | None = None) -> ProfileResult:
    """Measure the part against ``profile``.

    section : callable z -> contours (each (k, 2) float, mm), e.g. ``Stock.section``.
    zs : Z stations, mm. fit : ISO 286 class of d1. phase_deg : nominal phase, degrees, or None
    to fit it.
    """
    lim = limits(fit, profile.d1)
    samples = []
    for z in zs:
        c = axis_contour(section(float(z)))
        samples.append(np.zeros((0, 2)) if c is None else densify(c))
    phase = best_phase(profile, samples) if phase_deg is None else math.radians(phase_deg)
    out = []
    for z, pts in zip(zs, samples, strict=True):
        if len(pts) == 0:
            out.append(Station(float(z), math.nan, math.nan, math.nan, 0, found=False))
            continue
        d = profile.signed_distance(pts, phase)
        out.append(Station(float(z), float(d.max()), float(d.min()),
                           float(np.sqrt(np.mean(d ** 2))), len(d)))
    return ProfileResult(profile, tuple(out), math.degrees(phase), fit,
                         (lim.lower / 2.0, lim.upper / 2.0))
