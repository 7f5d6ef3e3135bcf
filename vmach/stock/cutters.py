"""Cutters made from a path's jobs: placed poses, translation hulls, fan and column cutters.

:class:`CutterMaker` is a mixin of :class:`vmach.stock.Stock`: it turns the jobs that
``Stock._sweep`` plans (:mod:`vmach.stock.sweep`, :mod:`vmach.stock.fan`,
:mod:`vmach.stock.column`) into solids, each trimmed exactly to the box around the stock within
its Z range, and measures what fans and columns may bridge. It uses the stock's state — its
statistics (``stats``), trim boxes (``_boxes``), cached tool shapes and pieces, the blank's
hull, ``fan_overcut`` — and keeps none of its own. All lengths mm; frames (3, 4) tool to work.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from vmach.stock import engine
from vmach.stock.clip import Shape, clip, shape, sweep_shape
from vmach.stock.column import Column
from vmach.stock.cusps import FIN_LEAST
from vmach.stock.fan import (
    EPS,
    covered,
    hull_planes,
    material_points,
    reaches,
    side_lines,
    side_samples,
)
from vmach.tooling.solid import RIM_SAG, ToolSolid, across, fin_points, frames, lateral, place, spun

_IDENTITY = np.hstack([np.eye(3), np.zeros((3, 1))])[None]


def _run_frames(tips: np.ndarray, axes: np.ndarray, ends: list, segments: int,
                sides: np.ndarray | None = None) -> list:
    """Frames ((3, 4), (3, 4)) of each translation run's two extreme poses (a, b) in ``ends``:
    the same turn about the (common) axis, with the polygon exact toward the run's own
    lateral direction (:func:`vmach.tooling.solid.spun`). A run along the tool's axis has
    none: it takes ``sides`` (n, 3), the path's lateral directions, at its inner pose (the
    deeper end), so that it is the very polygon a placed pose there is (a retract cut as the
    tool at its inner pose, ``Stock._axial``, removes what its hull removes; the polygon is not
    symmetric about its axis but for half turns, :func:`vmach.tooling.solid.ring_points`)."""
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


class CutterMaker:
    """Making and measuring cutters (mixin of :class:`vmach.stock.Stock`)."""

    def _fan_cutters(self, ts: ToolSolid, tips: np.ndarray, axes: np.ndarray, omega: np.ndarray,
                     fr: np.ndarray, box: np.ndarray, trimmed: list,
                     path: tuple[np.ndarray, np.ndarray] | None = None
                     ) -> list[tuple[engine.Solid, np.ndarray]]:
        """The cutters of one candidate fan run (:mod:`vmach.stock.fan`): [(solid, box (2, 3)),
        ...]. ``tips``, ``axes`` (n, 3): its poses (unit axes); ``fr`` (n, 3, 4): their frames,
        as placed poses have them (turned so that the polygon is exact to both sides of the
        travel, :func:`vmach.tooling.solid.spun`);
        ``box`` (2, 3): its trim box; ``trimmed``: its poses clipped to it; ``path``: the tips
        and unit axes (m, 3) of the whole path the run belongs to.

        A fan's H is the hull of its poses each trimmed to the box: inside the box it holds
        every trimmed pose (so the fan removes at least what they would) and lies in the hull
        of the untrimmed poses. H is measured — how far it bridges the floor or ceiling the
        tool's side sweeps (:func:`vmach.stock.fan.reaches`) — and a fan that bridges more than
        ``fan_overcut`` is made again shorter, in proportion (the bridge grows with the twist
        a run takes along its axis); the next fan starts at the length the last one's bridge
        suggests. Where the path's own poses cut the bridged place anyway (a helix's next or
        previous turn; :func:`vmach.stock.fan.covered`) the bridge does not count: the final
        stock is the same. Two steps that still bridge too much are cut as placed poses."""
        reach = np.broadcast_to(box, (len(tips), 2, 3))
        pr = self._prism(ts)
        self._blank_hull()
        lines = side_lines(fr, omega, pr, reach, self._hull.outer)
        n = len(tips)
        tol_ = self.fan_overcut

        def measure(i: int, j: int):
            """(hull, bridge, points, covered bridge) of the fan i..j; hull None when it
            misses the box. The bridge counts where no other pose of the path cuts anyway."""
            kept = [q for q in trimmed[i : j + 1] if q is not None]
            if not kept:
                return None, 0.0, None, 0.0
            q = np.concatenate(kept)
            hull = engine.hull(q)
            samples = side_samples(lines, i, j)
            if not samples:
                return hull, 0.0, q, 0.0
            t, a = tips[i : j + 1], axes[i : j + 1]
            faces = np.column_stack([a, np.einsum("ij,ij->i", t, a)])
            gap, hidden = self._bridges(hull_planes(*engine.to_mesh(hull, double=True)), samples, path, pr,
                                        faces)
            return hull, gap, q, hidden

        def end(i: int, j: int, shrink: bool = False) -> int:
            """j within i+2 .. n-1, leaving no run of one step over (rounding down when
            shrinking, so that the run does get shorter)."""
            j = min(n - 1, max(i + 2, j))
            if 0 < n - 1 - j < 2:
                j = n - 3 if shrink and n - 3 >= i + 2 else n - 1
            return j

        def scaled(i: int, j: int, gap: float, most: float) -> int:
            return i + int((j - i) * min(most, 0.95 * tol_ / max(gap, 1e-12)))

        out = []
        i = 0
        while i < n - 1:
            j = end(i, i + self._fan_guess)
            hull, gap, q, hidden = measure(i, j)
            while gap > tol_ and j - i > 2:                 # too twisted: shorter, in proportion
                k = end(i, min(j - 1, scaled(i, j, gap, 1.0)), shrink=True)
                if k >= j:
                    break
                j = k
                hull, gap, q, hidden = measure(i, j)
            while gap <= 0.6 * tol_ and j < n - 1:          # room to spare: one longer try
                k = end(i, max(j + 1, scaled(i, j, gap, 2.0)))
                h2, g2, q2, c2 = measure(i, k)
                if g2 > tol_:
                    break
                j, hull, gap, q, hidden = k, h2, g2, q2, c2
            if hull is None:
                self.stats.culled += 1
            elif gap > tol_:                # two steps still too twisted: placed poses, as made,
                own, _ = clip(self._tool_shapes(ts)[0], fr[i : j + 1], *box)
                out += [(engine.hull(k), np.stack([k.min(axis=0), k.max(axis=0)]))
                        for k in own if k is not None]
                # ... and translation hulls for its straight steps
                straight = [(k, k + 1) for k in range(i, j)
                            if np.linalg.norm(np.cross(axes[k], axes[k + 1])) <= 1e-12]
                out += self._make_runs(ts, 0, [[f] for f in _run_frames(tips, axes, straight, ts.segments,
                                                                            lateral(tips, axes))])
            else:
                m = material_points(tips[i : j + 1], axes[i : j + 1], omega, q)
                out.append((engine.subtract(hull, [engine.hull(m)]) if m is not None else hull,
                            np.stack([q.min(axis=0), q.max(axis=0)])))
                self.stats.fans += 1
                self.stats.fan_poses += j - i + 1
                self.stats.fan_overcut_mm = max(self.stats.fan_overcut_mm, gap)
                self.stats.fan_covered_mm = max(self.stats.fan_covered_mm, hidden)
                self._fan_guess = max(2, scaled(i, j, gap, 1.5) - i)
            i = j
        return out

    def _bridges(self, planes: np.ndarray, samples: list, path, pr, faces: np.ndarray) -> tuple[float, float]:
        """(bridge, covered bridge), mm: how far the convex solid of ``planes`` (f, 4) reaches
        beyond the sampled side surfaces ``samples`` (:func:`vmach.stock.fan.side_samples`)
        where no other pose of ``path`` (tips, unit axes) cuts anyway, and where one does (a
        helix's next and previous turns; :func:`vmach.stock.fan.covered`, its cylinders taken
        ``fan_overcut`` behind their faces too — the bridge then counts as that much). ``faces`` (k, 4):
        the cutter's face planes ``n·x <= h`` — M, which the cutter leaves: every face plane
        contains omega, so a sample whose point lies in M (the side's line where it starts on
        the face) has all of its bridge along ±omega in M too, and none counts."""
        gap = hidden = 0.0
        for _, grid, d in samples:
            r = reaches(planes, grid.reshape(-1, 3), d).reshape(grid.shape[:3])
            in_m = np.all(grid @ faces[:, :3].T - faces[:, 3] <= EPS, axis=-1)
            r[in_m] = 0.0
            over = r > self.fan_overcut
            if over.any() and path is not None:
                ok = covered(grid, over, float(r.max()), d, *path, pr, behind=self.fan_overcut)
                hidden = max(hidden, float(r[ok].max(initial=0.0)))
                r[ok] = 0.0
                if ok.any():            # what another pose holds, within fan_overcut behind its face
                    gap = max(gap, self.fan_overcut)
            gap = max(gap, float(r.max(initial=0.0)))
        return gap, hidden

    def _make_columns(self, ts: ToolSolid, col_jobs: list) -> list[tuple[engine.Solid, np.ndarray]]:
        """Column cutters (piece 0; :mod:`vmach.stock.column`), each ``(H ∩ W) \\ M`` with H the
        hull of its cells' poses trimmed to the box around the stock within its Z range. The
        hull is measured where it may bridge the floor or ceiling the tool's side sweeps — at the
        stack's two ends: the lowest cells' side toward -omega, the highest cells' toward
        +omega (a cell's side toward another cell lies in that cell's tool) — as fans are
        (:meth:`_bridges`). A cell at an end that bridges more than ``fan_overcut`` (a helix's
        last turn, with no turn below to cut its floor anyway) leaves the column and is cut as a
        fan, and the column is made again of the others; with fewer than two left, they are
        all cut as fans."""
        out: list[tuple[engine.Solid, np.ndarray]] = []
        if not col_jobs:
            return out
        pr = self._prism(ts)
        self._blank_hull()
        for col, tips, unit, fr, path in col_jobs:
            cells = col.cells
            while True:
                made = self._column(ts, replace(col, cells=cells), tips, unit, fr, path, pr)
                if made is None:                      # misses the stock
                    cells = cells[:0]
                    break
                cutter, box, gaps, hidden = made
                bad = gaps > self.fan_overcut
                if not bad.any():
                    out.append((cutter, box))
                    over = max(float(gaps.max(initial=0.0)), col.depth)
                    self.stats.columns += 1
                    self.stats.column_cells += len(cells)
                    self.stats.fan_poses += int(sum(b - a + 1 for a, b in cells))
                    self.stats.column_overcut_mm = max(self.stats.column_overcut_mm, over)
                    self.stats.fan_overcut_mm = max(self.stats.fan_overcut_mm, over)
                    self.stats.fan_covered_mm = max(self.stats.fan_covered_mm, hidden)
                    cells = cells[:0]
                    break
                out += self._cells_as_fans(ts, col, cells[bad], tips, unit, fr, path)
                cells = cells[~bad]
                if len(cells) < 2:
                    break
            out += self._cells_as_fans(ts, col, cells, tips, unit, fr, path)
        return out

    def _cells_as_fans(self, ts: ToolSolid, col: Column, cells: np.ndarray, tips, unit, fr, path) -> list:
        """The cells (k, 2) of a column cut as fans (:meth:`_make_fans`)."""
        return self._make_fans(ts, [(tips[a : b + 1], unit[a : b + 1], col.omega, fr[a : b + 1], path)
                                    for a, b in cells])

    def _column(self, ts: ToolSolid, col: Column, tips, unit, fr, path, pr):
        """(cutter, box (2, 3), bridges (k,) of its cells, covered bridge) of one column, or None
        when its trimmed hull misses the stock."""
        idx = col.poses
        z = place(ts.pieces[0], fr[idx])[:, :, 2]
        box = self._boxes(np.array([z.min()]), np.array([z.max()]))[0]
        trimmed, _ = clip(self._tool_shapes(ts)[0], fr[idx], box[0], box[1])
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
        gaps, hidden = self._column_bridges(col, tips, unit, fr, box, hull, path, pr)
        idx = col.poses                        # M: below every face plane of the column's poses
        m = material_points(tips[idx], unit[idx], col.omega, q)
        cutter = engine.subtract(hull, [engine.hull(m)]) if m is not None else hull
        return cutter, np.stack([q.min(axis=0), q.max(axis=0)]), gaps, hidden

    def _column_bridges(self, col: Column, tips, unit, fr, box, hull, path, pr) -> tuple[np.ndarray, float]:
        """The column hull's bridges (:meth:`_bridges`) over the side surfaces at the ends of
        its stack of cells — (k,) mm, one per cell, 0 for a cell with no end — and the largest
        covered one. A cell's side toward ±omega counts unless another cell lies that way by
        more than the tool's polygon differs from its inscribed cylinder (then the side lies in
        that cell's tool)."""
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
            lines = side_lines(fr[a : b + 1], om, pr, reach, self._hull.outer)
            samples = [s for s in side_samples(lines, 0, b - a)
                       if any(float(s[2] @ om) * d > 0 for d in ends)]
            gaps[k], c = self._bridges(planes, samples, path, pr, faces)
            hidden = max(hidden, c)
        return gaps, hidden

    def _make(self, ts: ToolSolid, jobs) -> tuple[list[engine.Solid], list[np.ndarray]]:
        """Cutters of one stretch, in this process, each trimmed to the box around the stock
        within its Z range (:meth:`_boxes`)."""
        made: list[tuple[engine.Solid, np.ndarray]] = []
        for k, fr, runs, fan_jobs, col_jobs, fins, tall in jobs:
            made += self._make_columns(ts, col_jobs)
            made += self._make_fans(ts, fan_jobs)
            made += self._make_placed(ts, k, fr, fins, tall)
            made += self._make_runs(ts, k, runs)
        return [c for c, _ in made], [b for _, b in made]

    def _make_fans(self, ts: ToolSolid, fan_jobs: list) -> list[tuple[engine.Solid, np.ndarray]]:
        """Fan cutters (piece 0), every run's poses trimmed in one go."""
        if not fan_jobs:
            return []
        out = []
        fan_fr = [job[3] for job in fan_jobs]
        z = [place(ts.pieces[0], f)[:, :, 2] for f in fan_fr]
        fan_box = self._boxes(np.array([v.min() for v in z]), np.array([v.max() for v in z]))
        sizes = [len(f) for f in fan_fr]
        boxes = np.repeat(fan_box, sizes, axis=0)
        trimmed, _ = clip(self._tool_shapes(ts)[0], np.concatenate(fan_fr), boxes[:, 0], boxes[:, 1])
        starts = np.cumsum([0, *sizes])
        for f, (tips, axes, omega, _, path) in enumerate(fan_jobs):
            out += self._fan_cutters(ts, tips, axes, omega, fan_fr[f], fan_box[f],
                                     trimmed[starts[f] : starts[f + 1]], path)
        return out

    def _make_placed(self, ts: ToolSolid, k: int, fr: np.ndarray, fins: np.ndarray | None = None,
                     tall: np.ndarray | None = None) -> list[tuple[engine.Solid, np.ndarray]]:
        """Piece k placed at poses fr (m, 3, 4), trimmed; where ``fins`` (m,) float is finite,
        only the pose's fin of that half-width (mm; :func:`vmach.stock.cusps.fin_widths`), up
        to the height ``tall`` (m,) mm along the axis (inf: the whole length;
        :func:`vmach.stock.cusps.fin_height`)."""
        if len(fr) == 0:
            return []
        if fins is None or not np.isfinite(fins).any():
            return self._placed(ts.pieces[k], self._tool_shapes(ts)[k], self._tool_pieces(ts)[k], fr)
        half = _fin_bucket(np.asarray(fins, dtype=float), ts.radius)
        tall = np.full(len(fr), np.inf) if tall is None else np.asarray(tall, dtype=float)
        out = self._placed(ts.pieces[k], self._tool_shapes(ts)[k], self._tool_pieces(ts)[k],
                           fr[~np.isfinite(half)])
        fin = np.isfinite(half)
        for h, t in np.unique(np.column_stack([half[fin], tall[fin]]), axis=0):
            piece = self._fin_piece(ts, k, float(h), float(t))
            if piece is not None:          # (None: piece k lies wholly above the height)
                out += self._placed(*piece, fr[fin & (half == h) & (tall == t)])
        return out

    def _fin_piece(self, ts: ToolSolid, k: int, half: float, height: float = np.inf
                   ) -> tuple[np.ndarray, Shape, engine.Solid] | None:
        """(points, Shape, Solid) that cut a pose of piece k as its fin, tool frame (cached):
        of half-width ``half`` mm — the true tool within that slab about the plane through its
        axis and the lateral direction placed poses are turned for, up to ``height`` mm from
        the tip (None where the piece lies above it)
        (:func:`vmach.tooling.solid.fin_points`; its arcs within 0.8 of the stock's ``cusp``
        of the true circles, and within ``RIM_SAG``: 0.0006 mm at ``fine`` made the program's
        stock 68,000 → 76,000 triangles and took 19.5 → 21.7 s; at ``standard``, 0.008 mm left
        the shoulder 0.012 mm high where the turn's own poses were cut as fins)."""
        key = (id(ts), k, half, height)
        if key not in self._fin_cache:
            # within 0.8 of the cusp they are to leave, and no coarser than a whole pose about its
            # lateral (a pose between two rotary steps is cut as its fin too, Stock._inner_fins)
            pts = fin_points(ts.pieces[k], ts.segments, half, sag=min(0.8 * self.cusp, RIM_SAG),
                             height=height)
            flat = len(pts) < 4 or np.ptp(pts[:, 2]) <= 1e-9
            self._fin_cache[key] = None if flat else (pts, shape(*engine.hull_mesh(pts)), engine.hull(pts))
        return self._fin_cache[key]

    def _placed(self, points: np.ndarray, sh: Shape, solid: engine.Solid,
                fr: np.ndarray) -> list[tuple[engine.Solid, np.ndarray]]:
        """A convex piece (its points (p, 3), Shape and Solid, tool frame) placed at poses fr
        (m, 3, 4), trimmed."""
        if len(fr) == 0:
            return []
        placed = place(points, fr)                                          # (m, p, 3)
        if not self.trim:
            return [(engine.transform(solid, fr[j]), np.stack([placed[j].min(axis=0), placed[j].max(axis=0)]))
                    for j in range(len(fr))]
        pose_box = self._boxes(placed[:, :, 2].min(axis=1), placed[:, :, 2].max(axis=1))
        trimmed, inside = clip(sh, fr, pose_box[:, 0], pose_box[:, 1])
        apart = self._apart(trimmed, fr[:, :, 2])
        out = []
        for j, q in enumerate(trimmed):
            if q is None or apart[j]:
                self.stats.culled += 1
                continue
            out.append((engine.transform(solid, fr[j]) if inside[j] else engine.hull(q),
                        np.stack([q.min(axis=0), q.max(axis=0)])))
        return out

    def _make_runs(self, ts: ToolSolid, k: int, groups: list) -> list[tuple[engine.Solid, np.ndarray]]:
        """Translation hulls of piece k, one per group of runs (each run the frames (3, 4) of
        its two extreme poses; a group of more than one run stacks, so that the hull of all is
        their union, :func:`vmach.stock.sweep.stacked_runs`), trimmed: each run's hull shape is
        written down (:func:`vmach.stock.clip.sweep_shape`) and clipped, without building the
        untrimmed hull, and the group's cutter is the hull of its runs' clipped points (the
        union trimmed is the union of the runs trimmed, whose hull it is)."""
        if not groups:
            return []
        sweeps = [[sweep_shape(self._tool_shapes(ts)[k], fa, fb) for fa, fb in g] for g in groups]
        box = None
        if self.trim:
            box = self._boxes(np.array([min(w.vertices[:, 2].min() for w in g) for g in sweeps]),
                              np.array([max(w.vertices[:, 2].max() for w in g) for g in sweeps]))
        out = []
        for r, g in enumerate(sweeps):
            points = []
            for w in g:
                both = w.vertices
                lo, hi = both.min(axis=0), both.max(axis=0)
                if self.trim and not (np.all(lo >= box[r, 0]) and np.all(hi <= box[r, 1])):
                    q = None
                    lo_b, hi_b = box[r]
                    if not (np.any(hi < lo_b) or np.any(lo > hi_b) or np.any(lo_b > hi_b)):
                        q = clip(w, _IDENTITY, lo_b, hi_b)[0][0]
                    if q is None:
                        continue
                    both = q
                points.append(both)
            both = np.concatenate(points) if points else None
            if both is None or self._apart([both], groups[r][0][0][None, :, 2])[0]:
                self.stats.culled += 1
                continue
            out.append((engine.hull(both), np.stack([both.min(axis=0), both.max(axis=0)])))
        return out

    def _apart(self, points: list, axes: np.ndarray) -> np.ndarray:
        """(m,) bool: cutters (their points (p, 3) each, or None) that lie wholly beyond the
        stock along their tool's axis (m, 3) — every point further out along it than the
        stock reaches within the cutter's Z range, by the trim slabs (the stock as last taken:
        it only shrinks; :meth:`vmach.stock.slabs.Slabs.support`): a tool moved away from the
        part (a rapid up beside it after a retract) whose box still meets the stock's box."""
        out = np.zeros(len(points), bool)
        if self._slabs is None or not self.SLABS:
            return out
        idx = [j for j, q in enumerate(points) if q is not None and len(q)]
        if not idx:
            return out
        a = np.asarray(axes, dtype=float)[idx]
        a = a / np.linalg.norm(a, axis=1, keepdims=True)
        near = np.array([float((points[j] @ a[i]).min()) for i, j in enumerate(idx)])
        zlo = np.array([points[j][:, 2].min() for j in idx])
        zhi = np.array([points[j][:, 2].max() for j in idx])
        out[idx] = near > self._slabs.support(zlo, zhi, a) + 1e-9
        return out


def _fin_bucket(half: np.ndarray, radius: float) -> np.ndarray:
    """Fin half-widths (mm) rounded up to steps of 2^(1/4) from FIN_LEAST, so that poses share
    their fin pieces; inf (the whole pose) from 0.7 of the tool's radius up, where a fin
    saves little."""
    with np.errstate(divide="ignore", invalid="ignore"):
        step = np.ceil(4.0 * np.log2(np.maximum(half, FIN_LEAST) / FIN_LEAST) - 1e-9)
    out = FIN_LEAST * 2.0 ** (step / 4.0)
    return np.where(np.isfinite(half) & (out < 0.7 * radius), out, np.inf)
