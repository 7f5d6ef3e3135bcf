"""Polygonal turning: a flywheel cutter coupled to the turning work cuts a polygon.

The tool spindle carries a flywheel cutter (:class:`vmach.tooling.flywheel.FlywheelTool`: n
inserts at cutting radius R, its axis parallel to the work's) and turns ``k`` times per turn of
the main spindle (the coupling's ratio, Sinumerik ``COUPDEF``/``COUPON``). Seen from the work,
the inserts run through a closed curve, and the work loses the region they sweep: a 2-D
cross-section, the same at every Z the edges pass, extruded along the axial feed.

Work frame W (turns with the main spindle, its angle α from the spindle's zero), machine frame
M (complex numbers x + iy). The cutter's centre sits at ``c = (X + R) + iY`` in M (X, Y: the
tool's point P, :mod:`vmach.tooling.flywheel`); the tool spindle's angle is β = k·α + offset
(position coupling: the control holds the following spindle at that angle, ``COUPON``'s
offset). Insert i of section points q (cutter frame, tip at (R, 0)) lies in M at
``c + e^{iθ} q``, θ = π − σ(β + 360°·i/n) (σ = +1: the cutter turns the same way round as the
work, −1 for a ``counter`` holder or a negative ratio's sense); the work turns by −α about
+Z, so in W every point is turned by +α::

    P_W(α) = e^{iα} c + e^{i(π + (1 − σk)α − σ(offset + 360°·i/n))} q

With σk = 2 and c = A real the tip (q = R) runs through A e^{iα} − R e^{−iα}: an ellipse of
semi-axes A + R and A − R = X, whose two vertices nearest the axis leave two slightly convex
flats per insert — the known shapes come from this alone (docs/polygonal-turning.md). The
flank is an arc of that curve, not a line: its curvature at the flat's middle is
|k'²R − A| / (A + k'R)² with k' = 1 − σk (convex while k'²R < A, concave beyond).

Error bound: the placements are taken at angle steps Δα such that no point of an insert leaves
the chord between its two placements by more than ``SAG`` (bound: Δα² (|c| + k'²R) / 8 ≤ SAG),
over ``q`` work turns for a ratio p/q (the curve closes), and each step is cut as the hull of
its two placements. Every point of the true sweep lies within SAG of that hull; a point of the
hull lies within SAG + Δθ·d/4 of the sweep (Δθ = |k'|Δα the insert's turn in the step, d the
distance between the two insert points the hull bridges — at the flanks the tip's, a fraction
of the nose radius). Measured: the four fixture shapes' sections lie within 1.3 µm of sections
made with a 100 times smaller SAG, corners included (``benchmarks/polygonal.py --converge``). A move
of P in X or Y takes, at each angle, the hull of the placements at both ends (the sweep over
the interval of centre distances: exact, as the centre's motion is a translation); a move in
both X and Z is cut in pieces of at most ``PIECE`` mm in X (the cut of a piece reaches its
whole Z span: an overcut of at most the piece's X change along a taper). The Z extent of a
step is the span of P's Z plus the edges' ``width`` toward +Z: exact once every Z the edges
cover has seen one period (feed per period below the width; the entry and exit ends of a pass
are cut as in steady state).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from vmach.stock import engine
from vmach.stock.jobs import Cutter, Polygonal, span
from vmach.stock.path import NOTHING, Bound, Claim, Free, Path
from vmach.stock.view import View

#: mm: the largest distance an insert point's path leaves the chord between two placements
SAG = 0.001
#: most work turns one period may take (a ratio p/q is taken as its best fraction of q <= this)
MAX_TURNS = 12
#: mm: largest X change of one piece of a move in both X and Z
PIECE = 0.01
#: most pieces one such move is cut in (beyond, the pieces grow and the bound with them)
MAX_PIECES = 64


@dataclass(frozen=True)
class Coupling:
    """The tool spindle's coupling to the main spindle, as the stock needs it.

    ratio : tool spindle turns per main spindle turn (COUPDEF's numerator / denominator; the
        sign: the same sense of rotation when positive). offset : degrees, the tool spindle's
        angle when the main spindle is at 0 (COUPON's angular offset). leading : the main
        spindle's number (whose speed turns a feed per minute into a feed per work turn).
    """

    ratio: float
    offset: float = 0.0
    leading: int = 1

    def turns(self) -> int:
        """Work turns after which the relative motion repeats (q of the ratio p/q)."""
        return Fraction(abs(self.ratio)).limit_denominator(MAX_TURNS).denominator

    def exact(self) -> bool:
        """Is the ratio p/q with q <= MAX_TURNS (else the pattern creeps round from turn to
        turn, and the cut is that of the nearest such fraction)?"""
        return abs(float(Fraction(abs(self.ratio)).limit_denominator(MAX_TURNS)) - abs(self.ratio)) <= 1e-9


def sense(tool, coupling: Coupling) -> float:
    """σ: +1 when the cutter turns the same way round as the work, −1 against it."""
    s = 1.0 if coupling.ratio >= 0 else -1.0
    return -s if getattr(tool, "counter", False) else s


def placements(tool, coupling: Coupling, centre: complex, chord: float = SAG, far: float = 0.0
               ) -> tuple[np.ndarray, float]:
    """(n, s, m) complex: every insert's section points in the work frame at the ``s`` angle
    steps of one period (first and last equal), the cutter's centre at ``centre`` (machine frame,
    mm); and the step Δα (rad). m: points of :meth:`FlywheelTool.insert_section`. ``far``: the
    steps are those of a centre at least this far (mm) from the axis (so that placements of two
    centres pair up)."""
    q = tool.insert_section(chord)
    q = q[:, 0] + 1j * q[:, 1]
    k = abs(coupling.ratio)
    sig = sense(tool, coupling)
    kk = 1.0 - sig * k
    bound = max(abs(centre), far) + kk * kk * float(np.abs(q).max())
    d_alpha = min(math.sqrt(8.0 * chord / max(bound, 1e-9)), math.radians(2.0))
    total = 2.0 * math.pi * coupling.turns()
    steps = max(8, math.ceil(total / d_alpha))
    alpha = np.linspace(0.0, total, steps + 1)
    out = np.empty((tool.inserts, steps + 1, len(q)), dtype=complex)
    for i in range(tool.inserts):
        phase = math.radians(coupling.offset + 360.0 * i / tool.inserts)
        turn = np.exp(1j * (math.pi + kk * alpha - sig * phase))
        out[i] = np.exp(1j * alpha)[:, None] * centre + turn[:, None] * q[None, :]
    return out, total / steps


def section(tool, coupling: Coupling, c0: complex, c1: complex | None = None, r_max: float = np.inf,
            chord: float = SAG) -> list[np.ndarray]:
    """The cross-section the inserts cut in the work frame while the cutter's centre is at
    ``c0`` (or anywhere between ``c0`` and ``c1``): convex point sets (k, 2) ``(x, y)`` mm, one
    per angle step and insert — the hull of its placements — whose union is the section; only
    steps that come within ``r_max`` mm of the work's axis (the stock's reach)."""
    # one grid of angles for every centre that can reach the stock: sections of one path pair up
    if min(abs(c0), abs(c1 if c1 is not None else c0)) - tool.reach() >= r_max:
        return []                                        # the inserts stay beyond the stock
    far = max(abs(c0), abs(c1 if c1 is not None else c0))
    if np.isfinite(r_max):
        far = max(far, r_max + tool.reach())
    if c1 is None or abs(c1 - c0) <= 1e-12:
        ends = [placements(tool, coupling, c0, chord, far)[0]]
    else:
        ends = [placements(tool, coupling, c, chord, far)[0] for c in (c0, c1)]
    near = np.zeros(ends[0].shape[:2], dtype=bool)
    for e in ends:
        near |= np.abs(e).min(axis=2) < r_max
    step = near[:, :-1] | near[:, 1:]
    hulls = []
    for i, j in zip(*np.nonzero(step), strict=True):
        pts = np.concatenate([e[i, j : j + 2].ravel() for e in ends])
        hulls.append(np.column_stack([pts.real, pts.imag]))
    return hulls


def in_machine(tips: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(n, 3): the tool's point P in the machine frame — tips (n, 3) work frame mm turned back
    by the main spindle's angle ``alpha`` (n,) rad (the work frame's turn against the machine
    at each pose)."""
    tips = np.asarray(tips, dtype=float).reshape(-1, 3)
    xy = (tips[:, 0] + 1j * tips[:, 1]) * np.exp(-1j * np.asarray(alpha, dtype=float))
    return np.column_stack([xy.real, xy.imag, tips[:, 2]])


NAME = "polygonal"
BOUND = Bound(over="tool_polygon", under="tool_polygon")   # SAG (1 µm) per placement: within it
JOB = Polygonal


def claim(path: Path, free: Free, view: View, cover) -> Claim:
    """A polygonal-turning path (one with ``coupled``) whole: its jobs (:func:`jobs_of`) within
    the stock's bounds."""
    if path.coupled is None:
        return NOTHING
    tool, coupling = path.coupled
    lo, hi = view.bounds
    r_max = float(np.hypot(np.abs([lo[0], hi[0]]).max(), np.abs([lo[1], hi[1]]).max())) + 1.0
    z_range = (float(lo[2]) - 1.0, float(hi[2]) + 1.0)
    jobs = jobs_of(tool, coupling, path.tips, path.rows, r_max, z_range=z_range)
    return Claim(steps=np.ones(max(path.n - 1, 0), bool), held=np.ones(path.n, bool),
                 jobs=[(float(k), job) for k, job in enumerate(jobs)])


def jobs_of(tool, coupling: Coupling, points: np.ndarray, rows: np.ndarray | None, r_max: float = np.inf,
            chord: float = SAG, z_range: tuple[float, float] = (-np.inf, np.inf)) -> list[Polygonal]:
    """The jobs of one coupled path: P at ``points`` (n, 3) machine frame mm (X its distance from
    the work's axis, Z along it; :func:`in_machine`), ``rows`` (n,) int or None. Consecutive
    steps at one X and Y share a job (their Z spans joined); a step in X or Y takes the sweep
    over its centre distances; a step in both X (or Y) and Z is cut in pieces. What stays
    beyond ``r_max`` mm of the axis or outside ``z_range`` (the stock's) makes no job."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if len(pts) == 0:
        return []
    centre = (pts[:, 0] + tool.radius) + 1j * pts[:, 1]
    z = pts[:, 2]
    w = tool.width
    if len(pts) == 1:
        return [Polygonal(section(tool, coupling, complex(centre[0]), None, r_max, chord), z[0], z[0] + w,
                          span(rows, 0, 0))]
    jobs: list[Polygonal] = []
    cache: dict[tuple, list] = {}

    def cut(c0: complex, c1: complex, za: float, zb: float, a: int, b: int) -> None:
        if min(abs(c0), abs(c1)) - tool.reach() >= r_max or min(za, zb) >= z_range[1] \
                or max(za, zb) + w <= z_range[0]:
            return
        key = (round(c0.real, 9), round(c0.imag, 9), round(c1.real, 9), round(c1.imag, 9))
        if key not in cache:
            cache[key] = section(tool, coupling, c0, c1, r_max, chord)
        jobs.append(Polygonal(cache[key], min(za, zb), max(za, zb) + w, span(rows, a, b)))

    i, n = 0, len(pts)
    while i < n - 1:
        if abs(centre[i + 1] - centre[i]) <= 1e-9:              # along Z at one X, Y: join the run
            j = i + 1
            while j < n - 1 and abs(centre[j + 1] - centre[i]) <= 1e-9:
                j += 1
            cut(complex(centre[i]), complex(centre[i]), float(z[i : j + 1].min()), float(z[i : j + 1].max()),
                i, j)
            i = j
            continue
        c0, c1 = complex(centre[i]), complex(centre[i + 1])
        if abs(z[i + 1] - z[i]) <= 1e-9:                        # across at one Z: the interval's sweep
            cut(c0, c1, float(z[i]), float(z[i]), i, i + 1)
        else:
            parts = min(MAX_PIECES, max(1, math.ceil(abs(c1 - c0) / PIECE)))
            t = np.linspace(0.0, 1.0, parts + 1)
            for a, b in zip(t[:-1], t[1:], strict=True):
                cut(c0 + (c1 - c0) * a, c0 + (c1 - c0) * b, float(z[i] + (z[i + 1] - z[i]) * a),
                    float(z[i] + (z[i + 1] - z[i]) * b), i, i + 1)
        i += 1
    return jobs


def make(job: Polygonal, maker) -> Cutter | None:
    """The cutter of one job within the stock's bounds (one millimetre more: what lies outside
    removes nothing); None when it misses the stock. ``maker``: :class:`vmach.stock.make.Maker`."""
    lo, hi = np.asarray(maker.view.bounds, dtype=float)
    z0, z1 = max(job.z0, lo[2] - 1.0), min(job.z1, hi[2] + 1.0)
    if not job.hulls or z1 <= z0:
        return None
    half = float(max(np.abs(lo[:2]).max(), np.abs(hi[:2]).max())) + 1.0
    solid = engine.extruded(job.hulls, z0, z1, half)
    if engine.is_empty(solid):
        return None
    return Cutter(solid, engine.bounds(solid), job.rows)


__all__ = ["BOUND", "JOB", "MAX_TURNS", "NAME", "SAG", "Coupling", "claim", "in_machine", "jobs_of", "make",
           "placements", "section", "sense"]
