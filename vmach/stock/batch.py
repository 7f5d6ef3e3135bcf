"""One piece of stock and its queue of cutters, subtracted in checked batches.

Used for every partition cell of a :class:`vmach.stock.Stock` (one cell unless ``cells`` asks
for more). Subtraction commutes, so the order in which cutters
are subtracted does not change the result; it changes the cost. A batch boolean's work is
mostly where the batch's cutters cross each other, and consecutive cutters of a path overlap
most, so a window of ``batch × spread`` queued cutters is subtracted as ``spread`` batches
that each take runs of ``group`` consecutive cutters spread over the window.

After every batch the piece is evaluated and checked: a valid manifold whose volume did not
grow (:class:`vmach.stock.engine.StockError` otherwise).

Once ``remote_after`` cutters were queued, the batches go to a worker process
(:mod:`vmach.stock.remote`), which subtracts and checks them in the same order while the
caller goes on making cutters; the piece's ``solid``, ``volume`` and ``box`` then wait for it.
The worker gets each run as soon as its cutters are made and unites it then (the unions do
not depend on the stock, and they are most of a batch's work), so that it need not wait for
a window to fill: at the start of a program the second core is otherwise idle until the
first window is made. A batch is then the worker's union of its runs' unions, subtracted;
in this process, the union of its cutters. The batches, so the part, are the same either
way (its mesh may differ by the order the booleans took; the same for every run).
"""

from __future__ import annotations

import time

import numpy as np

from vmach.stock import engine


class Piece:
    """solid : engine.Solid; batch, spread, group : int (see the module docstring);
    remote_after : int or None — cutters queued after which full windows go to a worker
    process (None: never)."""

    def __init__(self, solid: engine.Solid, batch: int = 64, spread: int = 8, group: int = 16,
                 remote_after: int | None = None):
        engine.check(solid, "stock")
        self._solid = solid
        self._volume = engine.volume(solid)
        self._box = engine.box_of(solid)
        self.batch = max(1, int(batch))
        self.spread = max(1, int(spread))
        self.group = max(1, int(group))
        self.remote_after = remote_after
        self.remote = None       # a vmach.stock.remote.Remote once the worker is started
        self.on_progress = None  # called as the worker reports progress (a progress bar)
        self._synced = True      # solid, volume and box are the worker's after its last batch
        self.pending: list[engine.Solid] = []   # queued, not yet in a batch
        self._runs: list[int] = []      # sizes of the runs the pending cutters begin with
        self._run_ids: list[int] = []   # ... and their numbers at the worker (with one)
        self.queued = 0          # cutters ever queued
        self.batches = 0
        self.sent = 0            # cutters taken into batches
        self._before = 0         # ... of them subtracted here before the worker started
        self._seconds = 0.0      # boolean time in this process
        self._waited = 0.0       # time waited for a worker since closed

    # the piece after every batch so far (waits for the worker, with one) ----------------------
    @property
    def solid(self) -> engine.Solid:
        self._sync()
        return self._solid

    @property
    def volume(self) -> float:
        self._sync()
        return self._volume

    @property
    def box(self) -> np.ndarray:
        self._sync()
        return self._box

    @property
    def seconds(self) -> float:
        """Boolean time, s: this process's, and the worker's as of its last answer."""
        return self._seconds + (self.remote.seconds if self.remote is not None else 0.0)

    @property
    def done(self) -> int:
        """Cutters subtracted (with a worker: as far as it has said)."""
        return self.sent if self.remote is None else self._before + self.remote.poll()

    @property
    def wait_seconds(self) -> float:
        """Time this process waited for the worker, s."""
        return self._waited + (self.remote.wait_seconds if self.remote is not None else 0.0)

    def snapshot(self):
        """The piece after every batch so far, as ``get() -> (vertices (n, 3), faces (m, 3),
        box (2, 3), volume)`` (:func:`vmach.stock.engine.to_arrays`; mm, mm³); with a worker,
        asked for now and waited for only when got."""
        if self.remote is not None:
            return self.remote.snapshot()
        return _Ready((*engine.to_arrays(self._solid), self._box.copy(), self._volume))

    def _sync(self) -> None:
        if self._synced:
            return
        v, f, box, volume = self.remote.snapshot().get()
        self._solid, self._volume, self._box = engine.from_arrays(v, f), volume, box
        self._synced = True

    def close(self) -> None:
        """Stop the worker, if any, once it has answered for every batch (the piece stays as
        it was after its last batch; later batches are subtracted here)."""
        if self.remote is not None:
            self._sync()
            self._seconds += self.remote.seconds
            self._waited += self.remote.wait_seconds
            self.remote.close()
            self.remote, self.remote_after = None, None
            self._before = self.sent

    # the queue ---------------------------------------------------------------------------------
    def add(self, cutters: list[engine.Solid]) -> None:
        """Queue cutters; full runs go to the worker (if any) and full windows are subtracted
        at once."""
        self.pending += cutters
        self.queued += len(cutters)
        self._runs_and_windows(final=False)

    def flush(self) -> None:
        self._runs_and_windows(final=True)

    def _runs_and_windows(self, final: bool) -> None:
        """Cut the pending cutters into runs of ``group`` (the last of a window or, with
        ``final``, of the queue shorter) and subtract every full window (with ``final``, the
        last one too)."""
        window = self.batch * self.spread
        g = min(self.group, self.batch)
        while True:
            made = sum(self._runs)
            room = min(g, window - made)
            left = len(self.pending) - made
            if room == 0 or (final and left == 0 and made):
                self._start()
                self._window(made)
            elif left >= room or (final and left):
                self._runs.append(min(room, left))
                self._start()
            else:
                return

    def _start(self) -> None:
        """Hand the runs and batches to a worker process from now on, once ``remote_after``
        cutters were queued (asked at every run and window, a flush's too: a path cut chunk
        by chunk, whose chunks are flushed to be measured, may never fill a window); with a
        worker, send it every run made that it has not got yet."""
        if self.remote is None and self.remote_after is not None and self.queued >= self.remote_after:
            from vmach.stock.remote import Remote

            try:
                self.remote = Remote(self._solid, self._volume)
            except (OSError, ValueError):   # no worker process here: the batches stay
                self.remote_after = None
            else:
                self.remote.on_progress = self.on_progress
                self._before = self.sent
        if self.remote is not None:                 # (a worker started mid-window: all of them)
            at = sum(self._runs[: len(self._run_ids)])
            for k in self._runs[len(self._run_ids) :]:
                self._run_ids.append(self.remote.run(self.pending[at : at + k]))
                at += k

    def local(self, lo: np.ndarray, hi: np.ndarray) -> engine.Solid:
        """The piece after every batch so far inside the box [lo, hi] (mm) — with a worker,
        made there, so that only that part of it travels."""
        if self.remote is not None:
            return engine.from_arrays(*self.remote.local(lo, hi).get()[:2])
        if np.any(self._box[0] > hi) or np.any(self._box[1] < lo):
            return engine.empty()
        return engine.intersect(self._solid, engine.box(lo, hi))

    def _window(self, made: int) -> None:
        """Subtract the window of the runs made (``made`` cutters): ``nb`` batches, batch b
        taking runs b, b + nb, … (spread over the window)."""
        take, self.pending = self.pending[:made], self.pending[made:]
        sizes, ids = self._runs, self._run_ids
        self._runs, self._run_ids = [], []
        starts = np.cumsum([0, *sizes])
        nb = -(-made // self.batch)
        for b in range(nb):
            runs = range(b, len(sizes), nb)
            count = int(sum(sizes[r] for r in runs))
            if self.remote is not None:
                self.remote.batch([ids[r] for r in runs], count)
                self._synced = False
            else:
                t0 = time.perf_counter()
                cutters = [c for r in runs for c in take[starts[r] : starts[r + 1]]]
                self._solid, self._volume = engine.subtract_checked(self._solid, self._volume, cutters)
                self._box = engine.box_of(self._solid)
                self._seconds += time.perf_counter() - t0
            self.batches += 1
            self.sent += count


class _Ready:
    """A snapshot taken at once (no worker)."""

    def __init__(self, value: tuple):
        self._value = value

    def get(self) -> tuple:
        return self._value
