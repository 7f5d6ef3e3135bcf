"""What the checks and the planners may ask of the blank: its convex hull, and whether points lie
in it or a convex solid meets it (the blank never changes, so the answers are kept)."""

from __future__ import annotations

import numpy as np

from vmach.stock import engine
from vmach.stock.clip import shape
from vmach.stock.events import overlap_volume
from vmach.stock.hull import BlankHull, blank_hull, box_corners, hull_of


class Blank:
    """The blank, a solid, and its convex hull (:mod:`vmach.stock.hull`: reduced to a few
    thousand planes for a finely meshed blank), made when first asked for.

    CELL : triangles of a finely meshed blank per grid cell (:meth:`meets`).
    CONVEX_TOL : relative volume difference up to which a blank counts as convex: a convex
        blank read from an STL carries float32 coordinates. Convexity only lets the verify checks
        settle a question at once (a part with a vertex inside the blank meets it;
        :meth:`holds`); every finding is measured on the stock itself.
    """

    CELL = 20_000
    CONVEX_TOL = 1e-6

    def __init__(self, solid: engine.Solid):
        self.solid = solid
        self.bounds = engine.bounds(solid)
        self._hull: BlankHull | None = None
        self._convex = False
        self.cells: dict | None = None   # (i, j, k) -> (the blank in that grid cell, its bounds)
        self._edges: list = []

    @property
    def hull(self) -> BlankHull:
        """The blank's hull; whether the blank is convex is settled with it (its volume is its
        hull's, to CONVEX_TOL; a blank too small for a hull of four planes is not convex)."""
        if self._hull is None:
            _, _, hull, hv, hf = hull_of(self.solid)
            self._hull = blank_hull(hv, hf)
            vol = engine.volume(hull)
            self._convex = (min(len(self._hull.outer), len(self._hull.inner)) >= 4
                            and abs(vol - engine.volume(self.solid)) <= self.CONVEX_TOL * max(vol, 1.0))
        return self._hull

    def planes(self) -> np.ndarray | None:
        """(f, 4) float: planes (unit outward normal, offset; mm) of a convex region that holds a
        convex blank, or None when the blank is not convex."""
        hull = self.hull
        return hull.outer if self._convex else None

    def holds(self, points: np.ndarray) -> np.ndarray:
        """(k,) bool: points (k, 3) that lie inside the blank, 1e-6 mm or more from its
        boundary — answered for a convex blank; all False for another, whose callers must meet
        solids instead (near the boundary of a finely meshed blank a point may be answered
        False, never wrongly True)."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        if self.planes() is None:
            return np.zeros(len(points), bool)
        planes = self.hull.inner
        k = max(1, (1 << 22) // len(planes))      # points per block: arrays of at most 4M
        return np.concatenate([np.all(points[i : i + k] @ planes[:, :3].T - planes[:, 3] < -1e-6, axis=1)
                               for i in range(0, len(points), k)] or [np.zeros(0, bool)])

    def meets(self, solid: engine.Solid, cell: int | None = None) -> bool:
        """Does the convex ``solid`` overlap the blank (by more than round-off)? A finely meshed
        blank is met piece by piece: its parts in the cells of a grid (each about ``cell``
        triangles, made the first time a solid's box reaches the cell), skipping a piece whose
        box lies beyond one of the solid's face planes."""
        cell = self.CELL if cell is None else cell
        if engine.num_triangles(self.solid) <= 2 * cell:
            return overlap_volume(self.solid, [solid], centre=False)[0] > 0.0
        if self.cells is None:
            k = int(np.ceil((engine.num_triangles(self.solid) / cell) ** (1 / 3)))
            b = np.asarray(self.bounds)
            self._edges = [np.linspace(b[0, i] - 1e-3, b[1, i] + 1e-3, k + 1) for i in range(3)]
            self.cells = {}
        lo, hi = engine.bounds(solid)
        e = self._edges
        # cells j with e[j] <= hi and lo < e[j + 1], per axis
        span = [range(*np.clip(np.searchsorted(e[a], [lo[a], hi[a]], side="right") + [-1, 0],
                               0, len(e[a]) - 1)) for a in range(3)]
        planes = shape(*engine.to_mesh(solid, double=True)).planes
        for c in ((i, j, k) for i in span[0] for j in span[1] for k in span[2]):
            if c not in self.cells:
                box = engine.box([e[a][i] for a, i in enumerate(c)], [e[a][i + 1] for a, i in enumerate(c)])
                piece = engine.intersect(self.solid, box)
                self.cells[c] = (piece, None if engine.is_empty(piece) else engine.bounds(piece))
            piece, pb = self.cells[c]
            if pb is None:
                continue
            corners = box_corners(*pb)
            if np.any((corners @ planes[:, :3].T - planes[:, 3]).min(axis=0) > 0.0):
                continue            # the piece's box lies beyond a face plane of the solid
            if overlap_volume(piece, [solid], centre=False)[0] > 0.0:
                return True
        return False
