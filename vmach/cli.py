"""Command line: ``vmach <command> ...``.

Each command lives in ``vmach/commands/<name>.py`` and provides ``HELP`` (one line),
``add_arguments(parser)`` and ``run(args) -> int``. ``main`` turns every :class:`VmachError`
into a diagnostic on stderr and an exit code (0 ok, 1 findings or program errors, 2 usage or
unreadable input); no Python traceback reaches the user for bad input.
"""

from __future__ import annotations

import argparse
import importlib
import re
import sys
from collections.abc import Sequence

from vmach import __version__
from vmach.errors import VmachError

#: command name -> module; a module that does not exist yet is simply not offered.
COMMANDS: dict[str, str] = {
    "check": "vmach.commands.check",
    "run": "vmach.commands.run",
    "verify": "vmach.commands.verify",
    "fk": "vmach.commands.fk",
    "ik": "vmach.commands.ik",
    "postcheck": "vmach.commands.postcheck",
    "profile": "vmach.commands.profile",
    "machines": "vmach.commands.machines",
    "batch": "vmach.commands.batch",
    "demo": "vmach.commands.demo",
}

#: the one-line help of each command, so that ``vmach --help`` and ``vmach --version`` import
#: no command module (each pulls numpy and more); a command missing here is imported for its
#: help (tests/test_cli_startup.py holds these equal to the modules' ``HELP``)
HELPS: dict[str, str] = {
    "check": "check a program without running it: syntax, unknown words, jumps, structure",
    "run": "run a program and print the canonical commands it produces",
    "verify": "verify a program on a machine: limits, collisions, stock, profile, cycle time, report",
    "fk": "forward kinematics: axis values -> tool tip and axis in the workpiece frame",
    "ik": "inverse kinematics: tool tip and axis in the workpiece frame -> axis values",
    "postcheck": "check post-processed G-code against the CAM cutter-location (APT CL) data",
    "profile": "print the sizes of a DIN 32711 P3G / DIN 32712 P4C profile (and draw it with --png)",
    "machines": "list the bundled machine models, one line each",
    "batch": "verify many programs, or a parametric program over a size family (DIN 32711 P3G), on Dask",
    "demo": "the instructor's demo: the polygon-shaft family verified, and an animation of one size's cut",
}


#: a negative number or a list or range starting with one (``-35:-5``, ``-1,2,3``, ``-.5``)
_NEGATIVE_VALUE = re.compile(r"^-\.?\d")


def negative_values_joined(argv: Sequence[str]) -> list[str]:
    """``argv`` with a value that starts with a minus sign and a digit joined to the option
    before it (``--profile-z -35:-5`` → ``--profile-z=-35:-5``): argparse takes such a token
    for an option unless it is a plain number, and no vmach option starts with a digit."""
    out: list[str] = []
    for tok in argv:
        if out and _NEGATIVE_VALUE.match(tok) and out[-1].startswith("--") and "=" not in out[-1]:
            out[-1] = f"{out[-1]}={tok}"
        else:
            out.append(tok)
    return out


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # usage errors exit 2 with one clear line
        self.print_usage(sys.stderr)
        sys.stderr.write(f"vmach: error[usage]: {message}\n")
        raise SystemExit(2)


def _module(modname: str):
    """The command's module, or None when it does not exist (yet)."""
    try:
        return importlib.import_module(modname)
    except ModuleNotFoundError as exc:
        if exc.name == modname:
            return None
        raise


def build_parser(only: str | None = None) -> tuple[argparse.ArgumentParser, dict[str, object]]:
    """The parser with every command; the arguments of ``only`` (when given) or of every
    command. Only the modules whose arguments are added are imported: ``vmach --version``
    and ``vmach check`` do not pay for the libraries of ``verify`` (benchmarks/startup.py)."""
    parser = _Parser(prog="vmach", description="G-code verifier and virtual machine simulator.")
    parser.add_argument("--version", action="version", version=f"vmach {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    modules: dict[str, object] = {}
    for name, modname in COMMANDS.items():
        if only is not None and name != only and name in HELPS:
            sub.add_parser(name, help=HELPS[name], description=HELPS[name])
            continue
        mod = _module(modname)
        if mod is None:
            continue
        p = sub.add_parser(name, help=mod.HELP, description=mod.HELP)
        mod.add_arguments(p)
        modules[name] = mod
    return parser, modules


def _command(argv: Sequence[str]) -> str:
    """The command named in ``argv`` (its first word that is not an option), or ''."""
    for tok in argv:
        if not tok.startswith("-"):
            return tok if tok in COMMANDS else ""
        if tok == "--":
            break
    return ""


def main(argv: Sequence[str] | None = None) -> int:
    argv = negative_values_joined(sys.argv[1:] if argv is None else argv)
    parser, modules = build_parser(_command(argv))
    args = parser.parse_args(argv)
    if not args.command:
        parser.print_help(sys.stderr)
        return 2
    try:
        return int(modules[args.command].run(args))  # type: ignore[attr-defined]
    except VmachError as exc:
        for f in exc.findings():
            sys.stderr.write(f.render() + "\n")
        return exc.exit_code
    except KeyboardInterrupt:
        sys.stderr.write("vmach: interrupted\n")
        return 130
    except BrokenPipeError:
        # the reader went away (``vmach run P | head``): stop writing, quietly, with the
        # command's own exit code when it was known before its output (never a clean 0 for a
        # program with errors)
        pipe_closed()
        return int(getattr(args, "exit_code", 0))


def pipe_closed() -> None:
    """Point stdout at /dev/null after its reader left, so that nothing more (nor the
    interpreter's flush at exit) raises BrokenPipeError."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):
        pass


if __name__ == "__main__":
    raise SystemExit(main())
