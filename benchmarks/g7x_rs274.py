"""LinuxCNC's lathe cycles G70/G71/G72 (and .1/.2) against rs274 on random contours.

Each seed makes one program: an outside contour of 3 to 7 elements running from the face
toward -Z and outward (lines, R-form arcs G2/G3, some corners with an A fillet or a C
chamfer), in G7 or G8, and one cycle on it with random D, E, P, I, R. The program is traced
by LinuxCNC's ``rs274 -g`` (its own HOME, at most ``--timeout`` seconds: rs274 2.9 loops for
ever on some contours) and by vmach (``FORMATS["rs274"]``), and the traces are compared line
for line. Printed: how many are identical, how many differ (named), and how many rs274 did
not finish (where vmach must stop with ``g7x_too_many_moves``).

    python benchmarks/g7x_rs274.py [--seeds 0:400] [--timeout 10]
"""

from __future__ import annotations

import argparse
import random
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from interpreters.rs274ngc import FORMATS  # noqa: E402


def program(seed: int) -> str:
    rnd = random.Random(seed)
    x, z = rnd.uniform(2, 6), 0.0
    body = [f"  G1 X{x:.3f} Z{z:.3f}"]
    for _ in range(rnd.randint(2, 6)):
        dz, dx = -rnd.uniform(1, 6), rnd.uniform(0, 4)
        nx, nz = x + dx, z + dz
        if rnd.random() < 0.25 and dx > 0.5:
            r = ((dx * dx + dz * dz) ** 0.5) / 2 * rnd.uniform(1.05, 3)
            body.append(f"  {rnd.choice(['G2', 'G3'])} X{nx:.3f} Z{nz:.3f} R{r:.3f}")
        else:
            corner = ""
            if rnd.random() < 0.2:
                corner = f" A{rnd.uniform(0.1, 0.5):.2f}"
            elif rnd.random() < 0.2:
                corner = f" C{rnd.uniform(0.1, 0.5):.2f}"
            body.append(f"  G1 X{nx:.3f} Z{nz:.3f}{corner}")
        x, z = nx, nz
    sx, sz = x + rnd.uniform(1, 5), rnd.uniform(1, 4)
    cycle = rnd.choice(["G71", "G71.1", "G71.2", "G72", "G72.1", "G72.2", "G70"])
    if cycle == "G70":
        call = (f"G70 Q10 X{sx:.3f} Z{sz:.3f} D{rnd.uniform(0, 1):.2f} E{rnd.uniform(0, 0.2):.2f} "
                f"P{rnd.randint(1, 3)}")
    else:
        call = (f"{cycle} Q10 X{sx:.3f} Z{sz:.3f} D{rnd.uniform(0, 0.5):.2f} I{rnd.uniform(0.2, 2):.2f} "
                f"R{rnd.uniform(0.1, 1):.2f}")
    head = ["G18 G21 G90 " + rnd.choice(["G7", "G8"]), "F300", "O10 SUB"]
    return "\n".join(head + body + ["O10 ENDSUB", call, "M2"]) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="0:400")
    ap.add_argument("--timeout", type=float, default=10.0)
    args = ap.parse_args()
    rs274 = shutil.which("rs274")
    if rs274 is None:
        sys.exit("rs274 (LinuxCNC's standalone interpreter, Debian linuxcnc-uspace) is not installed")
    lo, hi = (int(v) for v in args.seeds.split(":"))
    same, differ, loops = 0, [], []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(lo, hi):
            path = Path(tmp) / f"g7x_{seed}.ngc"
            path.write_text(program(seed))
            home = Path(tmp) / f"home{seed}"
            home.mkdir()
            try:
                proc = subprocess.run([rs274, "-g", path.name], cwd=tmp, capture_output=True, text=True,
                                      timeout=args.timeout, env={"HOME": str(home), "PATH": "/usr/bin:/bin"})
            except subprocess.TimeoutExpired:
                lines, result = FORMATS["rs274"](str(path), None, None, {})
                kinds = [f.kind for f in result.findings]
                loops.append((seed, "g7x_too_many_moves" in kinds))
                continue
            want = [ln for ln in proc.stdout.splitlines() if ln != "executing"]
            lines, _ = FORMATS["rs274"](str(path), None, None, {})
            if lines == want:
                same += 1
            else:
                differ.append(seed)
    print(f"G7x against rs274, seeds {lo}..{hi - 1}: {same} identical, {len(differ)} differ"
          + (f" (seeds {differ})" if differ else "")
          + f", {len(loops)} where rs274 did not finish in {args.timeout:g} s"
          + (f" (vmach stopped with g7x_too_many_moves on {sum(ok for _, ok in loops)})" if loops else ""))


if __name__ == "__main__":
    main()
