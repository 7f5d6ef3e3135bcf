"""The planner: a tool path in, typed jobs out (:mod:`vmach.stock.jobs`), stretch by stretch.

    for ts, jobs in planner.plan(tool, tips, axes, between, others, rows):
        cutters = maker.make(ts, jobs)

A path is the tool's poses (tips, unit axes (n, 3), work frame, mm), joined by motion in order.
Its steps are split into straight and rotary ones (:func:`vmach.stock.sweep.plan`); the cutter
strategies (:mod:`vmach.stock.strategies`) then claim them in their priority order, and the
poses left are placed. Every pose is turned about its axis so that the tool's polygon is exact
toward the sides of its travel (:func:`vmach.tooling.solid.spun`). Jobs come in path order, in
stretches of CHUNK, so that cutters are queued — and may be subtracted — as they come.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field

import numpy as np

from vmach.errors import InputError
from vmach.stock import make
from vmach.stock.jobs import ColumnJob, Fan, Job, Placed, Runs, span
from vmach.stock.make_fans import run_frames
from vmach.stock.stats import CutStats
from vmach.stock.strategies import cusps as cusp_poses
from vmach.stock.strategies import fans as fan_runs
from vmach.stock.strategies import fins, revolved, runs
from vmach.stock.sweep import plan, run_extremes, stacked_runs
from vmach.stock.view import View
from vmach.tol import tol
from vmach.tooling.model import Tool
from vmach.tooling.solid import ToolSolid, across, frames, lateral, spun, tool_solid


@dataclass(frozen=True)
class Settings:
    """What the planner may do. chord : tool polygon tolerance, mm; arcs : flat or face mills'
    rims exact toward each pose's sides (``Accuracy.rim_arcs``); trim : trim cutters and leave
    out poses a run holds; fans / columns : the fan strategy (with trim); cusp : the largest
    cusp left between placed poses, mm; fan_overcut : the most a fan may remove beyond the true
    sweep, mm."""

    chord: float = tol.tool_chord
    arcs: bool = False
    trim: bool = True
    fans: bool = True
    columns: bool = True
    cusp: float = tol.sweep_cusp
    fan_overcut: float = tol.fan_overcut
    without: frozenset = field(default_factory=lambda: without_env())

    def on(self, name: str) -> bool:
        """Whether the strategy (or the coverage index, ``cover``) ``name`` may run."""
        return name not in self.without


#: the environment variable that switches strategies off for a measurement (comma-separated
#: names: fans, columns, fins, cusps, axial, stacked, cover) — ``benchmarks/stock_strategies.py``
WITHOUT = "VMACH_STOCK_WITHOUT"
#: the names it takes
SWITCHES = ("fans", "columns", "fins", "cusps", "axial", "stacked", "cover")


def without_env() -> frozenset:
    """The strategies switched off by :data:`WITHOUT` (empty: none)."""
    return frozenset(w.strip() for w in os.environ.get(WITHOUT, "").split(",") if w.strip())


@dataclass
class _Path:
    """One path as the strategies leave it: poses ``tips``, ``axes``, ``unit`` (n, 3), frames
    ``fr`` (n + e, 3, 4) (e poses added by :mod:`.strategies.cusps`), lateral ``sides`` (n, 3),
    placed poses ``poses`` (m,) int and where they lie along the path ``key`` (m,) float, their
    fins ``fins`` / ``tall`` (n + e,) mm, the translation runs ``runs`` (r, 2) in ``groups``, fans
    and columns, and the source row of each pose ``rows`` (n + e,) int or None."""

    ts: ToolSolid
    tips: np.ndarray
    axes: np.ndarray
    unit: np.ndarray
    fr: np.ndarray
    sides: np.ndarray
    poses: np.ndarray
    key: np.ndarray
    fins: np.ndarray
    tall: np.ndarray
    runs: np.ndarray
    groups: list
    fans: object
    cols: list
    rows: np.ndarray | None


class Planner:
    """Plans paths against a :class:`vmach.stock.view.View`, with the tool shapes its
    :class:`vmach.stock.make.Maker` keeps; counts into ``stats``."""

    CHUNK = 256  # poses swept at a time (cutters are queued, and may be subtracted, as they come)

    def __init__(self, settings: Settings, view: View, maker: make.Maker, stats: CutStats):
        self.s = settings
        self.view = view
        self.maker = maker
        self.stats = stats

    def tool_solid(self, tool: Tool | ToolSolid) -> ToolSolid:
        return tool if isinstance(tool, ToolSolid) else tool_solid(tool, self.s.chord, arcs=self.s.arcs)

    def plan(self, tool: Tool | ToolSolid, tips: np.ndarray, axes: np.ndarray, between=None, others=None,
             rows: np.ndarray | None = None):
        """Yield (tool solid, [Job]) for consecutive stretches of a path, in path order (see
        :meth:`vmach.stock.Stock.cut` for the arguments)."""
        t0 = time.perf_counter()
        ts = self.tool_solid(tool)
        tips, axes = _checked(tips, axes, rows)
        others = others if self.s.on("cover") else None
        rows = None if rows is None else np.asarray(rows, dtype=int)
        self.stats.paths += 1
        self.stats.poses += len(tips)
        if len(tips) == 0:
            return
        p, t0 = self._claim(tool, ts, tips, axes, between, others, rows, t0)
        for jobs in self._stretches(p):
            self.stats.sweep_seconds += time.perf_counter() - t0
            yield ts, jobs
            t0 = time.perf_counter()
        self.stats.sweep_seconds += time.perf_counter() - t0

    def turn(self, section: np.ndarray, tips: np.ndarray, rows: np.ndarray | None = None) -> list[Job]:
        """The revolved jobs of a turning path (:mod:`vmach.stock.strategies.revolved`): the
        tool's cross-section ``section`` (k, 2) ``(x, z)`` mm from its tip, at ``tips`` (n, 3)
        work frame mm (their distance from the spindle axis and Z)."""
        tips, _ = _checked(tips, np.broadcast_to([1.0, 0.0, 0.0], np.shape(tips)), rows)
        self.stats.paths += 1
        self.stats.poses += len(tips)
        rows = None if rows is None else np.asarray(rows, dtype=int)
        return revolved.claim(section, revolved.half_plane(tips), rows)

    def _claim(self, tool, ts: ToolSolid, tips, axes, between, others, rows, t0: float):
        """The strategies, in their order, over one path: (_Path, t0 less the retake's time)."""
        s, view, pr = self.s, self.view, self.maker.prism(ts)
        sp = plan(tips, axes)
        sides = lateral(tips, axes)
        fr = spun(frames(tips, axes), sides, ts.segments)
        rotary = sp.angles > tol.hull_angle
        if s.trim:
            t1 = time.perf_counter()
            # trim slabs of the stock now (and the stock as it is for fans: their tool's back)
            force = s.fans and bool(rotary.any()) and pr is not None
            view.boxes(np.zeros(0), np.zeros(0), fresh=True, force=force)
            t0 += time.perf_counter() - t1                       # (its booleans are counted there)
            poses = runs.outside(sp.poses, sp.runs)
            self.stats.covered += (len(sp.poses) - len(poses)) * len(ts.pieces)
        else:
            poses = sp.poses
        unit = axes / np.linalg.norm(axes, axis=1, keepdims=True)
        fc = fan_runs.claim(ts, pr if s.fans and s.on("fans") else None, tips, unit, rotary, view,
                            columns=s.columns and s.on("columns"),
                            overcut=s.fan_overcut, others=others)
        run = sp.runs
        if len(fc.runs):
            # a fan's end poses turned for its own steps, not for the move beyond it
            a, b = fc.runs[:, 0], fc.runs[:, 1]
            ends = np.r_[a, b]
            step = np.r_[tips[a + 1] - tips[a], tips[b] - tips[b - 1]]
            sides[ends] = across(unit[ends], step)
            fr[ends] = spun(frames(tips[ends], axes[ends]), sides[ends], ts.segments)
            poses = runs.outside(poses, fc.runs)
            run = run[~runs.within(run, fc.runs)]
        if s.trim and len(run) and s.on("axial"):
            run, poses, k = runs.claim_axial(ts, tips, unit, run, poses, fc.runs, view)
            self.stats.axial_runs += k
        groups = (stacked_runs(tips, unit, run, pr.length) if pr is not None and s.trim and s.on("stacked")
                  else [[r] for r in range(len(run))])
        self.stats.stacked_runs += len(run) - len(groups)
        p = _Path(ts, tips, axes, unit, fr, sides, poses, poses.astype(float), np.full(len(fr), np.inf),
                  np.full(len(fr), np.inf), run, groups, fc.fans, fc.columns, rows)
        if s.trim and isinstance(tool, Tool) and s.on("fins"):
            p.fins, k = fins.claim(tool, ts, pr, fr, rotary, fc.runs, poses, view)
            self.stats.inner_fins += k
        if between is not None and s.trim and isinstance(tool, Tool) and s.on("cusps"):
            self._add_cusp_poses(p, tool, pr, rotary, fc.runs, between, others)
        return p, t0

    def _add_cusp_poses(self, p: _Path, tool: Tool, pr, rotary, fan_steps, between, others) -> None:
        add = cusp_poses.claim(tool, p.ts, pr, p.tips, p.fr, rotary, fan_steps, between, self.view,
                               cusp=self.s.cusp, chord=self.s.chord, others=others)
        self.stats.foot_steps += add.feet
        if not len(add.frames):
            return
        self.stats.cusp_poses += len(add.frames)
        p.poses = np.r_[p.poses, len(p.fr) + np.arange(len(add.frames))]
        p.key = np.r_[p.key, add.at]
        if p.rows is not None:     # an added pose lies on the step it parts: that step's row
            p.rows = np.r_[p.rows, p.rows[np.floor(add.at).astype(int) + 1]]
        p.fr = np.concatenate([p.fr, add.frames])
        p.fins = np.r_[p.fins, add.half]
        p.tall = np.r_[p.tall, add.height]
        self.stats.cusp_fins += int(np.isfinite(make.fin_bucket(add.half, p.ts.radius)).sum())

    def _stretches(self, p: _Path):
        """[Job] per stretch of CHUNK items (placed poses, run groups, fans, columns) in the
        order they start along the path."""
        fans, cols, groups, run = p.fans, p.cols, p.groups, p.runs
        start = np.concatenate([p.key, [run[g, 0].min() for g in groups], fans.runs[:, 0],
                                [c.cells[0, 0] for c in cols]])
        kind = np.r_[np.zeros(len(p.poses), int), np.ones(len(groups), int), np.full(len(fans.runs), 2),
                     np.full(len(cols), 3)]
        which = np.r_[np.arange(len(p.poses)), np.arange(len(groups)), np.arange(len(fans.runs)),
                      np.arange(len(cols))].astype(int)
        order = np.argsort(start, kind="stable")
        path = (p.tips, p.unit)                       # what else the path cuts
        for c0 in range(0, len(order), self.CHUNK):
            part = order[c0 : c0 + self.CHUNK]
            mine = [which[part][kind[part] == k] for k in range(4)]
            chunk_groups = [groups[g] for g in mine[1]]
            ends = [run_extremes(p.tips, run[r]) for g in chunk_groups for r in g]
            flat = run_frames(p.tips, p.axes, ends, p.ts.segments, p.sides)     # shared by every piece
            sizes = np.cumsum([0] + [len(g) for g in chunk_groups])
            run_fr = [flat[sizes[i] : sizes[i + 1]] for i in range(len(chunk_groups))]
            group_rows = np.array([span(p.rows, int(run[g, 0].min()), int(run[g, 1].max()))
                                   for g in chunk_groups], dtype=int).reshape(-1, 2)
            placed = p.poses[mine[0]]
            pose_rows = (np.full((len(placed), 2), -1) if p.rows is None
                         else np.repeat(p.rows[placed][:, None], 2, axis=1))
            jobs: list[Job] = [ColumnJob(cols[c], p.tips, p.unit, p.fr, path,
                                         span(p.rows, int(cols[c].cells.min()), int(cols[c].cells.max())))
                               for c in mine[3]]
            jobs += [Fan(p.tips[a : b + 1], p.unit[a : b + 1], fans.omega[f], p.fr[a : b + 1], path,
                         span(p.rows, a, b)) for f in mine[2] for a, b in [fans.runs[f]]]
            for k in range(len(p.ts.pieces)):
                jobs.append(Placed(k, p.fr[placed], p.fins[placed], p.tall[placed], pose_rows))
                jobs.append(Runs(k, run_fr, group_rows))
            yield jobs


def _checked(tips, axes, rows) -> tuple[np.ndarray, np.ndarray]:
    """Tips and axes (n, 3) float, or InputError (lengths differ, a non-finite pose)."""
    tips = np.asarray(tips, dtype=float).reshape(-1, 3)
    axes = np.asarray(axes, dtype=float).reshape(-1, 3)
    if len(tips) != len(axes) or (rows is not None and len(rows) != len(tips)):
        raise InputError("cut: tips, axes and rows differ in length", kind="stock_input")
    if not (np.isfinite(tips).all() and np.isfinite(axes).all()):
        raise InputError("cut: non-finite pose", kind="stock_input")
    return tips, axes


__all__ = ["Planner", "Settings"]
