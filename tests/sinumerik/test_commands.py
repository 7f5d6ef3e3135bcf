"""Predefined commands real programs write (Programming Manual Fundamentals / Job planning,
"List of instructions"): each acts in the simulation or is recorded as having no effect on
geometry (an ``info`` finding ``no_effect``, once per command with its count)."""

from __future__ import annotations

import pytest
from catalog import S5D
from nc import check, error_of, moves, ok, run

from vmach.canon import CycleCall, MasterSpindle
from vmach.machine.control import load_control

S5 = load_control(S5D)

#: a CAM post's and a machine builder's set-up lines, each command at least once
SETUP = """G17 G90 G94 G40 G710 G60 G601 FNORM
SOFT FFWON COMPCAD UPATH STOPFIFO
CYCLE832(0.01,_FINISH,1)
T1 D1 M6
G54 S1000 M3
STOPRE
G641 ADIS=0.05 ADISPOS=0.1
FA[C]=1000 ACC[X]=50 JERKLIM[X]=80 VELOLIM[Y]=90 FGREF[C]=50
G0 X10 Y0 Z10
WAITP(C) WAITM(1,1,2)
GET(Z)
RELEASE(Z)
STARTFIFO
G153 G0 Z0
SUPA G0 Z0
G500 DIAMCYCOF TRAFOOF
COMPOF FFWOF BRISK FLIN SPATH
FCUB
STOPRE
M30
"""


def infos(result) -> dict[str, tuple[int, int]]:
    """command -> (line of its first use, count) of the no_effect infos."""
    return {f.data["command"]: (f.line, f.data["count"]) for f in result.findings if f.kind == "no_effect"}


def test_setup_commands_run_and_are_recorded_once_each(tmp_path):
    r = ok(tmp_path, SETUP, S5)
    assert [f for f in r.findings if f.severity != "info"] == []
    seen = infos(r)
    assert seen["STOPRE"] == (6, 2)
    assert seen["CYCLE832"] == (3, 1) and seen["ADIS"] == (7, 1) and seen["FA"] == (8, 1)
    assert seen["WAITM"] == (10, 1) and seen["GET"] == (11, 1) and seen["RELEASE"] == (12, 1)
    for name in ("FNORM", "SOFT", "FFWON", "COMPCAD", "UPATH", "STOPFIFO", "G601", "DIAMCYCOF", "BRISK",
                 "FGREF", "ACC", "JERKLIM", "VELOLIM", "WAITP", "STARTFIFO", "FLIN", "FCUB", "SPATH"):
        assert name in seen, name
    assert [(m.axes["X"], m.axes["Z"]) for m in moves(r)] == [(10.0, 10.0), (10.0, 0.0), (10.0, 0.0)]
    assert check(tmp_path, SETUP, S5) == []


def test_positioning_axis_moves_after_the_path_motion(tmp_path):
    r = ok(tmp_path, "G0 X1 C10\nG1 X5 F100 POS[C]=ACP(90)\nPOSA[C]=IC(-20)\nG91 POS[C]=5\nM30\n", S5)
    assert [(m.kind, m.axes["X"], m.axes["C"]) for m in moves(r)] == [
        ("traverse", 1.0, 10.0), ("feed", 5.0, 10.0), ("traverse", 5.0, 90.0),
        ("traverse", 5.0, 70.0), ("traverse", 5.0, 75.0)]


def test_setal_raises_the_alarm_with_its_number(tmp_path):
    r = run(tmp_path, "G0 X1\nIF R1==0\nSETAL(61000)\nENDIF\nG0 X2\nM30\n")
    f = error_of(r)
    assert (f.kind, f.line, f.data["alarm"]) == ("program_alarm", 3, 61000)
    assert [m.axes["X"] for m in moves(r)] == [1.0]
    assert check(tmp_path, "G0 X1\nSETAL(61000)\nM30\n") == []


def test_h_functions_and_setms_alone(tmp_path):
    r = ok(tmp_path, "H7=1 H=3 H5\nSETMS(2)\nSETMS\nM30\n")
    assert [(c.name, c.args) for c in r.commands if isinstance(c, CycleCall)] == [
        ("H7", (1,)), ("H", (3,)), ("H", (5,))]
    assert [c.spindle for c in r.commands if isinstance(c, MasterSpindle)] == [2, 1]


def test_a_siemens_cycle_not_simulated_is_unsupported_naming_it(tmp_path):
    text = "G0 X1\nCYCLE996(1,2,3)\nM30\n"
    f = check(tmp_path, text, S5)
    assert [(x.kind, x.line, x.source.column) for x in f] == [("unsupported", 2, 1)]
    assert "CYCLE996" in f[0].message
    assert error_of(run(tmp_path, text, S5)).kind == "unsupported"
    # a program of that name beside the main one is called instead, as the control searches
    sub = "PROC CYCLE996(INT A, INT B)\nG0 X=A+B\nM17\n"
    r = ok(tmp_path, "CYCLE996(1,2)\nM30\n", S5, CYCLE996_DOT_SPF=sub)
    assert moves(r)[-1].axes["X"] == 3.0


@pytest.mark.parametrize("text, kind, column", [
    ("FA[Q]=100\nM30\n", "unknown_axis", 4),
    ("STOPRE(1)\nM30\n", "syntax", 7),
    ("ADIS 5\nM30\n", "syntax", 6),
])
def test_commands_written_wrongly(tmp_path, text, kind, column):
    assert [(f.kind, f.line, f.source.column) for f in check(tmp_path, text, S5)] == [(kind, 1, column)]


SUB = "PROC SUB(REAL A)\nG0 X=A\nM17\n"


@pytest.mark.parametrize("call", [
    'CALL "SUB"', 'CALL "/_N_WKS_DIR/_N_PART_WPD/_N_SUB_SPF"', "PCALL SUB(4)",
    "PCALL /_N_WKS_DIR/_N_PART_WPD/_N_SUB_SPF(4)", 'EXTCALL "SUB"', 'EXTCALL "USB:/JOBS/SUB.SPF"',
])
def test_call_pcall_extcall_run_the_program_beside_the_caller(tmp_path, call):
    r = ok(tmp_path, f"G0 X1\n{call}\nM30\n", SUB_DOT_SPF=SUB)
    assert [m.axes["X"] for m in moves(r)] == [1.0, 4.0 if "(4)" in call else 0.0]
    assert check(tmp_path, f"G0 X1\n{call}\nM30\n", SUB_DOT_SPF=SUB) == []


def test_a_named_file_that_is_missing_is_subprogram_not_found(tmp_path):
    for call, kind in (('CALL "NOPE"', "subprogram_not_found"), ("PCALL NOPE", "subprogram_not_found"),
                       ('EXTCALL "NOPE"', "subprogram_not_found"),
                       ('CALL "../SUB"', "subprogram_outside")):    # a path out is refused (issue 30)
        text = f"G0 X1\n{call}\nM30\n"
        found = check(tmp_path, text, SUB_DOT_SPF=SUB)
        assert [(f.kind, f.line) for f in found] == [(kind, 2)]
        f = error_of(run(tmp_path, text))
        assert (f.kind, f.line) == (kind, 2)


def test_a_name_that_is_nothing_is_unknown_cycle_in_check_and_run(tmp_path):
    # println is another interpreter's statement, not Sinumerik: rejected at its line,
    # with or without arguments, the same kind in check and run; a near name is suggested
    text = 'G0 X1\nprintln("END")\nM30\n'
    assert [(f.kind, f.line) for f in check(tmp_path, text)] == [("unknown_cycle", 2)]
    f = error_of(run(tmp_path, text))
    assert (f.kind, f.line, f.data["name"]) == ("unknown_cycle", 2, "PRINTLN")
    f = check(tmp_path, "SUBB(1)\nM30\n", SUB_DOT_SPF=SUB)[0]
    assert f.kind == "unknown_cycle" and "SUB?" in f.message


def test_gotos_jumps_back_to_the_program_start(tmp_path):
    r = ok(tmp_path, "R1=R1+1\nG0 X=R1\nIF R1<3 GOTOS\nM30\n")
    assert [m.axes["X"] for m in moves(r)] == [1.0, 2.0, 3.0]


@pytest.mark.parametrize("block", ["ID=1 WHENEVER $AA_IM[X]>10 DO POS[Y]=5", "MEAS=1 G1 X10 F100",
                                   "ORIRESET(0,0)", "PRESETON(X,0)"])
def test_synchronised_actions_measuring_and_carriers_are_unsupported(tmp_path, block):
    assert [(f.kind, f.line) for f in check(tmp_path, f"G0 X1\n{block}\nM30\n")] == [("unsupported", 2)]


def test_speed_limit_and_axis_acceleration_modes_have_no_effect(tmp_path):
    r = ok(tmp_path, "LIMS=3000 SPCON BRISKA(X) SOFTA(Y,Z)\nG0 X1\nM30\n")
    seen = {f.data["command"] for f in r.findings if f.kind == "no_effect"}
    assert seen == {"SPCON", "BRISKA", "SOFTA"}        # LIMS bounds G96's speed (tests/turning)


def test_any_other_cycle_of_the_control_is_unsupported_naming_it(tmp_path):
    # CYCLE4711 is no Siemens cycle vmach knows, but a CYCLEnnn lives in the control's cycle
    # directories (the machine maker's): unsupported, never unknown_cycle or not found
    text = "G0 X1\nCYCLE4711(1, 2)\nM30\n"
    f = check(tmp_path, text, S5)
    assert [(x.kind, x.line) for x in f] == [("unsupported", 2)] and "CYCLE4711" in f[0].message
    e = error_of(run(tmp_path, text, S5))
    assert (e.kind, e.line) == ("unsupported", 2)


def test_ax_addresses_an_axis_by_name(tmp_path):
    r = ok(tmp_path, "G0 AX[X]=5 AX[C]=ACP(90)\nM30\n", S5)
    assert (moves(r)[-1].axes["X"], moves(r)[-1].axes["C"]) == (5.0, 90.0)
    found = check(tmp_path, "DEF AXIS _A=X\nG0 AX[_A]=5\nAX[Q]=1\nM30\n", S5)
    assert [(f.kind, f.line) for f in found] == [("unknown_axis", 3)]
