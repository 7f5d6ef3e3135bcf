"""``vmach ik MODEL --tip x,y,z --axis i,j,k`` — inverse kinematics of one tool pose.

Prints the machine axis values (and the drives of a hybrid machine) that put the tool tip at
``--tip`` (mm, workpiece frame) with tool axis ``--axis`` (from the tip toward the spindle).
``--set rotation_centre=x,y,z`` sets r_R of the table-table machine (domain §2). Exit 0, or 1
when the pose is unreachable or beyond a limit.
"""

from __future__ import annotations

import argparse

import numpy as np

from vmach.commands.fk import add_common, assignments, emit, fmt, numbers, open_model
from vmach.errors import InputError
from vmach.machine import axis_limit_findings, unreachable_findings

HELP = "inverse kinematics: tool tip and axis in the workpiece frame -> axis values"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_common(parser)
    parser.add_argument("--tip", required=True, metavar="x,y,z", help="tool tip, mm")
    parser.add_argument("--axis", required=True, metavar="i,j,k", help="tool axis vector")
    parser.add_argument(
        "--strategy",
        choices=("keep", "shortest"),
        default="keep",
        help="choice of C at the B = 0 singularity (docs/kinematics.md)",
    )
    parser.add_argument(
        "--previous",
        default="",
        metavar="X=…,C=…",
        help="axis values before this pose (start guess, C kept at B = 0)",
    )


def run(args: argparse.Namespace) -> int:
    model = open_model(args)
    tip = np.array([numbers(args.tip, "--tip", 3)])
    axis = np.array([numbers(args.axis, "--axis", 3)])
    norm = float(np.linalg.norm(axis))
    if norm < 1e-9:
        raise InputError("--axis must not be the zero vector")
    if not model.axes:
        raise InputError(f"{model.name}: the model has no axes to solve for", kind="usage")
    previous = model.q(assignments(args.previous, "--previous"))[0]
    sol = model.ik(tip, axis, previous=previous, strategy=args.strategy)
    out: dict = {
        "model": model.name,
        "axes": {a: fmt(sol.q[0, i]) for i, a in enumerate(model.axes)},
    }
    if sol.drives:
        out["drives"] = {d: (None if np.isnan(v[0]) else fmt(v[0])) for d, v in sol.drives.items()}
    out["reachable"] = bool(sol.ok[0])
    out["singular"] = bool(sol.singular[0])
    findings = axis_limit_findings(model, sol.q) if sol.ok[0] else []
    if not sol.ok[0] and not model.drives:
        findings = unreachable_findings(sol.ok)
    elif not sol.ok[0]:
        findings = axis_limit_findings(model, sol.q)
    return emit(out, args, findings)
