"""Reading as the control reads: words without separators, jump targets, incremental moves
after a frame change (Programming Manual Fundamentals, "Block components", "Extended address
notation"; Job planning, "Program jumps")."""

from __future__ import annotations

from dataclasses import dataclass, field

import pytest
from catalog import TURNMILL
from nc import check, error_of, moves, ok, run

from vmach.canon import DEFAULT_CONTROL, ControlSpec, Spindle, ToolChange
from vmach.machine.control import load_control

TURN = load_control(TURNMILL)


def trace(result) -> list[tuple]:
    """Every command's kind, line and fields: two runs that read the same agree on all of it."""
    return [(c.kind, c.source.line, c.fields()) for c in result.commands]


@pytest.mark.parametrize(
    "glued, separated",
    [
        ("N10G0G90X0Y0Z5", "N10 G0 G90 X0 Y0 Z5"),
        ("G0X100Y-80Z-450", "G0 X100 Y-80 Z-450"),
        ("N10G1X5F100", "N10 G1 X5 F100"),
        ("S200M3", "S200 M3"),
        ("T1D1M6", "T1 D1 M6"),
        ("G4F30", "G4 F30"),
        ("G1X.5Y10.5Z3.F200", "G1 X.5 Y10.5 Z3. F200"),
        ("R1=4R2=R1+1G0X=R1Y=R2", "R1=4 R2=R1+1 G0 X=R1 Y=R2"),
        ("G91G1X10F100M8", "G91 G1 X10 F100 M8"),
    ],
)
def test_words_without_separators_read_as_separated_words(tmp_path, glued, separated):
    a = ok(tmp_path, f"G0 X1 Y1 Z1\n{glued}\nM30\n")
    b = ok(tmp_path, f"G0 X1 Y1 Z1\n{separated}\nM30\n")
    assert trace(a) == trace(b)
    assert check(tmp_path, f"{glued}\nM30\n") == []


def test_glued_tool_change_and_spindle_words_act(tmp_path):
    r = ok(tmp_path, "T1D1M6\nS200M3\nG0X10\nM30\n")
    tools = [c for c in r.commands if isinstance(c, ToolChange)]
    assert [(t.tool, t.offset) for t in tools] == [("1", 1)]
    spindles = [c for c in r.commands if isinstance(c, Spindle)]
    assert [(s.speed, s.direction) for s in spindles] == [(200.0, "cw")]


def test_extended_addresses_glued_to_each_other(tmp_path):
    # M2=3S2=640: spindle 2 clockwise at 640 rpm; G0C1=90: the turn-mill's axis C1
    r = ok(tmp_path, "M2=3S2=640\nG0C1=90\nM30\n", TURN)
    spindles = [c for c in r.commands if isinstance(c, Spindle)]
    assert [(s.spindle, s.speed, s.direction) for s in spindles] == [(2, 640.0, "cw")]
    assert moves(r)[-1].axes["C1"] == 90.0


def test_a_subprogram_name_is_never_split(tmp_path):
    # P3G_SUB is a program beside the main one: one call of it. Without it, the same letters
    # are the repeat count P3 and a call of G_SUB (three runs).
    sub = "G91 G0 X1\nM17\n"
    r = ok(tmp_path, "G90 G0 X0\nP3G_SUB\nM30\n", P3G_SUB_DOT_SPF=sub, G_SUB_DOT_SPF=sub)
    assert [m.axes["X"] for m in moves(r)] == [0.0, 1.0]
    (tmp_path / "P3G_SUB.SPF").unlink()
    r = ok(tmp_path, "G90 G0 X0\nP3G_SUB\nM30\n")
    assert [m.axes["X"] for m in moves(r)] == [0.0, 1.0, 2.0, 3.0]


def test_a_name_after_address_words_is_one_word(tmp_path):
    # N10DEPTH=2: block number N10, then the variable DEPTH; X10CR=5: X10, then CR
    r = ok(tmp_path, "DEF REAL DEPTH\nN10DEPTH=2\nG0X0Y0\nG2X10CR=5F100Z=DEPTH\nM30\n")
    arc = moves(r)[-1]
    assert (arc.axes["X"], arc.axes["Z"], arc.center) == (10.0, 2.0, pytest.approx((5.0, 0.0)))


def test_glued_words_report_their_own_column(tmp_path):
    # G0G1: two motion codes in one block, the second at column 3
    f = error_of(run(tmp_path, "G0G1X5\nM30\n"))
    assert (f.kind, f.line, f.source.column) == ("modal_conflict", 1, 3)


@pytest.mark.parametrize("how", ["GOTOF", "GOTO", "GOTOC"])
def test_a_jump_to_a_bare_number_lands_on_that_block_number(tmp_path, how):
    # the jump destination is a label, or a main or subblock number written with or without N
    r = ok(tmp_path, f"N10 G0 X1\nN20 {how} 40\nN30 G0 X99\nN40 G0 X2\n:50 G0 X3\nM30\n")
    assert [m.axes["X"] for m in moves(r)] == [1.0, 2.0, 3.0]
    r = ok(tmp_path, "N10 G0 X1\nN20 GOTOF 50\nN30 G0 X99\n:50 G0 X3\nM30\n")
    assert [m.axes["X"] for m in moves(r)] == [1.0, 3.0]


def test_a_backward_jump_to_a_bare_number(tmp_path):
    r = ok(tmp_path, "R1=0\nN10 R1=R1+1 G0 X=R1\nIF R1<3 GOTOB 10\nM30\n")
    assert [m.axes["X"] for m in moves(r)] == [1.0, 2.0, 3.0]
    assert [(f.kind, f.line) for f in check(tmp_path, "GOTOF 99\nN10 M30\n")] == [("undefined_label", 1)]


@dataclass(frozen=True)
class _WithData(ControlSpec):
    """A control with machine/setting data (the machine model's [machine_data])."""

    machine_data: dict = field(default_factory=dict)


@pytest.mark.parametrize(
    "text, xs",
    [
        # TRANS after the position was reached: the next increment traverses the offset too
        ("G0 X1\nTRANS X100\nX=IC(1)\nX=IC(2)\nM30\n", [1.0, 102.0, 104.0]),
        ("G0 X1\nTRANS X100\nG91 X1\nX2\nM30\n", [1.0, 102.0, 104.0]),
        # a settable offset change the same way; an absolute move is not affected
        ("G0 X1\nG54\nG91 X1\nG90 X1\nM30\n", [1.0, 12.0, 11.0]),
        # an axis not moved since the change keeps the frame its position was reached under
        ("G0 X1 Y0\nTRANS X100\nG0 Y5\nX=IC(1)\nM30\n", [1.0, 1.0, 102.0]),
    ],
)
def test_incremental_move_after_a_frame_change_traverses_the_offset(tmp_path, text, xs):
    # SD42440 FRAME_OFFSET_INCR_PROG = 1, the control's default
    control = ControlSpec(axes=DEFAULT_CONTROL.axes, zero_offsets={"G54": {"X": 10.0}})
    assert [m.axes["X"] for m in moves(ok(tmp_path, text, control))] == xs


def test_incremental_move_after_rotation_counts_from_the_programmed_point(tmp_path):
    # (10, 0) as programmed, plus (5, 0), in the rotated system: machine (0, 15)
    r = ok(tmp_path, "G0 X10 Y0\nROT RPL=90\nG91 X5 Y0\nM30\n")
    end = moves(r)[-1].axes
    assert (end["X"], end["Y"]) == (pytest.approx(0.0, abs=1e-12), pytest.approx(15.0))


def test_without_frame_offset_incr_prog_only_the_distance_is_traversed(tmp_path):
    control = _WithData(axes=DEFAULT_CONTROL.axes, machine_data={"$SC_FRAME_OFFSET_INCR_PROG": 0})
    r = ok(tmp_path, "G0 X1\nTRANS X100\nX=IC(1)\nX=IC(2)\nM30\n", control)
    assert [m.axes["X"] for m in moves(r)] == [1.0, 2.0, 4.0]


def test_a_jump_to_a_string_variable_lands_on_the_label_it_holds(tmp_path):
    # the jump destination may be a STRING variable (Job planning, "Program jumps")
    text = """DEF STRING[10] DEST
DEF INT N
N=N+1
DEST="LA" << N
GOTOF DEST
LA1: G0 X1
LA2: G0 X2
IF N<2 GOTOB 3
DEST="N90"
GOTO DEST
G0 X99
N90 M30
"""
    text = text.replace("GOTOB 3", "GOTOB TOP").replace("N=N+1", "TOP: N=N+1")
    r = ok(tmp_path, text)
    assert [m.axes["X"] for m in moves(r)] == [1.0, 2.0, 2.0]
    assert [f for f in check(tmp_path, text) if f.severity != "info"] == []
    f = error_of(run(tmp_path, 'DEF STRING[10] DEST="NOWHERE"\nGOTOF DEST\nM30\n'))
    assert (f.kind, f.line) == ("undefined_label", 2)
