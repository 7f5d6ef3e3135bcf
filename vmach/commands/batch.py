"""``vmach batch``: verify many programs, or one parametric program over a size family, on Dask."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from vmach.errors import InputError
from vmach.output import writable_dir

HELP = "verify many programs, or a parametric program over a size family (DIN 32711 P3G), on Dask"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("programs", nargs="+", help="NC programs; with --family: the one parametric program")
    p.add_argument("--family", help="size family the parametric program is run over: P3G (DIN 32711)")
    p.add_argument("--sizes", default="all", help="with --family: all (default) or d1 values, e.g. 14,50,100")
    p.add_argument("--out", default="out/batch", help="directory of the cases' reports and the summary "
                   "(default out/batch); a case already complete there is not run again")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="run on this existing Dask cluster (default: a local cluster); its workers need "
                   "vmach installed and the --out directory reachable")
    p.add_argument("--workers", type=int, help="local cluster: worker processes (default: cores / 2, "
                   "each case also runs the stock's boolean process)")
    p.add_argument("--memory-limit", help="local cluster: memory per worker, e.g. 4GB (default: its share)")
    p.add_argument("--machine", help="machine model for every case (default: each program's vmach.toml)")
    p.add_argument("--accuracy", help="stock simulation preset for every case (standard or fine)")
    p.add_argument("--no-images", action="store_true", help="skip the pictures of each case")
    p.add_argument("--quiet", action="store_true", help="no progress lines")


def run(args: argparse.Namespace) -> int:
    from vmach.batch.execute import Cluster, run_cases
    from vmach.batch.family import family_cases, file_cases
    from vmach.batch.summary import write_summary

    if args.workers is not None and args.workers < 1:
        raise InputError("--workers must be at least 1", kind="usage")
    if args.scheduler and (args.workers or args.memory_limit):
        raise InputError("--workers and --memory-limit are for the local cluster, not --scheduler",
                         kind="usage")
    out = writable_dir(args.out)
    programs = [Path(p) for p in args.programs]
    if args.family:
        if len(programs) != 1:
            raise InputError("--family takes one parametric program", kind="usage")
        if not programs[0].is_file():
            raise InputError(f"{programs[0]}: no such file", kind="unreadable")
        cases = family_cases(programs[0], args.family, args.sizes)
        batch = {"title": f"{programs[0].name} over DIN 32711 {args.family.upper()} sizes {args.sizes}",
                 "program": programs[0].name, "family": args.family.upper(), "sizes": args.sizes}
    else:
        cases = file_cases(programs)
        batch = {"title": f"vmach batch of {len(cases)} program(s)", "programs": [p.name for p in programs]}
    memory = None
    if args.memory_limit:
        from dask.utils import parse_bytes

        try:
            memory = parse_bytes(args.memory_limit)
        except ValueError:
            raise InputError(f"--memory-limit {args.memory_limit}: e.g. 4GB", kind="usage") from None
    options = {"images": not args.no_images, "machine": args.machine, "accuracy": args.accuracy}
    records, timings = run_cases(cases, out, Cluster(args.scheduler, args.workers, memory), options,
                                 None if args.quiet else sys.stderr)
    data = write_summary(out, batch, records, timings)
    counts = ", ".join(f"{n} {v}" for v, n in data["verdicts"].items() if n)
    print(f"{len(records)} case(s): {counts}")
    for r in records:
        if r["verdict"] not in ("pass", "warnings"):
            why = r.get("worst") or {}
            detail = (f"{why.get('kind')} at {why.get('file')}:{why.get('line')}" if why
                      else "; ".join(r.get("diagnostics", [])))
            print(f"  {r['name']}: {r['verdict']}: {detail}")
    print(f"summary: {out / 'summary.json'} ({out / 'index.html'})")
    bad = sum(r["verdict"] not in ("pass", "warnings") for r in records)
    return 1 if bad else 0
