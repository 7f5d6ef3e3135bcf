"""Column cutters: one solid for the same angular sector of several turns of a helix.

A finishing helix (the polygon program's D25: C +1.713° and Z −0.01 mm per point, 2.1 mm a
turn) passes every place of the flank a dozen times, once per turn while its 25 mm face
slides down. Cut turn by turn — fan cutters (:mod:`vmach.stock.fan`) over about 20° each —
every fan overlaps the fans of the dozen turns around it, and manifold3d pays for every one
of those overlaps in every batch. A *column* takes the same sector of ``turns`` consecutive
turns at once:

    K = (H ∩ W) \\ M,   H = hull(the turns' poses in the sector),   W = the sector's wedge,
                        M = ∩ {x : x·n_k <= h_k + ε} over all their face planes

— one convex hull, clipped to the wedge between two planes through the rotation axis, minus
the material below every face plane of every turn in it.

**Cells.** A turn's *cell* in sector k — the angles [kΔ, (k+1)Δ] of the tool axis about ω,
unwrapped along the path, Δ = ``sector`` — is its stretch of poses from the last one before
the sector to the first one after it, every step a fan step (:func:`vmach.stock.fan.plan_fans`:
the axis turns about ω and stays perpendicular to it, the face chain is convex, the face's rim
leaves no foot the hull would take, the tool's back lies beyond the blank). The same sector
of consecutive turns makes a column (``turns`` at most).

**Why it is right** — what K removes beyond the cells' own fans (each as :mod:`vmach.stock.fan`
makes and bounds it), and why that is no more than the true motion removes or within the
fans' bound:

- *Inside the wedge every turn sweeps everything.* The wedge's planes contain ω and pass
  through the face chain's crease at the sector's bounding angles (averaged over every turn
  that passes there, so that every column uses the same plane at a boundary), moved
  ``overlap`` outward so that neighbouring columns overlap instead of sharing a plane. Each
  cell is made long enough (:func:`_extend`) that its end poses' tool axis lines lie beyond
  the planes, so its tool's centre line passes over every point of the wedge — at any height
  the tool reaches (within its inscribed radius of the tip along ω) the turn sweeps the wedge
  beyond its own face chain — and that the chain's creases at its ends lie beyond them too,
  so that within the wedge its own faces make the whole chain. Consecutive cells lie less
  than two inscribed radii apart along ω (``_stacked``), so every height between the highest
  and the lowest cell is reached, and H ∩ W holds nothing there that a turn does not sweep —
  except below a face chain (below).
- *The face chain.* K cuts to the chain of every face plane of the column; at a height only
  some turns reach, the true motion cuts to theirs. Where the turns follow one profile the
  two agree to the sampling (a finer tangent polygon than one turn's); where they do not (a
  second pass 1 mm deeper, say) K would cut the deeper chain at every height. So the depth by
  which the column's chain lies below each turn's own (its cell's face lines with their
  neighbours, inside the wedge) is measured (:func:`chain_depth`, exact in the plane
  perpendicular to ω: the largest excess of the column's planes over the turn's polygon's
  corners) and must be within ``overcut``.
- *Above the highest and below the lowest turn* H may bridge the ruled surfaces the tool's
  side sweeps at its ±ω extremes, as a fan does: measured on the made solid
  (:mod:`vmach.stock.make_fans`, as for fans, with the bridges other poses of the path cut
  anyway not counted).
- *Outside the wedge* K removes nothing; the tools' parts there are swept by the same turns'
  neighbouring poses (the cell's stretch of fan steps goes on for a tool radius and more
  along the path on both sides, ``spill``), which their own cutters remove.

Lengths mm, angles degrees unless named otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vmach.stock.fan import NO_FANS, PARALLEL, FanPlan
from vmach.stock.fan_measure import basis
from vmach.stock.halfplanes import face_lines, polygon
from vmach.tol import tol

#: a cell's stretch of fan steps must go on this far (mm of tip travel) beyond the tool's
#: radius on both sides: the neighbouring poses that sweep the tool's parts outside the wedge
SPILL_MARGIN = 1.0
#: the plane through which the wedge is taken lies this far inside a 2D region the face lines
#: bound; a polygon of half-planes is taken within a box this much larger than its points
BOX_MARGIN = 5.0


@dataclass(frozen=True)
class Column:
    """One column cutter's plan.

    cells : (k, 2) int — [first, last] pose of each turn's cell, in path order (consecutive
        turns). omega : (3,) float — the rotation axis (unit). wedge : (w, 4) float — the
        wedge as half-spaces ``n·x <= c`` (w = 2). depth : float, mm — how far the column's
        face chain lies below any of its turns' own, inside the wedge (:func:`chain_depth`).
    """

    cells: np.ndarray
    omega: np.ndarray
    wedge: np.ndarray
    depth: float

    @property
    def poses(self) -> np.ndarray:
        """(p,) int — every pose of the column's cells."""
        return np.concatenate([np.arange(a, b + 1) for a, b in self.cells])


@dataclass(frozen=True)
class ColumnPlan:
    """columns : the columns; fans : the candidate fan runs left (FanPlan) — every fan step
    not in a column's cell, as runs of at least two steps within the original runs."""

    columns: list[Column] = field(default_factory=list)
    fans: FanPlan = NO_FANS


def plan_columns(tips: np.ndarray, axes: np.ndarray, fans: FanPlan, *, radius: float, inner: float,
                 sector: float = tol.column_sector, turns: int = tol.column_turns,
                 overcut: float = tol.fan_overcut, overlap: float = 0.02) -> ColumnPlan:
    """Columns over the candidate fan runs of a path (tips, unit axes (n, 3)), and the fan runs
    left. ``radius`` / ``inner``: the tool polygon's vertex and inscribed radius (mm);
    ``sector``: the wedge's angle Δ (degrees, 360/Δ a whole number); ``turns``: the most turns
    in a column; ``overcut``: the most the column's face chain may lie below a turn's own
    (mm); ``overlap``: how far (mm) each wedge reaches past its planes into its neighbours'."""
    tips = np.asarray(tips, dtype=float)
    axes = np.asarray(axes, dtype=float)
    n = len(tips)
    per_turn = int(round(360.0 / sector))
    if len(fans.runs) < 2 or n < 4 or turns < 2 or abs(per_turn * sector - 360.0) > 1e-9:
        return ColumnPlan([], fans)
    columns: list[Column] = []
    used = np.zeros(n - 1, bool)
    rounded = np.round(fans.omega, 6)
    for om in np.unique(rounded, axis=0):
        sel = np.all(rounded == om, axis=1)
        omega = fans.omega[np.nonzero(sel)[0][0]]
        valid = np.zeros(n - 1, bool)
        for a, b in fans.runs[sel]:
            valid[a:b] = True
        for col in _columns(tips, axes, omega, valid, radius, inner, sector, per_turn, turns, overcut,
                            overlap):
            columns.append(col)
            for a, b in col.cells:
                used[a:b] = True
    if not columns:
        return ColumnPlan([], fans)
    return ColumnPlan(columns, _left(fans, used))


def _columns(tips, axes, omega, valid, radius, inner, sector, per_turn, turns, overcut, overlap):
    """The columns of one rotation axis ``omega`` over the fan steps ``valid`` (n-1,) bool."""
    e1, e2 = basis(omega)
    theta = np.degrees(np.unwrap(np.arctan2(axes @ e2, axes @ e1)))
    step = np.diff(theta)
    if not valid.any():
        return []
    sense = 1.0 if np.median(step[valid]) >= 0 else -1.0
    th = sense * theta
    ok = valid & (sense * step > 1e-9)
    h = tips @ omega
    travel = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(tips, axis=0), axis=1))]
    spill = radius + SPILL_MARGIN
    u, v = basis(omega)
    lines = face_lines(tips, axes, u, v)
    # stretches of consecutive steps that turn forward about omega: poses s0 .. s1
    edges = np.diff(np.r_[0, ok.astype(np.int8), 0])
    stretches = list(zip(np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0], strict=True))
    wedge = _boundaries(th, tips, axes, omega, sense, lines, u, v, stretches, sector, per_turn, overlap)
    cells: dict[int, tuple[int, int]] = {}
    for s0, s1 in stretches:
        seg = th[s0 : s1 + 1]
        for k in range(int(np.ceil(seg[0] / sector)), int(np.floor(seg[-1] / sector))):
            j = k % per_turn
            if j not in wedge or (j + 1) % per_turn not in wedge:
                continue
            a = s0 + int(np.searchsorted(seg, k * sector, side="right")) - 1   # last pose at or before
            b = s0 + int(np.searchsorted(seg, (k + 1) * sector, side="left"))  # first pose at or after
            cell = _extend(a, b, s0, s1, tips, axes, lines, u, v,
                           np.array([wedge[j][0], wedge[(j + 1) % per_turn][1]]))
            if cell is None:
                continue
            a, b = cell
            if travel[a] - travel[s0] < spill or travel[s1] - travel[b] < spill:
                continue        # the poses beside the cell must sweep the tool's parts outside
            cells[k] = (a, b)
    return _stack(tips, axes, omega, h, th, cells, wedge, per_turn, turns, inner, overcut)


def _stack(tips, axes, omega, h, th, cells: dict, wedge: dict, per_turn: int, turns: int, inner: float,
           overcut: float) -> list[Column]:
    """The columns of the cells (turn-sector k -> poses (a, b)): the same sector of up to
    ``turns`` consecutive turns, each stack without its first or last turn of the whole path."""
    out = []
    groups: dict[tuple[int, int], list[int]] = {}
    for k in sorted(cells):
        turn = k // per_turn
        groups.setdefault((k % per_turn, turn // turns), []).append(k)
    for (j, _), ks in groups.items():
        # consecutive turns only
        runs_of: list[list[int]] = [[ks[0]]]
        for k in ks[1:]:
            if k - runs_of[-1][-1] == per_turn:
                runs_of[-1].append(k)
            else:
                runs_of.append([k])
        for group in runs_of:
            # a first or last turn of the whole path in this sector has no turn beyond it to
            # cut the floor (or ceiling) its side sweeps anyway: its hull would bridge it by
            # more than a fan's, so it is left to fans (the made column is measured in any case)
            if not _turn_beyond(th, cells[group[-1]], 1):
                group = group[:-1]
            if group and not _turn_beyond(th, cells[group[0]], -1):
                group = group[1:]
            if len(group) < 2:
                continue
            cell = np.array([cells[k] for k in group], dtype=int)
            col = _column(tips, axes, omega, h, cell, np.array([wedge[j][0], wedge[(j + 1) % per_turn][1]]),
                          inner, overcut)
            if col is not None:
                out.append(col)
    return out


def _boundaries(th, tips, axes, omega, sense, lines, u, v, stretches, sector, per_turn, overlap):
    """The wedges' planes: {j: (start, end)} — for each sector boundary j (the tool axis at
    angle jΔ, every turn), the plane containing omega through the crease of the two face
    lines around it (where the face chain passes from one pose's face to the next), the
    creases of every turn that passes it averaged, its normal the chain's there; moved by
    ``overlap`` mm outward of the wedge it bounds (start: the wedge after it, end: before), so
    that neighbouring columns overlap instead of sharing a plane. Every column uses the same
    plane at the same boundary, whatever its turns; each cell is then made long enough for
    its own turn (:func:`_extend`). As half-spaces (4,) ``n·x <= c`` of the kept side."""
    points: dict[int, list] = {}
    dirs: dict[int, list] = {}
    for s0, s1 in stretches:
        seg = th[s0 : s1 + 1]
        for k in range(int(np.ceil(seg[0] / sector)), int(np.floor(seg[-1] / sector)) + 1):
            i = s0 + int(np.searchsorted(seg, k * sector, side="right")) - 1
            if i < s0 or i >= s1:
                continue
            c = _crossing(lines[i], lines[i + 1])
            if c is None:
                continue
            points.setdefault(k % per_turn, []).append(c)
            dirs.setdefault(k % per_turn, []).append(axes[i] + axes[i + 1])
    out = {}
    for j, pts in points.items():
        p2 = np.mean(pts, axis=0)
        ax = np.mean(dirs[j], axis=0)
        ax -= (ax @ omega) * omega
        ax /= np.linalg.norm(ax)
        t = sense * np.cross(omega, ax)                 # the direction the turns travel there
        p = p2[0] * u + p2[1] * v
        out[j] = (np.r_[-t, -(t @ p) + overlap], np.r_[t, t @ p + overlap])
    return out


#: how far (mm) a cell's end poses — their tool axis lines and the end of the face chain's
#: stretch that goes on outside — lie beyond its wedge, at least
BEYOND = 0.05
#: the most poses a cell is made longer by, at either end, to lie beyond its wedge
EXTEND = 8


def _extend(a, b, s0, s1, tips, axes, lines, u, v, wedge):
    """The cell [a, b] made longer within the stretch [s0, s1] until both of its end poses
    lie beyond its wedge (half-spaces (2, 4): start, end): the tool's axis line (tip to
    tip + axis) of pose a beyond the start plane and of pose b beyond the end plane, and so
    the creases of the face chain at the cell's ends — the stretches of the faces outside
    the cell lie outside the wedge, so within it the cell's faces make the whole chain. None
    if that takes more than EXTEND poses or the stretch ends."""
    def beyond(plane, i, crease):
        n, c = plane[:3], plane[3]
        if min(tips[i] @ n, (tips[i] + axes[i]) @ n) <= c + BEYOND:
            return False
        x = _crossing(lines[crease[0]], lines[crease[1]])
        return x is not None and (x[0] * u + x[1] * v) @ n > c + BEYOND

    for _ in range(EXTEND + 1):
        if a > s0 and beyond(wedge[0], a, (a - 1, a)):
            break
        a -= 1
        if a <= s0:
            return None
    else:
        return None
    for _ in range(EXTEND + 1):
        if b < s1 and beyond(wedge[1], b, (b, b + 1)):
            break
        b += 1
        if b >= s1:
            return None
    else:
        return None
    return a, b


def _column(tips, axes, omega, h, cells, wedge, inner, overcut) -> Column | None:
    """The column of the cells (k, 2) in the wedge (2, 4), or None when it would not be
    right: cells not stacked within reach of each other along omega, a wedge whose planes do
    not meet inside the material, or a chain deeper than ``overcut`` below a turn's own."""
    heights = np.array([h[a : b + 1].mean() for a, b in cells])
    if not _stacked(heights, inner):
        return None
    u, v = basis(omega)
    idx = np.concatenate([np.arange(a, b + 1) for a, b in cells])
    lines = face_lines(tips[idx], axes[idx], u, v)
    box = _box(tips[idx], u, v)
    wedge2 = np.column_stack([wedge[:, :3] @ u, wedge[:, :3] @ v, wedge[:, 3]])
    apex = _crossing(wedge2[0], wedge2[1])
    if apex is not None and np.any(lines[:, :2] @ apex - lines[:, 2] > 1e-9 * _scale(box)):
        return None                         # the wedge's planes meet outside the material
    depth = 0.0
    for a, b in cells:
        # the turn's own chain: its cell's face lines and two neighbours' on each side
        near = np.arange(max(a - 2, 0), min(b + 2, len(tips) - 1) + 1)
        near = near[np.abs(axes[near] @ omega) <= PARALLEL]
        own = np.vstack([face_lines(tips[near], axes[near], u, v), wedge2])
        depth = max(depth, chain_depth(lines, own, box))
    if depth > overcut:
        return None
    return Column(cells, np.asarray(omega, dtype=float), np.asarray(wedge, dtype=float), depth)


def _turn_beyond(th: np.ndarray, cell: tuple[int, int], way: int) -> bool:
    """Does the path (tool axis angles th (n,), degrees, increasing along the cell) pass the
    cell's angles again a turn later (way 1) or earlier (way -1)?"""
    a, b = cell
    if way > 0:
        return bool(np.any(th[b + 1 :] >= th[b] + 360.0))
    return bool(np.any(th[:a] <= th[a] - 360.0))


def _stacked(heights: np.ndarray, inner: float) -> bool:
    """Do the cells' heights along omega (k,) leave no height between the highest and the
    lowest that no cell's tool reaches (consecutive ones, sorted, less than two inscribed
    radii apart)?"""
    gaps = np.diff(np.sort(heights))
    return bool(np.all(gaps < 2.0 * inner - 2.0 * SPILL_MARGIN))


def _box(points: np.ndarray, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A 2D box (lo, hi) around the points' projections on (u, v), grown by BOX_MARGIN and
    by how far the points lie from the origin (so that the face lines' corners lie inside)."""
    p = np.column_stack([points @ u, points @ v])
    grow = BOX_MARGIN + float(np.abs(p).max())
    return p.min(axis=0) - grow, p.max(axis=0) + grow


def _scale(box) -> float:
    return max(1.0, float(np.abs(np.asarray(box)).max()))


def _crossing(l0: np.ndarray, l1: np.ndarray) -> np.ndarray | None:
    """Where two lines a·x + b·y = c cross, or None (parallel)."""
    det = l0[0] * l1[1] - l0[1] * l1[0]
    if abs(det) <= 1e-12:
        return None
    return np.array([(l0[2] * l1[1] - l1[2] * l0[1]) / det, (l0[0] * l1[2] - l1[0] * l0[2]) / det])


def chain_depth(column_lines: np.ndarray, own_lines: np.ndarray, box) -> float:
    """How far (mm) the chain of ``column_lines`` (m, 3) lies below the polygon of
    ``own_lines`` (k, 3) (which may include a wedge's lines): the largest excess of a column
    line over the polygon's corners (0 when none is beyond)."""
    own = polygon(own_lines, *box)
    if len(own) == 0:
        return 0.0
    return float(np.max(own @ column_lines[:, :2].T - column_lines[:, 2], initial=0.0))


def _left(fans: FanPlan, used: np.ndarray) -> FanPlan:
    """The fan runs left once the steps ``used`` (n-1,) bool are taken: each run's stretches
    of unused steps, a stretch of one step grown to two into a used neighbour (a fan may
    overlap a column: each is right on its own)."""
    runs, omegas = [], []
    for (a, b), om in zip(fans.runs, fans.omega, strict=True):
        k = a
        while k < b:
            if used[k]:
                k += 1
                continue
            e = k
            while e < b and not used[e]:
                e += 1
            s, t = k, e
            if t - s < 2:
                t = min(b, s + 2)
                s = max(a, t - 2)
            if t - s >= 2:
                runs.append((s, t))
                omegas.append(om)
            k = e
    if not runs:
        return NO_FANS
    return FanPlan(np.array(runs, dtype=int), np.array(omegas, dtype=float))
