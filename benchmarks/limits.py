"""How fast vmach's input limits bite: for each, a program just beyond it, run as ``vmach run``
in a fresh process; prints the exit code, the finding's kind, CPU and wall seconds and the
process's peak memory (issue #30: every limit within ~5 s and ~500 MB).

    python benchmarks/limits.py            # every case
    python benchmarks/limits.py goto_loop  # one case

Figures depend on the machine and its load: CPU seconds are the fair measure on a shared one.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from vmach.tol import tol

#: name -> (file name, text or a callable writing the file, extra CLI arguments)
CASES: dict[str, tuple[str, object, list[str]]] = {
    "rs274_while_loop": ("loop.ngc", "#1=0\no100 while [1]\n#1=[#1+1]\no100 endwhile\nM2\n", []),
    "rs274_while_moving": ("move.ngc", "o100 while [1]\nG0 X1\nG0 X0\no100 endwhile\nM2\n", []),
    "rs274_g81_repeats": ("g81.ngc", "G90 G0 X0 Y0 Z10\nG91 G81 X1 Z-1 R1 F100 L1000000000\nM2\n", []),
    "sinumerik_gotob_loop": ("GOTO.MPF", "N10 R1=R1+1\nN20 GOTOB N10\nM30\n", []),
    "sinumerik_while_loop": ("WHILE.MPF", "WHILE 1\nR1=R1+1\nENDWHILE\nM30\n", []),
    "sinumerik_moving_loop": ("MOVE.MPF", "LBL: G0 X1\nG0 X0\nGOTOB LBL\nM30\n", []),
    "program_too_large": ("BIG.MPF", "big", []),
    "line_too_long": ("LINE.MPF", "line", []),
    "max_blocks_too_large": ("P.MPF", "G0 X1\nM30\n", ["--max-blocks", str(10**30)]),
    # the same runaway loop through the whole pipeline (stages after the interpreter included)
    "verify_moving_loop": ("MOVE.MPF", "LBL: G0 X1\nG0 X0\nGOTOB LBL\nM30\n",
                           ["--machine", "turnmill", "--no-images", "--quiet"]),
}


def _write(path: Path, text: str) -> None:
    if text == "big":                              # a real program text, repeated past the limit
        block = b"N10 G1 X12.345 Y23.456 Z-1.5 F800\n"
        with open(path, "wb") as fh:
            for _ in range(tol.max_program_bytes // len(block) + 2):
                fh.write(block)
    elif text == "line":                           # one line of 1 MB
        path.write_bytes(b"G0 X1\n;" + b"x" * 1_000_000 + b"\nM30\n")
    else:
        path.write_text(text)


def one(name: str) -> dict:
    """Run one case in this process (called in a child): its figures as a dict."""
    from vmach.cli import main

    file, text, extra = CASES[name]
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / file
        _write(p, text)
        wall, cpu = time.perf_counter(), time.process_time()
        if name.startswith("verify"):
            rc = main(["verify", str(p), "--out", str(Path(d) / "out"), *extra])
        else:
            rc = main(["run", str(p), "-o", str(Path(d) / "out.txt"), *extra])
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux
    return {"case": name, "exit": rc, "cpu_s": round(cpu, 2), "wall_s": round(wall, 2),
            "peak_mb": round(peak, 1)}


def main(argv: list[str]) -> int:
    if argv[:1] == ["--one"]:
        row = one(argv[1])
        print(json.dumps(row))
        return 0
    names = argv or list(CASES)
    print(f"{'case':24} {'exit':>4} {'kind':18} {'cpu s':>7} {'wall s':>7} {'peak MB':>8}")
    for name in names:
        proc = subprocess.run([sys.executable, __file__, "--one", name], capture_output=True,
                              text=True, env={**os.environ, "PYTHONHASHSEED": "0"})
        rows = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
        if not rows:
            print(f"{name:24} failed: {proc.stderr[-300:]}")
            continue
        row = json.loads(rows[-1])
        kinds = [w.split("[")[1].split("]")[0] for w in proc.stderr.split() if "error[" in w]
        print(f"{name:24} {row['exit']:>4} {(kinds[0] if kinds else '-'):18} {row['cpu_s']:>7.2f} "
              f"{row['wall_s']:>7.2f} {row['peak_mb']:>8.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
