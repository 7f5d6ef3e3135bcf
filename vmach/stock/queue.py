"""The boolean queue: cutters in, the cut solid out.

The stock is held as one piece or as the pieces of a partition into cells; each piece queues
the cutters whose boxes meet it and subtracts them in checked batches, in this process or in a
worker process (:mod:`vmach.stock.batch`, :mod:`vmach.stock.remote`). Subtraction commutes, so
the order of pieces and batches does not change the result. Nothing here knows how cutters are
made.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from vmach.stock import engine
from vmach.stock.batch import Piece
from vmach.stock.stats import CutStats


class Queue:
    """The stock's pieces and their queued cutters.

    solid : engine.Solid — the blank. cells : (3,) int — nx × ny × nz cells (1, 1, 1: none).
    batch : cutters per batch boolean; spread : batches taken from one window; group :
    consecutive cutters kept together in a batch; worker_after : cutters queued before a worker
    process takes the batches (None: never; one cell only). stats : where the booleans' seconds
    and batches are counted. progress : show a progress bar on stderr when it is a terminal.
    """

    def __init__(self, solid: engine.Solid, cells, *, batch: int, spread: int, group: int,
                 worker_after: int | None, stats: CutStats, progress: bool = False):
        self.batch = batch
        self._args = (batch, spread, group, worker_after)
        self.stats = stats
        self.pieces = self._partition(solid, cells)
        self._solid: engine.Solid | None = solid
        self._union_seconds = 0.0   # the cells' union into one solid
        self._bar = None
        self._progress = progress and sys.stderr.isatty()

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
        batch, spread, group, after = self._args
        piece = Piece(solid, batch, spread, group, remote_after=after)
        piece.on_progress = self._update_bar
        return piece

    # ----------------------------------------------------------------------------------------
    @property
    def batches(self) -> int:
        """Batches subtracted (or handed to the worker) so far, all pieces."""
        return sum(c.batches for c in self.pieces)

    @property
    def made(self) -> float:
        """Batches' worth of cutters queued so far (subtracted or pending)."""
        return self.batches + sum(len(c.pending) for c in self.pieces) / self.batch

    def boxes(self) -> np.ndarray:
        """(c, 2, 3) the pieces' boxes now (EMPTY_BOX[None] with none)."""
        return np.array([c.box for c in self.pieces]) if self.pieces else engine.EMPTY_BOX[None]

    def snapshots(self) -> list:
        """The pieces as they are now, asked for (``.get()`` each: vertices, faces, box)."""
        return [c.snapshot() for c in self.pieces]

    def add(self, cutters: list[engine.Solid], boxes: list[np.ndarray], seen: np.ndarray) -> None:
        """Queue cutters (boxes (c, 2, 3)) on each piece whose box in ``seen`` (p, 2, 3) they
        meet; a cutter that meets none is culled."""
        if not cutters:
            return
        self._solid = None
        bx = np.asarray(boxes)                                            # (c, 2, 3)
        used = np.zeros(len(cutters), bool)
        queued = 0
        for cell, box in zip(self.pieces, seen, strict=False):
            hit = np.all(bx[:, 0] <= box[1], axis=1) & np.all(bx[:, 1] >= box[0], axis=1)
            used |= hit
            queued += int(hit.sum())
            cell.add([cutters[i] for i in np.nonzero(hit)[0]])
        self.stats.cutters += len(cutters)
        self.stats.culled += int((~used).sum())
        self.account()
        if self._progress:
            self._open_bar(queued)

    def account(self) -> None:
        """The booleans' seconds and batches into ``stats``."""
        self.stats.boolean_seconds = sum(c.seconds for c in self.pieces) + self._union_seconds
        self.stats.wait_seconds = sum(c.wait_seconds for c in self.pieces)
        self.stats.batches = self.batches
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
        done = sum(c.done for c in self.pieces)
        self._bar.n = min(done, self._bar.total)
        self._bar.refresh()

    def _close_bar(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def send(self) -> None:
        """Hand every pending cutter to the booleans (a worker may still be subtracting)."""
        for cell in self.pieces:
            cell.flush()

    def flush(self) -> None:
        """Subtract every queued cutter (with a worker process: hand them to it)."""
        self.send()
        self.account()
        if not any(c.remote is not None for c in self.pieces):
            self._close_bar()

    def close(self) -> None:
        """Stop the worker process, if one took the batches, once it has subtracted them all."""
        for c in self.pieces:
            c.close()
        self.account()
        self._close_bar()

    # ----------------------------------------------------------------------------------------
    @property
    def solid(self) -> engine.Solid:
        """The cut part (all pending cutters subtracted)."""
        if self._solid is None:
            self.flush()
            cells = [c.solid for c in self.pieces]          # (waits for a worker)
            self.account()
            self._close_bar()
            t0 = time.perf_counter()
            self._solid = engine.union(cells)
            engine.check(self._solid, "stock")
            self._union_seconds += time.perf_counter() - t0
            self.account()
        return self._solid

    def local(self, lo: np.ndarray, hi: np.ndarray) -> engine.Solid:
        """The stock now inside the box [lo, hi] (pending cutters subtracted)."""
        if self._solid is not None:
            return engine.intersect(self._solid, engine.box(lo, hi))
        self.send()
        self.account()
        return engine.union([c.local(lo, hi) for c in self.pieces])

    @property
    def volume(self) -> float:
        if self._solid is None and not any(c.pending for c in self.pieces):
            return sum(c.volume for c in self.pieces)
        return engine.volume(self.solid)
