"""Forward and inverse kinematics throughput, batched, for every shipped machine model.

    python benchmarks/kinematics.py [--n 1000000] [--repeat 5]

Prints poses per second (best of ``--repeat`` runs) for FK (tool tip and axis in the workpiece
frame), the hybrids' drive transformation, and IK (closed form where the model declares one,
the numeric solver otherwise — the numeric one on fewer poses, it iterates).
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from functools import partial
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from vmach.machine import load_model  # noqa: E402

MODELS = ("turnmill", "s5d", "h5d", "hybrid5")


def sample_q(model, n: int, rng: np.random.Generator) -> np.ndarray:
    q = np.empty((n, len(model.axes)))
    for i, a in enumerate(model.axes):
        lo, hi = model.limits[i]
        if np.isnan(lo):
            lo, hi = -179.0, 179.0
        if a == "B":
            lo, hi = max(lo, 1.0), min(hi, 90.0)
        q[:, i] = rng.uniform(lo, hi, n)
    return q


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000, help="poses per batch (FK, closed IK)")
    ap.add_argument("--n-numeric", type=int, default=20_000, help="poses for the numeric IK")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(0)
    print(f"# vmach kinematics benchmark — numpy {np.__version__}, Python "
          f"{platform.python_version()}, {os.cpu_count()} CPUs, best of {args.repeat}")
    print(f"{'model':<10s} {'what':<22s} {'poses':>9s} {'seconds':>9s} {'poses/s':>12s}")
    for name in MODELS:
        m = load_model(name)
        q = sample_q(m, args.n, rng)
        rows = [("fk tip+axis", args.n, best(partial(m.fk, q), args.repeat))]
        if m.drives:
            rows.append(("drives (2nd transform)", args.n,
                         best(partial(m.drive_values, q), args.repeat)))
        pose = m.fk(q)
        if m.spec.ik == "numeric":
            k = min(args.n_numeric, args.n)
            solve = partial(m.ik, pose.tip[:k], pose.axis[:k])
            rows.append(("ik numeric", k, best(solve, max(1, args.repeat // 2))))
        else:
            solve = partial(m.ik, pose.tip, pose.axis)
            rows.append((f"ik {m.spec.ik}", args.n, best(solve, args.repeat)))
        small = q[:10_000]
        rows.append(("link2base (n,4,4)", len(small), best(partial(m.link2base, small),
                                                           args.repeat)))
        for what, n, sec in rows:
            print(f"{name:<10s} {what:<22s} {n:>9d} {sec:>9.4f} {n / sec:>12,.0f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
