"""The planner: a tool path in, typed jobs out (:mod:`vmach.stock.jobs`), stretch by stretch.

    for ts, jobs in planner.plan(tool, tips, axes, between, cover, rows):
        cutters = maker.make(ts, jobs)

A path (:class:`vmach.stock.path.Path`: the tool's poses, joined by motion in order) is offered
to the cutter strategies in the order of :data:`TABLE`; each claims what it cuts of what the
ones before left (:class:`~vmach.stock.path.Free`) and says how (:class:`~vmach.stock.path.Claim`);
the last line places every pose left. Every pose is turned about its axis so that the tool's
polygon is exact toward the sides of its travel (:func:`vmach.tooling.solid.spun`). What the
strategies made comes out in path order, in stretches of CHUNK, so that cutters are queued —
and may be subtracted — as they come. Cross-path knowledge is the optional coverage index
(``cover``, :class:`vmach.stock.sweeps.Coverage`): a caller streaming the program passes none.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field

import numpy as np

from vmach.errors import InputError
from vmach.stock import make
from vmach.stock.jobs import Job, Placed, Runs
from vmach.stock.make_fans import run_frames
from vmach.stock.path import Claim, Free, Path
from vmach.stock.stats import CutStats
from vmach.stock.strategies import cusps, fans, fins, placed, polygonal, revolved, runs
from vmach.stock.view import View
from vmach.tol import tol
from vmach.tooling.model import Tool
from vmach.tooling.solid import ToolSolid, tool_solid

#: the cutter strategies, in priority order (docs/stock.md says why each exists and its bound):
#: a new one is a module in vmach/stock/strategies/ and a line here
TABLE = (
    revolved,   # a turning path, whole
    polygonal,  # a polygonal-turning path (a flywheel coupled to the work), whole
    fans,       # rotary runs of a flat-faced prism (and the slides between them): fans, columns
    runs,       # straight runs: exact hulls
    fins,       # placed poses between two placed rotary steps: their fins
    cusps,      # poses added inside placed rotary steps against cusps
    placed,     # every pose left: the tool placed there (always last)
)

@dataclass(frozen=True)
class Settings:
    """What the planner may do. chord : tool polygon tolerance, mm; arcs : flat or face mills'
    rims exact toward each pose's sides (``Accuracy.rim_arcs``); trim : trim cutters and leave
    out poses a run holds; fans / columns : the fan strategy (with trim); cusp : the largest
    cusp left between placed poses, mm; fan_overcut : the most a fan may remove beyond the true
    sweep, mm; without : the strategies switched off (:data:`SWITCHES`; from :data:`WITHOUT`)."""

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
#: names: fans, columns, fins, cusps, axial, cover) — ``benchmarks/stock_strategies.py``
WITHOUT = "VMACH_STOCK_WITHOUT"
#: the names it takes (a strategy's NAME, or a part of one: the columns of fans, the axial
#: runs, the coverage index); runs, placed and revolved are the only way their paths are cut
SWITCHES = ("fans", "columns", "fins", "cusps", "axial", "cover")


def without_env() -> frozenset:
    """The strategies switched off by :data:`WITHOUT` (empty: none); a name it does not know is
    an InputError (a measurement must not silently measure something else)."""
    names = frozenset(w.strip() for w in os.environ.get(WITHOUT, "").split(",") if w.strip())
    if names - set(SWITCHES):
        raise InputError(f"{WITHOUT}: unknown {', '.join(sorted(names - set(SWITCHES)))} "
                         f"(known: {', '.join(SWITCHES)})", kind="usage")
    return names


class Planner:
    """Plans paths against a :class:`vmach.stock.view.View`, with the tool shapes its
    :class:`vmach.stock.make.Maker` keeps; counts into ``stats``."""

    CHUNK = 256  # poses swept at a time (cutters are queued, and may be subtracted, as they come)

    def __init__(self, settings: Settings, view: View, maker: make.Maker, stats: CutStats):
        self.s = settings
        self.view = view
        self.maker = maker
        self.stats = stats
        maker.own.update({m.JOB: m.make for m in TABLE if getattr(m, "JOB", None) is not None})

    def tool_solid(self, tool: Tool | ToolSolid) -> ToolSolid:
        return tool if isinstance(tool, ToolSolid) else tool_solid(tool, self.s.chord, arcs=self.s.arcs)

    def plan(self, tool: Tool | ToolSolid, tips: np.ndarray, axes: np.ndarray, between=None, cover=None,
             rows: np.ndarray | None = None):
        """Yield (tool solid, [Job]) for consecutive stretches of a path, in path order (see
        :meth:`vmach.stock.Stock.cut` for the arguments)."""
        t0 = time.perf_counter()
        ts = self.tool_solid(tool)
        tips, axes = _checked(tips, axes, rows)
        path = Path(tips, axes, _rows(rows), self.s, tool=tool, ts=ts, pr=self.maker.prism(ts),
                    between=between)
        self.stats.paths += 1
        self.stats.poses += len(tips)
        if len(tips) == 0:
            return
        t0 += self._retake(path)
        place = np.zeros(path.n, bool)
        place[path.sweep.poses] = True
        claims = self._claims(path, Free(np.ones(path.n - 1, bool), place),
                              cover if self.s.on("cover") else None)
        for jobs in self._stretches(path, claims):
            self.stats.sweep_seconds += time.perf_counter() - t0
            yield ts, jobs
            t0 = time.perf_counter()
        self.stats.sweep_seconds += time.perf_counter() - t0

    def turn(self, section: np.ndarray, tips: np.ndarray, rows: np.ndarray | None = None) -> list[Job]:
        """The jobs of a turning path (:mod:`vmach.stock.strategies.revolved`): the tool's
        cross-section ``section`` (k, 2) ``(x, z)`` mm from its tip, at ``tips`` (n, 3) work
        frame mm (their distance from the spindle axis and Z)."""
        tips, axes = _checked(tips, np.broadcast_to([1.0, 0.0, 0.0], np.shape(tips)), rows)
        self.stats.paths += 1
        self.stats.poses += len(tips)
        if len(tips) == 0:
            return []
        path = Path(tips, axes, _rows(rows), self.s, section=section)
        claims = self._claims(path, Free(np.ones(path.n - 1, bool), np.ones(path.n, bool)), None)
        return [job for c in claims for _, job in c.jobs]

    def polygon(self, tool, coupling, points: np.ndarray, rows: np.ndarray | None = None) -> list[Job]:
        """The jobs of a polygonal-turning path (:mod:`vmach.stock.strategies.polygonal`): the
        flywheel ``tool`` coupled by ``coupling``, its point P at ``points`` (n, 3) machine
        frame mm."""
        pts, axes = _checked(points, np.broadcast_to([1.0, 0.0, 0.0], np.shape(points)), rows)
        self.stats.paths += 1
        self.stats.poses += len(pts)
        if len(pts) == 0:
            return []
        path = Path(pts, axes, _rows(rows), self.s, coupled=(tool, coupling))
        claims = self._claims(path, Free(np.ones(path.n - 1, bool), np.ones(path.n, bool)), None)
        return [job for c in claims for _, job in c.jobs]

    def _retake(self, path: Path) -> float:
        """Retake the view's trim slabs for a new path (and the stock as it is, for fans: their
        tool's back); the seconds it took (its booleans are counted there)."""
        if not self.s.trim:
            return 0.0
        t1 = time.perf_counter()
        force = self.s.fans and self.s.on("fans") and path.pr is not None and bool(path.rotary.any())
        self.view.boxes(np.zeros(0), np.zeros(0), fresh=True, force=force)
        return time.perf_counter() - t1

    def _claims(self, path: Path, free: Free, cover) -> list[Claim]:
        """Each strategy of the table in turn (unless switched off) over what the ones before
        left of the path, ``free`` updated as they claim: their claims."""
        out = []
        for strategy in TABLE:
            if not free.any():
                break
            if not self.s.on(strategy.NAME):
                continue
            c = strategy.claim(path, free, self.view, cover)
            if c.steps is not None:
                free.steps &= ~c.steps
            if c.held is not None:
                free.place &= ~c.held
            free.place[c.place] = True
            for name, amount in c.counts.items():
                setattr(self.stats, name, getattr(self.stats, name) + amount)
            out.append(c)
        return out

    def _stretches(self, path: Path, claims: list[Claim]):
        """[Job] per stretch of CHUNK items (placed poses, run groups, single jobs) in the
        order they start along the path; in a stretch, single jobs in the order claimed, then
        per tool piece its placed poses and its translation hulls."""
        poses = [c.poses for c in claims if c.poses is not None]
        at = np.concatenate([p.at for p in poses]) if poses else np.zeros(0)
        frames = np.concatenate([p.frames for p in poses]) if poses else np.zeros((0, 3, 4))
        fins = np.concatenate([p.fins for p in poses]) if poses else np.zeros(0)
        tall = np.concatenate([p.tall for p in poses]) if poses else np.zeros(0)
        rows = np.concatenate([p.rows for p in poses]).astype(int) if poses else np.zeros((0, 2), int)
        groups = [c.groups for c in claims if c.groups is not None]
        ends = [e for g in groups for e in g.ends]
        g_rows = np.concatenate([g.rows for g in groups]) if groups else np.zeros((0, 2), int)
        singles = [j for c in claims for j in c.jobs]
        start = np.concatenate([at, *[g.at for g in groups], [a for a, _ in singles]])
        kind = np.r_[np.zeros(len(at), int), np.ones(len(ends), int), np.full(len(singles), 2)]
        which = np.r_[np.arange(len(at)), np.arange(len(ends)), np.arange(len(singles))].astype(int)
        order = np.argsort(start, kind="stable")
        for c0 in range(0, len(order), self.CHUNK):
            part = order[c0 : c0 + self.CHUNK]
            mine = [which[part][kind[part] == k] for k in range(3)]
            chunk = [ends[g] for g in mine[1]]
            flat = run_frames(path.tips, path.axes, [e for g in chunk for e in g], path.ts.segments,
                              path.sides)
            sizes = np.cumsum([0] + [len(g) for g in chunk])
            run_fr = [flat[sizes[i] : sizes[i + 1]] for i in range(len(chunk))]
            p = mine[0]
            jobs: list[Job] = [singles[j][1] for j in np.sort(mine[2])]
            for k in range(len(path.ts.pieces)):
                jobs.append(Placed(k, frames[p], fins[p], tall[p], rows[p]))
                jobs.append(Runs(k, run_fr, g_rows[mine[1]].reshape(-1, 2)))
            yield jobs


def _rows(rows) -> np.ndarray | None:
    return None if rows is None else np.asarray(rows, dtype=int)


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
