"""Cutters made from jobs (:mod:`vmach.stock.jobs`): ``Maker.make(tool, jobs) -> [Cutter]``.

Placed poses and translation hulls are made here; fans and columns in
:mod:`vmach.stock.make_fans`. Every cutter is trimmed exactly to the box around the stock within
its Z range (:meth:`vmach.stock.view.View.boxes`, :mod:`vmach.stock.clip`); a cutter that misses
the stock is culled. All lengths mm; frames (3, 4) tool to work.
"""

from __future__ import annotations

import numpy as np

from vmach.stock import engine
from vmach.stock.clip import Shape, clip, shape, sweep_shape
from vmach.stock.cusps import FIN_LEAST
from vmach.stock.fan import prism
from vmach.stock.jobs import ColumnJob, Cutter, Fan, Job, Placed, Runs
from vmach.stock.make_fans import FanMaker
from vmach.stock.stats import CutStats
from vmach.stock.view import View
from vmach.tooling.solid import RIM_SAG, ToolSolid, fin_points, place

_IDENTITY = np.hstack([np.eye(3), np.zeros((3, 1))])[None]


def _rows(rows: np.ndarray, j: int) -> tuple[int, int]:
    return int(rows[j, 0]), int(rows[j, 1])


class Maker:
    """Makes the cutters of jobs against the :class:`vmach.stock.view.View` of the stock.

    trim : trim cutters to the box around the stock (exact). cusp : the stock's cusp
    tolerance, mm (the fins' arcs). fan_overcut : the most a fan or column may remove beyond
    the true sweep, mm. Tool shapes, pieces and fins are kept per tool solid.
    """

    def __init__(self, view: View, stats: CutStats, *, trim: bool, cusp: float, fan_overcut: float):
        self.view = view
        self.stats = stats
        self.trim = trim
        self.cusp = cusp
        self.fan_overcut = fan_overcut
        self._pieces: dict[int, list[engine.Solid]] = {}
        self._shapes: dict[int, list[Shape]] = {}
        self._fins: dict[tuple, tuple] = {}
        self._prisms: dict[int, object] = {}
        self.fans = FanMaker(self)
        #: polygon count of revolved (turning) cutters: the blank's own (:class:`vmach.stock.Stock`)
        self.turn_segments = 256
        #: job type -> its strategy's ``make(job, maker) -> Cutter | None``, for the jobs a
        #: strategy makes itself (the planner's table fills it: :mod:`vmach.stock.plan`)
        self.own: dict[type, object] = {}

    # the tool, kept --------------------------------------------------------------------------
    def tool_pieces(self, ts: ToolSolid) -> list[engine.Solid]:
        if id(ts) not in self._pieces:
            self._pieces[id(ts)] = [engine.hull(p) for p in ts.pieces]
        return self._pieces[id(ts)]

    def prism(self, ts: ToolSolid):
        """The tool as a flat-faced prism (:func:`vmach.stock.fan.prism`), or None: a tool of
        several pieces, a cone, a ball."""
        if id(ts) not in self._prisms:
            self._prisms[id(ts)] = prism(ts.pieces[0]) if len(ts.pieces) == 1 else None
        return self._prisms[id(ts)]

    def tool_shapes(self, ts: ToolSolid) -> list[Shape]:
        if id(ts) not in self._shapes:
            self._shapes[id(ts)] = [shape(*engine.hull_mesh(p)) for p in ts.pieces]
        return self._shapes[id(ts)]

    def fin_piece(self, ts: ToolSolid, k: int, half: float, height: float = np.inf
                  ) -> tuple[np.ndarray, Shape, engine.Solid] | None:
        """(points, Shape, Solid) that cut a pose of piece k as its fin, tool frame (kept): of
        half-width ``half`` mm — the true tool within that slab about the plane through its
        axis and the lateral direction placed poses are turned for, up to ``height`` mm from
        the tip (None where the piece lies above it) (:func:`vmach.tooling.solid.fin_points`;
        its arcs within 0.8 of the stock's ``cusp`` of the true circles, and within
        ``RIM_SAG``)."""
        key = (id(ts), k, half, height)
        if key not in self._fins:
            pts = fin_points(ts.pieces[k], ts.segments, half, sag=min(0.8 * self.cusp, RIM_SAG),
                             height=height)
            flat = len(pts) < 4 or np.ptp(pts[:, 2]) <= 1e-9
            self._fins[key] = None if flat else (pts, shape(*engine.hull_mesh(pts)), engine.hull(pts))
        return self._fins[key]

    # ----------------------------------------------------------------------------------------
    def make(self, ts: ToolSolid, jobs: list[Job]) -> list[Cutter]:
        """The cutters of one stretch of a path: first the jobs a strategy makes itself
        (``own``: a turning path's revolved cutters, ``ts`` None), then piece by piece in the
        order the pieces first appear its columns, its fans (trimmed in one go), its placed
        poses, its runs."""
        out: list[Cutter] = []
        for j in jobs:
            if type(j) in self.own:
                c = self.own[type(j)](j, self)
                if c is None:
                    self.stats.culled += 1
                else:
                    out.append(c)
        jobs = [j for j in jobs if type(j) not in self.own]
        pieces = list(dict.fromkeys(0 if isinstance(j, Fan | ColumnJob) else j.piece for j in jobs))
        for k in pieces:
            mine = [j for j in jobs if (0 if isinstance(j, Fan | ColumnJob) else j.piece) == k]
            out += self.fans.columns(ts, [j for j in mine if isinstance(j, ColumnJob)])
            out += self.fans.fans(ts, [j for j in mine if isinstance(j, Fan)])
            for j in mine:
                if isinstance(j, Placed):
                    out += self.placed(ts, j)
            for j in mine:
                if isinstance(j, Runs):
                    out += self.runs(ts, j)
        return out

    def placed(self, ts: ToolSolid, job: Placed) -> list[Cutter]:
        """Piece k placed at its poses, trimmed; where a pose's fin is finite only its fin."""
        k, fr, rows = job.piece, job.frames, job.rows
        if len(fr) == 0:
            return []
        whole = (ts.pieces[k], self.tool_shapes(ts)[k], self.tool_pieces(ts)[k])
        if not np.isfinite(job.fins).any():
            return self._placed(*whole, fr, rows)
        half = fin_bucket(np.asarray(job.fins, dtype=float), ts.radius)
        tall = np.asarray(job.tall, dtype=float)
        fin = np.isfinite(half)
        out = self._placed(*whole, fr[~fin], rows[~fin])
        for h, t in np.unique(np.column_stack([half[fin], tall[fin]]), axis=0):
            piece = self.fin_piece(ts, k, float(h), float(t))
            if piece is not None:          # (None: piece k lies wholly above the height)
                sel = fin & (half == h) & (tall == t)
                out += self._placed(*piece, fr[sel], rows[sel])
        return out

    def _placed(self, points: np.ndarray, sh: Shape, solid: engine.Solid, fr: np.ndarray,
                rows: np.ndarray) -> list[Cutter]:
        """A convex piece (its points (p, 3), Shape and Solid, tool frame) placed at poses fr
        (m, 3, 4), trimmed."""
        if len(fr) == 0:
            return []
        placed = place(points, fr)                                          # (m, p, 3)
        if not self.trim:
            return [Cutter(engine.transform(solid, fr[j]),
                           np.stack([placed[j].min(axis=0), placed[j].max(axis=0)]), _rows(rows, j))
                    for j in range(len(fr))]
        pose_box = self.view.boxes(placed[:, :, 2].min(axis=1), placed[:, :, 2].max(axis=1))
        trimmed, inside = clip(sh, fr, pose_box[:, 0], pose_box[:, 1])
        apart = self.view.apart(trimmed, fr[:, :, 2])
        out = []
        for j, q in enumerate(trimmed):
            if q is None or apart[j]:
                self.stats.culled += 1
                continue
            out.append(Cutter(engine.transform(solid, fr[j]) if inside[j] else engine.hull(q),
                              np.stack([q.min(axis=0), q.max(axis=0)]), _rows(rows, j)))
        return out

    def runs(self, ts: ToolSolid, job: Runs) -> list[Cutter]:
        """Translation hulls, one per group of runs, trimmed: each run's hull shape is written
        down (:func:`vmach.stock.clip.sweep_shape`) and clipped, without building the untrimmed
        hull, and the group's cutter is the hull of its runs' clipped points (the union trimmed
        is the union of the runs trimmed, whose hull it is)."""
        groups = job.groups
        if not groups:
            return []
        sweeps = [[sweep_shape(self.tool_shapes(ts)[job.piece], fa, fb) for fa, fb in g] for g in groups]
        box = None
        if self.trim:
            box = self.view.boxes(np.array([min(w.vertices[:, 2].min() for w in g) for g in sweeps]),
                                  np.array([max(w.vertices[:, 2].max() for w in g) for g in sweeps]))
        out = []
        for r, g in enumerate(sweeps):
            points = [p for w in g if (p := self._run_points(w, None if box is None else box[r])) is not None]
            both = np.concatenate(points) if points else None
            if both is None or self.view.apart([both], groups[r][0][0][None, :, 2])[0]:
                self.stats.culled += 1
                continue
            out.append(Cutter(engine.hull(both), np.stack([both.min(axis=0), both.max(axis=0)]),
                              _rows(job.rows, r)))
        return out

    @staticmethod
    def _run_points(w: Shape, box: np.ndarray | None) -> np.ndarray | None:
        """The points of one run's hull shape ``w`` within ``box`` (2, 3) (None: untrimmed), or
        None when none are."""
        both = w.vertices
        lo, hi = both.min(axis=0), both.max(axis=0)
        if box is None or (np.all(lo >= box[0]) and np.all(hi <= box[1])):
            return both
        lo_b, hi_b = box
        if np.any(hi < lo_b) or np.any(lo > hi_b) or np.any(lo_b > hi_b):
            return None
        return clip(w, _IDENTITY, lo_b, hi_b)[0][0]


def fin_bucket(half: np.ndarray, radius: float) -> np.ndarray:
    """Fin half-widths (mm) rounded up to steps of 2^(1/4) from FIN_LEAST, so that poses share
    their fin pieces; inf (the whole pose) from 0.7 of the tool's radius up, where a fin
    saves little."""
    with np.errstate(divide="ignore", invalid="ignore"):
        step = np.ceil(4.0 * np.log2(np.maximum(half, FIN_LEAST) / FIN_LEAST) - 1e-9)
    out = FIN_LEAST * 2.0 ** (step / 4.0)
    return np.where(np.isfinite(half) & (out < 0.7 * radius), out, np.inf)
