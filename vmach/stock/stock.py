"""The stock: a blank that tool paths cut, in checked batches.

    stock = Stock.from_spec("cylinder:d=60,l=100")
    stock.cut(tool, tips, axes)          # one path: (n, 3) tips, (n, 3) unit axes, work frame
    part = stock.solid                   # flushes pending cutters
    stock.export("part.stl"); stock.export("removed.3mf", which="removed")

How a tool path becomes a cut solid, in three modules: :mod:`vmach.stock.plan` turns the path
into typed jobs (:mod:`vmach.stock.jobs`) — its cutter strategies (:mod:`vmach.stock.strategies`)
claim steps in a stated order; :mod:`vmach.stock.make` makes each job's cutters, trimmed to the
stock's :class:`~vmach.stock.view.View`; :mod:`vmach.stock.queue` subtracts them in checked
batches. This class holds the three together, with the blank (:mod:`vmach.stock.blank`).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from vmach.errors import InputError
from vmach.output import atomic_writer, make_dir, writable_dir
from vmach.stock import engine
from vmach.stock.blank import Blank
from vmach.stock.jobs import Cutter
from vmach.stock.make import Maker
from vmach.stock.plan import Planner, Settings
from vmach.stock.queue import Queue
from vmach.stock.spec import parse_stock
from vmach.stock.stats import CutStats
from vmach.stock.view import View
from vmach.tol import tol
from vmach.tooling.model import Tool
from vmach.tooling.solid import ToolSolid, segments_for
from vmach.tooling.turning import TurningTool

EXPORT_FORMATS = (".stl", ".3mf", ".ply")


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


class Stock:
    """Material that tool paths remove.

    solid : engine.Solid — the blank.
    batch : int — cutters per batch boolean; spread : int — batches taken from one window of
        queued cutters (:mod:`vmach.stock.batch`).
    cells : (3,) int — partition of the blank's bounds into nx × ny × nz cells (1, 1, 1: none;
        in-process only).
    chord : float, mm — polygonisation tolerance of tool solids.
    progress : bool — show a progress bar on stderr when it is a terminal.
    trim, fans, columns, cusp, fan_overcut, arcs : the planner's :class:`~vmach.stock.plan.Settings`
        (fans only with trim, columns only with fans).
    worker : bool — once ``WORKER_AFTER`` cutters were queued, subtract the batches in a worker
        process while the next cutters are made (:mod:`vmach.stock.remote`; one cell only).

    ``provenance`` : (c, 2) int — the first and last program row of each cutter made, in the
    order made (-1: a path cut without rows); :meth:`cutters_by_row` counts them per row.
    """

    GROUP = 4    # consecutive cutters kept together in a spread batch (a run the worker unites as it comes)
    WORKER_AFTER = 64   # cutters queued before a worker process takes the runs and batches
    BLANK_CELL = Blank.CELL  # triangles of a finely meshed blank per cell (:meth:`blank_meets`)

    def __init__(self, solid: engine.Solid, *, batch: int = 64,
                 cells: tuple[int, int, int] = (1, 1, 1), chord: float = tol.tool_chord,
                 progress: bool = False, trim: bool = True, spread: int = 16, fans: bool = True,
                 fan_overcut: float = tol.fan_overcut, cusp: float = tol.sweep_cusp, columns: bool = True,
                 arcs: bool = False, worker: bool = True):
        engine.check(solid, "blank")
        self.initial = solid
        self.blank = Blank(solid)
        self.initial_bounds = self.blank.bounds
        self.stats = CutStats()
        # a worker process takes one cell's batches: not with a partition
        worker = bool(worker) and all(max(1, int(c)) == 1 for c in cells)
        self.batches = Queue(solid, cells, batch=max(1, int(batch)), spread=max(1, int(spread)),
                             group=self.GROUP, worker_after=self.WORKER_AFTER if worker else None,
                             stats=self.stats, progress=progress)
        self.view = View(self.batches, self.blank)
        fans = fans and trim
        self.settings = Settings(chord=chord, arcs=bool(arcs), trim=trim, fans=fans, columns=columns and fans,
                                 cusp=cusp, fan_overcut=fan_overcut)
        self.maker = Maker(self.view, self.stats, trim=trim, cusp=cusp, fan_overcut=fan_overcut)
        self.planner = Planner(self.settings, self.view, self.maker, self.stats)
        # revolved (turning) cutters share the blank's polygon count, and so its vertices' angles
        lo, hi = self.initial_bounds
        self.maker.turn_segments = segments_for(float(max(-lo[0], hi[0], -lo[1], hi[1])), tol.blank_chord)
        self._rows: list[tuple[int, int]] = []

    @classmethod
    def from_spec(cls, spec: str, notes: list | None = None, **kw) -> Stock:
        """The stock of a spec string (:func:`vmach.stock.spec.parse_stock`, which fills
        ``notes``)."""
        return cls(parse_stock(spec, notes=notes), **kw)

    # ----------------------------------------------------------------------------------------
    def cut(self, tool: Tool | ToolSolid, tips: np.ndarray, axes: np.ndarray, between=None,
            cover=None, rows: np.ndarray | None = None) -> int:
        """Queue the swept volume of one path; returns the number of cutters made.

        tool : Tool (polygonised with this stock's chord) or a ready ToolSolid.
        tips : (n, 3) float, mm; axes : (n, 3) float, unit — poses in the work frame, joined by
        motion in order. A rotary path must be sampled densely enough for the wanted accuracy
        (see :mod:`vmach.stock.sweep`).
        between : callable ``(steps (s,) int, parts (s,) int) -> (tips (e, 3), axes (e, 3),
            at (e,) float)`` giving the poses that cut each step ``i`` (from pose i to i+1)
            into ``parts`` equal parts of the motion — the ``parts - 1`` poses strictly inside,
            step by step, ``at`` = i + fraction. With it, rotary steps get more poses where the
            tool would leave cusps over the stock's ``cusp`` (:mod:`vmach.stock.strategies.cusps`).
        cover : the optional coverage index of the program's other paths
            (:meth:`vmach.stock.sweeps.Sweeps.coverage`): which places their true tools sweep.
        rows : (n,) int — the program row of each pose (a step belongs to the row it ends
            in); the cutters made name them (:attr:`provenance`).
        """
        n = 0
        for cutters in self._made(tool, tips, axes, between, cover, rows):
            self.queue(cutters)
            n += len(cutters)
        return n

    def turn(self, tool: TurningTool, tips: np.ndarray, rows: np.ndarray | None = None) -> int:
        """Queue what a turning tool removes along one path while the workpiece turns: its
        cross-section swept through ``tips`` (n, 3) work frame mm (the theoretical tip P) in
        the X–Z half-plane and revolved about the spindle axis (work Z); returns the number of
        cutters made. ``rows`` as for :meth:`cut`."""
        cutters = self.turned(tool.section(self.turn_chord), tips, rows)
        self.queue(cutters)
        return len(cutters)

    def turned(self, section: np.ndarray, tips: np.ndarray, rows: np.ndarray | None = None) -> list[Cutter]:
        """The revolved cutters of a cross-section ``section`` (k, 2) ``(x, z)`` mm swept
        through ``tips`` (n, 3), not queued (what a turning tool's insert — or its holder —
        sweeps: :mod:`vmach.stock.strategies.revolved`)."""
        t0 = time.perf_counter()
        cutters = self.maker.make(None, self.planner.turn(section, tips, rows))
        self.stats.sweep_seconds += time.perf_counter() - t0
        return cutters

    def polygon(self, tool, coupling, points: np.ndarray, rows: np.ndarray | None = None) -> int:
        """Queue what a flywheel cutter (:class:`vmach.tooling.flywheel.FlywheelTool`) coupled to
        the main spindle by ``coupling`` (:class:`vmach.stock.strategies.polygonal.Coupling`)
        removes along one path, its point P at ``points`` (n, 3) machine frame mm (X, Y from the
        spindle axis, Z along it); returns the number of cutters made. ``rows`` as for :meth:`cut`."""
        cutters = self.polygon_cutters(tool, coupling, points, rows)
        self.queue(cutters)
        return len(cutters)

    def polygon_cutters(self, tool, coupling, points: np.ndarray, rows: np.ndarray | None = None
                        ) -> list[Cutter]:
        """The cutters of :meth:`polygon`, not queued."""
        t0 = time.perf_counter()
        cutters = self.maker.make(None, self.planner.polygon(tool, coupling, points, rows))
        self.stats.sweep_seconds += time.perf_counter() - t0
        return cutters

    @property
    def turn_chord(self) -> float:
        """mm: the chord of a turning insert's nose arcs (the finer of the tool and blank chords)."""
        return min(self.chord, tol.blank_chord)

    def _made(self, tool, tips, axes, between=None, cover=None, rows=None):
        """Yield the cutters of each stretch of a path, as made."""
        for ts, jobs in self.planner.plan(tool, tips, axes, between, cover, rows):
            t0 = time.perf_counter()
            cutters = self.maker.make(ts, jobs)
            self.stats.sweep_seconds += time.perf_counter() - t0
            yield cutters

    def cutters(self, tool: Tool | ToolSolid, tips: np.ndarray, axes: np.ndarray
                ) -> tuple[list[engine.Solid], list[np.ndarray]]:
        """The solids a path sweeps and their boxes (c, 2, 3), without queueing them (probes of
        the checks: what a move would remove)."""
        made = [c for stretch in self._made(tool, tips, axes) for c in stretch]
        return [c.solid for c in made], [c.box for c in made]

    def queue(self, cutters: list[Cutter]) -> None:
        """Queue made cutters, noting the rows that made them."""
        if cutters:
            self._rows += [c.rows for c in cutters]
            self.batches.add([c.solid for c in cutters], [c.box for c in cutters], self.view.seen)

    @property
    def chord(self) -> float:
        """mm: the tool polygons' tolerance (the planner's setting)."""
        return self.settings.chord

    @property
    def cusp(self) -> float:
        """mm: the largest cusp left between placed poses."""
        return self.settings.cusp

    @property
    def arcs(self) -> bool:
        """Flat and face mills' rims made round about each pose's laterals."""
        return self.settings.arcs

    @property
    def provenance(self) -> np.ndarray:
        """(c, 2) int: the first and last program row of each cutter made, in order."""
        return np.array(self._rows, dtype=int).reshape(-1, 2)

    def cutters_by_row(self) -> dict[int, int]:
        """Program row -> how many cutters its motion made (a cutter of several rows counts for
        its first); rows unknown (-1) left out."""
        first, count = np.unique(self.provenance[:, 0], return_counts=True)
        return {int(r): int(c) for r, c in zip(first, count, strict=True) if r >= 0}

    def flush(self) -> None:
        """Subtract every queued cutter (with a worker process: hand them to it)."""
        self.batches.flush()

    def close(self) -> None:
        """Stop the worker process, if one took the batches, once it has subtracted them all
        (the stock stays as it is; cutters queued later are subtracted in this process)."""
        self.batches.close()

    # ----------------------------------------------------------------------------------------
    @property
    def solid(self) -> engine.Solid:
        """The cut part (all pending cutters subtracted)."""
        return self.batches.solid

    def local(self, lo, hi) -> engine.Solid:
        """The stock now (pending cutters subtracted) inside the box [lo, hi] — exact there,
        and cheaper to measure against than the whole stock (empty if the box is)."""
        lo = np.asarray(lo, dtype=float)
        hi = np.asarray(hi, dtype=float)
        if np.any(lo > hi):
            return engine.empty()
        return self.batches.local(lo, hi)

    def removed(self) -> engine.Solid:
        """The removed material: blank minus part."""
        return engine.subtract(self.initial, [self.solid])

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float, mm — bounds of the stock as the view's last retake saw it (the stock
        only shrinks, so this is conservative)."""
        return self.view.bounds

    def trim_box(self) -> np.ndarray:
        """(2, 3) float, mm — the box cutters are trimmed to (:meth:`View.trim_box`)."""
        return self.view.trim_box()

    @property
    def volume(self) -> float:
        return self.batches.volume

    def blank_holds(self, points: np.ndarray) -> np.ndarray:
        """(k,) bool: points inside the (convex) blank (:meth:`vmach.stock.blank.Blank.holds`)."""
        return self.blank.holds(points)

    def blank_meets(self, solid: engine.Solid) -> bool:
        """Does the convex ``solid`` overlap the blank (:meth:`vmach.stock.blank.Blank.meets`)?"""
        return self.blank.meets(solid, self.BLANK_CELL)

    def blank_planes(self) -> np.ndarray | None:
        """(f, 4) planes of a convex region holding a convex blank, or None."""
        return self.blank.planes()

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
