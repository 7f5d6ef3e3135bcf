"""Constructs of real 840D programs (CAM posts, machine builders' warm-up and test programs,
measuring macros), in programs written for these tests after the Programming Manual's
descriptions: string and axis functions, axes chosen at run time, array fills from a
computed index."""

from __future__ import annotations

from dataclasses import replace

from catalog import MODELS
from nc import check, error_of, moves, ok, run

from vmach.canon import Message
from vmach.machine.control import load_control

MILL3 = load_control(MODELS / "mill3.toml")
MILL5AC = load_control(MODELS / "mill5ac.toml")
TURNMILL = load_control(MODELS / "turnmill.toml")


def messages(result) -> list[str]:
    return [c.text for c in result.commands if isinstance(c, Message)]


def test_string_functions_as_the_manual_describes(tmp_path):
    # Job planning, "String operations": positions count from 0, -1 when not found
    text = """DEF STRING[40] S
DEF INT N
S="WERKZEUG_12"
N=STRLEN(S)
MSG("L"<<N<<" I"<<INDEX(S,"E")<<" R"<<RINDEX(S,"E")<<" M"<<MINDEX(S,"ZG")<<" T"<<MATCH(S,"_1"))
MSG(SUBSTR(S,9,2)<<"/"<<SUBSTR(S,2)<<"/"<<TOLOWER("AbC")<<"/"<<TOUPPER("xY"))
MSG("N"<<NUMBER("-12.5")*2<<" "<<ISNUMBER("1.5EX3")<<ISNUMBER("12A")<<" "<<INDEX(S,"Q"))
M30
"""
    r = ok(tmp_path, text, MILL3)
    assert messages(r) == ["L11 I1 R5 M4 T8", "12/RKZEUG_12/abc/XY", "N-25 10 -1"]
    assert check(tmp_path, text, MILL3) == []


def test_sprint_formats_values(tmp_path):
    text = """DEF REAL L=12.5
MSG(SPRINT("T%D L=%.3F %S %B%B %X %%", 7, L, "OK", 1, 0, 255))
MSG(SPRINT("%F", 2))
M30
"""
    r = ok(tmp_path, text, MILL3)
    assert messages(r) == ["T7 L=12.500 OK TRUEFALSE FF %", "2.000000"]


def test_number_of_a_non_number_stops_at_its_line(tmp_path):
    text = "DEF REAL V\nG0 X1\nV=NUMBER(\"1,5\")\nM30\n"
    e = error_of(run(tmp_path, text, MILL3))
    assert (e.kind, e.line) == ("type_error", 3)


def test_axis_functions(tmp_path):
    # AXNAME makes an axis of a string, AXSTRING a string of an axis; AXTOSPI/SPI convert
    # between a spindle's axis and its number; ISAXIS tells whether geometry axis n exists
    text = """DEF AXIS _A
DEF STRING[8] T
_A=AXNAME("y")
T=AXSTRING(_A)
MSG(T<<AXSTRING(Z)<<" "<<AXTOSPI(C1)<<" "<<SPI(1)<<" "<<ISAXIS(1)<<ISAXIS(4))
MSG(ISVAR("_A")<<ISVAR("_NONE")<<ISVAR("R7")<<ISVAR("$P_TOOLNO"))
M30
"""
    r = ok(tmp_path, text, TURNMILL)
    assert messages(r) == ["YZ 1 C1 10", "1011"]
    assert check(tmp_path, text, TURNMILL) == []
    e = error_of(run(tmp_path, "R1=AXTOSPI(X)\nM30\n", TURNMILL))
    assert (e.kind, e.line) == ("unknown_axis", 1)


def test_axis_chosen_at_run_time(tmp_path):
    # a measuring macro gets the axis to probe as an AXIS parameter and moves it with AX[...]
    text = """DEF AXIS _AX=X
G17 G90 G54 G0 X0 Y0 Z50
AX[_AX]=10
_AX=AXNAME("Y")
G1 AX[_AX]=IC(5) F500
ATRANS AX[_AX]=100
G0 Y0
TRANS
M30
"""
    r = ok(tmp_path, text, MILL3)
    ends = [(m.axes["X"], m.axes["Y"]) for m in moves(r)]
    assert ends == [(0.0, 0.0), (10.0, 0.0), (10.0, 5.0), (10.0, 100.0)]
    assert check(tmp_path, text, MILL3) == []


def test_axis_variable_naming_no_axis_of_the_machine(tmp_path):
    text = "DEF AXIS _AX\n_AX=AXNAME(\"A\")\nG0 X1\nAX[_AX]=10\nM30\n"
    assert check(tmp_path, text, MILL3) == []
    e = error_of(run(tmp_path, text, MILL3))
    assert (e.kind, e.line) == ("unknown_axis", 4)
    ok(tmp_path, text, MILL5AC)


def test_set_and_rep_from_a_computed_index_fill_in_row_order(tmp_path):
    text = """DEF REAL A[3,4]
DEF INT I=1, J=2
A[I,J]=SET(1,2,,4)
A[0,I]=REP(9,2)
MSG(A[1,2]<<A[1,3]<<A[2,0]<<A[2,1]<<" "<<A[0,1]<<A[0,2]<<A[0,3])
I=2
A[I,J]=SET(1,2,3)
M30
"""
    r = run(tmp_path, text, MILL3)
    assert messages(r) == ["1204 990"]
    e = error_of(r)
    assert (e.kind, e.line) == ("index_range", 7)
    found = check(tmp_path, "DEF REAL A[3]\nDEF INT I\nA[I]=REP(1)\nM30\n", MILL3)
    assert [(f.kind, f.line) for f in found] == [("unsupported", 3)]


def test_a_label_defined_twice_is_a_warning_and_jumps_search_their_direction(tmp_path):
    # two loops reuse the label of the same name: GOTOB finds the one just above it
    text = """R1=0
R2=0
MARK: R1=R1+1
IF R1<3 GOTOB MARK
GOTOF WEITER
WEITER: G0 X=R1
MARK: R2=R2+1
IF R2<2 GOTOB MARK
GOTOF WEITER
G0 X99
WEITER: G0 Y=R2
M30
"""
    found = check(tmp_path, text, MILL3)
    assert sorted((f.kind, f.severity, f.line) for f in found) == [
        ("duplicate_label", "warning", 7), ("duplicate_label", "warning", 11),
        ("unreachable_block", "warning", 10)]
    r = ok(tmp_path, text, MILL3)
    assert [(m.axes["X"], m.axes["Y"]) for m in moves(r)] == [(3.0, 0.0), (3.0, 2.0)]


def test_fixed_point_and_reference_point_approach(tmp_path):
    # machine-builder programs retract with G75 (the tool-change point) and G74; the machine
    # axes may be written by their machine-axis names (Z1); the values written are ignored
    control = replace(MILL3, machine_data={**MILL3.machine_data,
                                           "$MA_FIX_POINT_POS": {(0, "Z"): -5.0, (1, "Z"): -50.0,
                                                                 (1, "X"): 200.0}})
    text = """G54 G90 G1 X10 Y10 Z-100 F1000
G75 FP=2 X1=0 Z1=0
G75 Z1=0
G74 X1=0 Y1=0
G1 Z-90
M30
"""
    r = ok(tmp_path, text, control)
    ends = [(m.source.line, m.axes["X"], m.axes["Y"], m.axes["Z"], m.kind) for m in moves(r)]
    assert ends == [(1, 10.0, 10.0, -100.0, "feed"), (2, 200.0, 10.0, -50.0, "traverse"),
                    (3, 200.0, 10.0, -5.0, "traverse"), (4, 0.0, 0.0, -5.0, "traverse"),
                    (5, 0.0, 0.0, -90.0, "feed")]     # G75/G74 leave G1 modal
    assert [f.data["name"] for f in r.findings if f.kind == "machine_data_default"] == ["$MA_REFP_SET_POS"]
    assert check(tmp_path, text, control) == []
    e = error_of(run(tmp_path, "G75 FP=7 Z1=0\nM30\n", control))
    assert (e.kind, e.line) == ("invalid_value", 1)
    assert [(f.kind, f.line) for f in check(tmp_path, "G75 Q1=0\nM30\n", control)] == [("unknown_axis", 1)]


def test_working_area_limits_fine_stops_and_quick_outputs_are_accepted(tmp_path):
    text = """G25 X-10 Y-10 Z-300
G26 X=500 Y=300 Z=0
WALIMON
G0 X0 Y0 Z10 FINEA=X
FINEA[Y] COARSEA[Z]
M=QU(8) H=QU(1)
G41 OFFN=0 G1 X10 F100
G40 X20
TOFFOF()
M30
"""
    r = ok(tmp_path, text, MILL3)
    assert check(tmp_path, text, MILL3) == []
    noted = {f.data["command"] for f in r.findings if f.kind == "no_effect"}
    assert {"G25", "G26", "FINEA", "COARSEA", "OFFN", "TOFFOF"} <= noted
    e = error_of(run(tmp_path, "G0 X0\nOFFN=0.5\nM30\n", MILL3))
    assert (e.kind, e.line) == ("unsupported", 2)


def test_system_variable_as_index_of_another(tmp_path):
    text = "T1 D1\nM6\nR2=$TC_DP6[$P_TOOLNO,$P_TOOL]\nMSG(\"R\"<<R2)\nM30\n"
    assert messages(ok(tmp_path, text, MILL3)) == ["R0"]


def test_machine_data_maker_cycles_read(tmp_path):
    # maker cycles branch on user machine data and the tool-change mode; unset, they read the
    # control's defaults, each named once by an info finding
    text = """IF $MN_USER_DATA_INT[2]<>0 GOTOF SPECIAL
IF $MC_TOOL_CHANGE_MODE==1 GOTOF SPECIAL
IF $P_SEARCHL>0 GOTOF SPECIAL
R1=$MC_CUTTING_EDGE_DEFAULT+$SC_WEAR_SIGN+$MN_USER_DATA_FLOAT[0]
G0 X=R1
M30
SPECIAL:
SETAL(61000)
M30
"""
    r = ok(tmp_path, text, MILL3)
    assert [m.axes["X"] for m in moves(r)] == [1.0]
    named = sorted(f.data["name"] for f in r.findings if f.kind == "machine_data_default")
    assert named == ["$MC_CUTTING_EDGE_DEFAULT", "$MC_TOOL_CHANGE_MODE", "$MN_USER_DATA_FLOAT",
                     "$MN_USER_DATA_INT", "$SC_WEAR_SIGN"]


def test_functions_vmach_does_not_simulate_are_unsupported_by_name(tmp_path):
    # never `unknown_cycle`, `unknown_word` or `undefined_variable` for the control's own words
    for line in ("GETSELT(R1)", 'TCA("BALL6", 1, 1)', "SPLINEPATH(1, X, Y, Z)", "G1 X1 PL=2 F100",
                 "G41 CUT3DC ISD=2 X1 F100", "TRAILON(Y, X, 1)", "LEADON(Y, X, 1)",
                 'R1=GETT("BALL6", 1)', "R1=CALCDAT(R[10], 3, R[20])", 'EXECSTRING("G0 X1")',
                 'E_HEAD(1, "PLATE", 0, 100)', "F_DRILL(1, 2)"):      # ShopMill / ShopTurn step cycles
        found = check(tmp_path, f"G0 X0 Y0 Z0\n{line}\nM30\n", MILL5AC)
        assert [(f.kind, f.line) for f in found] == [("unsupported", 2)], line
    assert check(tmp_path, "DRFOF\nCANCEL(1)\nSTOPREOF\nG0 X0\nM30\n", MILL5AC) == []


def _strokes(result) -> list[tuple[str, float]]:
    return [(m.kind, round(m.axes["Z"], 9)) for m in moves(result)[1:]]


def test_drilling_cycles_with_the_parameters_operate_appends(tmp_path):
    # CAM posts write the SINUMERIK Operate lists: CYCLE81(…, DTB, GMODE, DMODE, AMODE)
    head = "G17 G90 G0 X5 Y6 Z50\nF120\n"
    r = ok(tmp_path, head + "CYCLE81(10, 0, 2, -5, , 0.5, 0, 1, 11)\nM30\n", MILL3)
    assert _strokes(r) == [("traverse", 2.0), ("feed", -5.0), ("traverse", 10.0)]
    assert [c.seconds for c in r.commands if c.kind == "dwell"] == [0.5]
    # CYCLE83 chip breaking: _VRT 0.5 back-off, _DTD 2 s at the final depth, _DIS1 unused there
    r = ok(tmp_path, head + "CYCLE83(10, 0, 2, -9, , -4, , 3, 1, 0, 1, 0, 0, 0, 0.5, 2, 0, 0, 1, 11)\nM30\n",
           MILL3)
    assert _strokes(r) == [("traverse", 2.0), ("feed", -4.0), ("traverse", -3.5), ("feed", -7.0),
                           ("traverse", -6.5), ("feed", -9.0), ("traverse", 10.0)]
    assert [c.seconds for c in r.commands if c.kind == "dwell"] == [2.0]
    # _MDEP: the strokes get smaller by DAM, never below the minimum depth
    r = ok(tmp_path, head + "CYCLE83(10, 0, 2, -30, , -10, , 2, 0, 0, 1, 0, 0, 3, 0, 0, 0, 0, 1, 11)\nM30\n",
           MILL3)
    assert [z for k, z in _strokes(r) if k == "feed"] == [-10.0, -18.0, -24.0, -28.0, -30.0]
    for call in ("CYCLE81(10, 0, 2, -5, , 0, 1, 1, 11)",            # GMODE=1: depth to the diameter
                 "CYCLE83(10, 0, 2, -9, , -4, , 3, 0, 0, 1, 0, 1, 0, 0, 0, 0, 0, 1, 11)",  # _AXN=1
                 "CYCLE82(10, 0, 2, -5, , -3)"):                    # a dwell in revolutions
        e = error_of(run(tmp_path, head + call + "\nM30\n", MILL3))
        assert (e.kind, e.line) == ("unsupported", 3), call


def test_a_transfer_files_end_of_file_character_ends_it(tmp_path):
    text = "%\r\nN10 G0 X0 Y0 Z10\r\nN20 M30\r\n\x1a"
    assert check(tmp_path, text, MILL3) == []
    assert ok(tmp_path, text, MILL3).completed
    assert [(f.kind, f.line) for f in check(tmp_path, "G0 X0\n\x1aG0 X1\nM30\n", MILL3)] == [("syntax", 2)]


def test_a_warm_up_that_waits_on_the_controls_clock_ends(tmp_path):
    # a machine maker's warm-up: spindle steps, axes moving, until 3 minutes have passed on the
    # control's clock; vmach's clock runs on the estimated machining time from a fixed instant
    text = """DEF REAL T0, NOW
N10 G17 G90 G54 G0 X0 Y0 Z0 S2000 M3
N20 T0=$A_HOUR*60+$A_MINUTE+$A_SECOND/60
MARK:
N30 G1 X500 F10000
N40 X0
N50 STOPRE
N60 NOW=$A_HOUR*60+$A_MINUTE+$A_SECOND/60
N70 IF NOW-T0<3 GOTOB MARK
N80 MSG("W"<<ROUND($AN_POWERON_TIME)<<" "<<$A_YEAR<<" "<<$A_DAY)
N90 M5
N100 M30
"""
    r = ok(tmp_path, text, MILL3)
    feeds = [m for m in moves(r) if m.kind == "feed"]
    assert len(feeds) == 60                  # 30 rounds of 2 moves of 3 s: 180 s
    assert messages(r) == ["W3 2000 1"]


def test_indirect_calls_a_program_named_by_a_variable_and_a_section_of_this_one(tmp_path):
    text = """DEF STRING[32] PNAME
G0 X0 Y0 Z0
PNAME="UP_"<<2
CALL PNAME
CALL BLOCK START TO FINISH
G0 Z9
M30
START: G0 X5
FINISH: G0 X6
"""
    r = ok(tmp_path, text, MILL3, UP_2_DOT_SPF="G0 Y7\nM17\n")
    assert [(m.source.line, m.axes["X"], m.axes["Y"], m.axes["Z"]) for m in moves(r)] == [
        (2, 0.0, 0.0, 0.0), (1, 0.0, 7.0, 0.0), (8, 5.0, 7.0, 0.0), (9, 6.0, 7.0, 0.0), (6, 6.0, 7.0, 9.0)]
    assert check(tmp_path, text, MILL3, UP_2_DOT_SPF="G0 Y7\nM17\n") == []
    e = error_of(run(tmp_path, text.replace('"UP_"<<2', '"NONE"'), MILL3))
    assert (e.kind, e.line) == ("subprogram_not_found", 4)
    found = check(tmp_path, 'G0 X0\nCALL "UP_2" BLOCK START TO FINISH\nM30\n', MILL3, UP_2_DOT_SPF="M17\n")
    assert [(f.kind, f.line) for f in found] == [("unsupported", 2)]
