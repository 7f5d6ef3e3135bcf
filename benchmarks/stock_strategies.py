"""What each cutter strategy gains: the stock cut with all of them against the same with one
switched off (``VMACH_STOCK_WITHOUT``, :data:`vmach.stock.plan.WITHOUT`), interleaved.

    python benchmarks/stock_strategies.py [--rounds N] [--accuracy fine] [--only fans,fins]
                                          [--work reference,helix,plate,chamfer]

Work (each run in a fresh process, so that every figure is its own and the strategies'
switch is read as the stock is made):
- ``reference``: the polygon-shaft program (``benchmarks/stock.py``'s ``program`` case: the split
  reference when ../shared holds it, else POLY50.MPF) — what the strategies were tuned on;
- ``helix``: ``benchmarks/stock.py``'s synthetic 4,000-move finishing helix;
- ``plate``: ``vmach verify fixtures/milling/PLATE.MPF`` (three-axis milling: an outline and
  drilled holes), its report's stock seconds;
- ``chamfer``: ``vmach verify fixtures/five_axis/chamfer_traori.mpf`` (a five-axis TRAORI
  chamfer), its report's stock seconds.

Each switch is measured against all on side by side, A B B A ... (``--rounds`` pairs), so
that a machine loaded by others slows both alike. Printed per switch and work: the median and
the spread (min–max) of the seconds, the cutters made, and the part's volume (mm³: an answer
that moved shows there); the gain of a strategy is the median without it less the median
with all on.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT))

import stock as bench  # noqa: E402
import trimesh  # noqa: E402

from vmach.stock.plan import SWITCHES  # noqa: E402
from vmach.tol import ACCURACY  # noqa: E402

FIXTURES = {"plate": ROOT / "fixtures" / "milling" / "PLATE.MPF",
            "chamfer": ROOT / "fixtures" / "five_axis" / "chamfer_traori.mpf"}
WORK = ("reference", "helix", "plate", "chamfer")


def run(work: str, without: str, accuracy: str) -> dict:
    """Seconds, cutters and part volume of one run of ``work`` with ``without`` switched off."""
    env = dict(os.environ, VMACH_STOCK_WITHOUT=without)
    if work in FIXTURES:
        out = Path(tempfile.mkdtemp(prefix="vmach-strategies-"))
        cmd = [sys.executable, "-m", "vmach", "verify", str(FIXTURES[work]), "--no-images", "--quiet",
               "--out", str(out), "--accuracy", accuracy, "--export", str(out / "part.stl")]
        subprocess.run(cmd, env=env, capture_output=True, check=False)
        rep = json.loads((out / "report.json").read_text())
        return {"seconds": rep["timings_s"]["stock"], "cutters": rep["simulation"]["cutters"],
                "volume": float(trimesh.load(out / "part.stl").volume),
                "findings": len(rep["findings"])}
    os.environ["VMACH_STOCK_WITHOUT"] = without          # read by the forked child
    try:
        r = bench.run_case("program" if work == "reference" else "helix", 4000)
    finally:
        os.environ.pop("VMACH_STOCK_WITHOUT", None)
    return {"seconds": r["total"], "cutters": r["cutters"], "volume": r.get("volume", float("nan")),
            "findings": r.get("findings", 0)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--accuracy", default="standard", choices=tuple(ACCURACY))
    ap.add_argument("--only", default=",".join(SWITCHES), help="the switches to measure")
    ap.add_argument("--work", default=",".join(WORK), help="the work to run")
    args = ap.parse_args(argv)
    bench.PRESET.update(ACCURACY[args.accuracy].stock)
    configs = [""] + [w for w in args.only.split(",") if w]
    works = [w for w in args.work.split(",") if w]
    res: dict = {}
    print(f"vmach stock strategies, each off against all on ({args.accuracy} accuracy, {args.rounds} rounds)")
    print(bench.machine_figure(), flush=True)
    for c in configs[1:]:
        # all on and this one off, side by side: A B B A ... (the machine's load drifts)
        for k in range(args.rounds):
            for cc in (("", c) if k % 2 == 0 else (c, "")):
                for w in works:
                    r = run(w, cc, args.accuracy)
                    res.setdefault((w, c, cc), []).append(r)
                    print(f"  {c:<8s} round {k + 1} {w:<9s} without {cc or '-':<8s} {r['seconds']:7.2f} s "
                          f"{r['cutters']:6d} cutters volume {r['volume']:.3f}", flush=True)
    print(bench.machine_figure(), flush=True)
    for c in configs[1:]:
        print(f"\nwithout {c}: median s (min-max), cutters, volume; gain = median without - median all on")
        for w in works:
            on, off = res[w, c, ""], res[w, c, c]
            a = [r["seconds"] for r in on]
            b = [r["seconds"] for r in off]
            ma, mb = statistics.median(a), statistics.median(b)
            print(f"  {w:<9s} all on {ma:7.2f} ({min(a):.2f}-{max(a):.2f}) {on[-1]['cutters']:6d} cutters | "
                  f"off {mb:7.2f} ({min(b):.2f}-{max(b):.2f}) {off[-1]['cutters']:6d} cutters, "
                  f"volume {off[-1]['volume']:.3f} | gain {mb - ma:+.2f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
