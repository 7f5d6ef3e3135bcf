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

from vmach.checks import probing
from vmach.checks.polygon_events import polygon_path
from vmach.checks.stock_events import CheckedPath
from vmach.checks.turning_events import turn_checked
from vmach.errors import ProgramError
from vmach.findings import Finding, warning
from vmach.stock import cusps
from vmach.stock.events import (
    cylinder_boxes,
    overlaps,
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
    #: row -> :class:`vmach.checks.stock_events.Snapshot` of the stock right after a move that
    #: made a finding (first per block), for the close-up pictures
    snapshots: dict = field(default_factory=dict)


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
        passing closer than ``clearance`` mm to the stock) (see :mod:`vmach.checks.stock_events`):
        moves that may trigger them are cut one by one and measured.
    """
    t0 = time.perf_counter()
    res = SimResult()
    if len(table) == 0:
        return res
    axes = tuple(model.axes)
    rotary = np.array([table.rotary[table.axes.index(a)] if a in table.axes else False for a in axes])
    paths = _sampled_paths(table, model, library, rotary, res, angle, step)
    # the coverage index knows the milling paths only (a turning path's insert covers no rim
    # band, a probe cuts nothing, a flywheel is cut as polygonal turning)
    milling = [i for i, p in enumerate(paths)
               if not (getattr(p[2], "turning", False) or getattr(p[2], "polygon", False))
               and getattr(p[2], "kind", None) != "probe"]
    index = {i: j for j, i in enumerate(milling)}
    sweeps = Sweeps([Motion(q, model.fk, np.asarray(pose.tip, dtype=float), _unit(pose.axis),
                            *cusps.outline(found))
                     for (_, _, found, q, _, pose) in (paths[i] for i in milling)])
    for i, (a, b, found, q, k, pose) in enumerate(paths):
        rows = a + np.r_[0, np.repeat(np.arange(b - a), k)]     # each pose's row (a step: the row it ends)
        if getattr(found, "polygon", False):      # a flywheel cutter coupled to the turning work
            polygon_path(stock, found, table, model, q, np.asarray(pose.tip, dtype=float), rows, res, checks)
            res.moves += b - a
            res.samples += len(q)
            continue
        if getattr(found, "kind", None) == "probe":     # a touch probe cuts nothing
            if checks:
                probing.check_path(stock, found, table, a, b, k, pose, res)
            res.moves += b - a
            res.samples += len(q)
            continue
        if getattr(found, "turning", False):      # the workpiece turns under a fixed turning tool
            if checks:
                turn_checked(stock, found, table, rows, np.asarray(pose.tip, dtype=float), res)
            else:
                stock.turn(found, pose.tip, rows)
            res.moves += b - a
            res.samples += len(q)
            continue
        if checks:
            CheckedPath(stock, found, table, a, b, k, pose, res, clearance, partial(_between, q, model.fk),
                        sweeps.coverage(index[i]), rows).run()
        else:
            stock.cut(found, pose.tip, pose.axis, _between(q, model.fk), sweeps.coverage(index[i]), rows)
        res.moves += b - a
        res.samples += len(q)
        if rotary.any() and len(q) > 1:
            _scallops(res, q[:, rotary], pose, found, np.asarray(stock.initial_bounds))
    res.seconds = time.perf_counter() - t0
    return res


def _sampled_paths(table, model, library, rotary: np.ndarray, res: SimResult, angle: float,
                   step: float) -> list[tuple]:
    """The program's paths — maximal runs of rows with the same known tool — each sampled:
    (first row, end row, tool, axis values q (m, k), samples per row k, poses). All are sampled
    first: what each path's true tool sweeps tells the others' fans which rim bands are taken
    anyway (:mod:`vmach.stock.sweeps`). A tool the library lacks is a warning, once."""
    n = len(table)
    q0 = table.columns(tuple(model.axes), model.home, table.start)
    q1 = table.columns(tuple(model.axes), model.home, table.end)
    tool = np.asarray(table.tool)
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
    return paths


def _scallops(res: SimResult, q_rot: np.ndarray, pose, tool, box: np.ndarray) -> None:
    """The scallop bound over a path's rotary steps (``q_rot`` (m, r): its rotary axes' values)
    taken where the tip is inside the stock radius and the cutter may reach the blank (box
    (2, 3)) at all (the box around its two ends, grown by REACH_SLACK for the arc between them,
    meets the blank's box), into ``res``."""
    r_stock = float(np.hypot(np.abs(box[:, 0]).max(), np.abs(box[:, 1]).max()))
    dq = np.abs(np.diff(q_rot, axis=0)).max(axis=1)
    r = np.linalg.norm(pose.tip[:, :2], axis=1)
    r = np.maximum(r[:-1], r[1:])
    ends = cylinder_boxes(pose.tip, pose.axis, 0.0, tool.cutting_length, tool.radius)
    reach = np.stack([np.minimum(ends[:-1, 0], ends[1:, 0]) - REACH_SLACK,
                      np.maximum(ends[:-1, 1], ends[1:, 1]) + REACH_SLACK], axis=1)
    near = (dq > 0) & (r <= r_stock) & overlaps(reach, box)
    if near.any():
        res.max_step_deg = max(res.max_step_deg, float(dq[near].max()))
        res.bound_mm = max(res.bound_mm, float(scallop_bound(r[near], dq[near]).max()))


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
