"""Batches subtracted in a worker process (vmach/stock/remote.py) while the caller goes on."""

from __future__ import annotations

import gc
import socket
import threading
from multiprocessing.connection import Connection

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from tests.stock.conftest import turnmill
from vmach.stock import Stock, engine
from vmach.stock.batch import Piece
from vmach.stock.remote import BLAS, serve


def _cutters(n: int, seed: int = 0) -> list:
    """n small convex cutters around the rim of a Ø60 cylinder's top, overlapping their
    neighbours (mm)."""
    rng = np.random.default_rng(seed)
    out = []
    for a in np.linspace(0.0, 2.0 * np.pi, n, endpoint=False):
        c = np.array([29.0 * np.cos(a), 29.0 * np.sin(a), -2.0])
        out.append(engine.hull(c + rng.normal(size=(30, 3)) * [2.0, 2.0, 1.5]))
    return out


def test_a_worker_subtracts_the_same_batches_to_the_same_piece():
    """The same cutters through a local piece and one whose runs and batches go to a worker
    process from the first run on: the same batches, the same volume (to rounding: the
    worker's solids are made again from their exact double-precision meshes), both valid."""
    blank = engine.cylinder(30.0, -20.0, 0.0, 256)
    cutters = _cutters(96)
    local = Piece(blank, batch=8, spread=2, group=4)
    remote = Piece(blank, batch=8, spread=2, group=4, remote_after=0)
    try:
        for p in (local, remote):
            for i in range(0, len(cutters), 10):
                p.add(cutters[i : i + 10])
            p.flush()
        assert remote.remote is not None and local.remote is None
        assert remote.batches == local.batches == 12
        assert remote.volume == pytest.approx(local.volume, rel=1e-12)
        assert remote.volume < engine.volume(blank) - 100.0             # material went
        engine.check(remote.solid)
        assert np.allclose(remote.box, local.box, atol=1e-9)
        assert remote.seconds > 0.0
    finally:
        remote.close()
    assert remote.remote is None and remote.volume == pytest.approx(local.volume, rel=1e-12)
    assert remote.wait_seconds > 0.0 and local.wait_seconds == 0.0      # kept once closed


def test_runs_reach_the_worker_before_their_window_fills():
    """Each run of ``group`` cutters goes to the worker as soon as it is made (to be united
    while the window fills); a worker started in the middle of a window is sent the window's
    runs made before it. The same batches and volume as in process."""
    blank = engine.cylinder(30.0, -20.0, 0.0, 128)
    cutters = _cutters(40)
    local = Piece(blank, batch=8, spread=4, group=4)                    # windows of 32
    remote = Piece(blank, batch=8, spread=4, group=4, remote_after=6)
    try:
        remote.add(cutters[:5])                 # one run, made before the worker starts
        assert remote.remote is None and remote.batches == 0
        remote.add(cutters[5:10])               # the worker starts at the second run: both go
        assert remote.remote is not None and remote.remote._runs == 2 and remote.batches == 0
        remote.add(cutters[10:])
        assert remote.batches == 4 and remote.remote._runs == 10       # the window's 4 batches
        remote.flush()
        local.add(cutters)
        local.flush()
        assert remote.batches == local.batches == 5
        assert remote.volume == pytest.approx(local.volume, rel=1e-12)
        assert remote.volume < engine.volume(blank) - 10.0
    finally:
        remote.close()


def test_the_workers_process_ends_with_its_piece():
    blank = engine.cylinder(30.0, -20.0, 0.0, 64)
    piece = Piece(blank, batch=4, spread=1, remote_after=0)
    piece.add(_cutters(4))
    proc = piece.remote._proc
    assert proc.poll() is None
    piece.close()
    assert proc.poll() is not None


def test_a_batch_the_worker_cannot_subtract_is_an_error_at_the_next_answer():
    """The worker's loop over a socket pair (in a thread here): runs are united as they come
    and a batch of them subtracted (the volume the blank less the runs' union); a cutter
    that is not a closed mesh is an error at the next answer (kind and message), and later
    runs and batches are skipped (the cutters done stay at the first batch's)."""
    ours, theirs = socket.socketpair()
    a, b = Connection(ours.detach()), Connection(theirs.detach())
    worker = threading.Thread(target=serve, args=(b,))
    worker.start()
    try:
        blank = engine.cylinder(30.0, -20.0, 0.0, 64)
        cutters = _cutters(6)
        a.send(("solid", *engine.to_arrays(blank), engine.volume(blank)))
        a.send(("run", [engine.to_arrays(c) for c in cutters[:4]]))     # run 0
        a.send(("run", [engine.to_arrays(c) for c in cutters[4:]]))     # run 1
        a.send(("batch", [0, 1], 6))
        a.send(("snap", 1))
        assert a.recv() == ("done", 6)                                  # cutters subtracted
        msg = a.recv()
        assert msg[:2] == ("snap", 1) and msg[-1] is None
        good = msg[5]
        assert good == pytest.approx(engine.volume(engine.subtract(blank, cutters)), rel=1e-12)
        assert good < engine.volume(blank)
        v, f = engine.to_arrays(engine.box([25.0, -5.0, -5.0], [35.0, 5.0, 5.0]))
        a.send(("run", [(v, f[:-1])]))                                  # one face missing
        a.send(("batch", [2], 1))
        a.send(("run", [engine.to_arrays(c) for c in _cutters(4, seed=1)]))
        a.send(("batch", [3], 4))
        a.send(("snap", 2))
        msg = a.recv()                                          # no batch done after the bad run
        assert msg[1] == 2 and msg[-1][0] == "stock_invalid" and msg[5] == good
    finally:
        a.close()
        worker.join(timeout=10)
    assert not worker.is_alive()


def test_a_stock_gives_the_same_part_with_a_worker_and_without(face40):
    """A rotary facing pass of a few hundred cutters, once in process and once with the
    batches in a worker from the first window: the same cutters (what the sweep reads of the
    stock does not depend on the booleans' progress), the same part."""
    c = np.arange(0.0, 360.0, 0.75)
    tips, axes = turnmill(26.0, 0.0, -10.0 + 0.0 * c, c)
    parts = []
    for worker in (False, True):
        stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01, fans=False, batch=16, spread=2,
                                worker=worker)
        stock.batches.pieces[0].remote_after = 0 if worker else None      # from the first window
        stock.cut(face40, tips, axes)
        parts.append((stock.stats.cutters, stock.stats.batches, stock.volume, stock))
    (n0, b0, v0, s0), (n1, b1, v1, s1) = parts
    assert s1.batches.pieces[0].remote is not None and s0.batches.pieces[0].remote is None
    assert (n1, b1) == (n0, b0) and n0 > 64
    assert v1 == pytest.approx(v0, rel=1e-12)
    assert v0 < np.pi * 30.0 ** 2 * 60.0 - 1000.0
    s1.close()


def test_without_a_worker_process_the_batches_stay_in_this_process(monkeypatch):
    """Where no worker can be started (no socket pair, no fd passing), the piece subtracts
    its batches itself, with the same result."""
    import vmach.stock.remote as remote

    def refuse(*args, **kwargs):
        raise OSError("no processes here")

    monkeypatch.setattr(remote.Remote, "__init__", refuse)
    blank = engine.cylinder(30.0, -20.0, 0.0, 64)
    piece = Piece(blank, batch=4, spread=1, remote_after=0)
    local = Piece(blank, batch=4, spread=1)
    for p in (piece, local):
        p.add(_cutters(8))
        p.flush()
    assert piece.remote is None and piece.remote_after is None
    assert piece.batches == 2 and piece.volume == pytest.approx(local.volume, rel=1e-12)


def test_a_worker_that_dies_is_a_stock_worker_error():
    """A worker killed mid-run (out of memory, a signal): the next read of the piece raises
    StockError of kind ``stock_worker``, rendered by the CLI as ``error[stock_worker]``."""
    blank = engine.cylinder(30.0, -20.0, 0.0, 64)
    piece = Piece(blank, batch=4, spread=1, remote_after=0)
    try:
        piece.add(_cutters(4))
        piece.remote._proc.kill()
        piece.remote._proc.wait(timeout=10)
        with pytest.raises(engine.StockError) as exc:
            _ = piece.volume
        assert exc.value.kind == "stock_worker"
        assert [f.kind for f in exc.value.findings()] == ["stock_worker"]
        assert "error[stock_worker]" in exc.value.findings()[0].render()
    finally:
        piece.remote.close()


def test_a_flush_hands_the_batches_to_the_worker_and_it_answers_for_a_box_alone():
    """Chunks flushed to be measured (a checked run) may never fill a window: the worker takes
    the batches from the first flush after ``remote_after`` cutters too; and the piece inside
    a box is made there — the same solid as here (volume to rounding), only that part sent,
    after every batch so far (the one flushed just before included)."""
    blank = engine.cylinder(30.0, -20.0, 0.0, 256)
    cutters = _cutters(40)
    local = Piece(blank, batch=8, spread=8, group=4)
    remote = Piece(blank, batch=8, spread=8, group=4, remote_after=16)
    lo, hi = np.array([20.0, -12.0, -6.0]), np.array([32.0, 12.0, 0.5])
    try:
        for p in (local, remote):
            for i in range(0, len(cutters), 10):      # chunks of 10: a window is 64
                p.add(cutters[i : i + 10])
                p.flush()
        assert local.remote is None
        assert remote.remote is not None and remote._before == 10   # the second flush (20 queued)
        a, b = local.local(lo, hi), remote.local(lo, hi)
        assert engine.volume(b) == pytest.approx(engine.volume(a), rel=1e-9)
        assert 10.0 < engine.volume(b) < engine.volume(engine.box(lo, hi))
        assert np.all(engine.bounds(b)[0] >= lo - 1e-9) and np.all(engine.bounds(b)[1] <= hi + 1e-9)
        assert engine.num_triangles(b) < engine.num_triangles(remote.solid) / 2
        assert engine.is_empty(remote.local(lo + 100.0, hi + 100.0))
        assert engine.is_empty(local.local(lo + 100.0, hi + 100.0))
    finally:
        remote.close()


def _blas_threads() -> list[int]:
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


def test_while_a_worker_runs_this_processs_blas_keeps_to_one_thread():
    """The main process's BLAS runs one thread while any piece's worker runs (its idle
    threads would spin on the worker's core), counted over overlapping pieces, and is given
    back as it was when the last one closes; a piece without a worker leaves it alone."""
    gc.collect()                                        # pieces other tests dropped
    assert BLAS.holders == 0
    blank = engine.cylinder(30.0, -20.0, 0.0, 64)
    cutters = _cutters(8)
    with threadpool_limits(limits=2, user_api="blas"):   # two threads, whatever the machine
        assert _blas_threads() and set(_blas_threads()) == {2}
        local = Piece(blank, batch=4, spread=1)
        local.add(cutters[:4])
        assert set(_blas_threads()) == {2}
        a = Piece(blank, batch=4, spread=1, remote_after=0)
        b = Piece(blank, batch=4, spread=1, remote_after=0)
        try:
            a.add(cutters[:4])
            assert a.remote is not None and set(_blas_threads()) == {1}
            b.add(cutters[4:])
            a.close()
            assert set(_blas_threads()) == {1}          # b's worker still runs
            b.close()
            assert set(_blas_threads()) == {2}
            c = Piece(blank, batch=4, spread=1, remote_after=0)
            c.add(cutters[:4])
            assert set(_blas_threads()) == {1}
            del c                                       # collected without close: given back
            gc.collect()
            assert set(_blas_threads()) == {2}
        finally:
            a.close()
            b.close()


def test_the_worker_ends_quietly_when_its_caller_has_gone():
    """A caller that goes away (Ctrl-C, a batch case stopped) leaves the worker's answer with
    nowhere to go: the worker's loop returns instead of raising BrokenPipeError (a traceback
    on the user's terminal)."""
    from multiprocessing import Pipe

    from vmach.stock.remote import serve

    caller, worker = Pipe()
    caller.send(("batch", [], 0))           # asks for an answer …
    caller.send(("snap", 1))
    caller.close()                          # … and goes away before reading it
    serve(worker)                           # returns; raised BrokenPipeError before
