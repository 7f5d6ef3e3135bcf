"""Reading as the control reads: words without separators, jump targets, incremental moves
after a frame change (Programming Manual Fundamentals, "Block components", "Extended address
notation"; Job planning, "Program jumps")."""

from __future__ import annotations

import pytest
from catalog import TURNMILL
from nc import check, error_of, moves, ok, run

from vmach.canon import Spindle, ToolChange
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
