"""Jumps, loops, branches and subprograms, nested and combined."""

from __future__ import annotations

import pytest
from nc import error_of, linked_from_outside, moves, ok, run

from vmach.canon import RunOptions


def xs(result):
    return [m.axes["X"] for m in moves(result)]


def test_gotof_gotob_with_labels_and_block_numbers(tmp_path):
    r = ok(
        tmp_path,
        """
N10 R1=0
N20 LOOPTOP: G1 X=R1 F100
N30 R1=R1+1
N40 IF R1<3 GOTOB LOOPTOP
N50 GOTOF N70
N60 G1 X=99
N70 IF R1==3 GOTOF ENDE
N80 G1 X=98
N90 ENDE: M30
""",
    )
    assert xs(r) == [0, 1, 2]


def test_goto_searches_forward_then_backward_and_gotoc_continues(tmp_path):
    r = ok(
        tmp_path,
        """
R1=0
BACK: R1=R1+1
G1 X=R1 F100
IF R1<2 GOTO BACK
GOTOC NOWHERE
G1 X=10
M30
""",
    )
    assert xs(r) == [1, 2, 10]


def test_block_if_else_nested_in_while(tmp_path):
    r = ok(
        tmp_path,
        """
R1=0
WHILE (R1<6)
  IF R1 MOD 2 == 0
    IF R1 > 2
      G1 X=100+R1 F100
    ELSE
      G1 X=R1 F100
    ENDIF
  ELSE
    G1 X=-R1
  ENDIF
  R1=R1+1
ENDWHILE
M30
""",
    )
    assert xs(r) == [0, -1, 2, -3, 104, -5]


def test_for_repeat_loop_and_case(tmp_path):
    r = ok(
        tmp_path,
        """
DEF INT I, K
FOR I=1 TO 3
  G1 X=I F100
ENDFOR
R2=0
REPEAT
  R2=R2+10
  G1 X=R2
UNTIL R2>=30
K=0
LOOP
  K=K+1
  IF K>2 GOTOF OUT
  G1 X=-K
ENDLOOP
OUT:
K=2
CASE K OF 1 GOTOF ONE 2 GOTOF TWO DEFAULT GOTOF OTHER
ONE: G1 X=1001
TWO: G1 X=1002
GOTOF FIN
OTHER: G1 X=1003
FIN: M30
""",
    )
    assert xs(r) == [1, 2, 3, 10, 20, 30, -1, -2, 1002]


def test_for_loop_that_never_runs_and_loop_variable_after(tmp_path):
    r = ok(
        tmp_path,
        """
DEF INT I
FOR I=5 TO 1
  G1 X=I F100
ENDFOR
G1 X=I F100
M30
""",
    )
    assert xs(r) == [5]


def test_several_assignments_per_block_act_left_to_right(tmp_path):
    r = ok(
        tmp_path,
        """
R1=1 R2=R1+1 R1=R2*10
G1 X=R1 Y=R2 F100
R[R2+1]=7
G1 X=R3
M30
""",
    )
    m = moves(r)
    assert (m[0].axes["X"], m[0].axes["Y"]) == (20, 2)
    assert m[1].axes["X"] == 7


def test_def_locals_types_and_arrays(tmp_path):
    r = ok(
        tmp_path,
        """
DEF INT N=2, M
DEF REAL A[3]=SET(1.5, 2.5, 3.5)
DEF BOOL B=TRUE
DEF STRING[16] S="ab"
M=2.6
G1 X=A[N] Y=M F100
IF B AND (S=="ab") GOTOF OK
G1 X=-1
OK: M30
""",
    )
    m = moves(r)
    assert (m[0].axes["X"], m[0].axes["Y"]) == (3.5, 3)  # INT rounds 2.6 to 3
    assert len(m) == 1


def test_subprograms_by_name_with_arguments_l_number_call_and_repeat(tmp_path):
    r = ok(
        tmp_path,
        """
R10=0
SHIFT(5, 2)
L123 P2
CALL "Plain"
G1 X=R10 F100
M30
""",
        SHIFT_DOT_SPF="PROC SHIFT(REAL DX, REAL DY)\nG1 X=DX Y=DY F100\nRET\n",
        L123_DOT_SPF="R10=R10+1\nM17\n",
        plain_DOT_spf="PROC PLAIN\nG0 Z=50\nM17\n",
    )
    m = moves(r)
    assert (m[0].axes["X"], m[0].axes["Y"]) == (5, 2)
    assert m[1].axes["Z"] == 50
    assert m[2].axes["X"] == 2  # L123 ran twice


def test_var_parameters_are_passed_back(tmp_path):
    r = ok(
        tmp_path,
        """
R1=3
TWICE(R1)
G1 X=R1 F100
M30
""",
        TWICE_DOT_SPF="PROC TWICE(VAR REAL V)\nV=V*2\nM17\n",
    )
    assert xs(r) == [6]


def test_save_restores_modal_state_on_return(tmp_path):
    r = ok(
        tmp_path,
        """
G90 G1 F100
SUB1
X5
M30
""",
        SUB1_DOT_SPF="PROC SUB1 SAVE\nG91 X1\nM17\n",
    )
    assert xs(r) == [1, 5]  # G91 ended with the subprogram


def test_subprogram_lookup_never_leaves_the_directory(tmp_path):
    outside = tmp_path / "EVIL.SPF"
    outside.write_text("G1 X=666 F1\nM17\n")
    inner = tmp_path / "job"
    inner.mkdir()
    r = run(inner, 'CALL "../EVIL"\nM30\n')
    assert error_of(r).kind == "subprogram_not_found"
    r = run(inner, "EVIL\nM30\n")
    assert error_of(r).kind == "unknown_cycle"  # a name, not a file: as check says
    assert moves(r) == []


def test_a_subprogram_linked_from_outside_the_directory_is_refused_as_such(tmp_path):
    inner = linked_from_outside(tmp_path, "EVIL.SPF", "G1 X=666 F1\nM17\n")
    r = run(inner, "G1 X1 F1\nEVIL\nM30\n")
    err = error_of(r)
    assert (err.kind, err.line) == ("subprogram_outside", 2)
    assert xs(r) == [1]
    (inner / "EVIL.SPF").unlink()
    (inner / "EVIL.SPF").symlink_to(inner / "job.txt")   # a link that stays inside is read
    (inner / "job.txt").write_text("G1 X7 F1\nM17\n")
    assert xs(run(inner, "EVIL\nM30\n")) == [7]


def test_missing_jump_target_is_an_error_only_when_reached(tmp_path):
    r = run(tmp_path, "R1=1\nIF R1==0 GOTOF NOWHERE\nG1 X1 F1\nIF R1==1 GOTOF NOWHERE\nM30\n")
    err = error_of(r)
    assert (err.kind, err.line) == ("undefined_label", 4)
    assert xs(r) == [1]


def test_gotof_to_a_label_behind_fails_at_run_time(tmp_path):
    r = run(tmp_path, "BACK: R1=R1+1\nIF R1<3 GOTOF BACK\nM30\n")
    err = error_of(r)
    assert (err.kind, err.line) == ("jump_direction", 2)


def test_block_limit_stops_an_endless_loop(tmp_path):
    r = run(tmp_path, "LL: G1 X=R1 F100\nR1=R1+1\nGOTOB LL\n", options=RunOptions(max_blocks=1000))
    err = error_of(r)
    assert err.kind == "block_limit" and err.data["limit"] == 1000
    assert r.blocks == 1000


def test_recursion_stops_at_the_call_depth(tmp_path):
    r = run(tmp_path, "REC\nM30\n", REC_DOT_SPF="PROC REC\nREC\nM17\n")
    assert error_of(r).kind == "call_depth"


@pytest.mark.parametrize(
    "body, kind, line",
    [
        ("R1=0\nR2=1/R1\nM30", "division_by_zero", 2),
        ("R1=-4\nG1 X=SQRT(R1) F1\nM30", "domain_error", 2),
        ("DEF REAL A[2]\nR1=2\nG1 X=A[R1] F1\nM30", "index_range", 3),
        ("G1 X10\nM30", "zero_feed", 1),
        ("G2 X10 Y0 I5 J0 F100\nG2 X0 Y3 I1 F100\nM30", "arc_error", 2),
        ("R1=1\nWHILE R1\nM30", "unbalanced_block", 2),
    ],
)
def test_runtime_errors_stop_with_kind_and_line(tmp_path, body, kind, line):
    err = error_of(run(tmp_path, body + "\n"))
    assert (err.kind, err.line) == (kind, line)


def test_missing_program_end_is_a_warning(tmp_path):
    r = ok(tmp_path, "G1 X1 F1\n")
    assert [f.kind for f in r.findings] == ["missing_program_end"]


def test_skip_blocks_and_comments_and_latin1(tmp_path):
    p = tmp_path / "LAT.MPF"
    p.write_bytes(
        "; Prüfung der Maße\n/N10 G1 X1 F100 ; skip level off: runs\nN20 X2\nM30\n".encode("latin-1")
    )
    from interpreters import sinumerik

    r = sinumerik.run(p)
    assert r.completed and xs(r) == [1, 2]


def test_msg_and_string_concatenation(tmp_path):
    r = ok(tmp_path, 'R1=3\nMSG("pass " << R1)\nM30\n')
    msgs = [c.text for c in r.commands if c.kind == "message"]
    assert msgs == ["pass 3"]


def _xs(r):
    from nc import moves

    return [m.axes["X"] for m in moves(r)]


def test_repeat_between_two_labels_and_repeatb(tmp_path):
    from nc import ok

    r = ok(tmp_path, "G0 X0\nAA1: G1 X1 F100\nX2\nAA2: X3\nREPEAT AA1 AA2 P=2\nREPEATB AA1 P=1\nX9\nM30\n")
    assert _xs(r) == [0, 1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 9]


def test_repeat_one_label_runs_up_to_itself_and_endlabel_ends_a_section(tmp_path):
    from nc import ok

    r = ok(tmp_path, "R1=0\nLOOP1: R1=R1+1\nG0 X=R1\nREPEAT LOOP1 P=2\nX100\nM30\n")
    assert _xs(r) == [1, 2, 3, 100]
    r = ok(tmp_path, "G0 X0\nSS1: X1\nX2\nENDLABEL: X3\nX4\nREPEAT SS1 P=1\nM30\n")
    assert _xs(r) == [0, 1, 2, 3, 4, 1, 2, 3]


def test_repeated_sections_nest(tmp_path):
    from nc import ok

    r = ok(tmp_path, "G0 X0\nOUT1: X1\nIN1: X2\nREPEATB IN1 P=2\nOUT2: X3\nREPEAT OUT1 OUT2 P=1\nM30\n")
    assert _xs(r) == [0, 1, 2, 2, 2, 3, 1, 2, 2, 2, 3]


def test_a_repeat_of_a_missing_label_is_found_before_running(tmp_path):
    from nc import check, error_of, run

    found = check(tmp_path, "G0 X0\nREPEAT NOPE P=2\nM30\n")
    assert [(f.kind, f.line) for f in found] == [("undefined_label", 2)]
    f = error_of(run(tmp_path, "G0 X0\nAA1: X1\nREPEAT AA1 P=0\nM30\n"))
    assert (f.kind, f.line) == ("invalid_value", 3)
