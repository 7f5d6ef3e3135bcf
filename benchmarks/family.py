"""`vmach batch` figures: the DIN 32711 P3G family of the polygon-shaft program on Dask.

    python benchmarks/family.py [--sizes all|14,50,...] [--images] [--skip-family]
                                [--sim-workers 8] [--sim-tasks 160] [--sim-seconds 0.5]

1. The family (``--sizes``, default all 23 sizes) verified on a local cluster of 1 worker and
   then of 2 workers, each run from scratch in its own output directory: wall times, their
   ratio, the Dask overheads (cluster start; wall time less the per-case times over the
   workers), and from the per-case times a projection of the time on N workers (the cases
   placed longest first on the least-loaded worker, plus the measured overheads).
2. A simulated large cluster: ``--sim-workers`` in-process workers of this machine run
   ``--sim-tasks`` tiny cases that only wait ``--sim-seconds`` (a case of known length, costing no
   CPU, so that many run at once on 2 cores): the wall time against the ideal
   tasks × seconds / workers gives the overhead per case and in per cent (on a loaded machine
   mostly the worker processes waiting for a core), and the CPU time of the process that
   holds the scheduler and the client, per case, the scheduling's own cost.

Every figure is measured in this run; nothing is assumed. On a shared, loaded machine the
1 → 2 worker ratio is bounded by the cores the others leave (each case runs two processes).
"""

from __future__ import annotations

import argparse
import heapq
import logging
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from vmach.batch.execute import Cluster, run_cases  # noqa: E402
from vmach.batch.family import family_cases  # noqa: E402


def makespan(seconds: list[float], workers: int) -> float:
    """Longest-first list scheduling of case times on ``workers``: the batch's compute time."""
    loads = [0.0] * workers
    heapq.heapify(loads)
    for s in sorted(seconds, reverse=True):
        heapq.heappush(loads, heapq.heappop(loads) + s)
    return max(loads)


def family_run(sizes: str, workers: int, images: bool) -> dict:
    cases = family_cases(ROOT / "fixtures" / "polygon_shaft" / "POLY.MPF", "P3G", sizes)
    with tempfile.TemporaryDirectory(prefix="vmach-family-") as tmp:
        t0 = time.perf_counter()
        records, timings = run_cases(cases, Path(tmp), Cluster(workers=workers), {"images": images}, None)
        total = time.perf_counter() - t0
    per_case = timings["cases"]
    verdicts = {}
    for r in records:
        verdicts[r["verdict"]] = verdicts.get(r["verdict"], 0) + 1
    compute = makespan([s for s in per_case.values() if s is not None], workers)
    return {"workers": workers, "total_s": total, "start_s": timings.get("cluster_start_s", 0.0),
            "wall_s": timings.get("wall_s", 0.0), "cases": per_case, "verdicts": verdicts,
            "overhead_s": timings.get("wall_s", 0.0) - compute}


def _wait(seconds: float, i: int) -> int:
    time.sleep(seconds)
    return i


def simulated(workers: int, tasks: int, seconds: float) -> dict:
    from distributed import Client, LocalCluster, wait

    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                      silence_logs=logging.CRITICAL) as cluster, Client(cluster) as client:
        client.wait_for_workers(workers)
        client.run(lambda: None)                       # every worker up and answering
        client.submit(_wait, 0.0, -1, pure=False).result()   # the function shipped once
        t0, c0 = time.perf_counter(), time.process_time()
        wait(client.map(_wait, [seconds] * tasks, range(tasks), pure=False))
        wall = time.perf_counter() - t0
        cpu = time.process_time() - c0             # this process: the client and the scheduler
    ideal = tasks * seconds / workers
    return {"workers": workers, "tasks": tasks, "wall_s": wall, "ideal_s": ideal,
            "overhead_per_task_ms": (wall - ideal) / tasks * workers * 1000,
            "overhead_pct": 100 * (wall - ideal) / ideal, "scheduler_cpu_ms": cpu / tasks * 1000}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="all")
    ap.add_argument("--images", action="store_true", help="also render each case's pictures")
    ap.add_argument("--skip-family", action="store_true", help="only the simulated large cluster")
    ap.add_argument("--sim-workers", type=int, default=8)
    ap.add_argument("--sim-tasks", type=int, default=160)
    ap.add_argument("--sim-seconds", type=float, default=0.5)
    a = ap.parse_args()
    if not a.skip_family:
        runs = [family_run(a.sizes, w, a.images) for w in (1, 2)]
        for r in runs:
            print(f"family {a.sizes} on {r['workers']} local worker(s): {r['total_s']:.1f} s in all "
                  f"(cluster start {r['start_s']:.1f} s, cases {r['wall_s']:.1f} s, Dask overhead beyond "
                  f"the cases' own times {r['overhead_s']:.1f} s); verdicts {r['verdicts']}")
        one, two = runs
        print(f"ratio 1 worker / 2 workers: {one['total_s'] / two['total_s']:.2f}")
        times = sorted((s for s in one["cases"].values() if s is not None), reverse=True)
        print(f"per-case verify time on 1 worker: {min(times):.1f} .. {max(times):.1f} s, "
              f"sum {sum(times):.1f} s over {len(times)} cases")
        over = max(one["overhead_s"], 0.0) / max(len(times), 1)
        for n in sorted({1, 2, 4, 8, 16, len(times)}):
            est = one["start_s"] + makespan(times, n) + over * len(times) / n
            print(f"  projected on {n:>2} workers (uncontended cores, 2 per worker): {est:.1f} s")
    s = simulated(a.sim_workers, a.sim_tasks, a.sim_seconds)
    print(f"simulated cluster: {s['workers']} workers, {s['tasks']} cases of {a.sim_seconds:g} s: "
          f"{s['wall_s']:.2f} s against the ideal {s['ideal_s']:.2f} s: overhead "
          f"{s['overhead_per_task_ms']:.1f} ms per case ({s['overhead_pct']:.1f} %); "
          f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; the scheduler's and client's "
          f"CPU {s['scheduler_cpu_ms']:.2f} ms per case")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
