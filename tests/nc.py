"""Helpers to run small Sinumerik programs written inside tests."""

from __future__ import annotations

from pathlib import Path

from interpreters import sinumerik
from vmach.canon import DEFAULT_CONTROL, MOTIONS, ControlSpec, RunOptions, RunResult
from vmach.findings import Finding


def write(directory: Path, text: str, name: str = "TEST.MPF", **files: str) -> Path:
    for fname, body in files.items():
        (directory / fname.replace("_DOT_", ".")).write_text(body, encoding="utf-8")
    p = directory / name
    p.write_text(text, encoding="utf-8")
    return p


def linked_from_outside(tmp_path: Path, name: str, body: str) -> Path:
    """A job directory in ``tmp_path`` whose ``name`` is a symbolic link to a file of ``body``
    beside it, outside the job directory; returns the job directory."""
    outside = tmp_path / name
    outside.write_text(body, encoding="utf-8")
    job = tmp_path / "job"
    job.mkdir()
    (job / name).symlink_to(outside)
    return job


def run(
    directory: Path,
    text: str,
    control: ControlSpec = DEFAULT_CONTROL,
    options: RunOptions | None = None,
    name: str = "TEST.MPF",
    **files: str,
) -> RunResult:
    return sinumerik.run(write(directory, text, name, **files), control, options or RunOptions())


def ok(directory: Path, text: str, control: ControlSpec = DEFAULT_CONTROL, **files: str) -> RunResult:
    r = run(directory, text, control, **files)
    assert r.completed, [f.render() for f in r.findings]
    return r


def moves(result: RunResult) -> list:
    return [c for c in result.commands if isinstance(c, MOTIONS)]


def check(
    directory: Path, text: str, control: ControlSpec = DEFAULT_CONTROL, name: str = "TEST.MPF", **files: str
) -> list[Finding]:
    return sinumerik.check(write(directory, text, name, **files), control)


def kinds(findings: list[Finding], severity: str | None = None) -> list[tuple[str, int]]:
    return [(f.kind, f.line) for f in findings if severity is None or f.severity == severity]


def error_of(result: RunResult) -> Finding:
    assert not result.completed
    errs = [f for f in result.findings if f.severity == "error"]
    assert errs
    return errs[-1]


#: tool radii for compensation tests: T1 D1 5 mm, T1 D2 2 mm
RADII = RunOptions(tool_radius=lambda tool, d: {("1", 1): 5.0, ("1", 2): 2.0}.get((tool, d)))


def plane_path(result: RunResult) -> list[tuple]:
    """(kind, x, y[, centre, clockwise]) of every motion, rounded to 1e-9 mm: kind 'L' for a
    line or traverse, 'A' for an arc."""
    from vmach.canon import ArcFeed

    out = []
    for m in moves(result):
        if isinstance(m, ArcFeed):
            out.append(("A", round(m.axes["X"], 9), round(m.axes["Y"], 9), m.center, m.clockwise))
        else:
            out.append(("L", round(m.axes["X"], 9), round(m.axes["Y"], 9)))
    return out
