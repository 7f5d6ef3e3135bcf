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


def build_parser() -> tuple[argparse.ArgumentParser, dict[str, object]]:
    parser = _Parser(prog="vmach", description="G-code verifier and virtual machine simulator.")
    parser.add_argument("--version", action="version", version=f"vmach {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    modules: dict[str, object] = {}
    for name, modname in COMMANDS.items():
        try:
            mod = importlib.import_module(modname)
        except ModuleNotFoundError as exc:
            if exc.name == modname:
                continue
            raise
        p = sub.add_parser(name, help=mod.HELP, description=mod.HELP)
        mod.add_arguments(p)
        modules[name] = mod
    return parser, modules


def main(argv: Sequence[str] | None = None) -> int:
    parser, modules = build_parser()
    args = parser.parse_args(negative_values_joined(sys.argv[1:] if argv is None else argv))
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
