"""A flywheel cutter's path: polygonal turning while its spindle is coupled to the main spindle.

``polygon_path`` cuts one path of a :class:`vmach.tooling.flywheel.FlywheelTool` into the
stock (:mod:`vmach.stock.strategies.polygonal`), row by row, with the coupling each row runs
under (the last :class:`vmach.canon.SpindleCoupling` before it in the stream whose following
spindle is the machine's tool spindle, or any when the machine names none). Findings:

- ``flywheel_uncoupled`` (warning): the cutter comes within the stock's radius while its spindle
  is not coupled — vmach cuts nothing there (a free-running flywheel would mill, which is not
  simulated) — once per path, at the first such row;
- ``coupling_ratio`` and ``polygon_feed_coarse`` (warnings, :func:`_rates`): a ratio whose
  pattern does not close within 12 work turns, an axial feed too coarse for the steady state;
- with ``checks``: ``rapid_into_stock`` for a coupled rapid that removes material (more than
  a film of the section's tolerance), and
  ``holder_collision`` (part ``flywheel_body``) where the cutter's body — the disc inside its
  inserts, which sweeps an annulus about the work's axis — meets the stock.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from vmach import canon
from vmach.findings import Finding, warning
from vmach.motion.table import FEED_MODES, TRAVERSE
from vmach.stock import engine
from vmach.stock.strategies.polygonal import MAX_TURNS, SAG, Coupling, in_machine
from vmach.tol import tol


def couplings(table, spindle: int | None) -> list[Coupling | None]:
    """The coupling of the tool spindle each row of ``table`` runs under (None: uncoupled)."""
    state: Coupling | None = None
    at: dict[int, Coupling | None] = {}
    for i, c in enumerate(table.commands):
        if isinstance(c, canon.SpindleCoupling) and (spindle is None or c.following == spindle):
            state = Coupling(c.ratio, c.offset or 0.0, c.leading) if c.active else None
            at[i] = state
    if not at:
        return [None] * len(table)
    marks = np.array(sorted(at))
    vals = [at[int(k)] for k in marks]
    idx = np.searchsorted(marks, np.asarray(table.command), side="left") - 1
    return [vals[k] if k >= 0 else None for k in idx]


def spindle_angle(model, q: np.ndarray, tips: np.ndarray) -> np.ndarray:
    """(n,) rad: how far the work frame is turned against the machine at each pose — the
    direction of the machine's +X in the work frame (the kinematics at ``q`` (n, k) with X one
    millimetre more, minus ``tips`` (n, 3))."""
    col = list(model.axes).index("X")
    moved = np.array(q, dtype=float)
    moved[:, col] += 1.0
    d = np.asarray(model.fk(moved).tip, dtype=float) - tips
    return np.arctan2(d[:, 1], d[:, 0])


def polygon_path(stock, tool, table, model, q: np.ndarray, tips: np.ndarray, rows: np.ndarray, res,
                 checks: bool = False) -> None:
    """Cut the path of flywheel ``tool`` with axis values ``q`` (n, k), tips ``tips`` (n, 3) in
    the work frame and table ``rows`` (n,) int (a step belongs to the row it ends in); findings
    go to ``res.findings``."""
    tips = np.asarray(tips, dtype=float)
    pts = in_machine(tips, spindle_angle(model, q, tips))
    state = couplings(table, getattr(model, "tool_spindle", None))
    kind = np.asarray(table.kind)
    warned = False
    told: set[str] = set()
    i, n = 0, len(pts)
    while i < n - 1:
        row = int(rows[i + 1])
        coupling = state[row]
        j = i + 1
        while j < n - 1 and (state[int(rows[j + 1])] == coupling
                             and (not checks or int(rows[j + 1]) == row)):
            j += 1
        seg, seg_rows = pts[i : j + 1], rows[i : j + 1]
        if coupling is None:
            if not warned and _within(stock, tool, seg):
                warned = True
                res.findings.append(warning(
                    "flywheel_uncoupled", f'the flywheel cutter "{tool.name}" comes within the stock while '
                    "its spindle is not coupled to the main spindle: vmach cuts nothing here (COUPON first)",
                    table.source(row), tool=tool.name))
        else:
            _rates(tool, coupling, table, seg, seg_rows, told, res)
            cutters = stock.polygon_cutters(tool, coupling, seg, seg_rows)
            if checks and kind[row] == TRAVERSE and cutters:
                _rapid(stock, cutters, table, row, res)
            stock.queue(cutters)
            if checks:
                _body(stock, tool, seg, table, row, res)
        i = j


def _rates(tool, coupling: Coupling, table, seg: np.ndarray, seg_rows: np.ndarray, told: set, res) -> None:
    """Warnings, once per path each: ``coupling_ratio`` — the ratio is no fraction p/q of q <= 12
    (the cut is the nearest one's), at its COUPON; ``polygon_feed_coarse`` — the axial feed per period of the
    relative motion exceeds the edges' width (vmach cuts the steady-state section all along)."""
    if "ratio" not in told and not coupling.exact():
        told.add("ratio")
        res.findings.append(warning(
            "coupling_ratio", f"the coupling ratio {coupling.ratio:g} is no fraction p/q with q <= "
            f"{MAX_TURNS}: the pattern creeps round the work from turn to turn; vmach cuts the pattern of "
            f"{float(Fraction(abs(coupling.ratio)).limit_denominator(MAX_TURNS)):g}",
            _coupled_at(table, int(seg_rows[-1])), ratio=coupling.ratio))
    if "feed" in told:
        return
    for k in range(1, len(seg)):
        row = int(seg_rows[k])
        step = seg[k] - seg[k - 1]
        length = float(np.linalg.norm(step))
        if table.kind[row] == TRAVERSE or length == 0 or step[2] == 0:
            continue
        feed = float(table.feed[row])
        if FEED_MODES[int(table.feed_mode[row])] == "per_minute":
            col = table.spindles.index(coupling.leading) if coupling.leading in table.spindles else -1
            speed = float(table.speed[row, col]) if col >= 0 else 0.0
            feed = feed / speed if speed > 0 else np.inf
        elif FEED_MODES[int(table.feed_mode[row])] != "per_rev":
            continue
        advance = feed * abs(step[2]) / length * coupling.turns()
        if advance > tool.width:
            told.add("feed")
            res.findings.append(warning(
                "polygon_feed_coarse", f"the axial feed of {advance:g} mm per period of the polygon "
                f"({coupling.turns()} work turns) exceeds the inserts' edge width {tool.width:g} mm: not "
                "every Z is cut all round; vmach cuts the full section all along", table.source(row),
                advance_mm=round(advance, 4)))
            return


def _coupled_at(table, row: int):
    """The source of the coupling command (COUPON) the row runs under."""
    upto = int(table.command[row])
    for c in reversed(table.commands[:upto]):
        if isinstance(c, canon.SpindleCoupling) and c.active:
            return c.source
    return table.source(row)


def _rapid(stock, cutters, table, row: int, res) -> None:
    """``rapid_into_stock`` when a coupled rapid removes more than a film of the section's
    tolerance: ``SAG`` mm thick over the stock's mantle within the cutter's Z span (sections cut
    at neighbouring X differ by up to that much where they should coincide)."""
    cut = engine.union([c.solid for c in cutters])
    box = engine.bounds(cut)
    local = stock.local(box[0], box[1])
    if engine.is_empty(local):
        return
    removed = engine.volume(local) - engine.volume(engine.subtract(local, [cut]))
    lo, hi = engine.bounds(local)
    r = float(np.hypot(np.abs([lo[0], hi[0]]).max(), np.abs([lo[1], hi[1]]).max()))
    film = SAG * 2.0 * np.pi * r * float(hi[2] - lo[2])
    if removed > max(tol.removal_volume, film):
        res.findings.append(Finding(
            "rapid_into_stock", "error",
            f"rapid move removes {removed:.3f} mm³ of material (polygonal turning)",
            table.source(row), row, {"volume_mm3": round(removed, 4)}))


def _within(stock, tool, seg: np.ndarray) -> bool:
    """Does the cutter's tip circle come within the stock's radius and Z extent?"""
    lo, hi = stock.bounds
    r = float(np.hypot(np.abs([lo[0], hi[0]]).max(), np.abs([lo[1], hi[1]]).max()))
    near = np.hypot(seg[:, 0] + tool.radius, seg[:, 1]) - tool.radius < r
    inside = (seg[:, 2] + tool.width > lo[2]) & (seg[:, 2] < hi[2])
    return bool((near & inside).any())


def _body(stock, tool, seg: np.ndarray, table, row: int, res) -> None:
    """``holder_collision`` where the annulus the cutter's body sweeps about the work's axis
    meets the stock within the edges' Z span."""
    hub = tool.body_diameter / 2.0 if tool.body_diameter > 0 else tool.radius - tool.inscribed
    near = float(np.hypot(seg[:, 0] + tool.radius, seg[:, 1]).min()) - hub
    lo, hi = stock.bounds
    r = float(np.hypot(np.abs([lo[0], hi[0]]).max(), np.abs([lo[1], hi[1]]).max()))
    z0, z1 = max(float(seg[:, 2].min()), lo[2]), min(float(seg[:, 2].max()) + tool.width, hi[2])
    if near >= r or z1 <= z0:
        return
    segments = 256
    ring = engine.cylinder(r + 1.0, z0, z1, segments)
    if near > 0:            # the inner polygon holds the true circle (circumradius beyond it)
        ring = engine.subtract(ring, [engine.cylinder(near / np.cos(np.pi / segments), z0, z1, segments)])
    box = engine.bounds(ring)
    vol = engine.volume(engine.intersect(stock.local(box[0], box[1]), ring))
    if vol > tol.removal_volume:
        res.findings.append(Finding(
            "holder_collision", "error", f"the flywheel cutter's body runs {vol:.3f} mm³ into the stock "
            f"(it reaches {near:.3f} mm from the work's axis)", table.source(row), row,
            {"part": "flywheel_body", "volume_mm3": round(vol, 4)}))
