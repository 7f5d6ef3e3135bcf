"""Running a batch's cases on Dask: a local cluster, or an existing one by its scheduler.

Each case is one task (:func:`vmach.batch.worker.verify_case`); its result is written to
``OUT/<case>/case.json`` when it arrives, so a batch that stops (Ctrl-C, a lost machine) is
resumed by running it again: a case whose ``case.json`` holds the same input digest
(:meth:`Case.key`) and whose report.json is there is not run again. A failing case — a program
error, an exception, a worker that died under it — is that case's result, never the batch's.

The output directory must be one the workers can write (this machine's, or a shared file
system for a remote cluster): each worker writes its case's report where the case was put.
"""

from __future__ import annotations

import json
import logging
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TextIO

from vmach.batch.family import Case, materialise
from vmach.batch.worker import verify_case
from vmach.errors import InputError
from vmach.output import atomic_writer, make_dir

#: processes a case runs: the verify itself and the stock's boolean worker (vmach.stock.remote)
PROCESSES_PER_CASE = 2


@dataclass(frozen=True)
class Cluster:
    """Where the cases run: ``scheduler`` an address (``tcp://host:port``) or None for a local
    cluster of ``workers`` processes (None: cores / PROCESSES_PER_CASE, at least 1), each with
    ``memory_limit`` bytes (None: its share of the machine's memory, the stock's worker
    process's half left out)."""

    scheduler: str | None = None
    workers: int | None = None
    memory_limit: int | None = None


def local_workers(cores: int | None = None) -> int:
    """Default local workers: one per PROCESSES_PER_CASE cores (each case keeps two busy)."""
    n = cores if cores is not None else (os.cpu_count() or 1)
    return max(1, n // PROCESSES_PER_CASE)


def memory_per_worker(workers: int) -> int:
    """Bytes a local worker may use: 80 % of the machine's memory shared among the workers,
    of which the worker's own process gets 1 / PROCESSES_PER_CASE (its stock worker the rest;
    Dask's nanny watches only the worker's own process)."""
    import psutil

    return int(0.8 * psutil.virtual_memory().total / workers / PROCESSES_PER_CASE)


def client_for(cluster: Cluster):
    """A ``distributed.Client`` and the local cluster it made (None when connecting)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise InputError("vmach batch runs on Dask: pip install 'dask[distributed]>=2024.1' "
                         "(or: pip install vmach)", kind="usage") from None
    if cluster.scheduler:
        try:
            client = Client(cluster.scheduler, timeout="20s")
            client.wait_for_workers(1, timeout=120)
            return client, None
        except (OSError, TimeoutError) as exc:
            raise InputError(f"--scheduler {cluster.scheduler}: cannot connect: {exc}",
                             kind="usage") from None
    n = cluster.workers or local_workers()
    local = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                         memory_limit=cluster.memory_limit or memory_per_worker(n),
                         dashboard_address=":0", silence_logs=logging.CRITICAL)
    return Client(local), local


def done_before(case: Case, case_dir: Path) -> dict | None:
    """The result a previous run recorded for ``case``, if it is complete and of the same
    inputs; else None."""
    try:
        rec = json.loads((case_dir / "case.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if rec.get("key") != case.key():
        return None
    if rec.get("verdict") in ("pass", "warnings", "fail") and not (case_dir / "report.json").is_file():
        return None
    return rec


class Tally:
    """Cases done / running / failed, told on ``stream`` one line a finished case."""

    def __init__(self, total: int, stream: TextIO | None, skipped: int = 0):
        self.total, self.stream = total, stream
        self.done, self.failed = skipped, 0
        if stream is not None and skipped:
            stream.write(f"vmach batch: {skipped} case(s) complete from before (resumed)\n")

    def finished(self, name: str, rec: dict, running: int) -> None:
        self.done += 1
        self.failed += rec["verdict"] in ("fail", "error", "crashed")
        if self.stream is not None:
            self.stream.write(f"vmach batch: {self.done}/{self.total} done, {running} running, "
                              f"{self.failed} failed - {name}: {rec['verdict']} "
                              f"({rec.get('seconds', 0):.1f} s)\n")
            self.stream.flush()


def run_cases(cases: list[Case], out: Path, cluster: Cluster, options: dict,
              stream: TextIO | None = sys.stderr) -> tuple[list[dict], dict]:
    """Run every case not complete from before; each case's record (in the order of
    ``cases``) and the batch's timings (seconds: cluster start, wall, per case)."""
    make_dir(out)
    records: dict[str, dict] = {}
    todo: list[tuple[Case, Path, str]] = []
    for case in cases:
        case_dir = out / case.name
        rec = done_before(case, case_dir)
        if rec is not None:
            records[case.name] = rec
            continue
        program = materialise(case, case_dir)
        todo.append((case, case_dir, str(program)))
    tally = Tally(len(cases), stream, len(records))
    timings: dict = {"cases": {name: rec.get("seconds") for name, rec in records.items()},
                     "resumed": len(records)}
    if todo:
        t0 = time.perf_counter()
        client, local = client_for(cluster)
        timings["cluster_start_s"] = round(time.perf_counter() - t0, 3)
        timings["workers"] = len(client.nthreads())
        try:
            _run_on(client, todo, options, records, tally, timings)
        finally:
            client.close()
            if local is not None:
                local.close()
    return [records[c.name] for c in cases], timings


def _run_on(client, todo, options: dict, records: dict, tally: Tally, timings: dict) -> None:
    from distributed import as_completed

    t0 = time.perf_counter()
    futures = {}
    for case, case_dir, program in todo:
        fut = client.submit(verify_case, program, str(case_dir), options, pure=False,
                            key=f"vmach-case-{case.name}-{case.key()}")
        futures[fut] = (case, case_dir)
    pending = len(futures)
    for fut in as_completed(futures):
        case, case_dir = futures[fut]
        pending -= 1
        try:
            res = fut.result()
        except Exception as exc:  # noqa: BLE001 - a lost worker (killed, out of memory) fails its case only
            res = {"verdict": "crashed", "diagnostics": [f"{type(exc).__name__}: {exc}"]}
        seconds = res.pop("seconds", None)
        res.pop("traceback", None)
        rec = {"name": case.name, "label": case.label, "key": case.key(), **res}
        timings["cases"][case.name] = seconds
        make_dir(case_dir)
        with atomic_writer(case_dir / "case.json") as fh:
            json.dump({**rec, "seconds": seconds}, fh, indent=2)
            fh.write("\n")
        records[case.name] = rec
        tally.finished(case.name, {**rec, "seconds": seconds or 0.0}, min(pending, timings["workers"]))
    timings["wall_s"] = round(time.perf_counter() - t0, 3)
