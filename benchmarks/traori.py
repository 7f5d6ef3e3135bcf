"""TRAORI speed: a five-axis CAM-like program (a tilted tool sweeping a spiral, the vector
turning a little every block, as CAM output writes it) interpreted and solved on the four
five-axis models. Prints the CPU seconds of the interpreter and of the transformation
(resolve; CPU time, so that a shared machine's load does not count), blocks/s of the
transformation and the rows written; no assertion.

    python benchmarks/traori.py [--blocks 20000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from interpreters import sinumerik  # noqa: E402
from vmach.canon import MOTIONS, RunOptions  # noqa: E402
from vmach.machine import load_model  # noqa: E402
from vmach.machine.oriented import resolve  # noqa: E402


def program(blocks: int, tilt_axis: str = "B") -> str:
    lines = ["G90 G17", "TRAORI", "ORIWKS ORIVECT", f"G0 X20 Y0 Z20 {tilt_axis}10 C0"]
    for i in range(blocks):
        t = i * 0.02
        r = 20.0 - 10.0 * i / blocks
        tilt = math.radians(15 + 10 * math.sin(t / 3))
        a, b, c = math.sin(tilt) * math.cos(t), math.sin(tilt) * math.sin(t), math.cos(tilt)
        lines.append(f"G1 X{r * math.cos(t):.4f} Y{r * math.sin(t):.4f} Z{-i * 0.0005:.4f} "
                     f"A3={a:.6f} B3={b:.6f} C3={c:.6f}" + (" F2000" if i == 0 else ""))
    return "\n".join(lines + ["TRAFOOF", "M30", ""])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--blocks", type=int, default=20000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "TRAORI.MPF"
        print(f"{args.blocks} TRAORI blocks")
        print(f"{'model':10s} {'interpret CPU-s':>16s} {'resolve CPU-s':>14s} {'blocks/s':>10s} {'rows':>8s}")
        for name in ("s5d", "h5d", "hybrid5", "mill5ac"):
            model = load_model(name)
            path.write_text(program(args.blocks, "A" if name == "mill5ac" else "B"))
            best_i = best_r = float("inf")
            for _ in range(args.repeat):
                t0 = time.process_time()
                result = sinumerik.run(path, model.control, RunOptions())
                t1 = time.process_time()
                cmds, found = resolve(result.commands, model)
                t2 = time.process_time()
                best_i, best_r = min(best_i, t1 - t0), min(best_r, t2 - t1)
            rows = sum(isinstance(c, MOTIONS) for c in cmds)
            print(f"{name:10s} {best_i:16.3f} {best_r:14.3f} {args.blocks / best_r:10.0f} {rows:8d}"
                  + (f"  ({len(found)} findings)" if found else ""))


if __name__ == "__main__":
    main()
