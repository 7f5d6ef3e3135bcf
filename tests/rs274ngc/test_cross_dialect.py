"""The same turn-mill part written in RS274/NGC and in Sinumerik gives the same canonical stream.

Both programs turn a shoulder in the ZX plane (X as a radius, feed per revolution) and mill
a flat with the C axis; the only difference allowed is where each command came from.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from vmach.canon import AxisSpec, ControlSpec, RunOptions

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "rs274ngc"
CONTROL = ControlSpec(
    axes=(AxisSpec("X"), AxisSpec("Y"), AxisSpec("Z"), AxisSpec("C", "rotary")),
    strict_axes=True,
)


def _stream(result):
    rows = []
    for cmd in result.commands:
        row = cmd.to_json()
        del row["file"], row["line"]
        rows.append(row)
    return rows


def test_turnmill_part_same_canonical_stream_in_both_dialects():
    sinumerik = pytest.importorskip("interpreters.sinumerik")
    from interpreters import rs274ngc

    ngc = rs274ngc.run(FIXTURES / "turnmill_part.ngc", CONTROL, RunOptions())
    mpf = sinumerik.run(FIXTURES / "cross_dialect" / "TURNMILL_PART.MPF", CONTROL, RunOptions())
    assert ngc.completed and mpf.completed
    assert ngc.findings == [] and mpf.findings == []
    assert len(ngc.commands) > 20
    assert _stream(ngc) == _stream(mpf)
