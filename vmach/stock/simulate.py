"""Drive stock removal from a move table through a machine model's forward kinematics.

    result = simulate(table, model, library, stock)

Every row with a known tool is cut, rapid moves included (a rapid into material is reported by
the verify stage; the material is gone either way). Rows that turn a rotary axis are sampled
between their ends by evaluating the kinematics at linearly interpolated axis values — what the
control's interpolator does — so that each sample step stays within ``tol.sweep_angle`` of
rotation and ``tol.sweep_step`` of tip travel (:func:`vmach.stock.sweep.rotary_substeps`).
Straight rows without rotation are cut as exact translation hulls.

The kinematics is any object with ``fk(q) -> pose`` (``pose.tip``, ``pose.axis``: (n, 3)) and
``axes``/``home`` naming the columns of ``q``; the stage does not depend on how poses are made.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from vmach.errors import ProgramError
from vmach.findings import Finding, warning
from vmach.motion.table import TRAVERSE
from vmach.stock import cusps, engine
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
from vmach.stock.sweep import rotary_substeps, scallop_bound
from vmach.stock.sweeps import Motion, Sweeps
from vmach.tol import tol


@dataclass
class SimResult:
    """What a simulation did.

    moves : rows cut; samples : poses evaluated; seconds : wall time of kinematics + cutting.
    bound_mm : largest flat-face scallop the sampling allows (``r·(sec(δ/2) − 1)`` at the
        largest sampled rotation δ and the largest tip distance r from the work Z axis).
    findings : rows whose tool the library lacks (one warning per tool name).
    """

    moves: int = 0
    samples: int = 0
    seconds: float = 0.0
    kinematics_seconds: float = 0.0
    bound_mm: float = 0.0
    max_step_deg: float = 0.0
    findings: list[Finding] = field(default_factory=list)
    #: row -> :class:`Snapshot` of the stock right after a move that made a finding (first
    #: per block), for the close-up pictures
    snapshots: dict = field(default_factory=dict)


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


class SampleLimit(Exception):
    """A path's rows need more samples than ``tol.max_poses``: ``row`` (index in the path, the
    row that needs most) needs ``count``."""

    def __init__(self, row: int, count: int):
        super().__init__(row, count)
        self.row, self.count = row, count


def sample_rows(start: np.ndarray, end: np.ndarray, rotary: np.ndarray, fk,
                angle: float = tol.sweep_angle, step: float = tol.sweep_step):
    """Axis values of one connected path of rows, sampled for cutting.

    start, end : (n, k) float — rows in order (row i ends where row i+1 starts).
    rotary : (k,) bool. fk : callable (m, k) -> pose with tip, axis (m, 3).
    Returns q (m, k) float: the first start, then for each row its sub-samples up to its end.
    """
    start = np.asarray(start, dtype=float)
    end = np.asarray(end, dtype=float)
    rot = np.abs(end[:, rotary] - start[:, rotary]).max(axis=1) if rotary.any() else np.zeros(len(start))
    k = np.ones(len(start), dtype=int)
    if (rot > 0).any():
        ends = fk(np.concatenate([start[rot > 0], end[rot > 0]]))
        m = int((rot > 0).sum())
        travel = np.linalg.norm(ends.tip[:m] - ends.tip[m:], axis=1)
        k[rot > 0] = rotary_substeps(rot[rot > 0], travel, angle, step)
    if k.sum() > tol.max_poses:
        raise SampleLimit(int(np.argmax(k)), int(k.max()))
    total = int(k.sum())
    row = np.repeat(np.arange(len(start)), k)
    first = np.r_[0, np.cumsum(k)[:-1]]
    t = (np.arange(total) - np.repeat(first, k) + 1) / np.repeat(k, k)
    q = start[row] + (end[row] - start[row]) * t[:, None]
    return np.vstack([start[:1], q]), k


#: mm: how far a sampled rotary step's sweep may bulge beyond the boxes of its two ends (a
#: point ρ from the rotation axis leaves its chord by ρ(1 − cos 1°) ≤ 1 mm for ρ ≤ 6.5 m)
REACH_SLACK = 1.0


def simulate(table, model, library, stock: Stock, *, angle: float = tol.sweep_angle,
             step: float = tol.sweep_step, checks: bool = False,
             clearance: float = tol.near_miss) -> SimResult:
    """Cut ``stock`` with every row of ``table`` (a :class:`vmach.motion.table.MoveTable`).

    model : kinematics (``axes``, ``home``, ``fk``); library : tool library (``lookup``).
    checks : also report ``rapid_into_stock``, ``holder_collision`` and ``near_miss`` (a rapid
        passing closer than ``clearance`` mm to the stock) (see :mod:`vmach.stock.events`):
        moves that may trigger them are cut one by one and measured.
    """
    t0 = time.perf_counter()
    res = SimResult()
    n = len(table)
    if n == 0:
        return res
    axes = tuple(model.axes)
    rotary = np.array([table.rotary[table.axes.index(a)] if a in table.axes else False for a in axes])
    q0 = table.columns(axes, model.home, table.start)
    q1 = table.columns(axes, model.home, table.end)
    tool = np.asarray(table.tool)
    box = np.asarray(stock.initial_bounds)
    r_stock = float(np.hypot(np.abs(box[:, 0]).max(), np.abs(box[:, 1]).max()))
    # paths: maximal runs of rows with the same tool, all sampled first: what each path's
    # true tool sweeps tells the others' fans which rim bands are taken anyway (stock.sweeps)
    cuts = np.nonzero(np.diff(tool) != 0)[0] + 1
    missing: set[str] = set()
    paths = []
    for a, b in zip(np.r_[0, cuts], np.r_[cuts, n], strict=True):
        ti = int(tool[a])
        if ti < 0:
            continue
        name = table.tools[ti]
        found = library.lookup(name) if library is not None else None
        if found is None:
            if name not in missing:
                missing.add(name)
                res.findings.append(warning(
                    "stock_tool_unknown", f'tool "{name}" is not in the tool library: its moves '
                    "remove no material", table.source(a), tool=name))
            continue
        tk = time.perf_counter()
        try:
            q, k = sample_rows(q0[a:b], q1[a:b], rotary, model.fk, angle, step)
        except SampleLimit as exc:
            raise ProgramError("resource_limit", f"the tool's path needs {exc.count} poses of at most "
                               f"{angle:g}° at this move (vmach's limit: {tol.max_poses} per path)",
                               table.source(a + exc.row)) from None
        pose = model.fk(q)
        res.kinematics_seconds += time.perf_counter() - tk
        paths.append((a, b, found, q, k, pose))
    zr = [cusps.outline(found) for _, _, found, _, _, _ in paths]
    sweeps = Sweeps([Motion(q, model.fk, np.asarray(pose.tip, dtype=float), _unit(pose.axis), *o)
                     for (_, _, _, q, _, pose), o in zip(paths, zr, strict=True)])
    for i, (a, b, found, q, k, pose) in enumerate(paths):
        if checks:
            _cut_checked(stock, found, table, a, b, k, pose, res, clearance, partial(_between, q, model.fk),
                         sweeps.others(i))
        else:
            stock.cut(found, pose.tip, pose.axis, _between(q, model.fk), sweeps.others(i))
        res.moves += b - a
        res.samples += len(q)
        if rotary.any() and len(q) > 1:
            # scallop bound over the rotary steps taken where the tip is inside the stock radius
            # and the cutter may reach the blank at all (the box around its two ends, grown by
            # REACH_SLACK for the arc between them, meets the blank's box)
            dq = np.abs(np.diff(q[:, rotary], axis=0)).max(axis=1)
            r = np.linalg.norm(pose.tip[:, :2], axis=1)
            r = np.maximum(r[:-1], r[1:])
            ends = cylinder_boxes(pose.tip, pose.axis, 0.0, found.cutting_length, found.radius)
            reach = np.stack([np.minimum(ends[:-1, 0], ends[1:, 0]) - REACH_SLACK,
                              np.maximum(ends[:-1, 1], ends[1:, 1]) + REACH_SLACK], axis=1)
            near = (dq > 0) & (r <= r_stock) & overlaps(reach, box)
            if near.any():
                res.max_step_deg = max(res.max_step_deg, float(dq[near].max()))
                res.bound_mm = max(res.bound_mm, float(scallop_bound(r[near], dq[near]).max()))
    res.seconds = time.perf_counter() - t0
    return res


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def _between(q: np.ndarray, fk, offset: int = 0):
    """The poses inside sampled steps, as :meth:`Stock.cut` asks for them: the machine axes
    ``q`` (m, k) of a path's samples interpolated linearly — as the control moves them within
    a row — and run through the kinematics ``fk``. ``offset``: the first sample of the poses
    the stock is given."""
    def at(steps: np.ndarray, parts: np.ndarray):
        rows = np.repeat(np.asarray(steps, dtype=int) + offset, parts - 1)
        frac = np.concatenate([np.arange(1, p) / p for p in parts])
        pose = fk(q[rows] + (q[rows + 1] - q[rows]) * frac[:, None])
        return pose.tip, pose.axis, rows - offset + frac
    return at


CHUNK = 64  # moves screened together against the stock before them
RAPIDS_JUDGED = 8  # a chunk's rapids are judged on the stock before it when there are no more


def _cut_checked(stock: Stock, tool, table, a: int, b: int, k: np.ndarray, pose, res: SimResult,
                 clearance: float = tol.near_miss, between=None, others=None) -> None:
    """Cut rows a..b-1 (samples: row j spans pose[first_j .. first_j + k_j]) and report rapids
    into material and shank/holder contact (:mod:`vmach.stock.events`).

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
    inside sampled steps for :meth:`Stock.cut` given the samples from ``offset`` on
    (:func:`_between` of the path's machine axes); ``others``: what the other paths' true
    tools sweep (:class:`vmach.stock.sweeps.Others`), for the fans and feet of every cut."""
    tips, ax = pose.tip, pose.axis

    def inside(s: int):
        return None if between is None else between(s)

    def shifted(s: int):
        return None if others is None else others.shifted(s)

    first = np.r_[0, np.cumsum(k)[:-1]]
    span = [(first[j], first[j] + k[j] + 1) for j in range(b - a)]
    cut_boxes = cylinder_boxes(tips, ax, 0.0, tool.cutting_length, tool.radius)
    parts = body_parts(tool)
    blank = np.asarray(stock.initial_bounds)
    # a row's parts may reach the blank when the box around them over the row's poses does: a
    # straight row's sweep lies in the box around its two ends (both of which may lie outside
    # the blank's box while the move passes through it)
    part_hit = np.zeros(b - a, bool)
    if parts:
        boxes = np.stack([cylinder_boxes(tips, ax, p.z0, p.z1, p.radius) for p in parts])
        lo, hi = boxes[:, :, 0].min(axis=0), boxes[:, :, 1].max(axis=0)        # (poses, 3)
        last = first + k                                                    # each row's end pose
        row_lo = np.minimum(np.minimum.reduceat(lo, first, axis=0), lo[last])
        row_hi = np.maximum(np.maximum.reduceat(hi, first, axis=0), hi[last])
        part_hit = overlaps(np.stack([row_lo, row_hi], axis=1), blank)
    planes = stock.blank_planes()
    cutter = [Part("cutter", 0.0, tool.cutting_length, tool.radius)]   # as cut_boxes, for _apart
    rapid = table.kind[a:b] == TRAVERSE
    held = [None, None]             # poses [first, last + 1) of chunks not yet cut: one path

    def hold(s: int, e: int) -> None:
        held[:] = [s if held[0] is None else held[0], e]

    def release() -> None:
        if held[0] is not None:
            stock.cut(tool, tips[held[0] : held[1]], ax[held[0] : held[1]], inside(held[0]), shifted(held[0]))
            held[:] = [None, None]

    for c0 in range(0, b - a, CHUNK):
        rows = range(c0, min(c0 + CHUNK, b - a))
        here = stock.bounds
        probes: dict = {}
        near: dict = {}                  # rapids within the clearance of the stock's box
        spans = [span[j] for j in rows]
        apart = _apart(planes, parts, tips, ax, spans, part_hit[c0 : c0 + CHUNK])
        # a rapid whose cutter lies farther than the clearance beyond a face of the blank
        # neither cuts nor passes close
        clear = _apart(planes, cutter, tips, ax, spans, rapid[c0 : c0 + CHUNK], clearance)[:, 0]
        for j in rows:
            s, e = span[j]
            if rapid[j] and not clear[j - c0]:
                box = np.stack([cut_boxes[s:e, 0].min(axis=0), cut_boxes[s:e, 1].max(axis=0)])
                if overlaps(box[None], here)[0]:
                    probes[("rapid", j)] = stock.cutters(tool, tips[s:e], ax[s:e])
                elif clearance > 0 and overlaps((box + [[-clearance], [clearance]])[None], here)[0]:
                    near[j] = stock.cutters(tool, tips[s:e], ax[s:e])
            if part_hit[j]:
                for i, p in enumerate(parts):
                    if apart[j - c0, i]:
                        continue        # a face plane of the blank parts them: it meets no stock
                    q = part_solids(p, tips[s:e], ax[s:e], planes=planes)
                    if not q:
                        continue
                    probes[(p.name, j)] = (q, [engine.bounds(x) for x in q])
        # a rapid whose cutter meets the blank may meet the stock; else, only one that comes
        # within the clearance of the stock as it is before the chunk (a superset of the stock
        # during the chunk) can be a near miss
        for j, rc in list(probes.items()):
            if j[0] == "rapid" and not _meets(stock, rc[0]):
                near[j[1]] = rc
        probes = {key: v for key, v in probes.items() if _meets(stock, v[0])}
        s, e = span[rows[0]][0], span[rows[-1]][1]
        if probes and not near and held[0] is not None:
            # measured first on the stock without the chunks held back (more material than
            # now), so that most chunks need not cut those first
            probes = _reaching(stock.local(*_around(probes, here, clearance)), probes, clearance)
        if not probes and not near:
            hold(s, e)              # cut later with its neighbours, as one path
            continue
        release()
        if near:
            now = stock.solid
            near = {j: rc for j, rc in near.items()
                    if engine.min_gap(now, engine.union(rc[0]), clearance) < clearance}
        for j, rc in near.items():
            probes.setdefault(("rapid", j), rc)
        if not probes:
            hold(s, e)
            continue
        before = stock.local(*_around(probes, here, clearance))
        # a part that does not reach into the stock as it is before the chunk cannot reach
        # into it during the chunk (the stock only shrinks): measured here once, those parts
        # need no move-by-move cut
        probes = _reaching(before, probes, clearance)
        if not probes:
            hold(s, e)
            continue
        local = before
        done: list = []                  # the chunk's cutters so far (for close-up snapshots)
        last = max(j for _, j in probes)
        for j in rows:
            if j > last:
                break
            s_j, e_j = span[j]
            local = _cut_one(stock, local, done, tool, table, a + j, tips[s_j:e_j], ax[s_j:e_j],
                             probes.get(("rapid", j)),
                             [(p, probes[(p.name, j)][0]) for p in parts if (p.name, j) in probes], res,
                             clearance)
        stock.cut(tool, tips[s:e], ax[s:e], inside(s), shifted(s))
    release()


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
             res: SimResult, clearance: float = tol.near_miss):
    """Cut one move from ``local`` (the stock inside a box that holds every probe); measure on
    it what a rapid removes and what the parts touch after the move's own cut. Returns the
    local stock after the move."""
    cutters, _ = rapid if rapid is not None else stock.cutters(tool, tips, ax)
    if rapid is not None:
        cut = engine.union(cutters)
        after = engine.subtract(local, [cut])            # the rest; what the rapid removes:
        removed = engine.volume(local) - engine.volume(after)
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


def _snapshot(stock: Stock, done: list, row: int, res: SimResult) -> None:
    """The stock right after ``row``: the stock before its chunk minus the chunk's cutters up
    to and including the row's own (``done``)."""
    lines = {f.line for f in res.findings if f.move_index in res.snapshots}
    here = next((f.line for f in reversed(res.findings) if f.move_index == row), None)
    if len(res.snapshots) < SNAPSHOTS and row not in res.snapshots and here not in lines:
        res.snapshots[row] = Snapshot(engine.subtract(stock.solid, list(done)))
