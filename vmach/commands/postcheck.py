"""``vmach postcheck PROG --cl FILE --machine MODEL`` — check a post-processor's output.

Runs the program on the machine model, pairs its moves with the CL file's poses and reports, per
pose, how far the machine's tool (forward kinematics of the programmed axes) is from the CAM pose
(domain §2). Every pose beyond ``--tol-position``/``--tol-angle`` is an error finding at its
G-code line, naming the CL line. Exit 0 when every pose is within tolerance, 1 otherwise, 2 for
unreadable input.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import interpreters
from vmach.canon import RunOptions
from vmach.commands.fk import numbers, open_model
from vmach.errors import InputError
from vmach.files import input_file
from vmach.machine.cl import read_cl
from vmach.machine.oriented import resolve as resolve_orientation
from vmach.machine.postcheck import (
    TOL_ANGLE,
    TOL_POSITION,
    WINDOW,
    moves_from_commands,
    postcheck,
)
from vmach.setup import read_setup

HELP = "check post-processed G-code against the CAM cutter-location (APT CL) data"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("program", metavar="PROG", help="the post-processor's NC program")
    parser.add_argument("--cl", required=True, metavar="FILE", help="APT CL data (GOTO/…)")
    parser.add_argument(
        "--machine",
        dest="model",
        metavar="MODEL",
        help="machine model (path or name in models/); default: the vmach.toml beside the program",
    )
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="set a model parameter, e.g. rotation_centre=0,0,-30 (wins over the [parameters] "
        "of the vmach.toml beside the program)",
    )
    parser.add_argument("--dialect", help="override the dialect chosen by the file extension")
    parser.add_argument(
        "--tol-position",
        default=str(TOL_POSITION),
        metavar="MM",
        help=f"tool-tip tolerance, mm (default {TOL_POSITION})",
    )
    parser.add_argument(
        "--tol-angle",
        default=str(TOL_ANGLE),
        metavar="DEG",
        help=f"tool-axis tolerance, degrees (default {TOL_ANGLE})",
    )
    parser.add_argument("--all", action="store_true", help="text: list every pose")
    parser.add_argument("--format", choices=("text", "json"), default="text")


def _set_up_model(args: argparse.Namespace, program: Path):
    """The model with its set-up parameters — ``--set`` over the ``[parameters]`` of the
    vmach.toml beside the program over the model's own — and a line saying which came from
    where (a post is checked against the fixture it was written for, never silently against
    the model's default set-up)."""
    setup = read_setup(program)
    if args.model is None:
        if setup.machine is None:
            raise InputError(f"{program}: which machine? give --machine (or a vmach.toml beside the "
                             "program)", kind="usage")
        args.model = str(setup.machine)
    model = open_model(args)
    given = {item.partition("=")[0].strip() for item in args.set}
    from_file = {k: v for k, v in setup.parameters.items() if k not in given}
    if from_file:
        model = model.with_parameters(**from_file)
    params = model.spec.parameters
    said = []
    for name in sorted(params):
        where = "--set" if name in given else (str(setup.source) if name in from_file else "the model")
        said.append(f"{name} = {_fmt(params[name])} ({where})")
    return model, "; ".join(said) or "no parameters"


def _fmt(v) -> str:
    return ",".join(f"{x:g}" for x in v) if isinstance(v, tuple) else f"{v:g}"


def run(args: argparse.Namespace) -> int:
    tol_p = numbers(args.tol_position, "--tol-position", 1)[0]
    tol_a = numbers(args.tol_angle, "--tol-angle", 1)[0]
    if tol_p <= 0 or tol_a <= 0:
        raise InputError("tolerances must be > 0")
    program = Path(args.program)
    input_file(program, str(args.program))  # a directory, a device or a pipe is named as such
    model, setup_note = _set_up_model(args, program)
    cl = read_cl(args.cl)
    dialect = interpreters.dialect_for(program, args.dialect, model.control.dialect)
    result = dialect.run(str(program), model.control, RunOptions())
    # a TRAORI program: its blocks' poses through the model's transformation (machine/oriented.py)
    commands, oriented = resolve_orientation(result.commands, model, ends_only=True)
    moves = moves_from_commands(commands, model.axes, model.home)
    check = postcheck(model, cl, moves, tol_position=tol_p, tol_angle=tol_a, window=WINDOW)
    findings = list(result.findings) + oriented + list(check.findings)
    paired = check.move >= 0
    summary = {
        "poses": len(cl),
        "moves": len(moves.q),
        "paired": int(paired.sum()),
        "unpaired_moves": len(check.unpaired),
        "beyond_tolerance": sum(f.kind == "post_deviation" for f in findings),
        "max_position_mm": float(np.nanmax(check.position)) if paired.any() else None,
        "max_angle_deg": float(np.nanmax(check.angle)) if paired.any() else None,
        "completed": result.completed,
    }
    if args.format == "json":
        out = {
            "program": str(program),
            "cl": str(args.cl),
            "machine": model.name,
            "setup": setup_note,
            "tolerance": {"position_mm": tol_p, "angle_deg": tol_a},
            "summary": summary,
            "poses": [check.pose_json(i) for i in range(len(cl))],
            "unpaired_moves": [check.moves.sources[j].line for j in check.unpaired],
            "findings": [f.to_json() for f in findings],
        }
        sys.stdout.write(json.dumps(out) + "\n")
    else:
        w = sys.stdout.write
        w(f"postcheck {program} against {args.cl} on {model.name}\n")
        w(f"  set-up: {setup_note}\n")
        w(
            f"  {summary['poses']} CL poses, {summary['moves']} moves, {summary['paired']} paired, "
            f"{summary['unpaired_moves']} moves without a pose\n"
        )
        if paired.any():
            w(
                f"  largest deviation {summary['max_position_mm']:.6f} mm, "
                f"{summary['max_angle_deg']:.6f}°; beyond tolerance ({tol_p:g} mm, {tol_a:g}°): "
                f"{summary['beyond_tolerance']}\n"
            )
        if args.all:
            w("  cl_line  nc_line   position_mm   angle_deg\n")
            for i in range(len(cl)):
                p = check.pose_json(i)
                if p["nc_line"] is None:
                    w(f"  {p['cl_line']:7d}        -             -           -\n")
                else:
                    w(
                        f"  {p['cl_line']:7d}  {p['nc_line']:7d}  {p['position_mm']:12.6f}"
                        f"  {p['angle_deg']:10.6f}\n"
                    )
        for f in findings:
            w(f.render() + "\n")
    bad = any(f.severity == "error" for f in findings) or not result.completed
    return 1 if bad else 0
