"""Rapids into the stock, the tool's body in the stock, rapids passing close: measured on the
stock as it is cut (``simulate(..., checks=True)``; what ``vmach verify`` runs).

Findings: ``rapid_into_stock`` (error: a rapid removes material), ``holder_collision`` (error:
the tool's shank or holder runs into the stock), ``near_miss`` (warning: a rapid passes closer
than the clearance). Each is screened cheaply first — boxes, the blank's face planes, the convex
blank's points — and only the moves that may make one are measured, exactly, on the stock inside
a box around them (:meth:`vmach.stock.Stock.local`). Close-ups of the first few findings are kept
as :class:`Snapshot` (lazy: evaluated only if a picture asks).
"""

from __future__ import annotations

import numpy as np

from vmach.findings import Finding
from vmach.motion.table import TRAVERSE
from vmach.stock import engine
from vmach.stock.events import (
    Part,
    body_parts,
    cylinder_boxes,
    cylinders_beyond,
    overlap_volume,
    overlaps,
    part_solids,
)
from vmach.stock.stock import Stock
from vmach.tol import tol

CHUNK = 64  # moves screened together against the stock before them
RAPIDS_JUDGED = 8  # a chunk's rapids are judged on the stock before it when there are no more


class Snapshot:
    """The stock at one moment, kept as manifold3d's lazy expression (the stock then minus
    the cutters since): evaluated only if a picture asks for its mesh."""

    def __init__(self, solid: engine.Solid):
        self._solid = solid
        self._mesh: tuple[np.ndarray, np.ndarray] | None = None

    def mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """Vertices (n, 3) float, mm and faces (m, 3) int."""
        if self._mesh is None:
            self._mesh = engine.to_mesh(self._solid)
            self._solid = None
        return self._mesh


class CheckedPath:
    """Cut rows a..b-1 of one path (samples: row j spans pose[first_j .. first_j + k_j]) and
    report rapids into material and shank/holder contact (:mod:`vmach.stock.events`) into
    ``res`` (``findings``, ``snapshots``).

    Per chunk of ``CHUNK`` rows: boxes pick the rows whose rapid cutter or parts could reach
    material, and their solids are met with the blank one by one (convex, a few hundred
    triangles each). The parts that do are then measured, solid by solid, on the stock inside
    the box around them (:meth:`Stock.local`: exact there, and much smaller than the stock) as
    it is before the chunk — or, when only parts are left, before the chunks held back (below),
    which holds more material; the stock only shrinks, so a part that reaches nothing there
    reaches nothing during the chunk. A chunk with nothing left to measure is held back and
    cut later together with its neighbours, as one path (as without checks: fans and
    translation hulls run on across chunks). Otherwise the held chunks are cut, the chunk's
    rows are cut one by one from the local stock, and each watched row is measured on it
    exactly; the chunk is then cut from the stock as one path. ``between(offset)``: the poses
    inside sampled steps for :meth:`Stock.cut` given the samples from ``offset`` on;
    ``cover``: the coverage index of the other paths (:class:`vmach.stock.sweeps.Coverage`);
    ``pose_rows`` (poses,) int: each pose's row, which the cutters name.
    """

    def __init__(self, stock: Stock, tool, table, a: int, b: int, k: np.ndarray, pose, res,
                 clearance: float = tol.near_miss, between=None, cover=None, pose_rows=None):
        self.stock, self.tool, self.table, self.a, self.n, self.res = stock, tool, table, a, b - a, res
        self.clearance = clearance
        self.between, self.cover, self.pose_rows = between, cover, pose_rows
        self.tips, self.ax = pose.tip, pose.axis
        first = np.r_[0, np.cumsum(k)[:-1]]
        self.span = [(first[j], first[j] + k[j] + 1) for j in range(self.n)]
        self.cut_boxes = cylinder_boxes(self.tips, self.ax, 0.0, tool.cutting_length, tool.radius)
        self.parts = body_parts(tool)
        self.part_hit = self._part_hit(first, k)
        self.planes = stock.blank_planes()
        self.cutter = [Part("cutter", 0.0, tool.cutting_length, tool.radius)]   # as cut_boxes, for apart
        self.rapid = table.kind[a:b] == TRAVERSE
        self.held = [None, None]        # poses [first, last + 1) of chunks not yet cut: one path

    def _part_hit(self, first: np.ndarray, k: np.ndarray) -> np.ndarray:
        """(rows,) bool: a row's parts may reach the blank when the box around them over the
        row's poses does (a straight row's sweep lies in the box around its two ends, both of
        which may lie outside the blank's box while the move passes through it)."""
        if not self.parts:
            return np.zeros(self.n, bool)
        tips, ax = self.tips, self.ax
        boxes = np.stack([cylinder_boxes(tips, ax, p.z0, p.z1, p.radius) for p in self.parts])
        lo, hi = boxes[:, :, 0].min(axis=0), boxes[:, :, 1].max(axis=0)        # (poses, 3)
        last = first + k                                                    # each row's end pose
        row_lo = np.minimum(np.minimum.reduceat(lo, first, axis=0), lo[last])
        row_hi = np.maximum(np.maximum.reduceat(hi, first, axis=0), hi[last])
        return overlaps(np.stack([row_lo, row_hi], axis=1), np.asarray(self.stock.initial_bounds))

    def cut(self, s: int, e: int) -> None:
        """Cut poses [s, e) from the stock as one path."""
        self.stock.cut(self.tool, self.tips[s:e], self.ax[s:e],
                       None if self.between is None else self.between(s),
                       None if self.cover is None else self.cover.shifted(s),
                       None if self.pose_rows is None else self.pose_rows[s:e])

    def hold(self, s: int, e: int) -> None:
        self.held[:] = [s if self.held[0] is None else self.held[0], e]

    def release(self) -> None:
        if self.held[0] is not None:
            self.cut(*self.held)
            self.held[:] = [None, None]

    def run(self) -> None:
        for c0 in range(0, self.n, CHUNK):
            self._chunk(range(c0, min(c0 + CHUNK, self.n)))
        self.release()

    def _probes(self, rows: range, here: np.ndarray) -> tuple[dict, dict]:
        """(probes, near) of a chunk: ``("rapid", row)`` / ``(part name, row)`` -> (solids,
        boxes) that may reach the stock's box ``here``; rapids within the clearance of it."""
        c0, tips, ax, clearance = rows[0], self.tips, self.ax, self.clearance
        probes: dict = {}
        near: dict = {}
        spans = [self.span[j] for j in rows]
        apart = _apart(self.planes, self.parts, tips, ax, spans, self.part_hit[c0 : c0 + CHUNK])
        # a rapid whose cutter lies farther than the clearance beyond a face of the blank
        # neither cuts nor passes close
        clear = _apart(self.planes, self.cutter, tips, ax, spans, self.rapid[c0 : c0 + CHUNK],
                       clearance)[:, 0]
        for j in rows:
            s, e = self.span[j]
            if self.rapid[j] and not clear[j - c0]:
                box = np.stack([self.cut_boxes[s:e, 0].min(axis=0), self.cut_boxes[s:e, 1].max(axis=0)])
                if overlaps(box[None], here)[0]:
                    probes[("rapid", j)] = self.stock.cutters(self.tool, tips[s:e], ax[s:e])
                elif clearance > 0 and overlaps((box + [[-clearance], [clearance]])[None], here)[0]:
                    near[j] = self.stock.cutters(self.tool, tips[s:e], ax[s:e])
            if self.part_hit[j]:
                for i, p in enumerate(self.parts):
                    if apart[j - c0, i]:
                        continue        # a face plane of the blank parts them: it meets no stock
                    q = part_solids(p, tips[s:e], ax[s:e], planes=self.planes)
                    if q:
                        probes[(p.name, j)] = (q, [engine.bounds(x) for x in q])
        return probes, near

    def _chunk(self, rows: range) -> None:
        stock, clearance = self.stock, self.clearance
        here = stock.bounds
        probes, near = self._probes(rows, here)
        # a rapid whose cutter meets the blank may meet the stock; else, only one that comes
        # within the clearance of the stock as it is before the chunk (a superset of the stock
        # during the chunk) can be a near miss
        for j, rc in list(probes.items()):
            if j[0] == "rapid" and not _meets(stock, rc[0]):
                near[j[1]] = rc
        probes = {key: v for key, v in probes.items() if _meets(stock, v[0])}
        s, e = self.span[rows[0]][0], self.span[rows[-1]][1]
        if probes and not near and self.held[0] is not None:
            # measured first on the stock without the chunks held back (more material than
            # now), so that most chunks need not cut those first
            probes = _reaching(stock.local(*_around(probes, here, clearance)), probes, clearance)
        if not probes and not near:
            self.hold(s, e)              # cut later with its neighbours, as one path
            return
        self.release()
        if near:
            now = stock.solid
            near = {j: rc for j, rc in near.items()
                    if engine.min_gap(now, engine.union(rc[0]), clearance) < clearance}
        for j, rc in near.items():
            probes.setdefault(("rapid", j), rc)
        if not probes:
            self.hold(s, e)
            return
        before = stock.local(*_around(probes, here, clearance))
        # a part that does not reach into the stock as it is before the chunk cannot reach
        # into it during the chunk (the stock only shrinks): measured here once, those parts
        # need no move-by-move cut
        probes = _reaching(before, probes, clearance)
        if not probes:
            self.hold(s, e)
            return
        self._measure(rows, probes, before)
        self.cut(s, e)

    def _measure(self, rows: range, probes: dict, local) -> None:
        """Cut the chunk's rows one by one from ``local`` up to the last probed one, measuring
        each probed row on it."""
        done: list = []                  # the chunk's cutters so far (for close-up snapshots)
        last = max(j for _, j in probes)
        for j in rows:
            if j > last:
                break
            s_j, e_j = self.span[j]
            local = _cut_one(self.stock, local, done, self.tool, self.table, self.a + j, self.tips[s_j:e_j],
                             self.ax[s_j:e_j], probes.get(("rapid", j)),
                             [(p, probes[(p.name, j)][0]) for p in self.parts if (p.name, j) in probes],
                             self.res, self.clearance)


def _apart(planes, parts: list, tips: np.ndarray, ax: np.ndarray, spans: list, hit: np.ndarray,
           gap: float = 0.0) -> np.ndarray:
    """(rows, parts) bool: rows (poses ``spans`` [s, e) each) whose part (a cylinder) — in
    every pose, so in every solid swept between them, which lie in the hull of the poses —
    lies wholly beyond one face plane of the convex blank, by more than ``gap`` mm (``planes``
    (f, 4); None: not convex, nothing is apart). Only rows with ``hit`` are looked at."""
    out = np.zeros((len(spans), len(parts)), bool)
    todo = np.nonzero(hit)[0]
    if planes is None or not parts or len(todo) == 0:
        return out
    idx = np.concatenate([np.arange(*spans[j]) for j in todo])
    starts = np.cumsum([0] + [spans[j][1] - spans[j][0] for j in todo])[:-1]
    for i, p in enumerate(parts):
        beyond = cylinders_beyond(planes, tips[idx], ax[idx], p.z0, p.z1, p.radius)   # (poses, f)
        out[todo, i] = np.minimum.reduceat(beyond, starts, axis=0).max(axis=1) > gap + 1e-6
    return out


def _around(probes: dict, here: np.ndarray, clearance: float) -> tuple[np.ndarray, np.ndarray]:
    """The box (lo, hi) around the probes' solids, grown by the clearance, within ``here``
    (the stock's bounds) grown by the trim margin."""
    boxes = np.array([bx for _, bxs in probes.values() for bx in bxs])
    lo = np.maximum(boxes[:, 0].min(axis=0) - clearance, here[0]) - tol.trim_margin
    hi = np.minimum(boxes[:, 1].max(axis=0) + clearance, here[1]) + tol.trim_margin
    return lo, hi


def _reaching(before, probes: dict, clearance: float) -> dict:
    """``probes`` without those that cannot make a finding during the chunk, judged on
    ``before`` (the stock before the chunk, or a superset of it, inside a box that holds the
    probes grown by the clearance): a part (``(part name, row)``: (solids, boxes)) that
    overlaps it by no more than ``tol.removal_volume``, measured solid by solid; a rapid
    (``("rapid", row)``) that removes no more than that from it and passes at least
    ``clearance`` from it. Rapids are judged only when a chunk has few (RAPIDS_JUDGED): a
    chunk full of rapids that cut (a facing pass that indexes with G0) is measured move by
    move anyway, and judging them first would double the work."""
    drop = set()
    rapids = [key for key in probes if key[0] == "rapid"]
    if len(rapids) <= RAPIDS_JUDGED:
        for key in rapids:
            cutters = probes[key][0]
            if overlap_volume(before, cutters, centre=False)[0] > tol.removal_volume:
                continue                                   # it cuts
            if clearance > 0 and engine.min_gap(before, engine.union(cutters), clearance) < clearance:
                continue                                   # it may pass close
            drop.add(key)
    drop |= {key for key in probes if key[0] != "rapid"
             and sum(overlap_volume(before, [q], centre=False)[0] for q in probes[key][0])
             <= tol.removal_volume}
    return {key: v for key, v in probes.items() if key not in drop}


def _sliver(local, cut, bound: float) -> bool:
    """Is what ``cut`` takes from ``local`` a skin no thicker on average than ``bound`` mm
    (2·volume / surface area of the chip)? A rapid that leaves a feed along the tool axis
    meets the feed's last tool polygon with its own, turned otherwise: the crescent between
    the two lies within the polygons' tolerance and is not material the rapid hits."""
    chip = engine.intersect(local, cut)
    a = engine.area(chip)
    return a > 0.0 and 2.0 * engine.volume(chip) / a <= bound


def _meets(stock: Stock, probe: list) -> bool:
    """Does any of the (convex) probe solids overlap the stock's blank at all? A vertex inside
    a convex blank says so at once (:meth:`Stock.blank_holds`); else the solids are met."""
    for q in probe:
        if stock.blank_holds(engine.to_mesh(q, double=True)[0]).any():
            return True
        if stock.blank_meets(q):
            return True
    return False


def _cut_one(stock: Stock, local, done: list, tool, table, row: int, tips, ax, rapid, parts: list,
             res, clearance: float = tol.near_miss):
    """Cut one move from ``local`` (the stock inside a box that holds every probe); measure on
    it what a rapid removes and what the parts touch after the move's own cut. Returns the
    local stock after the move."""
    cutters, _ = rapid if rapid is not None else stock.cutters(tool, tips, ax)
    if rapid is not None:
        cut = engine.union(cutters)
        after = engine.subtract(local, [cut])            # the rest; what the rapid removes:
        removed = engine.volume(local) - engine.volume(after)
        if removed > tol.removal_volume and _sliver(local, cut, max(stock.chord, stock.cusp)):
            removed = 0.0           # a skin thinner than the tool polygons' bound: their rounding
        if removed > tol.removal_volume:
            src = table.source(row)
            data = {"volume_mm3": round(removed, 4)}
            where = ""
            # where: for a block's first rapid into the stock (the report gives the first per
            # block; the chip's centroid costs a boolean of its own)
            if not any(f.kind == "rapid_into_stock" and f.source == src for f in res.findings):
                c = np.round(engine.centroid(engine.intersect(local, cut)), 3).tolist()
                data["at_mm"] = c
                where = f" around ({c[0]:.2f}, {c[1]:.2f}, {c[2]:.2f}) mm (work frame)"
            res.findings.append(Finding(
                "rapid_into_stock", "error", f"rapid move removes {removed:.3f} mm³ of material{where}",
                src, row, data))
        elif clearance > 0 and cutters and not ((row == 0 or table.kind[row - 1] != TRAVERSE)
                                                and retracts(tool, tips, ax)):
            gap = engine.min_gap(local, cut, clearance)
            if gap < clearance and (row == 0 or table.kind[row - 1] != TRAVERSE):
                gap = _gap_leaving(local, tool, tips, ax, clearance, gap)
            if gap < clearance:
                res.findings.append(Finding(
                    "near_miss", "warning",
                    f"rapid move passes {gap:.3f} mm from the stock (clearance {clearance:g} mm)",
                    table.source(row), row, {"distance_mm": round(gap, 4), "clearance_mm": clearance,
                                             "obstacle": "stock"}))
    done += cutters
    if rapid is not None:
        local = after
    elif cutters:
        local = engine.subtract(local, cutters)   # lazy: evaluated by the next measurement
    if rapid is not None and res.findings and res.findings[-1].move_index == row:
        _snapshot(stock, done, row, res)
    for p, solids in parts:
        vol, centre = overlap_volume(local, solids)  # the stock after this move's own cut
        if vol > tol.removal_volume:
            res.findings.append(Finding(
                "holder_collision", "error", f"the tool's {p.name} runs {vol:.3f} mm³ into the stock",
                table.source(row), row,
                {"part": p.name, "volume_mm3": round(vol, 4), "at_mm": np.round(centre, 3).tolist()}))
            _snapshot(stock, done, row, res)
    return local


def _gap_leaving(local, tool, tips: np.ndarray, ax: np.ndarray, clearance: float, gap: float) -> float:
    """The gap of a straight rapid right after a feed once it has left where the feed put the
    tool: the cutter's cylinder swept from 2 × ``clearance`` mm along the path on. A rapid that
    starts touching the face the feed ended on and draws straight away from it (a face mill
    lifted off the shoulder it slid along) keeps the clearance there and is no near miss; one
    that slides along the wall or heads for other material is. ``gap`` when the move is no
    straight translation or too short. tips, ax : (n, 3) of the move, mm."""
    d = tips[-1] - tips[0]
    length = float(np.linalg.norm(d))
    if length <= 2 * clearance or not np.allclose(ax, ax[0], atol=1e-9):
        return gap
    u = d / length
    along = (tips - tips[0]) @ u
    if not np.allclose(tips, tips[0] + np.outer(along, u), atol=1e-9):
        return gap
    tail = np.vstack([tips[0] + 2 * clearance * u, tips[-1]])
    cutter = Part("cutter", 0.0, tool.cutting_length, tool.radius)
    solids = part_solids(cutter, tail, np.vstack([ax[0], ax[0]]))
    return engine.min_gap(local, engine.union(solids), clearance) if solids else gap


def retracts(tool, tips: np.ndarray, ax: np.ndarray) -> bool:
    """Whether a rapid only draws the tool back along its own axis with a tool that does not
    widen above its cutter. Right after a feed (a drilling cycle's retract out of its hole),
    or from where the program starts, the cutter then passes only where the tool itself was,
    so its touching the walls it has just cut is no near miss (material in its way is still
    ``rapid_into_stock``); after a rapid the tool was as close before, and the near miss is
    reported.

    tips, ax : (n, 3) tip positions and unit axes (tip toward the spindle) of the move, mm.
    """
    d = tips[-1] - tips[0]
    length = float(np.linalg.norm(d))
    a = ax[0]
    if length == 0.0 or not np.allclose(ax, a, atol=1e-9) or float(d @ a) < length * (1 - 1e-12):
        return False
    radii = [r for _, _, _, r in tool.stack()] if hasattr(tool, "stack") else []
    return bool(radii) and all(r1 >= r0 - 1e-12 for r0, r1 in zip(radii, radii[1:], strict=False))


SNAPSHOTS = 12  # close-up pictures are made of the first few findings only


def _snapshot(stock: Stock, done: list, row: int, res) -> None:
    """The stock right after ``row``: the stock before its chunk minus the chunk's cutters up
    to and including the row's own (``done``)."""
    lines = {f.line for f in res.findings if f.move_index in res.snapshots}
    here = next((f.line for f in reversed(res.findings) if f.move_index == row), None)
    if len(res.snapshots) < SNAPSHOTS and row not in res.snapshots and here not in lines:
        res.snapshots[row] = Snapshot(engine.subtract(stock.solid, list(done)))
