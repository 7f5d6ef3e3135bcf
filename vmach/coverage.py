"""What ``vmach verify`` could and could not check: never a silent pass.

- The static checks (``vmach check``) run first and every one of their findings is reported;
  the run's own findings follow, the same defect at the same place said once.
- A stage that could not run (no tool library, no stock, an unfinished program ...) is named in
  ``report.skipped`` (stage -> reason; ``skipped`` in report.json and a line of the text
  summary) and is a ``stage_skipped`` warning.
- A run that stopped early is partial: :func:`stop_place` says where, and the figures that would
  cover the whole program (cycle time, profile verdict) are not given.
"""

from __future__ import annotations

from collections.abc import Iterable

from vmach.findings import Finding
from vmach.source import SourceRef

#: the stages ``skipped`` may name, in pipeline order, with what each would have checked
STAGES = {
    "stock": "material removal, rapid_into_stock, holder_collision, near_miss",
    "fixture_collisions": "fixture_collision and near_miss of the tools against chuck, jaws, table",
    "profile": "the part against its DIN profile band",
    "design": "the part against its design (design_gouge, design_excess)",
    "cycle_time": "the program's cycle time",
}


def skip(report, stage: str, reason: str, source: SourceRef | None = None) -> None:
    """Record that ``stage`` did not run and why: ``report.skipped`` and a warning finding."""
    assert stage in STAGES, stage
    if stage in report.skipped:
        return
    report.skipped[stage] = reason
    report.findings.append(Finding("stage_skipped", "warning", f"not checked: {STAGES[stage]} ({reason})",
                                   source, None, {"stage": stage, "reason": reason}))


#: errors that stop a runaway program at one of vmach's limits (an endless loop or recursion, a
#: program that makes more than vmach holds): verify checks nothing after the interpreter then
RUNAWAY = frozenset({"block_limit", "call_depth", "resource_limit"})


def runaway(result) -> Finding | None:
    """The error that stopped ``result`` (a RunResult) at one of vmach's limits, or None."""
    if result is None or result.completed:
        return None
    for f in reversed(result.findings):
        if f.severity == "error":
            return f if f.kind in RUNAWAY else None
    return None


def say_skipped(report, spec: str | None, library, profile: bool, stopped: Finding | None = None,
                design: bool = False) -> None:
    """Each stage of ``report`` (vmach.verify.Report) that cannot run, with its reason: no stock
    ``spec``, no tool ``library``, an unfinished run; ``profile``: a profile check was asked
    for; ``stopped``: the run stopped at a limit (:func:`runaway`), so no stage after the
    interpreter runs (a limit bites as fast in ``verify`` as in ``run``); ``design``: a design
    comparison was asked for."""
    if stopped is not None:
        reason = (f"the run stopped at vmach's limit ({stopped.kind} at {where(stopped.source)}): "
                  "nothing after the interpreter is checked")
        asked = {"profile": profile, "design": design}
        for stage in STAGES:
            if asked.get(stage, True):
                skip(report, stage, reason, stopped.source)
    no_lib = "no tool library: give --tools (or tools = in vmach.toml), or --default-tool"
    if not spec:
        skip(report, "stock", "no stock: give --stock (or stock = in vmach.toml, or the program's "
                      "WORKPIECE)")
    elif library is None:
        skip(report, "stock", no_lib)
    if library is None:
        skip(report, "fixture_collisions", no_lib)
    if report.stopped_at is not None:
        stop = f"the program stopped at {where(report.stopped_at)}"
        skip(report, "cycle_time", stop, report.stopped_at)
        if profile:
            skip(report, "profile", f"{stop}: the part is unfinished", report.stopped_at)
    elif profile and (not spec or library is None):
        skip(report, "profile", "no simulated stock to measure")


def merged(static: Iterable[Finding], runtime: Iterable[Finding]) -> list[Finding]:
    """The static findings, then the run's that do not repeat one: a defect both find is said
    once, in the static checks' kind and words — the same kind at the same place, or a run's
    error on a line where the static checks already found one (a call to a missing subprogram
    is ``unknown_cycle`` there and ``subprogram_not_found`` when the run reaches it)."""
    out = list(static)

    def place(f: Finding) -> tuple:
        return (f.source.path if f.source else None, f.line)

    seen = {(f.kind, *place(f)) for f in out}
    wrong = {place(f) for f in out if f.severity == "error" and f.source is not None}
    out.extend(f for f in runtime if (f.kind, *place(f)) not in seen
               and not (f.severity == "error" and place(f) in wrong))
    return out


def stop_place(result) -> SourceRef | None:
    """Where an unfinished run stopped: the place of the error that stopped it (the last error
    the interpreter reported), None for a run that finished."""
    if result is None or result.completed:
        return None
    for f in reversed(result.findings):
        if f.severity == "error" and f.source is not None:
            return f.source
    return SourceRef("?", 0)


def where(source: SourceRef | None) -> str:
    """``FILE:LINE`` of a place (``?`` when unknown)."""
    if source is None:
        return "?"
    return f"{source.path}:{source.line}"


def summary_lines(report) -> list[str]:
    """The text summary's lines about what was not checked and a partial run."""
    lines = []
    if report.stopped_at is not None:
        lines.append(f"stopped at {where(report.stopped_at)}: the figures below cover the program up "
                     "to there only (partial); no cycle time or verdict for an unfinished program")
    for stage, reason in report.skipped.items():
        lines.append(f"skipped {stage}: {reason}")
    return lines


def toolless_feeds(table, simulated: bool) -> list[Finding]:
    """A ``no_tool`` warning at the first feed move made with no tool selected (before any T,
    or after T0) when the stock is simulated: such moves remove no material."""
    import numpy as np

    from vmach.motion.table import TRAVERSE

    if not simulated or len(table) == 0:
        return []
    rows = np.flatnonzero((np.asarray(table.tool) < 0) & (table.kind != TRAVERSE))
    if len(rows) == 0:
        return []
    return [Finding("no_tool", "warning", f"feed move with no tool selected ({len(rows)} moves): the "
                    "simulation removes no material with it", table.source(int(rows[0])), int(rows[0]),
                    {"moves": int(len(rows))})]
