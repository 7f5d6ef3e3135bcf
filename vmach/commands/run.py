"""``vmach run PROG``: interpret a program and print its canonical command trace."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import interpreters
from vmach.canon import MOTIONS, RunOptions, RunResult, dumps, format_json, format_text
from vmach.errors import InputError
from vmach.files import input_file
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
    p.add_argument("-o", "--output", help="write the trace to this file (only when the run succeeds)")
    p.add_argument(
        "--max-blocks",
        type=int,
        default=tol.max_blocks,
        help=f"stop after this many blocks (default {tol.max_blocks:,})",
    )
    add_linuxcnc_arguments(p)
    p.add_argument("--var-file-update", action="store_true",
                   help="write the parameters back into --var-file (LinuxCNC's way; the old "
                   "file kept as .bak) instead of into NAME.vmach.var beside it")
    p.add_argument("--block-delete", action="store_true",
                   help="RS274/NGC: skip lines starting with / (rs274 -b)")
    p.add_argument("--continue-after-error", action="store_true",
                   help="RS274/NGC: report an error and go on after the top-level call "
                   "(rs274 -n 0); the errors are still findings")
    p.add_argument("--tools", help="tool library (.toml): the D offsets' radii for G41/G42 "
                   "(default: the setup file's)")
    p.add_argument("--default-tool", metavar="KIND:d=D[,l=L]",
                   help="stand in for every tool the library lacks (or all, without one) with "
                   "this cutter, e.g. flat:d=10: its radius under G41/G42; each is a "
                   "default_tool warning, never assumed silently")


def run(args: argparse.Namespace) -> int:
    path = Path(args.program)
    input_file(path, str(args.program))  # a directory, a device or a pipe is named as such
    if not 1 <= args.max_blocks <= tol.max_blocks_ceiling:   # a huge value must not switch it off
        raise InputError(f"--max-blocks must be 1 to {tol.max_blocks_ceiling:,}", kind="usage")
    control, model_path = control_for(path, args.machine)
    dialect = interpreters.dialect_for(path, args.dialect, control.dialect)
    library = _library(path, args.tools, args.default_tool)
    options = RunOptions(max_blocks=args.max_blocks, tool_radius=library.radius if library else None,
                         tool_data=library.data if library else None,
                         dialect_options=linuxcnc_options(args))
    if args.format in ("text", "json"):
        result = dialect.run(args.program, control, options)
        if args.format == "json":
            drives = _drive_values(model_path, result)
            lines = (_json_line(c, drives.get(i)) for i, c in enumerate(result.commands))
        else:
            lines = (format_text(c, i) for i, c in enumerate(result.commands, 1))
    else:
        formats = getattr(dialect, "FORMATS", {})
        if args.format not in formats:
            known = ", ".join(["text", "json", *formats])
            raise InputError(
                f"--format {args.format}: not available for this dialect (use {known})",
                kind="usage",
            )
        text_lines, result = formats[args.format](args.program, control, options)
        lines = iter(text_lines)
    if args.output:
        if result.completed:
            with atomic_writer(args.output) as fh:
                for line in lines:
                    fh.write(line + "\n")
    errors = any(f.severity == "error" for f in result.findings)
    args.exit_code = code = 1 if errors or not result.completed else 0
    if not args.output:
        out = sys.stdout
        try:
            for line in lines:
                out.write(line + "\n")
            out.flush()
        except BrokenPipeError:       # the reader left (| head): the findings still go to stderr
            from vmach.cli import pipe_closed

            pipe_closed()
    for f in [*result.findings, *_stood_in(result, library)]:
        sys.stderr.write(f.render() + "\n")
    return code


def _stood_in(result: RunResult, library) -> list:
    """A ``default_tool`` warning at every tool change to a tool the stand-in replaces."""
    if getattr(library, "stood_in", None) is None:
        return []
    from vmach.checks.process import unknown_tools

    return [f for f in unknown_tools(result.commands, library) if f.kind == "default_tool"]


def add_linuxcnc_arguments(p: argparse.ArgumentParser) -> None:
    """The options of RS274/NGC programs that stand for LinuxCNC's configuration files."""
    p.add_argument("--tool-table", help="LinuxCNC tool table (.tbl) for RS274/NGC programs")
    p.add_argument("--ini", help="LinuxCNC INI file for RS274/NGC programs: its [RS274NGC] "
                   "settings, #<_ini[...]> values and SUBROUTINE_PATH directories")
    p.add_argument("--var-file", help="LinuxCNC parameter file (.var) for RS274/NGC programs: "
                   "read at the start; the parameters at the end go to NAME.vmach.var")


def linuxcnc_options(args: argparse.Namespace) -> dict:
    """``RunOptions.dialect_options`` from the options of :func:`add_linuxcnc_arguments`
    (and run's --var-file-update/--continue-after-error). The dialect reads the files (a
    file it cannot read is its finding)."""
    out: dict = {}
    for name in ("tool_table", "ini", "var_file"):
        value = getattr(args, name, None)
        if value:
            out[name] = value
    if getattr(args, "var_file_update", False):
        out["var_file_update"] = True
    if getattr(args, "block_delete", False):
        out["block_delete"] = True
    if getattr(args, "continue_after_error", False):
        out["continue_after_error"] = True
    return out


def _oriented_ends(commands: list, model) -> dict[int, dict]:
    """Axis values the model's transformation gives (vmach.machine.oriented), by command index:
    the end of each TRAORI/CYCLE800 block (OrientedMove) and the motions whose positions only
    the machine knew (``nan`` after TRAORI or TRAFOOF)."""
    from vmach.canon import OrientedMove
    from vmach.machine.oriented import needs_resolving, resolve

    if not needs_resolving(commands):
        return {}
    solved, _ = resolve(commands, model, ends_only=True)
    out: dict[int, dict] = {}
    j = 0
    for i, c in enumerate(commands):
        row = solved[j + 1] if j + 1 < len(solved) else None
        if isinstance(c, OrientedMove) and isinstance(row, MOTIONS) and row.source is c.source:
            out[i] = dict(row.axes)
            j += 1
        elif isinstance(c, MOTIONS) and any(v != v for v in c.axes.values()):
            out[i] = dict(solved[j].axes)
        j += 1
    return out


def _json_line(cmd, drives: dict | None) -> str:
    if drives is None:
        return format_json(cmd)
    row = cmd.to_json()
    row["drives"] = drives
    return dumps(row)


def _library(program: Path, tools: str | None, default: str | None = None):
    """The tool library (tool radius compensation, the control's tool data): ``--tools``, else
    the setup file's library, else None; with ``--default-tool`` (or the setup's
    ``default_tool``) a stand-in answers for the tools it lacks."""
    from vmach.setup import read_setup, setting
    from vmach.tooling.library import load_tools

    setup = read_setup(program)
    path = Path(tools) if tools else setup.tools
    library = load_tools(path) if path is not None else None
    spec = default or setup.default_tool
    if spec:
        from vmach.tooling.default import WithDefault, parse_default_tool

        with setting(setup, "default_tool", default):
            library = WithDefault(library, parse_default_tool(
                spec, "--default-tool" if default else "default_tool"))
    return library


def _drive_values(model_path: Path | None, result: RunResult) -> dict[int, dict]:
    """Actuator values of every motion's end pose on a machine with parallel drives (the
    "second post-processor computation" of a hybrid machine); unreachable poses become findings
    and carry ``null`` drives."""
    if model_path is None:
        return {}
    import numpy as np

    from vmach.machine import load_model, unreachable_findings

    model = load_model(model_path)
    if not model.spec.parallel:
        return {}
    ends = _oriented_ends(result.commands, model)
    idx = [i for i, c in enumerate(result.commands) if isinstance(c, MOTIONS) or i in ends]
    if not idx:
        return {}
    home = dict(zip(model.axes, model.home, strict=True))
    q = np.array([[ends.get(i, result.commands[i].axes).get(a, home[a]) for a in model.axes] for i in idx])
    values, ok = model.drive_values(q)
    known = ~np.isnan(q).any(axis=1)     # nan: a position only the machine knows (after TRAORI)
    out = {}
    for row, i in enumerate(idx):
        out[i] = {d: (float(v[row]) if ok[row] else None) for d, v in values.items()}
    result.findings.extend(
        unreachable_findings(ok | ~known, sources=[result.commands[i].source for i in idx], move_index=idx)
    )
    return out
