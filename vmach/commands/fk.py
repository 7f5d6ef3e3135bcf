"""``vmach fk MODEL --axes X=…,Y=…`` — forward kinematics of one pose.

Prints the tool tip and tool axis in the workpiece frame (mm; unit vector from the tip toward the
spindle), the drive values of a hybrid machine, and any travel finding. Drive values may be given
instead of the virtual axes they produce (``--axes X=0,p1=-120,p2=130,B=0,C=0`` on ``h5d``).
Exit 0, or 1 when the pose is beyond a limit or unreachable.
"""

from __future__ import annotations

import argparse
import json
import math
import sys

import numpy as np

from vmach.errors import InputError
from vmach.machine import Model, axis_limit_findings, load_model

HELP = "forward kinematics: axis values -> tool tip and axis in the workpiece frame"


def add_common(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("model", metavar="MODEL", help="model file, or a name in models/ (s5d)")
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="set a model parameter, e.g. rotation_centre=10,0,-5 (repeatable)",
    )
    parser.add_argument("--format", choices=("text", "json"), default="text")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_common(parser)
    parser.add_argument(
        "--axes",
        required=True,
        metavar="X=…,Y=…",
        help="axis (or drive) values, mm and degrees; missing axes take home",
    )


def numbers(text: str, what: str, count: int | None = None) -> list[float]:
    """Comma-separated finite numbers; InputError otherwise."""
    out = []
    for part in text.split(","):
        try:
            v = float(part)
        except ValueError:
            raise InputError(f"{what}: {part.strip()!r} is not a number") from None
        if not math.isfinite(v):
            raise InputError(f"{what}: {part.strip()!r} is not a finite number")
        out.append(v)
    if count is not None and len(out) != count:
        raise InputError(f"{what} needs {count} comma-separated numbers, got {len(out)}")
    return out


def assignments(text: str, what: str) -> dict[str, float]:
    """``A=1,B=2`` → ``{"A": 1.0, "B": 2.0}``."""
    out: dict[str, float] = {}
    for part in filter(None, (p.strip() for p in text.split(","))):
        name, eq, value = part.partition("=")
        if not eq or not name.strip():
            raise InputError(f"{what}: expected NAME=VALUE, got {part!r}")
        out[name.strip()] = numbers(value, f"{what} {name.strip()}", 1)[0]
    return out


def open_model(args: argparse.Namespace) -> Model:
    model = load_model(args.model)
    params = {}
    for item in args.set:
        name, eq, value = item.partition("=")
        if not eq or not name.strip():
            raise InputError(f"--set: expected NAME=VALUE, got {item!r}")
        vals = numbers(value, f"--set {name.strip()}")
        params[name.strip()] = vals if len(vals) > 1 else vals[0]
    return model.with_parameters(**params) if params else model


def fmt(v: float) -> float:
    return float(round(v, 9)) + 0.0


def emit(out: dict, args: argparse.Namespace, findings) -> int:
    out["findings"] = [f.to_json() for f in findings]
    if args.format == "json":
        sys.stdout.write(json.dumps(out) + "\n")
    else:
        for key, val in out.items():
            if key == "findings":
                continue
            if isinstance(val, dict):
                val = " ".join(f"{k}={v:.6f}" if isinstance(v, float) else f"{k}={v}" for k, v in val.items())
            elif isinstance(val, list):
                val = " ".join(f"{v:.6f}" for v in val)
            sys.stdout.write(f"{key:<10s} {val}\n")
        for f in findings:
            sys.stdout.write(f.render() + "\n")
    return 1 if findings else 0


def run(args: argparse.Namespace) -> int:
    model = open_model(args)
    given = assignments(args.axes, "--axes")
    unknown = [k for k in given if k not in model.axes and k not in model.drives]
    if unknown:
        names = " ".join(model.axes + model.drives)
        raise InputError(f"{model.name} has no axis or drive {unknown[0]!r} (known: {names})")
    q = model.q({k: v for k, v in given.items() if k in model.axes})
    q, ok = model.axes_from_drives(q, {k: v for k, v in given.items() if k in model.drives})
    if not ok.all():
        raise InputError("no assembly of the parallel mechanism has these drive values", kind="unreachable")
    pose = model.fk(q)
    out: dict = {
        "model": model.name,
        "axes": {a: fmt(q[0, i]) for i, a in enumerate(model.axes)},
        "tip": [fmt(v) for v in pose.tip[0]],
        "axis": [fmt(v) for v in pose.axis[0]],
    }
    if model.drives:
        drives, _ = model.drive_values(q)
        out["drives"] = {d: (None if np.isnan(v[0]) else fmt(v[0])) for d, v in drives.items()}
    return emit(out, args, axis_limit_findings(model, q))
