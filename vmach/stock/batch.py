"""One piece of stock and its queue of cutters, subtracted in checked batches.

Used for every partition cell of a :class:`vmach.stock.Stock` (one cell unless ``cells`` asks
for more). Subtraction commutes, so the order in which cutters
are subtracted does not change the result; it changes the cost. A batch boolean's work is
mostly where the batch's cutters cross each other, and consecutive cutters of a path overlap
most, so a window of ``batch × spread`` queued cutters is subtracted as ``spread`` batches
that each take runs of ``group`` consecutive cutters spread over the window.

After every batch the piece is evaluated and checked: a valid manifold whose volume did not
grow (:class:`vmach.stock.engine.StockError` otherwise).
"""

from __future__ import annotations

import time

import numpy as np

from vmach.stock import engine

EMPTY_BOX = np.array([[np.inf] * 3, [-np.inf] * 3])


class Piece:
    """solid : engine.Solid; batch, spread, group : int (see the module docstring)."""

    def __init__(self, solid: engine.Solid, batch: int = 64, spread: int = 8, group: int = 16):
        engine.check(solid, "stock")
        self.solid = solid
        self.volume = engine.volume(solid)
        self.box = engine.bounds(solid) if not engine.is_empty(solid) else EMPTY_BOX.copy()
        self.batch = max(1, int(batch))
        self.spread = max(1, int(spread))
        self.group = max(1, int(group))
        self.pending: list[engine.Solid] = []
        self.batches = 0
        self.done = 0            # cutters subtracted
        self.seconds = 0.0       # boolean time

    def add(self, cutters: list[engine.Solid]) -> None:
        """Queue cutters; full windows are subtracted at once."""
        self.pending += cutters
        window = self.batch * self.spread
        while len(self.pending) >= window:
            self._window(window)

    def flush(self) -> None:
        while self.pending:
            self._window(self.batch * self.spread)

    def _window(self, window: int) -> None:
        take, self.pending = self.pending[:window], self.pending[window:]
        if self.spread == 1 or len(take) <= self.batch:
            self._subtract(take)
            return
        g = min(self.group, self.batch)
        runs = [take[i : i + g] for i in range(0, len(take), g)]
        nb = -(-len(take) // self.batch)
        for b in range(nb):
            self._subtract([c for run in runs[b::nb] for c in run])

    def _subtract(self, take: list[engine.Solid]) -> None:
        if not take:
            return
        t0 = time.perf_counter()
        new = engine.subtract(self.solid, take)
        engine.check(new, "stock")
        vol = engine.volume(new)
        if vol > self.volume * (1 + 1e-9) + 1e-9:
            raise engine.StockError(f"stock volume grew from {self.volume:.6f} to {vol:.6f} mm³")
        self.solid, self.volume = new, vol
        self.box = engine.bounds(new) if not engine.is_empty(new) else EMPTY_BOX.copy()
        self.batches += 1
        self.done += len(take)
        self.seconds += time.perf_counter() - t0
