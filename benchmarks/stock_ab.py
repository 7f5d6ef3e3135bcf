"""This tree's stock engine against another tree's (a ``git worktree`` of an older commit),
interleaved: A B A B ... on the same loaded machine.

    python benchmarks/stock_ab.py OTHER_TREE [--rounds N] [--accuracy fine] [--cases program,helix]

Each run is one case of each tree's own ``benchmarks/stock.py`` (``program``: the reference
program; ``helix``: the 4,000-move helix) in a fresh interpreter whose ``vmach`` is that
tree's, so that both measure the same work the same way. Printed per run: seconds, cutters,
the part's volume (when the tree's benchmark reports it) and peak memory (the main process
and the stock's worker); at the end per tree and case the median and the spread (min–max)
of the seconds and the largest peak.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = """
import json, sys
sys.path.insert(0, {bench!r})
import stock as bench
from vmach.tol import ACCURACY
bench.PRESET.update(ACCURACY[{accuracy!r}].stock)
r = bench.run_case({kind!r}, {n})
import vmach
r["vmach"] = vmach.__file__
print(json.dumps({{k: v for k, v in r.items() if isinstance(v, (int, float, str, list))}}))
"""


def run(tree: Path, case: str, accuracy: str) -> dict:
    """One case of ``tree``'s benchmarks/stock.py in a fresh interpreter (cwd: the tree)."""
    kind, n = ("program", 0) if case == "program" else ("helix", 4000)
    code = CHILD.format(bench=str(tree / "benchmarks"), accuracy=accuracy, kind=kind, n=n)
    out = subprocess.run([sys.executable, "-c", code], cwd=tree, capture_output=True, text=True, check=True)
    r = json.loads(out.stdout.strip().splitlines()[-1])
    if not r["vmach"].startswith(str(tree)):
        raise SystemExit(f"{tree}: ran {r['vmach']}, not its own vmach")
    return r


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("other", type=Path, help="the other tree (e.g. a git worktree of the base)")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--accuracy", default="standard", choices=("standard", "fine"))
    ap.add_argument("--cases", default="program")
    args = ap.parse_args(argv)
    trees = {"this": ROOT, "other": args.other.resolve()}
    cases = args.cases.split(",")
    res: dict = {(t, c): [] for t in trees for c in cases}
    print(f"stock engine A/B ({args.accuracy}): this = {ROOT}, other = {trees['other']}")
    for k in range(args.rounds):
        order = list(trees) if k % 2 == 0 else list(trees)[::-1]
        for c in cases:
            for t in order:
                r = run(trees[t], c, args.accuracy)
                res[t, c].append(r)
                print(f"  round {k + 1} {c:<8s} {t:<5s} {r['total']:7.2f} s {r['cutters']:6d} cutters "
                      f"volume {r.get('volume', float('nan')):.3f} peak {r['peak_mb']:.0f} MB "
                      f"+ worker {r.get('worker_mb', 0.0):.0f} MB", flush=True)
    for c in cases:
        for t in trees:
            s = [r["total"] for r in res[t, c]]
            peak = max(r["peak_mb"] for r in res[t, c])
            worker = max(r.get("worker_mb", 0.0) for r in res[t, c])
            print(f"{c:<8s} {t:<5s} median {statistics.median(s):7.2f} s ({min(s):.2f}-{max(s):.2f}), "
                  f"peak {peak:.0f} MB + worker {worker:.0f} MB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
