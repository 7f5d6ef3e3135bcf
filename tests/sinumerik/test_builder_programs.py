"""Machine builders' archives, warm-up and axis test programs, shop programs (issue 32): files
named as the control's file system names them, machine axis names in machine data, interrupts
and synchronised actions as such programs use them. Programs written for these tests after the
Programming Manuals' descriptions (Fundamentals; Job planning: "Flexible NC programming",
"Motion-synchronous actions"; Operating Manual: "Formats for saving and importing data")."""

from __future__ import annotations

import pytest
from catalog import MODELS
from nc import check, error_of, moves, ok, run

from interpreters import dialect_for, sinumerik
from vmach.canon import RunOptions
from vmach.machine.loader import load_model_control

MILL3 = load_model_control(MODELS / "mill3.toml")
TURNMILL = load_model_control(MODELS / "turnmill.toml")


def test_programs_named_as_the_control_names_them_are_called(tmp_path):
    # a service archive copied from the control: _N_WARM_MPF calls _N_AXES_SPF and L100 (_N_L100_SPF)
    (tmp_path / "_N_AXES_SPF").write_text("%_N_AXES_SPF\n;$PATH=/_N_SPF_DIR\nPROC AXES(REAL _X)\n"
                                          "G1 X=_X F2000\nRET\n")
    (tmp_path / "_N_L100_SPF").write_text("G1 Y-40 F2000\nM17\n")
    main = tmp_path / "_N_WARM_MPF"
    main.write_text("%_N_WARM_MPF\n;$PATH=/_N_MPF_DIR\nG0 X0 Y0 Z50\nAXES(120)\nL100\nM30\n")
    assert dialect_for(main) is sinumerik and dialect_for(tmp_path / "_N_L100_SPF") is sinumerik
    assert sinumerik.check(main, MILL3) == []
    r = sinumerik.run(main, MILL3)
    assert r.completed
    got = [(m.axes["X"], m.axes["Y"], m.source.path.rsplit("/", 1)[-1], m.source.line) for m in moves(r)]
    assert got == [
        (0.0, 0.0, "_N_WARM_MPF", 3), (120.0, 0.0, "_N_AXES_SPF", 4), (120.0, -40.0, "_N_L100_SPF", 1)]


def test_machine_data_indexed_by_machine_axis_names(tmp_path):
    # MD 10000 names the machine axes X1, Y1, Z1 by default; a builder's program indexes axis
    # machine data by them ($MA_MAX_AX_VELO[X1]) as well as by channel axis and AXn
    text = ("R1=$MA_MAX_AX_VELO[X1] R2=$MA_POS_LIMIT_PLUS[Z1] R3=$MA_MAX_AX_ACCEL[AX2]\n"
            "G0 X=R1/1000 Y=R2/10 Z=R3\nM30\n")
    r = ok(tmp_path, text, MILL3)
    assert moves(r)[-1].axes == {"X": 36.0, "Y": 45.0, "Z": 5.0}
    assert check(tmp_path, text, MILL3) == []
    e = error_of(run(tmp_path, "R1=$MA_MAX_AX_VELO[B1]\nM30\n", MILL3))
    assert (e.kind, e.line) == ("unknown_axis", 1)


def test_interrupt_routines_are_assigned_but_never_started(tmp_path):
    # Job planning, "Interrupt routine": SETINT(3) PRIO=1 LIFT_OFF assigns the routine to fast
    # input 3; vmach's inputs stay 0, so the routine never runs and the program goes on
    text = ("N10 SETINT(3) PRIO=1 LIFT_OFF LIFTFAST\nN20 ENABLE(3)\nN30 G0 X10 Y0 Z50\nN40 DISABLE(3)\n"
            "N50 CLRINT(3)\nN60 M30\n")
    assert check(tmp_path, text, MILL3) == []
    r = ok(tmp_path, text, MILL3)
    assert [m.axes["X"] for m in moves(r)] == [10.0]
    assert sorted((f.kind, f.line, f.severity) for f in r.findings if f.data.get("command") in
                  ("SETINT", "ENABLE", "DISABLE", "CLRINT")) == [
        ("no_effect", 1, "info"), ("no_effect", 2, "info"), ("no_effect", 4, "info"),
        ("no_effect", 5, "info")]


SYNC = """N10 DEF REAL _V
N20 G0 X0 Y0 Z50
N30 ID=1 WHENEVER $AA_IM[Z]<-10 DO $R10=1 M8 H2=5 M1=10
N40 ID=2 WHEN $AC_TIME>5 DO $AC_MARKER[2]=$AC_MARKER[2]+1
N50 G1 X20 F1000
N60 STOPRE
"""


def test_a_synchronised_action_writing_variables_is_accepted_and_its_variables_unknown(tmp_path):
    # Job planning, "Motion-synchronous actions": an action that writes variables or outputs
    # auxiliary functions leaves the path alone; vmach does not evaluate it, and says so
    text = SYNC + ("N70 R10=0\nN80 G1 X=R10+30\nN85 LOCK(1)\nN86 UNLOCK(1)\nN87 RESET(1)\nN90 CANCEL(1)\n"
                   "N100 M30\n")
    assert check(tmp_path, text, MILL3) == []
    r = ok(tmp_path, text, MILL3)
    assert [m.axes["X"] for m in moves(r)] == [0.0, 20.0, 30.0]      # R10 written anew: known again
    notes = [(f.kind, f.line, f.severity, tuple(f.data["writes"])) for f in r.findings
             if f.kind == "synchronized_action"]
    assert notes == [("synchronized_action", 3, "info", ("R10",)),
                     ("synchronized_action", 4, "info", ("$AC_MARKER",))]


def test_reading_a_variable_a_synchronised_action_writes_is_unsupported(tmp_path):
    for tail, line in (("N70 G1 X=R10*5\nN80 M30\n", 7), ("N70 _V=R10\nN80 M30\n", 7),
                       ("N70 G1 Y=R10\nM30\n", 7), ("N70 SUB1(R10)\nM30\n", 7),
                       ("N70 IF $AC_MARKER[2]>0\nN80 M0\nN90 ENDIF\nM30\n", 7)):
        e = error_of(run(tmp_path, SYNC + tail, MILL3, SUB1_DOT_SPF="PROC SUB1(REAL _A)\nM17\n"))
        assert (e.kind, e.line) == ("unsupported", line), tail
    e = error_of(run(tmp_path, SYNC + "N70 R1=$AC_MARKER[1]\nN75 $AC_MARKER[2]=4\nN80 G0 X=$AC_MARKER[2]+R1\n"
                     "N90 MSG(\"R10=\"<<R10)\nM30\n", MILL3))
    assert (e.kind, e.line) == ("unsupported", 7)                   # $AC_MARKER[1] as well


def test_a_synchronised_action_that_moves_or_stops_is_unsupported_naming_it(tmp_path):
    for action, col in (("POS[X]=100 FA[X]=500", 25), ("M5", 25), ("DELDTG", 25), ("$R1=2 SPOS=0", 31),
                        ("M1=3", 25), ("M=R1", 25), ("G0 X10", 25)):
        text = f"N10 G0 X0 Y0 Z50\nN20 WHEN $AA_IW[Z]<5 DO {action}\nN30 G1 Z0 F100\nM30\n"
        found = [(f.kind, f.line, f.source.column) for f in check(tmp_path, text, MILL3)]
        assert found == [("unsupported", 2, col)], action
        e = error_of(run(tmp_path, text, MILL3))
        assert (e.kind, e.line) == ("unsupported", 2)


SETUP_ARC = """%_N_SETUP_MPF
;$PATH=/_N_WKS_DIR/_N_SETUP_WPD
G17 G90 G54 T1 D1
G0 X0 Y0 Z=R1
G1 Z=-$TC_DP3[1,1]/10 F200
G0 X=SAFE_X
M30
%_N_SETUP_UFR_INI
CHANDATA(1)
$P_UIFR[1]=CTRANS(X,100,Y,50,Z,-20)
M17
%_N_SETUP_RPA_INI
CHANDATA(1)
R1=25.5
$MC_CHAN_NAME="CHAN1"
CHANDATA(2)
R1=99
M17
%_N_SETUP_TOA_INI
CHANDATA(1)
$TC_MPP1[1,1]=1
$TC_MPP1[1,2]=1
$TC_DP1[1,1]=120 $TC_DPC1[1,1]=0
$TC_DP3[1,1]=80.0
$TC_DP6[1,1]=5.0
M17
%_N_UGUD_DEF
;$PATH=/_N_DEF_DIR
DEF NCK REAL SAFE_X=-40
M30
"""


def test_an_archive_loads_its_initialisation_and_definition_sections_first(tmp_path):
    # Operating Manual, archives: the _INI sections (zero offsets, R parameters, tool offsets)
    # are loaded into the NCK when the archive is read in, the _DEF sections define the GUD
    assert [(f.kind, f.line) for f in check(tmp_path, SETUP_ARC, MILL3, name="SETUP.ARC")] == []
    r = ok(tmp_path, SETUP_ARC, MILL3, name="SETUP.ARC")
    got = [(m.axes["X"], m.axes["Y"], m.axes["Z"], m.source.line) for m in moves(r)]
    assert got == [(100.0, 50.0, 5.5, 4), (100.0, 50.0, -28.0, 5), (60.0, 50.0, -28.0, 6)]
    notes = sorted((f.kind, f.line, f.severity, f.data["count"]) for f in r.findings
                   if f.kind == "archive_section")
    assert notes == [("archive_section", 15, "info", 1), ("archive_section", 17, "info", 1),
                     ("archive_section", 21, "info", 3)]      # machine data, channel 2, magazine data


def test_an_error_in_an_initialisation_section_is_found_at_its_line(tmp_path):
    text = SETUP_ARC.replace("$TC_DP6[1,1]=5.0", "$TC_DP6[1,1]=5.0 Q7")
    found = [(f.kind, f.line) for f in check(tmp_path, text, MILL3, name="SETUP.ARC")]
    assert found == [("unknown_word", 25)]
    e = error_of(run(tmp_path, text, MILL3, name="SETUP.ARC"))
    assert e.line == 25


def test_dwell_in_revolutions_of_a_named_spindle(tmp_path):
    # Fundamentals, "Dwell time": G4 S<n>=… waits that many revolutions of spindle n; the S
    # of a G4 block is no new speed
    text = "SETMS(1)\nS1=600 M1=3\nG4 S1=10\nG4 S=5\nM30\n"
    r = ok(tmp_path, text, MILL3)
    dwells = [(c.seconds, c.revolutions, c.source.line) for c in r.commands if c.kind == "dwell"]
    assert dwells == [(None, 10.0, 3), (None, 5.0, 4)]
    assert [c.speed for c in r.commands if c.kind == "spindle"] == [600.0]
    e = error_of(run(tmp_path, "S1=600 M1=3\nG4 S2=10\nM30\n", TURNMILL))
    assert (e.kind, e.line) == ("invalid_value", 2)
    r = ok(tmp_path, "S1=600 M1=3 S2=1200 M2=3\nG4 S2=10\nM30\n", TURNMILL)
    assert [(c.seconds, c.revolutions) for c in r.commands if c.kind == "dwell"] == [(0.5, None)]


def test_channel_state_a_service_program_reads(tmp_path):
    text = "R1=$AC_OVR R2=$AA_OVR[Y] R3=$AC_STAT R4=$AC_PROG\nG0 X=R1 Y=R2 Z=R3*10+R4\nM30\n"
    assert check(tmp_path, text, MILL3) == []
    assert moves(ok(tmp_path, text, MILL3))[-1].axes == {"X": 100.0, "Y": 100.0, "Z": 22.0}


def test_a_program_waiting_for_the_plc_stops_as_unsupported_naming_it(tmp_path):
    # a builder's tool-clamp macro hands over to the PLC and waits for its acknowledgement
    text = "N10 $A_DBB[10]=1\nN20 G4 F0.1\nN30 WHILE $A_DBB[11]==0\nN40 ENDWHILE\nN50 M30\n"
    assert check(tmp_path, text, MILL3) == []
    few = RunOptions(max_blocks=20000)
    e = error_of(run(tmp_path, text, MILL3, few))
    assert (e.kind, e.data["variable"]) == ("unsupported", "$A_DBB[11]")
    assert e.line in (3, 4)
    e = error_of(run(tmp_path, "N10 R1=R1+1\nN20 GOTOB N10\nM30\n", MILL3, few))  # no PLC: endless
    assert e.kind == "block_limit"


def test_modal_subprogram_call(tmp_path):
    # Fundamentals, "Modal subprogram call": MCALL NAME(args) calls the subprogram after every
    # block that moves an axis, with the values of the MCALL block; MCALL alone ends it; the
    # subprogram's own moves do not call it again
    spot = "PROC SPOT(REAL _D)\nG1 Z=-_D F100\nG0 Z5\nM17\n"
    text = "N10 G17 G90 G54\nN20 G0 X0 Y0 Z50\nN30 MCALL SPOT(2)\nN40 X10 Y10\nN50 R1=3\nN60 G0 X20\n" \
           "N70 MCALL\nN80 X30\nN90 M30\n"
    assert check(tmp_path, text, MILL3, SPOT_DOT_SPF=spot) == []
    r = ok(tmp_path, text, MILL3, SPOT_DOT_SPF=spot)
    got = [(m.axes["X"], m.axes["Z"], m.source.path.rsplit("/", 1)[-1], m.source.line) for m in moves(r)]
    assert got == [(0.0, 50.0, "TEST.MPF", 2), (10.0, 50.0, "TEST.MPF", 4), (10.0, -2.0, "SPOT.SPF", 2),
                   (10.0, 5.0, "SPOT.SPF", 3), (20.0, 5.0, "TEST.MPF", 6), (20.0, -2.0, "SPOT.SPF", 2),
                   (20.0, 5.0, "SPOT.SPF", 3), (30.0, 5.0, "TEST.MPF", 8)]
    # L-numbered subprogram without parameters; a drilling cycle's MCALL ends it too
    r = ok(tmp_path, "G0 X0 Y0 Z50\nMCALL L10\nX5\nMCALL CYCLE81(5,0,1,-1)\nMCALL\nX6\nM30\n", MILL3,
           L10_DOT_SPF="G1 Z40 F100\nG0 Z50\nM17\n")
    assert [(m.axes["X"], m.axes["Z"]) for m in moves(r)] == [(0.0, 50.0), (5.0, 50.0), (5.0, 40.0),
                                                                (5.0, 50.0), (6.0, 50.0)]


def test_computed_jump_destination(tmp_path):
    # Job planning, "Program jumps to jump markers": the destination may be a STRING expression
    text = ("N10 DEF INT _K='H25' B_AND 'B111'\nN20 IF _K==5 GOTOF (\"LB\"<<_K)\nN30 G0 X1\n"
            "N40 LB5: G0 X=_K\nN50 GOTOF \"N\"<<10*R9+60\nN60 G0 Y3\nN70 M30\n")
    assert check(tmp_path, text, MILL3) == []
    assert [(m.axes["X"], m.source.line) for m in moves(ok(tmp_path, text, MILL3))] == [(5.0, 4), (5.0, 6)]
    e = error_of(run(tmp_path, text.replace("GOTOF (\"LB\"<<_K)", "GOTOF (\"LX\"<<_K)"), MILL3))
    assert (e.kind, e.line) == ("undefined_label", 2)


def test_parameterised_return_from_a_subprogram(tmp_path):
    # Fundamentals, "Parameterizable subprogram return jump": RET("label") goes on at the label
    # of the caller, RET(target, 1) at the block after it, RET(target, 0, 2) two levels up
    sub = "G0 Y7\nRET(\"BACK\")\n"
    text = "N10 G0 X0 Y0 Z50\nN20 SUBR\nN30 G0 X1\nN40 BACK: G0 X2\nN50 G0 X3\nN60 M30\n"
    assert check(tmp_path, text, MILL3, SUBR_DOT_SPF=sub) == []
    got = [(m.axes["X"], m.source.line) for m in moves(ok(tmp_path, text, MILL3, SUBR_DOT_SPF=sub))]
    assert got == [(0.0, 1), (0.0, 1), (2.0, 4), (3.0, 5)]
    r = ok(tmp_path, text, MILL3, SUBR_DOT_SPF="G0 Y7\nRET(\"N40\", 1)\n")
    assert [m.source.line for m in moves(r)] == [1, 1, 5]
    r = ok(tmp_path, text, MILL3, SUBR_DOT_SPF="INNER\nG0 Y8\nM17\n",
           INNER_DOT_SPF="G0 Y9\nRET(\"BACK\",0,2)\n")
    assert [(m.axes["Y"], m.source.line) for m in moves(r)] == [(0.0, 1), (9.0, 1), (9.0, 4), (9.0, 5)]
    e = error_of(run(tmp_path, text, MILL3, SUBR_DOT_SPF="G0 Y7\nRET(\"NOWHERE\")\n"))
    assert (e.kind, e.line) == ("undefined_label", 2)


def test_a_global_variable_passed_to_a_subprogram(tmp_path):
    # a GUD variable as a call's argument (was a KeyError traceback)
    r = ok(tmp_path, "SUB1(GFEED)\nM30\n", MILL3, SUB1_DOT_SPF="PROC SUB1(REAL _F)\nG1 X10 F=_F\nM17\n",
           UGUD_DOT_DEF="DEF NCK REAL GFEED=1234\n")
    assert [(m.axes["X"], m.feed) for m in moves(r)] == [(10.0, 1234.0)]


def test_mcall_of_a_simulated_cycle_stays_the_cycle_with_a_file_of_its_name_beside(tmp_path):
    # as a plain call of CYCLE81 does (drilling.py): a CYCLE81.SPF beside is not what MCALL runs
    text = "G0 X0 Y0 Z50 F100\nMCALL CYCLE81(10,0,2,-5)\nX10\nMCALL\nM30\n"
    own = "PROC CYCLE81(REAL A, REAL B, REAL C, REAL D)\nG0 Y99\nM17\n"
    m = moves(ok(tmp_path, text, MILL3, CYCLE81_DOT_SPF=own))
    assert {c.axes["Y"] for c in m} == {0.0} and min(c.axes["Z"] for c in m) == -5.0


def test_state_a_tool_change_or_test_macro_reads(tmp_path):
    # Lists of system variables: $P_TOOLEXIST / $P_TOOLND from the tool library, $VA_IM the
    # encoder's actual value, $AC_F the path feed, $A_PROBE a probe's state; MD 32020/36200
    tools = {("1", 1): {"radius": 5.0}, ("1", 2): {"radius": 4.0}, ("7", 1): {"radius": 2.0}}
    opts = RunOptions(tool_data=lambda t, d: tools.get((t, d)))
    text = ("G1 X5 Y2 F300\nR1=$P_TOOLEXIST[1]+$P_TOOLEXIST[3]*10 R2=$P_TOOLND[1]*10+$P_TOOLND[7]\n"
            "R3=$VA_IM[X]+$AC_F+$A_PROBE[1] R4=$MA_JOG_VELO[Y1]+$MA_AX_VELO_LIMIT[0,AX1]\n"
            "G0 X=R1 Y=R2 Z=R3+R4/1000\nM30\n")
    assert check(tmp_path, text, MILL3) == []
    r = run(tmp_path, text, MILL3, opts)
    assert r.completed and moves(r)[-1].axes == {"X": 1.0, "Y": 21.0, "Z": 318.5}


RUN_IN = {
    "GOTOB": ("N10 G0 X0 Y0 Z50\nN20 S2000 M3\nN30 START:\nN40 G1 X100 F3000\nN50 X0\nN60 GOTOB START\n"
              "N70 M30\n", 6),
    "LOOP": ("N10 G0 X0 Y0 Z50\nN20 S2000 M3\nN30 LOOP\nN40 G1 X100 F3000\nN50 X0\nN60 ENDLOOP\n"
             "N70 M30\n", 6),
    "WHILE": ("N10 G0 X0 Y0 Z50\nN20 S2000 M3\nN30 WHILE TRUE\nN40 G1 X100 F3000\nN50 X0\nN60 ENDWHILE\n"
              "N70 M30\n", 6),
}


@pytest.mark.parametrize("how", sorted(RUN_IN))
def test_a_run_in_program_that_repeats_until_reset_ends_when_a_pass_repeats(tmp_path, how):
    # a run-in program loops until the operator resets the control: once a pass leaves the
    # state as the pass before, every further pass moves the same; the run ends there
    text, back = RUN_IN[how]
    r = ok(tmp_path, text, MILL3)
    assert [(m.axes["X"], m.source.line) for m in moves(r)] == [(0.0, 1)] + [(100.0, 4), (0.0, 5)] * 2
    assert [(f.kind, f.line) for f in r.findings if f.severity == "warning"] == [("endless_program", back)]
    assert [c.code for c in r.commands if c.kind == "program_end"] == ["RESET"]
    assert [f.kind for f in check(tmp_path, text, MILL3) if f.severity == "error"] == []


def test_a_loop_that_changes_the_state_or_has_a_way_out_is_no_endless_program(tmp_path):
    few = RunOptions(max_blocks=5000)
    e = error_of(run(tmp_path, "G0 X0 Y0 Z50\nLOOP\nR1=R1+1\nG1 X=R1/1000 F3000\nENDLOOP\nM30\n", MILL3, few))
    assert e.kind == "block_limit"
    text = "G0 X0 Y0 Z50\nLOOP\nG1 X5 F3000\nX0\nIF R1>0 GOTOF OUT\nENDLOOP\nOUT:\nM30\n"
    assert error_of(run(tmp_path, text, MILL3, few)).kind == "block_limit"


def test_machine_axes_by_number(tmp_path):
    # Fundamentals, "Axis identifiers": AX1, AX2 … name the machine axes by number, in words,
    # in brackets and in the approach to a fixed point
    text = ('DEF AXIS _YY\n_YY=AXNAME("Y")\nG0 AX1=10 AX[_YY]=.20 AX3=50\nAX[AX3]=40\nPOS[AX2]=5\n'
            "G75 FP=1 AX3=0\nM30\n")
    assert check(tmp_path, text, MILL3) == []
    assert [tuple(m.axes.values()) for m in moves(ok(tmp_path, text, MILL3))] == [
        (10.0, 0.2, 50.0), (10.0, 0.2, 40.0), (10.0, 5.0, 40.0), (10.0, 5.0, 0.0)]
    assert [(f.kind, f.line) for f in check(tmp_path, "G0 AX4=1\nM30\n", MILL3)] == [("unknown_word", 1)]


def test_a_builders_initial_block_and_retraction_settings_are_accepted(tmp_path):
    # Programming Manual, lists of G groups 41, 46, 48, 55, 60 and fast retraction (LFON, ALF,
    # POLF): settings without effect on the simulated geometry are recorded; the ones that
    # change it stop as unsupported naming them
    text = ("N10 G0 G17 G90 G40 G500 RTLION WALCS1 G460 LFOF LFTXT TOFFL=0 TOFFR=0\n"
            "N20 ALF=3 DILF=2 POLF[Z]=100 POLFMASK(Z) SCPARA=1\nN30 LFON\nN40 G0 X5 Y5 Z50\nN50 M30\n")
    assert check(tmp_path, text, MILL3) == []
    r = ok(tmp_path, text, MILL3)
    assert [m.axes["X"] for m in moves(r)] == [5.0]
    assert {f.data.get("command") for f in r.findings if f.kind == "no_effect"} >= {
        "RTLION", "WALCS1", "G460", "LFOF", "LFTXT", "ALF", "DILF", "POLF", "POLFMASK", "SCPARA", "LFON"}
    for bad in ("RTLIOF", "TOFFL=0.2", "TOFF[Z]=1", "G461"):
        e = error_of(run(tmp_path, f"G0 X0\n{bad}\nM30\n", MILL3))
        assert (e.kind, e.line) == ("unsupported", 2), bad


def test_a_loop_waiting_on_the_clock_alone_ends(tmp_path):
    # a warm-up pause written as a busy loop on a timer: reading a main-run variable stops the
    # preprocessing until the main run caught up, at least one interpolation cycle (4 ms) a read
    text = "$AC_TIMER[1]=0\nWHILE $AC_TIMER[1]<5\nENDWHILE\nR1=$A_SECOND+$A_MSECOND/1000\nG0 X=R1\nM30\n"
    r = ok(tmp_path, text, MILL3)
    assert 5.0 <= moves(r)[-1].axes["X"] <= 5.0 + 3 * 0.004       # the wait, then two reads


def test_a_programs_initialisation_files_beside_it_are_loaded_first(tmp_path):
    # Programming Guide, "Workpiece directory": a workpiece directory holds, beside _N_PART_MPF,
    # its initialisation programs _N_PART_INI, _N_PART_UFR (frames), _N_PART_SEA …; the
    # control runs the ones of the program's name when the program is selected
    (tmp_path / "PART.RPA").write_text("CHANDATA(1)\nR1=12.5\nM17\n")
    (tmp_path / "_N_PART_UFR").write_text("%_N_PART_UFR\nCHANDATA(1)\n$P_UIFR[1]=CTRANS(X,100)\n"
                                          "$MN_AXCONF_MACHAX_NAME_TAB[0]=\"X1\"\nM17\n")
    (tmp_path / "PART.TOA").write_text("$TC_DP3[1,1]=7\n")
    (tmp_path / "OTHER.RPA").write_text("R1=99\n")
    text = "G54 G0 X=R1 Y=$TC_DP3[1,1]\nM30\n"
    assert check(tmp_path, text, MILL3, name="PART.MPF") == []
    r = ok(tmp_path, text, MILL3, name="PART.MPF")
    assert moves(r)[-1].axes["X"] == 112.5 and moves(r)[-1].axes["Y"] == 7.0
    notes = [(f.kind, f.source.path.rsplit("/", 1)[-1], f.line) for f in r.findings
             if f.kind == "archive_section"]
    assert notes == [("archive_section", "_N_PART_UFR", 4)]
    (tmp_path / "PART.TOA").write_text("$TC_DP3[1,1]=7 Q5\n")
    assert [(f.kind, f.line) for f in check(tmp_path, text, MILL3, name="PART.MPF")] == [("unknown_word", 1)]


def test_actual_values_of_a_modulo_rotary_axis_lie_within_its_range(tmp_path):
    # a rotary table's warm-up turns C ten times; MD 30310 ROT_IS_MODULO: its positions are
    # reduced to 0 ≤ C < 360 in $AA_IM, $AA_IW and $P_EP
    control = load_model_control(MODELS / "mill5ac.toml")
    text = ("G0 X0 Y0 Z100 A0 C0\nG91 G1 C3645 F20000\nG90\nR1=$AA_IM[C] R2=$AA_IW[C1] R3=$P_EP[C]\n"
            "POS[C]=IC(-90)\nR4=$AA_IM[C]\nG0 X=R1 Y=R2 Z=R3+R4\nM30\n")
    assert check(tmp_path, text, control) == []
    end = moves(ok(tmp_path, text, control))[-1].axes
    assert (end["X"], end["Y"], end["Z"]) == (45.0, 45.0, 45.0 + 315.0)
