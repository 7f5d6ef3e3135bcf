"""Golden traces: each fixture program beside its expected canonical trace.

Regenerate after a deliberate change with ``VMACH_REGEN=1 python -m pytest tests/sinumerik/test_golden.py``
and review the diff like code.
"""

from __future__ import annotations

import os

import pytest
from catalog import FIXTURES, ROOT

from interpreters import sinumerik
from vmach.canon import RunOptions, format_text
from vmach.setup import control_for

GOLDEN = sorted((FIXTURES / "sinumerik").glob("*.MPF")) + [FIXTURES / "polygon_shaft" / "POLY14.MPF"]


@pytest.mark.parametrize("program", GOLDEN, ids=lambda p: p.name)
def test_trace_matches_golden(program, monkeypatch):
    monkeypatch.chdir(ROOT)
    rel = program.relative_to(ROOT)
    control, _ = control_for(rel, None)
    result = sinumerik.run(str(rel), control, RunOptions())
    assert result.completed, [f.render() for f in result.findings]
    text = "".join(format_text(c, i) + "\n" for i, c in enumerate(result.commands, 1))
    expected = program.with_suffix(".trace")
    if os.environ.get("VMACH_REGEN"):
        expected.write_text(text, encoding="utf-8")
    assert expected.is_file(), f"no golden trace {expected.name}; run with VMACH_REGEN=1"
    assert text == expected.read_text(encoding="utf-8")
