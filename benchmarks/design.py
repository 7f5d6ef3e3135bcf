"""`verify --design` figures: the time to compare the reference polygon part with its design.

The part is the fixture POLY50 (fixtures/polygon_shaft) simulated once on the turn-mill with
`standard` accuracy; the design is the nominal P3G-50 shaft end that `vmach profile P3G 50
--design-stl … --length 40 --chamfer 15x3 --shoulder 60:60 --phase 30` writes. Printed: the
meshes' sizes, then per repeat the comparison's parts — the exact signed distance of every
vertex of the part (libigl), the two booleans and their regions (manifold3d), and the lines
behind each region (the move table's tools) — and the best total.

    python benchmarks/design.py [--repeat 3] [--tolerance +-0.005]

The machine's load matters: on this 2-core machine shared by several engineers (load average
15-20) the same comparison took 12-22 s; the booleans and the distance searches each take
about half of it.

With the default band (±0.005 mm, tighter than the simulation's 0.01 mm side error) regions
appear and the line search runs; with ±0.02 the part is within it (no region).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--tolerance", default="+-0.005")
    args = ap.parse_args()

    from vmach.checks import design as design_mod
    from vmach.checks.design_findings import check_design, plan_design
    from vmach.checks.distance import SignedDistance
    from vmach.cli import main as vmach
    from vmach.stock import engine
    from vmach.verify import VerifyOptions, verify

    with tempfile.TemporaryDirectory() as tmp:
        shaft = Path(tmp) / "shaft.stl"
        vmach(["profile", "P3G", "50", "--design-stl", str(shaft), "--length", "40", "--chamfer", "15x3",
               "--shoulder", "60:60", "--phase", "30"])
        t = time.perf_counter()
        report = verify(ROOT / "fixtures" / "polygon_shaft" / "POLY50.MPF", VerifyOptions(images=False))
        print(f"POLY50 verified in {time.perf_counter() - t:.1f} s (once, to have the part)")
        plan = plan_design(str(shaft), args.tolerance, None)
        part = report.part.solid
        pv, pf = engine.to_mesh(part, double=True)
        print(f"part: {len(pv)} vertices, {len(pf)} triangles; design: {len(plan.vertices)} vertices, "
              f"{len(plan.faces)} triangles; band {plan.band.lo:+g}/{plan.band.hi:+g} mm")
        best = float("inf")
        for i in range(args.repeat):
            t0 = time.perf_counter()
            SignedDistance(plan.vertices, plan.faces)(pv)
            t1 = time.perf_counter()
            comp = design_mod.compare(part, (plan.vertices, plan.faces), plan.band)
            t2 = time.perf_counter()
            out = check_design(plan, part, report.table, report.model, report.library,
                               report.part.initial_bounds)
            t3 = time.perf_counter()
            total = t3 - t2
            lines = total - out.comparison.seconds      # check_design compares, then the lines
            best = min(best, total)
            print(f"run {i + 1}: distance of the part's vertices {t1 - t0:.2f} s; compare (distances, "
                  f"booleans, regions) {comp.seconds:.2f} s; lines {max(lines, 0.0):.2f} s; "
                  f"check_design total {total:.2f} s; {len(out.findings)} finding(s)")
        print(f"best check_design: {best:.2f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
