"""``vmach check PROG``: static checks before running (syntax, names, jumps, structure)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import interpreters
from vmach.errors import InputError
from vmach.setup import control_for

HELP = "check a program without running it: syntax, unknown words, jumps, structure"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("program", help="NC program (.mpf/.spf Sinumerik, .ngc RS274/NGC)")
    p.add_argument("--machine", help="machine model (path or name in models/)")
    p.add_argument("--dialect", help="override the dialect chosen by the file extension")
    p.add_argument("--format", choices=("text", "json"), default="text")


def run(args: argparse.Namespace) -> int:
    path = Path(args.program)
    if not path.is_file():
        raise InputError(f"{args.program}: no such file", kind="unreadable")
    control, _ = control_for(path, args.machine, machine_data=False)   # static checks only
    dialect = interpreters.dialect_for(path, args.dialect, control.dialect)
    findings = dialect.check(args.program, control)
    errors = sum(f.severity == "error" for f in findings)
    warnings = sum(f.severity == "warning" for f in findings)
    args.exit_code = 1 if errors else 0           # known before the output (a closed pipe keeps it)
    if args.format == "json":
        json.dump([f.to_json() for f in findings], sys.stdout, indent=2, ensure_ascii=False)
        sys.stdout.write("\n")
    else:
        for f in findings:
            print(f.render())
        print(f"{args.program}: {errors} error(s), {warnings} warning(s)")
    return 1 if errors else 0
