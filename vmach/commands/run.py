"""``vmach run PROG``: interpret a program and print its canonical command trace."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import interpreters
from vmach.canon import RunOptions, format_json, format_text
from vmach.errors import InputError
from vmach.output import atomic_writer
from vmach.setup import control_for
from vmach.tol import tol

HELP = "run a program and print the canonical commands it produces"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("program", help="NC program (.mpf/.spf Sinumerik, .ngc RS274/NGC)")
    p.add_argument("--machine", help="machine model (path or name in models/)")
    p.add_argument("--dialect", help="override the dialect chosen by the file extension")
    p.add_argument(
        "--format",
        default="text",
        help="text (default), json (JSON Lines), or a dialect's own trace (rs274)",
    )
    p.add_argument(
        "-o", "--output", help="write the trace to this file (only when the run succeeds)"
    )
    p.add_argument(
        "--max-blocks",
        type=int,
        default=tol.max_blocks,
        help=f"stop after this many blocks (default {tol.max_blocks:,})",
    )
    p.add_argument("--tool-table", help="LinuxCNC tool table (.tbl) for RS274/NGC programs")


def run(args: argparse.Namespace) -> int:
    path = Path(args.program)
    if not path.is_file():
        raise InputError(f"{args.program}: no such file", kind="unreadable")
    if args.max_blocks < 1:
        raise InputError("--max-blocks must be at least 1", kind="usage")
    dialect = interpreters.dialect_for(path, args.dialect)
    control, _ = control_for(path, args.machine)
    options = RunOptions(max_blocks=args.max_blocks)
    if args.format in ("text", "json"):
        result = dialect.run(args.program, control, options)
        fmt = format_json if args.format == "json" else None
        lines = (fmt(c) if fmt else format_text(c, i) for i, c in enumerate(result.commands, 1))
    else:
        formats = getattr(dialect, "FORMATS", {})
        if args.format not in formats:
            known = ", ".join(["text", "json", *formats])
            raise InputError(
                f"--format {args.format}: not available for this dialect (use {known})",
                kind="usage",
            )
        text_lines, result = formats[args.format](
            args.program, control, options, {"tool_table": args.tool_table}
        )
        lines = iter(text_lines)
    if args.output:
        if result.completed:
            with atomic_writer(args.output) as fh:
                for line in lines:
                    fh.write(line + "\n")
    else:
        out = sys.stdout
        for line in lines:
            out.write(line + "\n")
    for f in result.findings:
        sys.stderr.write(f.render() + "\n")
    errors = any(f.severity == "error" for f in result.findings)
    return 1 if errors or not result.completed else 0
