"""``vmach demo polygon-shaft``: the instructor's demo — the P3G family verified, one size's
cut animated (GIF and MP4), X/Y over C1 and the profile against its band."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from vmach.errors import InputError
from vmach.output import writable_dir

HELP = "the instructor's demo: the polygon-shaft family verified, and an animation of one size's cut"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("name", choices=("polygon-shaft",), help="the demo to run")
    p.add_argument("--size", type=float, default=50.0, help="d1 of the size animated (default 50)")
    p.add_argument("--sizes", help="also verify these sizes as a batch first: all, or d1 values "
                   "(e.g. 14,50,100); the summary goes to OUT/index.html")
    p.add_argument("--out", default="out/demo", help="output directory (default out/demo)")
    p.add_argument("--program", help="the parametric program (default: the fixture's POLY.MPF)")
    p.add_argument("--frames", type=int, default=48, help="frames of the animation (default 48)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="with --sizes: an existing Dask cluster")
    p.add_argument("--workers", type=int, help="with --sizes: local worker processes")


def run(args: argparse.Namespace) -> int:
    from vmach.demo.polygon import default_program, run_demo

    if args.frames < 2:
        raise InputError("--frames must be at least 2", kind="usage")
    out = writable_dir(args.out)
    program = Path(args.program) if args.program else default_program()
    if not program.is_file():
        raise InputError(f"{program}: no such file", kind="unreadable")
    bad = 0
    if args.sizes:
        from vmach.batch.execute import Cluster, run_cases
        from vmach.batch.family import family_cases
        from vmach.batch.summary import write_summary

        cases = family_cases(program, "P3G", args.sizes)
        records, timings = run_cases(cases, out, Cluster(args.scheduler, args.workers), {"images": True},
                                     sys.stderr)
        data = write_summary(out, {"title": f"{program.name} over DIN 32711 P3G sizes {args.sizes}",
                                   "program": program.name, "family": "P3G", "sizes": args.sizes},
                             records, timings)
        print(", ".join(f"{n} {v}" for v, n in data["verdicts"].items() if n) + f": {out / 'index.html'}")
        bad = sum(r["verdict"] not in ("pass", "warnings") for r in records)
    sys.stderr.write(f"vmach demo: verifying and animating d1 = {args.size:g}\n")
    written = run_demo(out, args.size, program, args.frames)
    print(written["summary"])
    print(f"animation: {out / written['gif']} and {out / written['mp4']}; page: {out / written['page']}")
    return 1 if bad else 0
