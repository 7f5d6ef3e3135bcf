"""A piece of stock held by a worker process, which subtracts batches of cutters while the
caller goes on making the next ones.

manifold3d holds the GIL while it evaluates a boolean (a Python loop runs several times slower
beside a boolean on another thread, hardly slower beside one in another process), so
the sweep (Python and numpy, one core) and the booleans (manifold3d, both cores) overlap only
in two processes. The worker is a fresh interpreter (``python -m vmach.stock.remote FD``, which
imports manifold3d and numpy only): manifold3d's thread pool does not survive ``fork``.

Protocol, over a socket pair (``multiprocessing.connection``, numpy arrays pickled):
``("solid", vertices, faces, volume)`` once, then ``("run", [(vertices, faces), ...])`` — a run
of cutters, united at once and kept under its number (0, 1, … in the order sent) —,
``("batch", [run numbers], cutters)`` — the union of those runs' unions, subtracted and
checked as :func:`vmach.stock.engine.subtract_checked` does, in the order sent, each answered
by ``("done", cutters subtracted so far)`` for a progress bar — and
``("snap", n)``, answered with the piece after every batch sent before it, its box,
volume, the worker's boolean seconds and the first error (kind, message) if a batch failed
(later runs and batches are then skipped); ``("local", n, lo, hi)`` the same for the piece's part
inside the box [lo, hi] (what a checked run measures against, chunk by chunk: a few
thousand triangles instead of the whole stock). All arrays in double precision (:func:`engine.to_arrays`),
so the worker's batches are the caller's exactly.

While any worker runs, the caller's BLAS (numpy's OpenBLAS) is held to one thread: its idle
threads spin for a while after every matrix product, on the core the worker's booleans need
(measured: docs/stock-history.md).
"""

from __future__ import annotations

import queue
import signal
import socket
import subprocess
import sys
import threading
import time
import weakref
from multiprocessing.connection import Connection

import numpy as np
from threadpoolctl import threadpool_limits

from vmach.stock import engine


class _OneBlasThread:
    """This process's BLAS held to one thread while any worker runs (counted: workers may
    overlap; the limits found when the first started come back when the last ends)."""

    def __init__(self):
        self.holders = 0
        self._limits = None

    def hold(self) -> None:
        if self.holders == 0:
            self._limits = threadpool_limits(limits=1, user_api="blas")
        self.holders += 1

    def release(self) -> None:
        self.holders -= 1
        if self.holders == 0:
            self._limits.restore_original_limits()
            self._limits = None


BLAS = _OneBlasThread()


class Remote:
    """The client: a worker process holding ``solid`` (volume ``volume`` mm³)."""

    def __init__(self, solid: engine.Solid, volume: float):
        ours, theirs = socket.socketpair()
        self._proc = subprocess.Popen(
            [sys.executable, "-m", "vmach.stock.remote", str(theirs.fileno())],
            pass_fds=(theirs.fileno(),), stdin=subprocess.DEVNULL)
        theirs.close()
        self._conn = Connection(ours.detach())
        self._out: queue.SimpleQueue = queue.SimpleQueue()
        self._broken: list[BaseException] = []   # the sender's error, if the worker went away
        # a thread sends, so that the caller never blocks on a full socket while the worker
        # is inside a boolean (sending releases the GIL); it holds no reference to self, so
        # that a Remote dropped without close() is collected and its worker stopped
        self._sender = threading.Thread(target=_send_loop, args=(self._conn, self._out, self._broken),
                                        daemon=True)
        self._sender.start()
        self._asked = 0                 # answers asked for (snapshots and boxes' pieces)
        self._runs = 0                  # runs sent
        self._answers: dict[int, tuple] = {}
        self.seconds = 0.0              # the worker's boolean time as of its last answer
        self.wait_seconds = 0.0         # time spent waiting for answers
        self.subtracted = 0             # cutters the worker has subtracted, as last heard
        self.on_progress = None         # called as the worker reports while waited for
        BLAS.hold()
        self._finalizer = weakref.finalize(self, _stop, self._proc, self._out, self._sender)
        self._out.put(("solid", *engine.to_arrays(solid), float(volume)))

    def run(self, cutters: list[engine.Solid]) -> int:
        """Send a run of cutters for the worker to unite now (evaluated here: the arrays are
        the cutters' exact meshes); its number (for :meth:`batch`)."""
        self._out.put(("run", [engine.to_arrays(c) for c in cutters]))
        self._runs += 1
        return self._runs - 1

    def batch(self, runs: list[int], count: int) -> None:
        """Subtract the union of the runs numbered ``runs`` (``count`` cutters in all)."""
        self._out.put(("batch", list(runs), int(count)))

    def snapshot(self) -> _Answer:
        """Ask for the piece after every batch sent so far."""
        self._asked += 1
        self._out.put(("snap", self._asked))
        return _Answer(self, self._asked)

    def local(self, lo, hi) -> _Answer:
        """Ask for the piece after every batch sent so far inside the box [lo, hi] (mm): its
        answer is that part's (vertices, faces, box, volume)."""
        self._asked += 1
        self._out.put(("local", self._asked, np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)))
        return _Answer(self, self._asked)

    def poll(self) -> int:
        """Read what the worker has said so far, without waiting; the cutters it subtracted."""
        while self._conn.poll(0):
            self._read()
        return self.subtracted

    def _read(self, notify: bool = False) -> None:
        try:
            msg = self._conn.recv()
        except (EOFError, OSError):
            code = self._proc.poll()
            raise engine.StockError(f"the stock's worker process stopped (exit code {code})",
                                    kind="stock_worker") from (self._broken[0] if self._broken else None)
        if msg[0] == "done":
            self.subtracted = msg[1]
            if notify and self.on_progress is not None:
                self.on_progress()
        else:
            self._answers[msg[1]] = msg[2:]

    def _answer(self, n: int) -> tuple:
        t0 = time.perf_counter()
        while n not in self._answers:
            self._read(notify=True)
        self.wait_seconds += time.perf_counter() - t0
        v, f, box, volume, seconds, error = self._answers.pop(n)
        self.seconds = seconds
        if error is not None:
            raise engine.StockError(error[1], kind=error[0])
        return v, f, box, volume

    def close(self) -> None:
        self._finalizer()


class _Answer:
    def __init__(self, remote: Remote, n: int):
        self._remote, self._n, self._value = remote, n, None

    def get(self) -> tuple:
        """(vertices (n, 3), faces (m, 3), box (2, 3), volume mm³); waits for the worker."""
        if self._value is None:
            self._value = self._remote._answer(self._n)
        return self._value


def _send_loop(conn: Connection, out: queue.SimpleQueue, broken: list) -> None:
    while True:
        msg = out.get()
        if msg is None:
            return
        try:
            conn.send(msg)
        except OSError as exc:      # the worker is gone: reported at the next answer
            broken.append(exc)
            return


def _stop(proc: subprocess.Popen, out: queue.SimpleQueue, sender: threading.Thread) -> None:
    BLAS.release()
    out.put(None)
    sender.join(timeout=5)
    proc.terminate()
    try:
        proc.wait(timeout=5)
    except subprocess.TimeoutExpired:  # pragma: no cover - a worker deaf to SIGTERM
        proc.kill()


def serve(conn: Connection) -> None:
    """The worker's loop (see the module docstring); returns when the caller goes away."""
    solid, volume, seconds, error, done = engine.empty(), 0.0, 0.0, None, 0
    runs: dict[int, engine.Solid] = {}      # run number -> its union
    next_run = 0
    while True:
        try:
            msg = conn.recv()
        except (EOFError, OSError):
            return
        if msg[0] == "solid":
            solid, volume = engine.from_arrays(msg[1], msg[2]), msg[3]
        elif msg[0] == "run":
            if error is None:
                t0 = time.perf_counter()
                try:
                    cutters = [engine.from_arrays(v, f) for v, f in msg[1]]
                    for c in cutters:
                        engine.check(c, "a cutter")
                    union = engine.union(cutters)
                    engine.check(union, "a run of cutters")     # evaluated now, while it waits
                    runs[next_run] = union
                except engine.StockError as exc:
                    error = (exc.kind, str(exc))
                except Exception as exc:    # noqa: BLE001 - reported to the caller, not printed
                    error = ("stock_worker", f"the stock's worker process failed: {exc!r}")
                seconds += time.perf_counter() - t0
            next_run += 1
        elif msg[0] == "batch" and error is None:
            t0 = time.perf_counter()
            try:
                solid, volume = engine.subtract_checked(solid, volume, [runs.pop(r) for r in msg[1]])
                done += msg[2]
            except engine.StockError as exc:
                error = (exc.kind, str(exc))
            except Exception as exc:    # noqa: BLE001 - reported to the caller, not printed
                error = ("stock_worker", f"the stock's worker process failed: {exc!r}")
            seconds += time.perf_counter() - t0
            if not _send(conn, ("done", done)):
                return
        elif msg[0] in ("snap", "local"):
            part, vol = solid, volume
            if msg[0] == "local" and error is None:
                part = engine.intersect(solid, engine.box(msg[2], msg[3]))
                vol = engine.volume(part)
            arrays = engine.to_arrays(part) if error is None else (None, None)
            box = engine.box_of(part) if error is None else None
            if not _send(conn, ("snap", msg[1], *arrays, box, vol, seconds, error)):
                return


def _send(conn: Connection, msg: tuple) -> bool:
    """Send ``msg`` to the caller; False when the caller has gone away (its pipe is closed: a
    Ctrl-C, a batch case stopped), which ends the worker quietly, without a traceback."""
    try:
        conn.send(msg)
    except (OSError, EOFError):         # BrokenPipeError and ConnectionResetError among them
        return False
    return True


if __name__ == "__main__":
    # Ctrl-C reaches the whole process group: the caller handles it, and its going away ends
    # this loop (no traceback from here)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    serve(Connection(int(sys.argv[1])))
