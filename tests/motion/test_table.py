"""The move table: rows, provenance, state columns, arc chords within tolerance."""

from __future__ import annotations

import math

import numpy as np
import pytest
from catalog import TURNMILL
from nc import ok

from vmach.canon import DEFAULT_CONTROL
from vmach.machine.control import load_control
from vmach.motion import ARC, FEED, TRAVERSE, build

TURN = load_control(TURNMILL)


def test_rows_carry_state_and_source(tmp_path):
    r = ok(
        tmp_path,
        """
T="GLOD D40" D1
SETMS(2)
S2=640 M2=3
G0 X40 Y0 Z5
G1 Z-10 F620
G95 F0.1
G1 X30
M30
""",
        TURN,
    )
    t = build(r.commands, TURN)
    assert t.axes == ("X", "Y", "Z", "C1") and len(t) == 3
    assert list(t.kind) == [TRAVERSE, FEED, FEED]
    assert math.isnan(t.feed[0]) and t.feed[1] == 620 and t.feed[2] == 0.1
    assert list(t.feed_mode) == [0, 0, 1]
    assert t.tools == ("GLOD D40",) and list(t.tool) == [0, 0, 0] and list(t.offset) == [1, 1, 1]
    s2 = t.spindles.index(2)
    assert list(t.speed[:, s2]) == [640, 640, 640] and list(t.direction[:, s2]) == [1, 1, 1]
    assert list(t.master) == [2, 2, 2]
    assert list(t.line) == [5, 6, 8]
    assert t.start[0].tolist() == [a.home for a in TURN.axes]
    assert np.array_equal(t.start[1:], t.end[:-1])
    assert t.source(2).line == 8 and t.files == (str(tmp_path / "TEST.MPF"),)
    with pytest.raises(ValueError):
        t.end[0, 0] = 1.0  # read-only


@pytest.mark.parametrize("chord", [0.01, 0.001])
def test_arc_chords_stay_within_tolerance(tmp_path, chord):
    r = ok(tmp_path, "G0 X10 Y0 Z0\nG3 X-10 Y0 I-10 J0 Z-4 TURN=1 F100\nM30\n")
    from vmach.canon import DEFAULT_CONTROL

    t = build(r.commands, DEFAULT_CONTROL, chord=chord)
    arc = t.kind == ARC
    a, b = t.start[arc], t.end[arc]
    # every chord end lies on the circle, the sagitta of each chord is within the tolerance
    for p in (a, b):
        assert np.allclose(np.hypot(p[:, 0], p[:, 1]), 10.0)
    half = np.hypot(*(b[:, :2] - a[:, :2]).T) / 2
    sagitta = 10.0 - np.sqrt(100.0 - half**2)
    assert sagitta.max() <= chord + 1e-12
    # one and a half turns counter-clockwise, Z falls linearly with the angle
    ang = np.unwrap(np.arctan2(b[:, 1], b[:, 0]))
    assert ang[-1] - np.arctan2(a[0, 1], a[0, 0]) == pytest.approx(3 * math.pi)
    assert np.all(np.diff(b[:, 2]) < 0) and b[-1, 2] == -4


def test_exact_stop_column_follows_path_mode(tmp_path):
    """G60 marks every block end, G9 only its own block, arcs only their last chord."""
    r = ok(
        tmp_path,
        """
G0 X0 Y0 Z0
G1 X10 F100
G9 G1 Y10
G1 X0
G60
G1 Y0
G2 X10 Y0 I5 J0
G64 G1 X20
G9 G2 X30 Y0 I5 J0
G1 X40
M30
""",
    )
    t = build(r.commands, DEFAULT_CONTROL)
    by_line: dict[int, list[bool]] = {}
    for line, stop in zip(t.line.tolist(), t.exact_stop.tolist(), strict=True):
        by_line.setdefault(line, []).append(stop)
    assert by_line[2] == [False] and by_line[3] == [False]
    assert by_line[4] == [True] and by_line[5] == [False]
    assert by_line[7] == [True]
    assert len(by_line[8]) > 10 and by_line[8][-1] and not any(by_line[8][:-1])
    assert by_line[9] == [False]
    assert by_line[10][-1] and not any(by_line[10][:-1])
    assert by_line[11] == [False]
    assert t.exact_stop.dtype == bool and not t.exact_stop.flags.writeable


def test_an_arc_or_a_program_beyond_the_tables_size_is_a_resource_limit_at_its_line(tmp_path):
    """Found by fuzzing: `G2 ... TURN=1000000000` asked numpy for 1.6 TiB of chord points."""
    from vmach.errors import ProgramError

    r = ok(tmp_path, "G0 X10 Y0 Z0\nG1 Z-1 F100\nG3 X10 Y0 I-10 J0 TURN=1000000000 F100\nM30\n")
    with pytest.raises(ProgramError) as exc:
        build(r.commands, DEFAULT_CONTROL)
    assert (exc.value.kind, exc.value.source.line) == ("resource_limit", 3)
    # the budget is the table's: a small one stops at the move that passes it
    r = ok(tmp_path, "G0 X10 Y0 Z0\nG3 X-10 Y0 I-10 J0 F100\nG1 X0\nG1 X1\nG1 X2\nM30\n")
    rows = len(build(r.commands, DEFAULT_CONTROL))
    assert len(build(r.commands, DEFAULT_CONTROL, max_moves=rows)) == rows
    for most, line in ((rows - 1, 5), (rows - 3, 3), (5, 2)):
        with pytest.raises(ProgramError) as exc:
            build(r.commands, DEFAULT_CONTROL, max_moves=most)
        assert (exc.value.kind, exc.value.source.line) == ("resource_limit", line)


def test_huge_arcs_and_positions_beyond_any_machine_are_resource_limits(tmp_path):
    """Found by fuzzing: an arc of radius 1e300 divided by a zero angle step (now: arcs of a
    radius up to 1e9 mm are cut into chords, beyond that a resource_limit); a TRANS of 1e200
    mm made the collision sampler ask for an array of negative size (now: beyond tol.max_size
    is a resource_limit at the move)."""
    from vmach.errors import ProgramError

    t = build(ok(tmp_path, "G0 X40 Y0 Z0\nG2 X41 Y0 CR=1EX8 F100\nM30\n").commands, DEFAULT_CONTROL)
    assert list(t.kind) == [TRAVERSE, ARC] and t.end[-1, 0] == 41
    for text, line in (("G0 X40 Y0 Z0\nG2 X41 Y0 CR=1EX300 F100\nM30\n", 2),
                       ("G0 X40 Y0 Z0\nTRANS Z=1EX200\nG0 Z0\nM30\n", 3),
                       ("G0 X40 Y0 Z0\nG1 X=10001 F100\nM30\n", 2)):
        r = ok(tmp_path, text)
        with pytest.raises(ProgramError) as exc:
            build(r.commands, DEFAULT_CONTROL)
        assert (exc.value.kind, exc.value.source.line) == ("resource_limit", line)
    assert len(build(ok(tmp_path, "G0 X40 Y0 Z0\nG1 X=9999 F100\nM30\n").commands, DEFAULT_CONTROL)) == 2
