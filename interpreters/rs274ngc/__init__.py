"""RS274/NGC as LinuxCNC 2.9 runs it.

Entry points (see ``interpreters/__init__.py``)::

    EXTENSIONS                         file extensions read by this dialect
    check(path, control)               static diagnostics, without running the program
    run(path, control, options)        canonical commands (mm, machine axes) and findings
    FORMATS["rs274"](path, control, options, extra)
                                       the trace LinuxCNC's ``rs274 -g`` prints, line for line

Deliberate differences from LinuxCNC are listed in ``DEVIATIONS.md`` beside this file.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from interpreters.rs274ngc.checker import check_program
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.interp import Interpreter
from interpreters.rs274ngc.output import Output
from interpreters.rs274ngc.state import OpenToolTable, default_tool_table, read_tool_table
from vmach.canon import DEFAULT_CONTROL, ControlSpec, RunOptions, RunResult
from vmach.findings import Finding, error
from vmach.source import SourceRef

EXTENSIONS = (".ngc", ".nc", ".tap")


def _axes(control: ControlSpec) -> dict[str, float]:
    axes = {a.name: a.home for a in control.axes}
    for name in "XYZ":
        axes.setdefault(name, 0.0)
    return axes


def _interpret(path, control, options, extra, trace: bool, commands: bool):
    control = control or DEFAULT_CONTROL
    options = options or RunOptions()
    extra = extra or {}
    out = Output(trace, commands, _axes(control))
    table = extra.get("tool_table")
    if table and options.tool_radius is not None:
        options = replace(options, tool_radius=None)   # a LinuxCNC tool table given: its diameters
    try:
        # rs274 prints its notes on the tool table before anything else
        tools = read_tool_table(table, out.lines if trace else None) if table else (
            default_tool_table() if options.tool_radius is None else OpenToolTable())
    except NgcError as exc:
        f = error(exc.kind, exc.message, SourceRef(str(table), 1))
        return out, RunResult([], [f], False, 0)
    interp = Interpreter(str(path), control, options, out, tools,
                         block_delete=bool(extra.get("block_delete", False)))
    if not control.strict_axes:
        out.extra_axes = {"A", "B", "C"}
    completed, finding = interp.run()
    findings: list[Finding] = [] if finding is None else [finding]
    return out, RunResult(out.commands, findings, completed, interp.blocks)


def run(path, control: ControlSpec = DEFAULT_CONTROL,
        options: RunOptions | None = None) -> RunResult:
    """Interpret ``path``; canonical commands in mm with their SourceRef.

    A runtime error stops the run: ``completed`` is False and the error is the last finding.
    """
    return _interpret(path, control, options, None, trace=False, commands=True)[1]


def rs274_trace(path, control: ControlSpec = DEFAULT_CONTROL, options: RunOptions | None = None,
                extra: dict | None = None, *, commands: bool = False
                ) -> tuple[list[str], RunResult]:
    """The lines ``rs274 -g [-t TOOLTABLE] path`` prints on stdout, and the run's result.

    extra : ``{"tool_table": path}`` for a LinuxCNC tool table, ``{"block_delete": True}``
        for rs274's ``-b``.
    commands : also build the canonical commands (``result.commands``, as :func:`run`
        gives them). Off by default: the trace is this format's output, and ``result`` is
        for ``completed``, ``findings`` and ``blocks``, which are the same either way.
    """
    out, result = _interpret(path, control, options, extra, trace=True, commands=commands)
    return out.lines, result


FORMATS: dict[str, Callable] = {"rs274": rs274_trace}


def check(path, control: ControlSpec = DEFAULT_CONTROL) -> list[Finding]:
    """Static diagnostics: syntax, unknown words, unbalanced O-blocks, undefined subs ..."""
    return check_program(str(path), control or DEFAULT_CONTROL)
