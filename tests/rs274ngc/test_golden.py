"""Golden traces: vmach prints what LinuxCNC's ``rs274 -g`` printed for the same program.

The expected files were generated once with LinuxCNC 2.9's standalone interpreter (see
``fixtures/rs274ngc/README.md`` and ``regen.py``); these tests do not need rs274.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from rs274ngc.fixture_options import fixture_options

from interpreters.rs274ngc import FORMATS

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "rs274ngc"
PROGRAMS = sorted(p for p in FIXTURES.glob("*.ngc") if not p.name.startswith("lib_"))


def test_enough_golden_programs():
    assert len(PROGRAMS) >= 40
    assert all(p.with_suffix(".expected").exists() for p in PROGRAMS)


def _trace(program: Path, tmp: Path):
    """Run as regen.py ran rs274: from the fixture directory, the file by its name."""
    return FORMATS["rs274"](program.name, None, None, fixture_options(program, tmp))


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_trace_matches_rs274(program: Path, monkeypatch, tmp_path):
    expected = program.with_suffix(".expected").read_text(encoding="utf-8").splitlines()
    monkeypatch.chdir(FIXTURES)
    lines, result = _trace(program, tmp_path)
    assert lines == expected
    var_out = program.with_suffix(".var.out")
    if var_out.exists():  # the parameter file as rs274 left it
        assert (tmp_path / program.with_suffix(".var").name).read_text() == var_out.read_text()
    stderr = program.with_suffix(".stderr")
    if stderr.exists():
        # rs274 prints "executing", then for each error its message and the offending line
        err = stderr.read_text(encoding="utf-8").split("\n")[1:-1]
        errors = [f for f in result.findings if f.is_error]
        assert [(f.message, f.source.text.rstrip()) for f in errors] == list(
            zip(err[0::2], err[1::2], strict=True))
        go_on = "-n 0" in (program.with_suffix(".opts").read_text(encoding="utf-8")
                           if program.with_suffix(".opts").exists() else "")
        assert result.completed == go_on
    else:
        assert result.completed, [f.render() for f in result.findings]
        assert result.findings == []
