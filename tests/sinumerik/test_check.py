"""Static diagnostics of ``check``: kind, line and column, never the prose."""

from __future__ import annotations

import pytest
from catalog import TURNMILL
from nc import check, error_of, kinds, linked_from_outside, run

from vmach.canon import DEFAULT_CONTROL
from vmach.machine.control import load_control

TURN = load_control(TURNMILL)


def where(findings, severity=None):
    return [(f.kind, f.line, f.source.column) for f in findings if severity is None or f.severity == severity]


def test_clean_program_has_no_findings(tmp_path):
    assert check(tmp_path, "N10 G0 X1\nN20 LBL: G1 X2 F100\nN30 IF R1<1 GOTOB LBL\nN40 M30\n") == []


@pytest.mark.parametrize(
    "text, expected",
    [
        ("G0 X1\nGOTOF MISSING\nM30\n", [("undefined_label", 2, 7)]),
        ("HERE: G0 X1\nGOTOF HERE\nM30\n", [("jump_direction", 2, 7)]),
        ("GOTOB THERE\nTHERE: M30\n", [("jump_direction", 1, 7)]),
        ("GOTOF N99\nN50 M30\n", [("undefined_label", 1, 7)]),
        ("N20 G0 X1\nN10 G0 X2\nM30\n", [("block_number_order", 2, 1)]),
        ("IF R1>0\nG0 X1\nM30\n", [("unbalanced_block", 1, 1)]),
        ("G0 X1\nENDWHILE\nM30\n", [("unbalanced_block", 2, 1)]),
        ("WHILE 1\nENDFOR\nM30\n", [("unbalanced_block", 1, 1), ("unbalanced_block", 2, 1)]),
        ("REPEAT\nG0 X1\nM30\n", [("unbalanced_block", 1, 1)]),
        ("G0 X1\nM30\nG0 X2\n", [("unreachable_block", 3, 1)]),
        ("GOTOF END\nG0 X1\nG0 X2\nEND: M30\n", [("unreachable_block", 2, 1)]),
        ("G0 X1 Q5\nM30\n", [("unknown_word", 1, 7)]),
        ("G999 X1\nM30\n", [("unknown_gcode", 1, 1)]),
        ("G0 G1 X1\nM30\n", [("modal_conflict", 1, 4)]),
        ("ASPLINE X1\nM30\n", [("unsupported", 1, 1)]),
        ("G1 X=(1+2 F10\nM30\n", [("syntax", 1, 11)]),
        ("G1 X=FOO F10\nM30\n", [("undefined_variable", 1, 6)]),
        ("G0 X1\nDEF REAL A\nM30\n", [("def_position", 2, 1)]),
        ("N10 G0 X1\nPROC LATE\nM30\n", [("proc_not_first", 2, 1)]),
        ("NOSUCHCYCLE\nM30\n", [("unknown_cycle", 1, 1)]),
        ("R1000=1\nM30\n", [("index_range", 1, 1)]),
        ("G0 X1 @\nM30\n", [("syntax", 1, 7)]),
        ("GOTOC NOWHERE\nM30\n", [("undefined_label", 1, 7)]),
    ],
)
def test_defects_are_reported_at_their_place(tmp_path, text, expected):
    assert where(check(tmp_path, text)) == expected


@pytest.mark.parametrize("control", [DEFAULT_CONTROL, TURN], ids=["default", "turnmill"])
@pytest.mark.parametrize(
    "block, column",
    [
        ("TRANS X +", 7),
        ("ATRANS X -", 8),
        ("TRANS X *", 7),
        ("TRANS X * 3", 7),
        ("TRANS X / 2", 7),
        ("TRANS X - -3", 7),
        ("TRANS X + (3)", 7),
        ("TRANS X + Y1", 7),
        ("ROT RPL=3 Z", 11),
        ("ROT Z=", 7),
        ("TRANS X=", 9),
        ("TRANS X=3+", 11),
        ("AROT RPL=", 10),
        ("AROT RPL=-", 11),
    ],
)
def test_frame_axis_without_a_whole_value_is_a_syntax_error(tmp_path, control, block, column):
    # a frame instruction's short axis value is a number or a sign and a number, never a dangling
    # operator (once a TypeError, and "X * 3" was read as X3); check and run report the same place
    text = f"G0 X1\n{block}\nM30\n"
    assert where(check(tmp_path, text, control)) == [("syntax", 2, column)]
    assert where([error_of(run(tmp_path, text, control))]) == [("syntax", 2, column)]


@pytest.mark.parametrize("block", ["TRANS X -3", "TRANS X + 3", "ATRANS X 3 Y-1", "ROT RPL=-30", "TRANS"])
def test_frame_short_axis_values_still_read(tmp_path, block):
    assert check(tmp_path, f"G0 X1\n{block}\nM30\n", TURN) == []


def test_gotoc_missing_target_is_only_a_warning(tmp_path):
    f = check(tmp_path, "GOTOC NOWHERE\nM30\n")
    assert [x.severity for x in f] == ["warning"]


def test_every_error_in_a_file_is_reported_at_once(tmp_path):
    f = check(tmp_path, "G0 X1 Q5\nG999\nGOTOF NIX\nIF R1\nM30\n")
    assert kinds(f, "error") == [
        ("unknown_word", 1),
        ("unknown_gcode", 2),
        ("undefined_label", 3),
        ("unbalanced_block", 4),
    ]


def test_machine_names_come_from_the_model(tmp_path):
    text = "C_AXIS_ON\nG0 C1=10\nC_AXIS_OF\nM30\n"
    assert kinds(check(tmp_path, text, TURN)) == [("unknown_cycle", 3)]
    # without a machine, every axis letter is accepted but maker's cycles are unknown
    assert kinds(check(tmp_path, text)) == [("unknown_cycle", 1), ("unknown_cycle", 3)]


def test_did_you_mean_names_the_declared_cycle(tmp_path):
    f = check(tmp_path, "C_AXIS_OF\nM30\n", TURN)
    assert f[0].data["name"] == "C_AXIS_OF" and "C_AXIS_OFF" in f[0].message


def test_subprogram_beside_the_program_is_known(tmp_path):
    (tmp_path / "Helper.spf").write_text("PROC HELPER\nM17\n")
    assert check(tmp_path, "HELPER\nM30\n") == []


def test_stray_text_line_is_named_as_such(tmp_path):
    f = check(tmp_path, "N10 G0 X1\nTHIS IS A NOTE 0.12 (+0.12)!!!\nM30\n")
    assert where(f) == [("syntax", 2, 1)]
    assert "comment" in f[0].message


def test_unreachable_run_is_reported_once_with_its_span(tmp_path):
    f = check(tmp_path, "GOTOF END\nG0 X1\nG0 X2\nG0 X3\nEND: M30\n")
    assert len(f) == 1 and f[0].data == {"first_line": 2, "last_line": 4}


def test_loop_exits_are_followed(tmp_path):
    # a LOOP without exit makes what follows it unreachable; with an exit it does not
    assert kinds(check(tmp_path, "LOOP\nG0 X1\nENDLOOP\nM30\n")) == [("unreachable_block", 4)]
    assert check(tmp_path, "LOOP\nIF R1 GOTOF OUT\nENDLOOP\nOUT: M30\n") == []


def test_a_subprogram_linked_from_outside_is_named_as_such(tmp_path):
    job = linked_from_outside(tmp_path, "EVIL.SPF", "M17\n")
    assert kinds(check(job, "G0 X1\nEVIL\nM30\n")) == [("subprogram_outside", 2)]
    (job / "EVIL.SPF").unlink()
    assert kinds(check(job, "G0 X1\nEVIL\nM30\n")) == [("unknown_cycle", 2)]


@pytest.mark.parametrize(
    "head",
    ["IF $P_NOSUCH==1", "IF NOSUCH>0", "WHILE NOSUCH<3", "IF (1+", "FOR R1=NOSUCH TO 3"],
)
def test_a_structure_whose_head_does_not_parse_still_pairs(tmp_path, head):
    # one finding at the head itself; its ELSE/ENDIF, ENDWHILE, ENDFOR are not unbalanced
    close = {"IF": "ENDIF", "WHILE": "ENDWHILE", "FOR": "ENDFOR"}[head.split()[0]]
    middle = "ELSE\nG0 X2\n" if close == "ENDIF" else ""
    text = f"G0 X0\n{head}\nG0 X1\n{middle}{close}\nIF R1>0\nG0 X3\nENDIF\nM30\n"
    found = check(tmp_path, text)
    assert [(f.kind, f.line) for f in found if f.severity == "error"] == [(found[0].kind, 2)]
    assert "unbalanced_block" not in [f.kind for f in found]


def test_a_for_that_does_not_parse_stops_the_run_at_itself(tmp_path):
    # its ENDFOR pairs with it (no cascade) and the run stops at the FOR with its own error
    r = run(tmp_path, "G0 X1\nFOR NN=0 TO 1\nG0 X2\nENDFOR\nM30\n")
    f = [x for x in r.findings if x.severity == "error"]
    assert not r.completed and [(x.kind, x.line) for x in f] == [("undefined_variable", 2)]


@pytest.mark.parametrize("text", ["$P_NOSUCH=1\nM30\n", "$A_NOSUCH[1]=1\nM30\n", "R1=$P_NOSUCH\nM30\n"])
def test_writing_and_reading_an_unsupported_variable_give_the_same_kind(tmp_path, text):
    assert [f.kind for f in check(tmp_path, text)] == ["unsupported"]
