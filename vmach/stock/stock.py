"""The stock: a solid cut by tool paths, in batches, checked after every batch.

    stock = Stock.from_spec("cylinder:d=60,l=100")
    stock.cut(tool, tips, axes)          # one path: (n, 3) tips, (n, 3) unit axes, work frame
    part = stock.solid                   # flushes pending cutters
    stock.export("part.stl"); stock.export("removed.3mf", which="removed")

A path becomes cutters (placed tool pieces and translation hulls, :mod:`vmach.stock.sweep`;
fan cutters for rotary runs of a flat-faced tool, :mod:`vmach.stock.fan`), each trimmed
exactly to the box around the stock within its Z range (:mod:`vmach.stock.clip`,
:mod:`vmach.stock.slabs`); placed poses that a translation hull of the same path contains are
left out. Cutters are queued per piece of stock and subtracted in checked batches
(:mod:`vmach.stock.batch`). Subtraction commutes, so the order of pieces and batches does not
change the result.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from vmach.errors import InputError
from vmach.output import atomic_writer, make_dir, writable_dir
from vmach.stock import cusps, cutters, engine, feet
from vmach.stock.batch import Piece
from vmach.stock.clip import Shape, shape
from vmach.stock.column import Column, plan_columns
from vmach.stock.cutters import CutterMaker, _run_frames
from vmach.stock.events import cylinder_boxes, overlap_volume
from vmach.stock.fan import (
    NO_FANS,
    back_clear,
    may_fan,
    plan_fans,
    prism,
)
from vmach.stock.hull import BlankHull, blank_hull, box_corners, hull_of
from vmach.stock.slabs import Slabs
from vmach.stock.spec import parse_stock
from vmach.stock.stats import CutStats
from vmach.stock.sweep import axial_runs, plan, run_extremes, stacked_runs
from vmach.tol import tol
from vmach.tooling.model import Tool
from vmach.tooling.solid import ToolSolid, across, frames, lateral, spun, tool_solid

EXPORT_FORMATS = (".stl", ".3mf", ".ply")


def _within(runs: np.ndarray, outer: np.ndarray) -> np.ndarray:
    """(r,) bool: which runs [first, last] (r, 2) lie wholly within one of the ``outer`` runs
    (f, 2) (every step of the run is one of its steps)."""
    if len(runs) == 0 or len(outer) == 0:
        return np.zeros(len(runs), bool)
    k = np.searchsorted(outer[:, 0], runs[:, 0], side="right") - 1   # outer runs are in order
    ok = k >= 0
    kk = np.maximum(k, 0)
    return ok & (outer[kk, 0] <= runs[:, 0]) & (runs[:, 1] <= outer[kk, 1])


def _placed_steps(rotary: np.ndarray, fan_runs: np.ndarray) -> np.ndarray:
    """(n-1,) bool: the ``rotary`` steps of a path that no fan or column holds (``fan_runs``
    (f, 2): [first, last] pose of each): left to placed poses."""
    steps = np.asarray(rotary, bool).copy()
    for first, last in fan_runs:
        steps[first:last] = False
    return steps


def _outside_runs(poses: np.ndarray, runs: np.ndarray) -> np.ndarray:
    """Placed poses not on a translation run: the run's hull (the tool swept along the run's
    segment, same axis) already contains the tool at every pose of the run."""
    if len(runs) == 0 or len(poses) == 0:
        return poses
    covered = np.zeros(int(max(poses.max(), runs.max())) + 1, bool)
    for a, b in runs:
        covered[a : b + 1] = True
    return poses[~covered[poses]]


def export_target(path: str | Path) -> Path:
    """``path`` as an export target — a known format (EXPORT_FORMATS), not a directory, in a
    directory that exists or can be made, as ``--out`` (:func:`vmach.output.writable_dir`; it
    is made when the file is written, so an export may go into the ``--out`` directory that
    verify makes) — checked before any work is done, creating nothing (InputError otherwise)."""
    p = Path(path)
    if p.suffix.lower() not in EXPORT_FORMATS:
        raise InputError(f"{p}: export format must be one of {', '.join(EXPORT_FORMATS)}",
                         kind="export_format")
    if p.is_dir():
        raise InputError(f"{p}: is a directory", kind="unwritable")
    writable_dir(p.parent)
    return p


class Stock(CutterMaker):
    """Material that tool paths remove.

    solid : engine.Solid — the blank.
    batch : int — cutters per batch boolean.
    cells : (3,) int — partition of the blank's bounds into nx × ny × nz cells (1, 1, 1: none;
        in-process only).
    chord : float, mm — polygonisation tolerance of tool solids (surfaces made by a tool's
        side; a flat face is exact).
    progress : bool — show a progress bar on stderr when it is a terminal.
    trim : bool — trim cutters to the box around the stock (exact) and leave out placed poses
        that a translation hull of the same path contains.
    fans : bool — cut runs of rotary steps of a flat-faced prism tool with fan cutters
        (:mod:`vmach.stock.fan`) instead of placed poses (only with ``trim``).
    fan_overcut : float, mm — the most a fan cutter may remove beyond the true sweep.
    columns : bool — cut the same sector of consecutive turns of a helix with one column cutter
        (:mod:`vmach.stock.column`) instead of a fan per turn (only with ``fans``).
    cusp : float, mm — the largest cusp a curved side may leave between placed poses of a
        rotary step before poses are added between them (:mod:`vmach.stock.cusps`).
    spread : int — batches taken from one window of queued cutters (:mod:`vmach.stock.batch`).
    arcs : bool — a flat or face mill's polygon round about the directions each pose is made
        exact toward (:func:`vmach.tooling.solid.ring_points`; ``Accuracy.rim_arcs``).
    worker : bool — once ``WORKER_AFTER`` cutters were queued, subtract the batches in a worker
        process while the next cutters are made (:mod:`vmach.stock.remote`; one cell only).

    What the making of cutters reads of the stock — its bounds and trim slabs — is taken at
    the slabs' retakes (:meth:`_boxes`), each from the stock as it was at the retake before
    (the blank at the first two): the cutters, and so the part, do not depend on how far the
    booleans have got, in this process or in the worker.
    """

    CHUNK = 256  # poses swept at a time (cutters are queued, and may be subtracted, as they come)
    SLAB_REFRESH = 32  # batches after which the trim slabs are taken again
    FRESH_AFTER = 4    # batches' worth of cutters after which a new path retakes them
    SLABS = True       # trim to the stock's extent per Z range (False: one box, for comparison)
    GROUP = 4    # consecutive cutters kept together in a spread batch (a run the worker unites as it comes)
    WORKER_AFTER = 64   # cutters queued before a worker process takes the runs and batches
    BLANK_CELL = 20_000  # triangles of a finely meshed blank per cell (:meth:`blank_meets`)
    #: relative volume difference up to which a blank counts as convex: a convex blank read
    #: from an STL carries float32 coordinates (a Ø60 cylinder of 80,000 triangles: 2e-7).
    #: Convexity only lets the verify checks settle a question at once (a part with a vertex
    #: inside the blank meets it; :meth:`blank_holds`); every finding is measured on the
    #: stock itself.
    CONVEX_TOL = 1e-6

    def __init__(self, solid: engine.Solid, *, batch: int = 64,
                 cells: tuple[int, int, int] = (1, 1, 1), chord: float = tol.tool_chord,
                 progress: bool = False, trim: bool = True, spread: int = 16, fans: bool = True,
                 fan_overcut: float = tol.fan_overcut, cusp: float = tol.sweep_cusp, columns: bool = True,
                 arcs: bool = False, worker: bool = True):
        engine.check(solid, "blank")
        self.initial = solid
        self.initial_bounds = engine.bounds(solid)
        self.batch = max(1, int(batch))
        self.spread = max(1, int(spread))
        self.chord = chord
        self.arcs = bool(arcs)
        self.trim = trim
        self.fans = fans and trim
        self.columns = columns and self.fans
        self.fan_overcut = fan_overcut
        self.cusp = cusp
        # a worker process takes one cell's batches: not with a partition
        self.worker = bool(worker) and all(max(1, int(c)) == 1 for c in cells)
        self._hull: BlankHull | None = None    # the blank's hull for the screening (hull.py)
        self._blank_cells: dict | None = None   # (i, j, k) -> the blank in that grid cell
        self._blank_edges: list = []
        self._blank_convex = False
        self._slabs: Slabs | None = None
        self._fan_guess = 8         # poses of the last fan that fitted
        self._slabs_at = -1         # batches done when the slabs were taken
        self.stats = CutStats()
        self._cells = self._partition(solid, cells)
        # the cells' boxes (c, 2, 3) the cutters are made against, and the cells as they were
        # at the last retake of the slabs (what the next one takes: :meth:`_boxes`)
        self._seen = np.array([c.box for c in self._cells]) if self._cells else engine.EMPTY_BOX[None]
        self._next_view: list | None = None
        self._solid: engine.Solid | None = solid
        self._bar = None
        self._progress = progress and sys.stderr.isatty()
        self._piece_cache: dict[int, list[engine.Solid]] = {}
        self._shape_cache: dict[int, list[Shape]] = {}
        self._fin_cache: dict[tuple, tuple] = {}
        self._prism_cache: dict[int, object] = {}
        self._union_seconds = 0.0   # the cells' union into one solid

    @classmethod
    def from_spec(cls, spec: str, notes: list | None = None, **kw) -> Stock:
        """The stock of a spec string (:func:`vmach.stock.spec.parse_stock`, which fills
        ``notes``)."""
        return cls(parse_stock(spec, notes=notes), **kw)

    # ----------------------------------------------------------------------------------------
    def _partition(self, solid: engine.Solid, cells) -> list[Piece]:
        nx, ny, nz = (max(1, int(c)) for c in cells)
        if nx * ny * nz == 1:
            return [self._piece(solid)]
        b = engine.bounds(solid)
        pad = 1e-3
        edges = [np.linspace(b[0, i] - pad, b[1, i] + pad, n + 1) for i, n in enumerate((nx, ny, nz))]
        out = []
        for i in range(nx):
            for j in range(ny):
                for k in range(nz):
                    lo = (edges[0][i], edges[1][j], edges[2][k])
                    hi = (edges[0][i + 1], edges[1][j + 1], edges[2][k + 1])
                    piece = engine.intersect(solid, engine.box(lo, hi))
                    engine.check(piece, "stock cell")
                    if not engine.is_empty(piece):
                        out.append(self._piece(piece))
        return out

    def _piece(self, solid: engine.Solid) -> Piece:
        piece = Piece(solid, self.batch, self.spread, self.GROUP,
                      remote_after=self.WORKER_AFTER if self.worker else None)
        piece.on_progress = self._update_bar
        return piece

    def _tool_pieces(self, ts: ToolSolid) -> list[engine.Solid]:
        if id(ts) not in self._piece_cache:
            self._piece_cache[id(ts)] = [engine.hull(p) for p in ts.pieces]
        return self._piece_cache[id(ts)]

    def _prism(self, ts: ToolSolid):
        """The tool as a flat-faced prism (:func:`vmach.stock.fan.prism`), or None: a tool of
        several pieces, a cone, a ball."""
        if id(ts) not in self._prism_cache:
            self._prism_cache[id(ts)] = prism(ts.pieces[0]) if len(ts.pieces) == 1 else None
        return self._prism_cache[id(ts)]

    def _tool_shapes(self, ts: ToolSolid) -> list[Shape]:
        if id(ts) not in self._shape_cache:
            self._shape_cache[id(ts)] = [shape(*engine.hull_mesh(p)) for p in ts.pieces]
        return self._shape_cache[id(ts)]

    def trim_box(self) -> np.ndarray:
        """(2, 3) float, mm — the box cutters are trimmed to: the stock's bounds now, grown by
        ``tol.trim_margin`` so that no trimmed face touches the stock."""
        b = self.bounds
        return np.stack([b[0] - tol.trim_margin, b[1] + tol.trim_margin])

    # ----------------------------------------------------------------------------------------
    def cut(self, tool: Tool | ToolSolid, tips: np.ndarray, axes: np.ndarray, between=None,
            others=None) -> int:
        """Queue the swept volume of one path; returns the number of cutters made.

        tool : Tool (polygonised with this stock's chord) or a ready ToolSolid.
        tips : (n, 3) float, mm; axes : (n, 3) float, unit — poses in the work frame, joined by
        motion in order. A rotary path must be sampled densely enough for the wanted accuracy
        (see :mod:`vmach.stock.sweep`).
        between : callable ``(steps (s,) int, parts (s,) int) -> (tips (e, 3), axes (e, 3),
            at (e,) float)`` giving the poses that cut each step ``i`` (from pose i to i+1)
            into ``parts`` equal parts of the motion — the ``parts - 1`` poses strictly inside,
            step by step, ``at`` = i + fraction. With it, rotary steps placed as poses get
            more poses where a curved side of a Tool would leave cusps over
            the stock's ``cusp`` (``tol.sweep_cusp``; :mod:`vmach.stock.cusps`).
        others : callable ``(groups (g, k, 3), omega (3,)) -> (g,) bool``: which groups of
            points the true tools of the program's other paths sweep whole
            (:meth:`vmach.stock.sweeps.Sweeps.others`); a fan may take a flat face's rim band
            there (:func:`vmach.stock.fan.plan_fans`). With a ``recut`` method too (an
            :class:`vmach.stock.sweeps.Others`), placed steps are also parted against the feet
            of a flat face's rim that no other pass cuts again (:func:`vmach.stock.feet.parts`).
        """
        n = 0
        for ts, jobs in self._sweep(tool, tips, axes, between, others):
            t0 = time.perf_counter()
            cutters, boxes = self._make(ts, jobs)
            self.stats.sweep_seconds += time.perf_counter() - t0
            self._queue(cutters, boxes)
            n += len(cutters)
        return n

    def cutters(self, tool: Tool | ToolSolid, tips: np.ndarray, axes: np.ndarray):
        """The solids a path sweeps (placed pieces and translation hulls, trimmed to
        :meth:`trim_box`) and their boxes (c, 2, 3), without queueing them."""
        cutters: list[engine.Solid] = []
        boxes: list[np.ndarray] = []
        for ts, jobs in self._sweep(tool, tips, axes):
            t0 = time.perf_counter()
            c, b = self._make(ts, jobs)
            self.stats.sweep_seconds += time.perf_counter() - t0
            cutters += c
            boxes += b
        return cutters, boxes

    def _sweep(self, tool: Tool | ToolSolid, tips: np.ndarray, axes: np.ndarray, between=None, others=None):
        """Yield (tool solid, jobs) for consecutive stretches of a path, in path order. A job
        is ``(piece, frames (m, 3, 4) of placed poses, [(frame_a, frame_b) of each translation
        run], [(tips, unit axes, omega, frames, path) of each fan run — piece 0 only])``, with
        ``path`` the whole path's tips and unit axes (what else it cuts). Every pose is
        turned about its axis so that the tool's polygon is exact toward the sides of its
        travel (:func:`vmach.tooling.solid.spun`)."""
        t0 = time.perf_counter()
        ts = tool if isinstance(tool, ToolSolid) else tool_solid(tool, self.chord, arcs=self.arcs)
        tips = np.asarray(tips, dtype=float).reshape(-1, 3)
        axes = np.asarray(axes, dtype=float).reshape(-1, 3)
        if len(tips) != len(axes):
            raise InputError("cut: tips and axes differ in length", kind="stock_input")
        if not (np.isfinite(tips).all() and np.isfinite(axes).all()):
            raise InputError("cut: non-finite pose", kind="stock_input")
        self.stats.paths += 1
        self.stats.poses += len(tips)
        if len(tips) == 0:
            return
        sp = plan(tips, axes)
        sides = lateral(tips, axes)
        fr = spun(frames(tips, axes), sides, ts.segments)
        rotary = sp.angles > tol.hull_angle
        if self.trim:
            t1 = time.perf_counter()
            # trim slabs of the stock now (and the stock as it is for fans: their tool's back)
            self._boxes(np.zeros(0), np.zeros(0), fresh=True,
                        force=self.fans and bool(rotary.any()) and self._prism(ts) is not None)
            t0 += time.perf_counter() - t1                       # (its booleans are counted there)
        poses = sp.poses
        if self.trim:
            poses = _outside_runs(poses, sp.runs)
            self.stats.covered += (len(sp.poses) - len(poses)) * len(ts.pieces)
        # fan runs over rotary steps and the straight steps between them (fan.plan_fans);
        # the placed poses and translation runs they hold are left out
        unit = axes / np.linalg.norm(axes, axis=1, keepdims=True)
        fans = self._fans(ts, tips, unit, rotary, ~rotary, others)
        runs = sp.runs
        if len(fans.runs):
            # a fan's end poses turned for its own steps, not for the move beyond it (a retract
            # along the rotation axis would tilt their polygon's exact directions off the floor
            # the fan's side makes, and its hull spreads what the tilt takes below it)
            a, b = fans.runs[:, 0], fans.runs[:, 1]
            ends = np.r_[a, b]
            step = np.r_[tips[a + 1] - tips[a], tips[b] - tips[b - 1]]
            sides[ends] = across(unit[ends], step)
            fr[ends] = spun(frames(tips[ends], axes[ends]), sides[ends], ts.segments)
            poses = _outside_runs(poses, fans.runs)
            runs = runs[~_within(runs, fans.runs)]
        fan_runs = fans.runs                      # every step a fan or a column holds
        if self.trim and len(runs):
            runs, poses = self._axial(ts, tips, unit, runs, poses, fan_runs)
        pr = self._prism(ts)
        groups = (stacked_runs(tips, unit, runs, pr.length) if pr is not None and self.trim
                  else [[r] for r in range(len(runs))])
        self.stats.stacked_runs += len(runs) - len(groups)
        cols: list[Column] = []
        if self.columns and len(fans.runs):
            cp = plan_columns(tips, unit, fans, radius=ts.radius,
                              inner=ts.radius * np.cos(np.pi / ts.segments), overcut=self.fan_overcut)
            cols, fans = cp.columns, cp.fans
        path = (tips, unit)                       # what else the path cuts
        key = poses.astype(float)                 # where each placed pose lies along the path
        fins = np.full(len(fr), np.inf)           # poses cut as their fin only (cusps.fin_widths)
        tall = np.full(len(fr), np.inf)           # ... up to this height along the axis
        if self.trim and isinstance(tool, Tool):
            fins = self._inner_fins(tool, ts, fr, rotary, fan_runs, poses)
        if between is not None and self.trim and isinstance(tool, Tool):
            more, at, half, height = self._cusp_poses(tool, ts, tips, fr, rotary, fan_runs, between, others)
            if len(more):
                poses = np.r_[poses, len(fr) + np.arange(len(more))]
                key = np.r_[key, at]
                fr = np.concatenate([fr, more])
                fins = np.r_[fins, half]
                tall = np.r_[tall, height]
                self.stats.cusp_fins += int(np.isfinite(cutters._fin_bucket(half, ts.radius)).sum())
        start = np.concatenate([key, [runs[g, 0].min() for g in groups], fans.runs[:, 0],
                                [c.cells[0, 0] for c in cols]])
        kind = np.r_[np.zeros(len(poses), int), np.ones(len(groups), int), np.full(len(fans.runs), 2),
                     np.full(len(cols), 3)]
        which = np.r_[np.arange(len(poses)), np.arange(len(groups)), np.arange(len(fans.runs)),
                      np.arange(len(cols))].astype(int)
        order = np.argsort(start, kind="stable")
        for c0 in range(0, len(order), self.CHUNK):
            part = order[c0 : c0 + self.CHUNK]
            chunk_poses = poses[which[part][kind[part] == 0]]
            chunk_groups = [groups[g] for g in which[part][kind[part] == 1]]
            ends = [run_extremes(tips, runs[r]) for g in chunk_groups for r in g]
            fan_jobs = [(tips[a : b + 1], unit[a : b + 1], fans.omega[f], fr[a : b + 1], path)
                        for f in which[part][kind[part] == 2] for a, b in [fans.runs[f]]]
            col_jobs = [(cols[c], tips, unit, fr, path) for c in which[part][kind[part] == 3]]
            flat = _run_frames(tips, axes, ends, ts.segments, sides)     # shared by every piece
            sizes = np.cumsum([0] + [len(g) for g in chunk_groups])
            run_fr = [flat[sizes[i] : sizes[i + 1]] for i in range(len(chunk_groups))]
            jobs = [(k, fr[chunk_poses], run_fr, fan_jobs if k == 0 else [], col_jobs if k == 0 else [],
                     fins[chunk_poses], tall[chunk_poses]) for k in range(len(ts.pieces))]
            self.stats.sweep_seconds += time.perf_counter() - t0
            yield ts, jobs
            t0 = time.perf_counter()
        self.stats.sweep_seconds += time.perf_counter() - t0

    def _axial(self, ts: ToolSolid, tips: np.ndarray, unit: np.ndarray, runs: np.ndarray,
               poses: np.ndarray, fan_runs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(runs, placed poses) with the translation runs along the tool's own axis whose
        inner pose has the stock in front of its back (:func:`vmach.stock.sweep.axial_runs`,
        :meth:`_behind`, over the Z range of the run's two ends) replaced by the tool placed at
        that pose — all such a run removes (a retract from a cut along the tool, an approach to
        it) — unless a run or fan of the path holds that pose already."""
        axial, inner = axial_runs(tips, unit, runs)
        if not axial.any():
            return runs, poses
        idx = np.nonzero(axial)[0]
        ends = np.array([run_extremes(tips, r) for r in runs[idx]], dtype=int)
        b0 = cylinder_boxes(tips[ends[:, 0]], unit[ends[:, 0]], 0.0, ts.length, ts.radius)
        b1 = cylinder_boxes(tips[ends[:, 1]], unit[ends[:, 1]], 0.0, ts.length, ts.radius)
        zlo = np.minimum(b0[:, 0, 2], b1[:, 0, 2])
        zhi = np.maximum(b0[:, 1, 2], b1[:, 1, 2])
        gone = idx[self._behind(tips[inner[idx]], unit[inner[idx]], ts, zlo, zhi)]
        if len(gone) == 0:
            return runs, poses
        keep = np.ones(len(runs), bool)
        keep[gone] = False
        runs = runs[keep]
        placed = _outside_runs(_outside_runs(np.unique(inner[gone]), runs), fan_runs)
        self.stats.axial_runs += len(gone)
        return runs, np.unique(np.r_[poses, placed]).astype(int)

    def _cusp_poses(self, tool: Tool, ts: ToolSolid, tips: np.ndarray, fr: np.ndarray, rotary: np.ndarray,
                    fan_runs: np.ndarray, between, others=None) -> tuple[np.ndarray, np.ndarray]:
        """Placed poses to add inside the rotary steps (n-1,) bool that no fan cutter holds,
        where the tool's curved side would leave cusps over ``self.cusp`` between the
        step's two poses (:mod:`vmach.stock.cusps`) — or, for a flat-faced prism told what
        the true tools sweep (``others``: :class:`vmach.stock.sweeps.Others`), where its
        rim's feet would (:func:`vmach.stock.feet.parts`): frames (e, 3, 4) — turned as
        placed poses are — their places along the path (e,) float (step + fraction) and the
        half-widths (e,) mm of the fins that cut them (:func:`vmach.stock.cusps.fin_widths`)
        and their heights (e,) mm along the axis (:func:`vmach.stock.cusps.fin_height`: up to
        the cusps over the tolerance; inf — the whole length — for a flat-faced prism, whose
        rim's feet lie at its face and whose fins cost the same at any length)."""
        none = np.zeros((0, 3, 4)), np.zeros(0), np.zeros(0), np.zeros(0)
        steps = _placed_steps(rotary, fan_runs)
        # steps whose tool may reach the stock's bounds at all
        lo, hi = self.bounds
        reach = ts.length + ts.radius
        near = np.all((tips >= lo - reach) & (tips <= hi + reach), axis=1)
        idx = np.nonzero(steps & (near[:-1] | near[1:]))[0]
        sd = cusps.side(tool)
        if len(idx) == 0 or len(sd.points) == 0:
            return none
        c, over = cusps.step_cusps(sd, fr[idx], fr[idx + 1], self._holds, self.cusp, reach=True)
        height = np.full(len(idx), np.inf)
        if self._prism(ts) is None:
            keep = self._not_recut(over, fr, idx, ts, others)
            height = cusps.fin_height(over, len(idx), ts.length, keep)
        parts = cusps.substeps(c, self.cusp)
        if others is not None and hasattr(others, "recut") and self._prism(ts) is not None:
            more = feet.parts(tool, ts, fr, idx, self.cusp, self.chord, self._holds, others, between)
            self.stats.foot_steps += int((more > 1).sum())
            parts = np.maximum(parts, more)
        need = parts > 1
        if not need.any():
            return none
        t, ax, at = between(idx[need], parts[need])
        unit = np.asarray(ax, dtype=float) / np.linalg.norm(ax, axis=1, keepdims=True)
        step = np.repeat(idx[need], parts[need] - 1)
        more = spun(frames(t, unit), across(unit, tips[step + 1] - tips[step]), ts.segments)
        height = np.repeat(height[need], parts[need] - 1)
        half = cusps.fin_widths(more, fr[step], fr[step + 1], cusps.fin_normal(ts.segments),
                                np.repeat(parts[need], parts[need] - 1), sd, self._holds,
                                cusps.face_radius(tool), height)
        self.stats.cusp_poses += len(t)
        return more, np.asarray(at, dtype=float), half, height

    def _not_recut(self, over: cusps.Over, fr: np.ndarray, idx: np.ndarray, ts: ToolSolid,
                   others) -> np.ndarray | None:
        """(k,) bool: the samples over the cusp tolerance (``over``, of the steps ``idx``)
        that no other path cuts again — none of its sampled poses near them, which every cutter
        holds whole, holding the point by the cusp and the tool chord
        (:meth:`vmach.stock.sweeps.Sweeps.at_poses`); None (all) without ``others``. The added
        poses' fins need reach only those (:func:`vmach.stock.cusps.fin_height`)."""
        if others is None or not hasattr(others, "at_poses") or len(over.step) == 0:
            return None
        return ~others.at_poses(over.point, over.cusp + self.chord)

    def _inner_fins(self, tool: Tool, ts: ToolSolid, fr: np.ndarray, rotary: np.ndarray, fan_runs: np.ndarray,
                    poses: np.ndarray) -> np.ndarray:
        """(n,) mm: the fin half-widths of the placed poses ``poses`` of a flat or face mill
        (a prism: its fins are slabs of a few of its facets; a cone's hold nearly all of it)
        between two rotary steps that no fan or column holds (:mod:`vmach.stock.cusps`: widths
        over the two steps, as an added pose's over one; rounded as cut,
        :func:`vmach.stock.cutters._fin_bucket`) whose neighbours' fins hold the rest of them
        (:func:`vmach.stock.cusps.fins_cover`); inf for every other pose (cut whole, or not
        placed: a fan's, a translation run's)."""
        n = len(fr)
        out = np.full(n, np.inf)
        if n < 3 or self._prism(ts) is None:
            return out
        steps = _placed_steps(rotary, fan_runs)
        inner = np.zeros(n, bool)
        inner[1:-1] = steps[:-1] & steps[1:]
        placed = np.zeros(n, bool)
        placed[poses] = True
        # (poses whose tool's box misses the stock's are culled anyway)
        box = cylinder_boxes(fr[:, :, 3], fr[:, :, 2], 0.0, ts.length, ts.radius)
        lo, hi = self.bounds
        placed &= np.all(box[:, 0] <= hi, axis=1) & np.all(box[:, 1] >= lo, axis=1)
        idx = np.nonzero(inner & placed)[0]
        sd = cusps.side(tool)
        if len(idx) == 0 or len(sd.points) == 0:
            return out
        normal = cusps.fin_normal(ts.segments)
        half = cusps.fin_widths(fr[idx], fr[idx - 1], fr[idx + 1], normal, np.full(len(idx), 2), sd,
                                self._holds, cusps.face_radius(tool))
        out[idx] = cutters._fin_bucket(half, ts.radius)
        idx = idx[np.isfinite(out[idx])]
        ok = cusps.fins_cover(tool, fr, out, idx, normal, self._holds)
        out[idx[~ok]] = np.inf
        self.stats.inner_fins += int(ok.sum())
        return out

    def _holds(self, points: np.ndarray) -> np.ndarray:
        """(...) bool: points (..., 3) that may lie in the stock (a superset: the trim slabs'
        extents, :meth:`vmach.stock.slabs.Slabs.holds`, or the stock's bounds)."""
        if self._slabs is not None and self.SLABS:
            return self._slabs.holds(points)
        b = self.bounds
        return np.all((points >= b[0]) & (points <= b[1]), axis=-1)

    def _blank_hull(self) -> None:
        """The blank's convex hull (:mod:`vmach.stock.hull`: reduced to a few thousand planes
        for a finely meshed blank) and whether the blank is convex (its volume is its hull's,
        to ``CONVEX_TOL``; a blank too small for a hull of four planes is not taken for
        convex)."""
        if self._hull is None:
            _, _, hull, hv, hf = hull_of(self.initial)
            self._hull = blank_hull(hv, hf)
            vol = engine.volume(hull)
            self._blank_convex = (min(len(self._hull.outer), len(self._hull.inner)) >= 4
                                  and abs(vol - engine.volume(self.initial))
                                  <= self.CONVEX_TOL * max(vol, 1.0))

    def blank_holds(self, points: np.ndarray) -> np.ndarray:
        """(k,) bool: points (k, 3) that lie inside the blank, 1e-6 mm or more from its
        boundary — answered for a convex blank (a cylinder, a box); all False for another, whose
        callers must meet solids instead. (For a finely meshed blank, inside a region within
        it: a point near the boundary may be answered False, never wrongly True.)"""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        if self.blank_planes() is None:
            return np.zeros(len(points), bool)
        planes = self._hull.inner
        k = max(1, (1 << 22) // len(planes))      # points per block: arrays of at most 4M
        return np.concatenate([np.all(points[i : i + k] @ planes[:, :3].T - planes[:, 3] < -1e-6, axis=1)
                               for i in range(0, len(points), k)] or [np.zeros(0, bool)])

    def blank_meets(self, solid: engine.Solid) -> bool:
        """Does the convex ``solid`` overlap the blank (by more than round-off)? A finely meshed
        blank is met piece by piece: its parts in the cells of a grid (each about
        ``BLANK_CELL`` triangles, made the first time a solid's box reaches the cell) — the
        overlap is the sum of the pieces' — skipping a piece whose box lies beyond one of the
        solid's face planes; a piece is far cheaper to meet than the whole blank."""
        if engine.num_triangles(self.initial) <= 2 * self.BLANK_CELL:
            return overlap_volume(self.initial, [solid], centre=False)[0] > 0.0
        if self._blank_cells is None:
            k = int(np.ceil((engine.num_triangles(self.initial) / self.BLANK_CELL) ** (1 / 3)))
            b = np.asarray(self.initial_bounds)
            self._blank_edges = [np.linspace(b[0, i] - 1e-3, b[1, i] + 1e-3, k + 1) for i in range(3)]
            self._blank_cells = {}
        lo, hi = engine.bounds(solid)
        e = self._blank_edges
        # cells j with e[j] <= hi and lo < e[j + 1], per axis
        span = [range(*np.clip(np.searchsorted(e[a], [lo[a], hi[a]], side="right") + [-1, 0],
                               0, len(e[a]) - 1)) for a in range(3)]
        planes = shape(*engine.to_mesh(solid, double=True)).planes
        for cell in ((i, j, k) for i in span[0] for j in span[1] for k in span[2]):
            if cell not in self._blank_cells:
                box = engine.box([e[a][c] for a, c in enumerate(cell)],
                                 [e[a][c + 1] for a, c in enumerate(cell)])
                piece = engine.intersect(self.initial, box)
                self._blank_cells[cell] = (piece, None if engine.is_empty(piece) else engine.bounds(piece))
            piece, pb = self._blank_cells[cell]
            if pb is None:
                continue
            corners = box_corners(*pb)
            if np.any((corners @ planes[:, :3].T - planes[:, 3]).min(axis=0) > 0.0):
                continue            # the piece's box lies beyond a face plane of the solid
            if overlap_volume(piece, [solid], centre=False)[0] > 0.0:
                return True
        return False

    def blank_planes(self) -> np.ndarray | None:
        """(f, 4) float: planes (unit outward normal, offset; mm) of a convex region that holds a
        convex blank — its hull's face planes, or up to a few thousand of its supporting planes
        for a finely meshed one (:mod:`vmach.stock.hull`) — or None when the blank is not convex."""
        self._blank_hull()
        return self._hull.outer if self._blank_convex else None

    def _fans(self, ts: ToolSolid, tips: np.ndarray, axes: np.ndarray, rotary: np.ndarray,
              slides: np.ndarray, others=None):
        """Candidate fan runs over the ``rotary`` steps (n-1,) bool of a path (tips, unit
        axes (n, 3)) and the ``slides`` between them (:func:`vmach.stock.fan.plan_fans`; none
        unless the tool is one flat-faced prism and fans are on); ``others``: what other
        paths' true tools sweep (:meth:`vmach.stock.sweeps.Sweeps.others`)."""
        pr = self._prism(ts) if self.fans else None
        if pr is None or not may_fan(rotary):
            return NO_FANS                 # (before the back test, which costs)
        return plan_fans(tips, axes, rotary, pr, slides=slides, clear=self._back_clear(tips, axes, pr),
                         stock_box=self.bounds, others=others)

    def _back_clear(self, tips: np.ndarray, axes: np.ndarray, pr) -> np.ndarray:
        """(n,) bool: poses (tips, unit axes (n, 3)) whose prism's back face has the stock
        behind it where the fans it may join could fill a notch (:func:`vmach.stock.fan.back_clear`):
        the stock within the Z range of this pose's tool and its neighbours' (a notch between
        two back faces lies in the box of the two tools; :meth:`_behind`)."""
        if len(tips) == 0:
            return np.zeros(0, bool)
        box = cylinder_boxes(tips, axes, 0.0, pr.length, pr.radius)
        lo, hi = box[:, 0, 2], box[:, 1, 2]
        lo = np.minimum(lo, np.minimum(np.r_[lo[:1], lo[:-1]], np.r_[lo[1:], lo[-1:]]))
        hi = np.maximum(hi, np.maximum(np.r_[hi[:1], hi[:-1]], np.r_[hi[1:], hi[-1:]]))
        return self._behind(tips, axes, pr, lo, hi)

    def _behind(self, tips: np.ndarray, axes: np.ndarray, tool, zlo: np.ndarray,
                zhi: np.ndarray) -> np.ndarray:
        """(n,) bool: poses (tips, unit axes (n, 3)) with the stock in front of the plane
        ``tool.length`` behind the tip (the tool's back; a Prism or a ToolSolid): the whole
        blank (:func:`vmach.stock.fan.back_clear`), or — with the trim slabs of the stock as it
        was last taken (it only shrinks) — the stock within the Z ranges [zlo, zhi] (n,)
        (:meth:`vmach.stock.slabs.Slabs.support`)."""
        self._blank_hull()
        clear = back_clear(tips, axes, tool, self._hull.corners)
        if self._slabs is not None and self.SLABS:
            reach = np.einsum("ij,ij->i", tips, axes) + tool.length
            clear |= self._slabs.support(zlo, zhi, axes) <= reach
        return clear

    def _boxes(self, zlo: np.ndarray, zhi: np.ndarray, fresh: bool = False,
               force: bool = False) -> np.ndarray:
        """Trim boxes (k, 2, 3) for cutters spanning Z ranges [zlo, zhi] (k,): the stock's
        extent within the range (:mod:`vmach.stock.slabs`), inside :meth:`trim_box`. The
        slabs are taken again after every SLAB_REFRESH batches, and for a new path
        (``fresh``) once FRESH_AFTER batches' worth of cutters were made since — or one, with
        ``force`` (a path that may make fans, which judge the tool's back by the stock,
        :meth:`_back_clear`) — the pending cutters then handed to the booleans. Each retake
        reads the stock as the retake before left it (a snapshot asked for then, which a worker
        has had the time between to make), and asks for the stock as it is now for the next:
        a stale snapshot is only looser (the stock shrinks), and the cutters never depend on
        how far the booleans have got. A path cut chunk by chunk does not retake it for every
        chunk."""
        done = sum(c.batches for c in self._cells)
        made = done + sum(len(c.pending) for c in self._cells) / self.batch
        since = made - self._slabs_at
        if (fresh and self.SLABS and self._slabs is not None
                and (since >= self.FRESH_AFTER or (force and since >= 1))):
            self._flush_cells()
            done = sum(c.batches for c in self._cells)
            stale = True
        else:
            stale = done - self._slabs_at >= self.SLAB_REFRESH
        if self.SLABS and (self._slabs is None or stale):
            now = [c.snapshot() for c in self._cells]       # for the next retake
            view = [s.get() for s in (self._next_view or now)]
            self._next_view = now
            self._seen = np.array([s[2] for s in view])
            meshes = [(s[0], s[1].astype(np.int64)) for s in view if len(s[1])]
            if meshes:
                offset = np.cumsum([0] + [len(m[0]) for m in meshes])[:-1]
                faces = [m[1] + o for m, o in zip(meshes, offset, strict=True)]
                self._slabs = Slabs.from_mesh(np.concatenate([m[0] for m in meshes]), np.concatenate(faces))
            self._slabs_at = done
        outer = self.trim_box()
        if self._slabs is None or not self.SLABS:
            return np.broadcast_to(outer, (len(zlo), 2, 3)).copy()
        return self._slabs.boxes(zlo, zhi, outer)

    def queue(self, cutters: list, boxes: list) -> None:
        """Queue ready cutters (from :meth:`cutters`)."""
        self._queue(cutters, boxes)

    def _queue(self, cutters: list[engine.Solid], boxes: list[np.ndarray]) -> None:
        if not cutters:
            return
        self._solid = None
        bx = np.asarray(boxes)                                            # (c, 2, 3)
        used = np.zeros(len(cutters), bool)
        queued = 0
        for cell, box in zip(self._cells, self._seen, strict=False):
            hit = np.all(bx[:, 0] <= box[1], axis=1) & np.all(bx[:, 1] >= box[0], axis=1)
            used |= hit
            queued += int(hit.sum())
            cell.add([cutters[i] for i in np.nonzero(hit)[0]])
        self.stats.cutters += len(cutters)
        self.stats.culled += int((~used).sum())
        self._account()
        if self._progress:
            self._open_bar(queued)

    def _account(self) -> None:
        self.stats.boolean_seconds = sum(c.seconds for c in self._cells) + self._union_seconds
        self.stats.wait_seconds = sum(c.wait_seconds for c in self._cells)
        self.stats.batches = sum(c.batches for c in self._cells)
        self._update_bar()

    def _open_bar(self, more: int) -> None:
        if self._bar is None:
            from tqdm import tqdm

            self._bar = tqdm(total=0, unit="cutter", desc="stock", leave=False)
        self._bar.total += more
        self._update_bar()

    def _update_bar(self) -> None:
        if self._bar is None:
            return
        done = sum(c.done for c in self._cells)
        self._bar.n = min(done, self._bar.total)
        self._bar.refresh()

    def _flush_cells(self) -> None:
        for cell in self._cells:
            cell.flush()

    def flush(self) -> None:
        """Subtract every queued cutter (with a worker process: hand them to it)."""
        self._flush_cells()
        self._account()
        if not any(c.remote is not None for c in self._cells):
            self._close_bar()

    def _close_bar(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def close(self) -> None:
        """Stop the worker process, if one took the batches, once it has subtracted them all
        (the stock stays as it is; cutters queued later are subtracted in this process)."""
        for c in self._cells:
            c.close()
        self._account()
        self._close_bar()

    # ----------------------------------------------------------------------------------------
    @property
    def solid(self) -> engine.Solid:
        """The cut part (all pending cutters subtracted)."""
        if self._solid is None:
            self.flush()
            cells = [c.solid for c in self._cells]          # (waits for a worker)
            self._account()
            self._close_bar()
            t0 = time.perf_counter()
            self._solid = engine.union(cells)
            engine.check(self._solid, "stock")
            self._union_seconds += time.perf_counter() - t0
            self._account()
        return self._solid

    def local(self, lo, hi) -> engine.Solid:
        """The stock now (pending cutters subtracted) inside the box [lo, hi] — exact there,
        and cheaper to measure against than the whole stock (empty if the box is)."""
        lo = np.asarray(lo, dtype=float)
        hi = np.asarray(hi, dtype=float)
        if np.any(lo > hi):
            return engine.empty()
        if self._solid is not None:
            return engine.intersect(self._solid, engine.box(lo, hi))
        self._flush_cells()
        self._account()
        return engine.union([c.local(lo, hi) for c in self._cells])

    def removed(self) -> engine.Solid:
        """The removed material: blank minus part."""
        return engine.subtract(self.initial, [self.solid])

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float, mm — bounds of the stock as the slabs' last retake saw it (the stock
        only shrinks, so this is conservative; see the class docstring)."""
        return np.stack([self._seen[:, 0].min(axis=0), self._seen[:, 1].max(axis=0)])

    @property
    def volume(self) -> float:
        if self._solid is None and not any(c.pending for c in self._cells):
            return sum(c.volume for c in self._cells)
        return engine.volume(self.solid)

    def section(self, z: float) -> list[np.ndarray]:
        """Contours of the part at Z = z, each (k, 2) float, mm."""
        return engine.slice_polygons(self.solid, z)

    def mesh(self, which: str = "part") -> tuple[np.ndarray, np.ndarray]:
        """Vertices (n, 3) and faces (m, 3) of the part or the removed volume."""
        return engine.to_mesh(self.solid if which == "part" else self.removed())

    def export(self, path: str | Path, which: str = "part") -> Path:
        """Write the part (``which="part"``) or the removed volume (``"removed"``) as .stl,
        .3mf or .ply (trimesh), whole or not at all (:func:`vmach.output.atomic_writer`)."""
        import trimesh

        p = export_target(path)
        if which not in ("part", "removed"):
            raise InputError(f"export: which must be 'part' or 'removed', not {which!r}",
                             kind="export_format")
        v, f = self.mesh(which)
        data = trimesh.Trimesh(v, f, process=False).export(file_type=p.suffix.lower()[1:])
        make_dir(p.parent)
        try:
            with atomic_writer(p, "wb") as fh:
                fh.write(data if isinstance(data, bytes) else data.encode())
        except OSError as exc:
            raise InputError(f"{p}: cannot write: {exc.strerror or exc}", kind="unwritable") from None
        return p
