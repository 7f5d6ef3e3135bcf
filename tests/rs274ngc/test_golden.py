"""Golden traces: vmach prints what LinuxCNC's ``rs274 -g`` printed for the same program.

The expected files were generated once with LinuxCNC 2.9's standalone interpreter (see
``fixtures/rs274ngc/README.md`` and ``regen.py``); these tests do not need rs274.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from interpreters.rs274ngc import FORMATS

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "rs274ngc"
PROGRAMS = sorted(p for p in FIXTURES.glob("*.ngc") if not p.name.startswith("lib_"))


def test_enough_golden_programs():
    assert len(PROGRAMS) >= 40
    assert all(p.with_suffix(".expected").exists() for p in PROGRAMS)


def _trace(program: Path):
    """Run as regen.py ran rs274: from the fixture directory, the file by its name."""
    extra = {}
    table = program.with_suffix(".tbl")
    if table.exists():
        extra["tool_table"] = table.name
    return FORMATS["rs274"](program.name, None, None, extra)


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_trace_matches_rs274(program: Path, monkeypatch):
    expected = program.with_suffix(".expected").read_text(encoding="utf-8").splitlines()
    monkeypatch.chdir(FIXTURES)
    lines, result = _trace(program)
    assert lines == expected
    stderr = program.with_suffix(".stderr")
    if stderr.exists():
        # rs274 prints "executing", its message, then the text of the offending line
        err = stderr.read_text(encoding="utf-8").split("\n")
        assert not result.completed
        finding = result.findings[-1]
        assert finding.is_error
        assert finding.message == err[1]
        assert finding.source.text.rstrip() == err[2]
    else:
        assert result.completed, [f.render() for f in result.findings]
        assert result.findings == []
