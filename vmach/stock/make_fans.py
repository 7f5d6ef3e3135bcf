"""Fan and column cutters made from :class:`vmach.stock.jobs.Fan` and
:class:`~vmach.stock.jobs.ColumnJob` jobs, each measured: how far its hull bridges the floor or
ceiling the tool's side sweeps (:func:`vmach.stock.fan_measure.reaches`), where no other pose of the path
cuts anyway. A fan that bridges more than ``fan_overcut`` is made again shorter; a column cell
that does leaves the column and is cut as a fan. All lengths mm; frames (3, 4) tool to work.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Protocol

import numpy as np

from vmach.stock import engine
from vmach.stock.clip import clip
from vmach.stock.column import Column
from vmach.stock.fan_measure import (
    EPS,
    covered,
    hull_planes,
    material_points,
    reaches,
    side_lines,
    side_samples,
)
from vmach.stock.jobs import ColumnJob, Cutter, Fan, Runs
from vmach.stock.stats import CutStats
from vmach.stock.view import View
from vmach.tooling.solid import ToolSolid, across, frames, lateral, place, spun


class Maker(Protocol):
    """What fans and columns use of their :class:`vmach.stock.make.Maker` (named by its shape:
    the maker imports this module)."""

    view: View
    stats: CutStats
    fan_overcut: float

    def prism(self, ts: ToolSolid): ...

    def tool_shapes(self, ts: ToolSolid) -> list: ...

    def runs(self, ts: ToolSolid, job: Runs) -> list[Cutter]: ...


def run_frames(tips: np.ndarray, axes: np.ndarray, ends: list, segments: int,
               sides: np.ndarray | None = None) -> list:
    """Frames ((3, 4), (3, 4)) of each translation run's two extreme poses (a, b) in ``ends``:
    the same turn about the (common) axis, with the polygon exact toward the run's own
    lateral direction (:func:`vmach.tooling.solid.spun`). A run along the tool's axis has
    none: it takes ``sides`` (n, 3), the path's lateral directions, at its inner pose (the
    deeper end), so that it is the very polygon a placed pose there is."""
    if not ends:
        return []
    ab = np.asarray(ends, dtype=int)                                        # (r, 2)
    a, b = ab[:, 0], ab[:, 1]
    unit = axes[a] / np.linalg.norm(axes[a], axis=1, keepdims=True)
    side = across(unit, tips[b] - tips[a])
    if sides is not None:
        none = ~np.any(side, axis=1)
        inner = np.where(np.einsum("ij,ij->i", tips[b] - tips[a], unit) >= 0.0, a, b)
        side[none] = sides[inner[none]]
    side = np.repeat(side, 2, axis=0)
    pair = np.stack([tips[a], tips[b]], axis=1).reshape(-1, 3)             # a0 b0 a1 b1 ...
    fr = spun(frames(pair, np.repeat(axes[a], 2, axis=0)), side, segments)
    return list(zip(fr[0::2], fr[1::2], strict=True))


class FanMaker:
    """Fans and columns for a :class:`vmach.stock.make.Maker` (its view, stats, tool shapes and
    ``fan_overcut``). It keeps one thing: how many poses the last fan that fitted had (the next
    fan starts at that length)."""

    def __init__(self, maker: Maker):
        self.maker = maker
        self.stats = maker.stats
        self.guess = 8

    @property
    def overcut(self) -> float:
        return self.maker.fan_overcut

    def fans(self, ts: ToolSolid, jobs: list[Fan]) -> list[Cutter]:
        """Fan cutters (piece 0), every run's poses trimmed in one go."""
        if not jobs:
            return []
        out = []
        z = [place(ts.pieces[0], j.frames)[:, :, 2] for j in jobs]
        fan_box = self.maker.view.boxes(np.array([v.min() for v in z]), np.array([v.max() for v in z]))
        sizes = [len(j.frames) for j in jobs]
        boxes = np.repeat(fan_box, sizes, axis=0)
        trimmed, _ = clip(self.maker.tool_shapes(ts)[0], np.concatenate([j.frames for j in jobs]),
                          boxes[:, 0], boxes[:, 1])
        starts = np.cumsum([0, *sizes])
        for f, job in enumerate(jobs):
            out += self._fan_cutters(ts, job, fan_box[f], trimmed[starts[f] : starts[f + 1]])
        return out

    def _measure(self, job: Fan, trimmed: list, lines, pr, i: int, j: int):
        """(hull, bridge, points, covered bridge) of the fan i..j; hull None when it misses the
        box. The bridge counts where no other pose of the path cuts anyway."""
        kept = [q for q in trimmed[i : j + 1] if q is not None]
        if not kept:
            return None, 0.0, None, 0.0
        q = np.concatenate(kept)
        hull = engine.hull(q)
        samples = side_samples(lines, i, j)
        if not samples:
            return hull, 0.0, q, 0.0
        t, a = job.tips[i : j + 1], job.axes[i : j + 1]
        faces = np.column_stack([a, np.einsum("ij,ij->i", t, a)])
        planes = hull_planes(*engine.to_mesh(hull, double=True))
        gap, hidden = self.bridges(planes, samples, job.path, pr, faces)
        return hull, gap, q, hidden

    def _fan_cutters(self, ts: ToolSolid, job: Fan, box: np.ndarray, trimmed: list) -> list[Cutter]:
        """The cutters of one candidate fan run: fans, each the hull of its poses trimmed to
        ``box`` (2, 3) minus the material its faces leave, as long as the bridge allows (the
        next fan starts at the length the last one's bridge suggests); two steps that still
        bridge too much are cut as placed poses (and translation hulls for straight steps)."""
        tips, axes, fr = job.tips, job.axes, job.frames
        pr = self.maker.prism(ts)
        lines = side_lines(fr, job.omega, pr, np.broadcast_to(box, (len(tips), 2, 3)),
                           self.maker.view.blank.hull.outer)
        n, tol_ = len(tips), self.overcut

        def measure(i, j):
            return self._measure(job, trimmed, lines, pr, i, j)

        out: list[Cutter] = []
        i = 0
        while i < n - 1:
            j = _end(n, i, i + self.guess)
            hull, gap, q, hidden = measure(i, j)
            while gap > tol_ and j - i > 2:                 # too twisted: shorter, in proportion
                k = _end(n, i, min(j - 1, _scaled(i, j, gap, 1.0, tol_)), shrink=True)
                if k >= j:
                    break
                j = k
                hull, gap, q, hidden = measure(i, j)
            while gap <= 0.6 * tol_ and j < n - 1:          # room to spare: one longer try
                k = _end(n, i, max(j + 1, _scaled(i, j, gap, 2.0, tol_)))
                h2, g2, q2, c2 = measure(i, k)
                if g2 > tol_:
                    break
                j, hull, gap, q, hidden = k, h2, g2, q2, c2
            if hull is None:
                self.stats.culled += 1
            elif gap > tol_:
                out += self._as_placed(ts, job, box, i, j)
            else:
                m = material_points(tips[i : j + 1], axes[i : j + 1], job.omega, q)
                out.append(Cutter(engine.subtract(hull, [engine.hull(m)]) if m is not None else hull,
                                  np.stack([q.min(axis=0), q.max(axis=0)]), job.rows))
                self.stats.fans += 1
                self.stats.fan_poses += j - i + 1
                self.stats.fan_overcut_mm = max(self.stats.fan_overcut_mm, gap)
                self.stats.fan_covered_mm = max(self.stats.fan_covered_mm, hidden)
                self.guess = max(2, _scaled(i, j, gap, 1.5, tol_) - i)
            i = j
        return out

    def _as_placed(self, ts: ToolSolid, job: Fan, box: np.ndarray, i: int, j: int) -> list[Cutter]:
        """Steps i..j of a fan run that bridge too much: placed poses, as made, and translation
        hulls for its straight steps."""
        tips, axes = job.tips, job.axes
        own, _ = clip(self.maker.tool_shapes(ts)[0], job.frames[i : j + 1], *box)
        out = [Cutter(engine.hull(k), np.stack([k.min(axis=0), k.max(axis=0)]), job.rows)
               for k in own if k is not None]
        straight = [(k, k + 1) for k in range(i, j)
                    if np.linalg.norm(np.cross(axes[k], axes[k + 1])) <= 1e-12]
        groups = [[f] for f in run_frames(tips, axes, straight, ts.segments, lateral(tips, axes))]
        return out + self.maker.runs(ts, Runs(0, groups, np.tile(job.rows, (len(groups), 1))))

    def bridges(self, planes: np.ndarray, samples: list, path, pr, faces: np.ndarray) -> tuple[float, float]:
        """(bridge, covered bridge), mm: how far the convex solid of ``planes`` (f, 4) reaches
        beyond the sampled side surfaces ``samples`` (:func:`vmach.stock.fan_measure.side_samples`)
        where no other pose of ``path`` (tips, unit axes) cuts anyway, and where one does
        (:func:`vmach.stock.fan_measure.covered`, its cylinders taken ``fan_overcut`` behind their
        faces too — the bridge then counts as that much). ``faces`` (k, 4): the cutter's face
        planes ``n·x <= h`` — M, which the cutter leaves: a sample whose point lies in M has all
        of its bridge along ±omega in M too, and none counts."""
        gap = hidden = 0.0
        for _, grid, d in samples:
            r = reaches(planes, grid.reshape(-1, 3), d).reshape(grid.shape[:3])
            in_m = np.all(grid @ faces[:, :3].T - faces[:, 3] <= EPS, axis=-1)
            r[in_m] = 0.0
            over = r > self.overcut
            if over.any() and path is not None:
                ok = covered(grid, over, float(r.max()), d, *path, pr, behind=self.overcut)
                hidden = max(hidden, float(r[ok].max(initial=0.0)))
                r[ok] = 0.0
                if ok.any():            # what another pose holds, within fan_overcut behind its face
                    gap = max(gap, self.overcut)
            gap = max(gap, float(r.max(initial=0.0)))
        return gap, hidden

    # columns ---------------------------------------------------------------------------------
    def columns(self, ts: ToolSolid, jobs: list[ColumnJob]) -> list[Cutter]:
        """Column cutters (piece 0; :mod:`vmach.stock.column`), each ``(H ∩ W) \\ M`` with H the
        hull of its cells' poses trimmed to the box around the stock within its Z range. A cell
        at an end of the stack that bridges more than ``fan_overcut`` leaves the column and is
        cut as a fan, and the column is made again of the others; with fewer than two left,
        they are all cut as fans."""
        out: list[Cutter] = []
        pr = self.maker.prism(ts) if jobs else None
        for job in jobs:
            cells = job.column.cells
            while True:
                made = self._column(ts, replace(job, column=replace(job.column, cells=cells)), pr)
                if made is None:                      # misses the stock
                    cells = cells[:0]
                    break
                cutter, gaps, hidden = made
                bad = gaps > self.overcut
                if not bad.any():
                    out.append(cutter)
                    self._count_column(job.column, cells, gaps, hidden)
                    cells = cells[:0]
                    break
                out += self.cells_as_fans(ts, job, cells[bad])
                cells = cells[~bad]
                if len(cells) < 2:
                    break
            out += self.cells_as_fans(ts, job, cells)
        return out

    def _count_column(self, col: Column, cells: np.ndarray, gaps: np.ndarray, hidden: float) -> None:
        over = max(float(gaps.max(initial=0.0)), col.depth)
        s = self.stats
        s.columns += 1
        s.column_cells += len(cells)
        s.fan_poses += int(sum(b - a + 1 for a, b in cells))
        s.column_overcut_mm = max(s.column_overcut_mm, over)
        s.fan_overcut_mm = max(s.fan_overcut_mm, over)
        s.fan_covered_mm = max(s.fan_covered_mm, hidden)

    def cells_as_fans(self, ts: ToolSolid, job: ColumnJob, cells: np.ndarray) -> list[Cutter]:
        """The cells (k, 2) of a column cut as fans (:meth:`fans`)."""
        t, u, fr = job.tips, job.axes, job.frames
        om = job.column.omega
        return self.fans(ts, [Fan(t[a : b + 1], u[a : b + 1], om, fr[a : b + 1], job.path, job.rows)
                              for a, b in cells])

    def _column(self, ts: ToolSolid, job: ColumnJob, pr):
        """(cutter, bridges (k,) of its cells, covered bridge) of one column, or None when its
        trimmed hull misses the stock."""
        col, tips, unit, fr = job.column, job.tips, job.axes, job.frames
        idx = col.poses
        z = place(ts.pieces[0], fr[idx])[:, :, 2]
        box = self.maker.view.boxes(np.array([z.min()]), np.array([z.max()]))[0]
        trimmed, _ = clip(self.maker.tool_shapes(ts)[0], fr[idx], box[0], box[1])
        kept = [q for q in trimmed if q is not None]
        if not kept:
            self.stats.culled += 1
            return None
        q = np.concatenate(kept)
        hull = engine.hull(q)
        for plane in col.wedge:
            hull = engine.trim(hull, plane)
        if engine.is_empty(hull):
            self.stats.culled += 1
            return None
        gaps, hidden = self.column_bridges(job, box, hull, pr)
        m = material_points(tips[idx], unit[idx], col.omega, q)   # M: below every face plane
        cutter = engine.subtract(hull, [engine.hull(m)]) if m is not None else hull
        return Cutter(cutter, np.stack([q.min(axis=0), q.max(axis=0)]), job.rows), gaps, hidden

    def column_bridges(self, job: ColumnJob, box, hull, pr) -> tuple[np.ndarray, float]:
        """The column hull's bridges (:meth:`bridges`) over the side surfaces at the ends of
        its stack of cells — (k,) mm, one per cell, 0 for a cell with no end — and the largest
        covered one. A cell's side toward ±omega counts unless another cell lies that way by
        more than the tool's polygon differs from its inscribed cylinder."""
        col, tips, unit, fr = job.column, job.tips, job.axes, job.frames
        om = col.omega
        h = np.array([float(np.mean(tips[a : b + 1] @ om)) for a, b in col.cells])
        apart = pr.radius - pr.inner + 1e-3
        planes = hull_planes(*engine.to_mesh(hull, double=True))
        idx = col.poses
        faces = np.column_stack([unit[idx], np.einsum("ij,ij->i", tips[idx], unit[idx])])
        gaps = np.zeros(len(col.cells))
        hidden = 0.0
        for k, ((a, b), hc) in enumerate(zip(col.cells, h, strict=True)):
            # the sides (+1: toward +omega) with no cell beyond them
            ends = [d for d, beyond in ((1.0, h - hc), (-1.0, hc - h)) if not np.any(beyond >= apart)]
            if not ends:
                continue
            reach = np.broadcast_to(box, (b - a + 1, 2, 3))
            lines = side_lines(fr[a : b + 1], om, pr, reach, self.maker.view.blank.hull.outer)
            samples = [s for s in side_samples(lines, 0, b - a)
                       if any(float(s[2] @ om) * d > 0 for d in ends)]
            gaps[k], c = self.bridges(planes, samples, job.path, pr, faces)
            hidden = max(hidden, c)
        return gaps, hidden


def _end(n: int, i: int, j: int, shrink: bool = False) -> int:
    """j within i+2 .. n-1, leaving no run of one step over (rounding down when shrinking, so
    that the run does get shorter)."""
    j = min(n - 1, max(i + 2, j))
    if 0 < n - 1 - j < 2:
        j = n - 3 if shrink and n - 3 >= i + 2 else n - 1
    return j


def _scaled(i: int, j: int, gap: float, most: float, tol_: float) -> int:
    return i + int((j - i) * min(most, 0.95 * tol_ / max(gap, 1e-12)))
