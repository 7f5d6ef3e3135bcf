"""System variables and machine data: the virtual NCK (issue 32). Each program follows an
example of the Siemens manuals (Lists of system variables, Job planning: frames, machine data
in cycles), written anew; values come out as the axis targets of a final G0."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import pytest
from nc import check, error_of, kinds, moves, ok, run

from vmach.canon import DEFAULT_CONTROL, ControlSpec, RunOptions, SetVariable
from vmach.machine.loader import load_model_control

MODELS = Path(__file__).resolve().parents[2] / "models"


def last(result) -> dict:
    return moves(result)[-1].axes


def test_machine_data_come_from_the_model(tmp_path):
    """A cycle reads the travel limits and the basic system of the machine (MD 36100/36110,
    MD 10240) to decide where to retract."""
    control = load_model_control(MODELS / "mill5ac.toml")
    r = ok(tmp_path, "R1=$MA_POS_LIMIT_PLUS[A] R2=$MA_POS_LIMIT_MINUS[AX1]\n"
           "IF $MN_SCALING_SYSTEM_IS_METRIC==1 GOTOF METRIC\nR3=25.4\nMETRIC:\n"
           "R4=$MA_MAX_AX_VELO[Z]\nG0 X=R1 Y=R2 Z=R3+R4/1000\nM30\n", control)
    assert last(r)["X"] == 120.0 and last(r)["Y"] == -325.0 and last(r)["Z"] == 45.0
    assert not [f for f in r.findings if f.kind == "machine_data_default"]


def test_an_undocumented_datum_reads_as_its_default_with_an_info_finding(tmp_path):
    r = ok(tmp_path, "N10 G0 X=$MN_SCALING_VALUE_INCH\nN20 Y=$MN_SCALING_VALUE_INCH\nM30\n")
    assert last(r)["X"] == 25.4 and last(r)["Y"] == 25.4
    notes = [f for f in r.findings if f.kind == "machine_data_default"]
    assert [(f.severity, f.line, f.source.column, f.data["name"]) for f in notes] == [
        ("info", 1, 10, "$MN_SCALING_VALUE_INCH")]               # once, at the first read


def test_machine_data_table_of_the_model_overrides_the_default(tmp_path):
    control = ControlSpec(machine_data={"$MN_SCALING_SYSTEM_IS_METRIC": 0,
                                        "$MA_DRIVE_AX_RATIO_DENOM": {(1, "Z"): 4}})
    r = ok(tmp_path, "DEF AXIS _Z\n_Z=$P_AXN3\nR1=$MA_DRIVE_AX_RATIO_DENOM[1,_Z]\n"
           "R2=$MN_SCALING_SYSTEM_IS_METRIC\nG0 X=R1 Y=R2\nM30\n", control)
    assert (last(r)["X"], last(r)["Y"]) == (4.0, 0.0)


def test_settable_frames_are_written_read_and_selected(tmp_path):
    """Job planning, frames: $P_UIFR[1]=CTRANS(X,10,Y,20) then G54 moves in the offset system;
    a component is read and written as $P_UIFR[n, axis, TR]; CFINE adds a fine offset."""
    r = ok(tmp_path, "N10 $P_UIFR[1]=CTRANS(X,10,Y,20,Z,-5)\nN20 $P_UIFR[1,Z,TR]=-7\n"
           "N30 $P_UIFR[2]=CTRANS(X,1):CFINE(X,0.25)\nN40 G54 G0 X0 Y0 Z0\n"
           "N50 R1=$P_UIFR[1,X,TR] R2=$P_UIFR[2,X,FI] R3=$P_GG[8]\nN60 G55 G0 X0 Y0 Z0\n"
           "N70 G500 G0 X=R1 Y=R2 Z=R3\nM30\n")
    m = moves(r)
    assert (m[0].axes["X"], m[0].axes["Y"], m[0].axes["Z"]) == (10.0, 20.0, -7.0)
    assert m[1].axes["X"] == 1.25
    assert (m[2].axes["X"], m[2].axes["Y"], m[2].axes["Z"]) == (10.0, 0.25, 2.0)   # G54 = group 8 #2


def test_frame_chain_translates_in_the_rotated_system(tmp_path):
    """CTRANS(X,10):CROT(Z,90):CTRANS(X,5): the second offset runs along the turned X (= Y)."""
    r = ok(tmp_path, "$P_UIFR[3]=CTRANS(X,10):CROT(Z,90):CTRANS(X,5)\n"
           "G0 X=$P_UIFR[3,X,TR] Y=$P_UIFR[3,Y,TR] Z=$P_UIFR[3,Z,RT]\nM30\n")
    x, y, z = (last(r)[a] for a in "XYZ")
    assert math.isclose(x, 10.0, abs_tol=1e-12) and math.isclose(y, 5.0) and math.isclose(z, 90.0)


def test_a_rotated_settable_frame_chains_before_the_programmable_one(tmp_path):
    """G54 = CTRANS(X,10):CROT(Z,90): X5 in the work system is machine (10, 5); a TRANS X1 on
    top runs along the turned X (machine Y); $P_EP reads work coordinates back."""
    r = ok(tmp_path, "$P_UIFR[1]=CTRANS(X,10):CROT(Z,90)\nG54 G0 X5 Y0\nTRANS X1\nG0 X0 Y0\n"
           "R1=$P_EP[X] R2=$P_EP[Y]\nTRANS\nG0 X=R1 Y=R2\nM30\n")
    got = [(m.axes["X"], m.axes["Y"]) for m in moves(r)]
    assert got == [pytest.approx((10.0, 5.0)), pytest.approx((10.0, 1.0)), pytest.approx((10.0, 0.0))]


def test_a_mirrored_settable_frame_turns_arcs_as_mirror_does(tmp_path):
    """A settable frame CMIRROR(X) and the programmable MIRROR X give the same arc."""
    a = ok(tmp_path, "$P_UIFR[2]=CMIRROR(X)\nG55 G0 X0 Y0\nG2 X10 Y0 CR=5 F100\nM30\n")
    b = ok(tmp_path, "MIRROR X0\nG0 X0 Y0\nG2 X10 Y0 CR=5 F100\nM30\n")
    arc_a, arc_b = moves(a)[-1], moves(b)[-1]
    assert (arc_a.axes["X"], arc_a.clockwise, arc_a.center) == (arc_b.axes["X"], arc_b.clockwise,
                                                                 arc_b.center)
    assert arc_a.axes["X"] == -10.0 and not arc_a.clockwise


def test_model_zero_offsets_are_the_settable_frames(tmp_path):
    control = ControlSpec(zero_offsets={"G54": {"X": 100.0}, "G505": {"Y": 7.0}})
    r = ok(tmp_path, "G0 X=$P_UIFR[1,X,TR] Y=$P_UIFR[5,Y,TR]\nM30\n", control)
    assert (last(r)["X"], last(r)["Y"]) == (100.0, 7.0)


def test_p_gg_gives_the_active_code_of_a_group(tmp_path):
    """$P_GG[6] 1/2/3 for G17/G18/G19 (as cycles test the plane), [14] G90/G91, [13] G70/G71."""
    r = ok(tmp_path, "G18 G91 G55\nR1=$P_GG[6] R2=$P_GG[14] R3=$P_GG[8]\nG17 G90 G70\n"
           "R4=$P_GG[6] R5=$P_GG[13] R6=$P_GG[1]\nG71 G500 G0 X=R1*10+R2 Y=R3 Z=R4*100+R5*10+R6\nM30\n")
    assert (last(r)["X"], last(r)["Y"], last(r)["Z"]) == (22.0, 3.0, 111.0)


def test_programmed_end_point_and_actual_values(tmp_path):
    """$P_EP is in the work system (after G54), $AA_IM in the machine system; DIAMON doubles X."""
    control = ControlSpec(zero_offsets={"G54": {"X": 5.0, "Z": 100.0}}, transverse="X")
    r = ok(tmp_path, "G54 G0 X20 Z-3\nR1=$P_EP[X] R2=$AA_IM[X] R3=$AA_IW[Z]\nDIAMON\nR4=$P_EP[X]\n"
           "G500 DIAMOF G0 X=R1 Y=R2 Z=R3*1000+R4\nM30\n", control)
    assert (last(r)["X"], last(r)["Y"], last(r)["Z"]) == (20.0, 25.0, -3000.0 + 40.0)


def test_synchronised_action_variables_and_plc_writes(tmp_path):
    """$AC_MARKER and $AC_PARAM keep what was written; a PLC write ($A_OUT, $A_DBB) is recorded
    in the trace at its line; $A_IN reads the model's value, else 0."""
    control = ControlSpec(machine_data={"$A_IN": {2: 1}})
    r = ok(tmp_path, "N10 $AC_MARKER[1]=3 $AC_PARAM[0]=2.5\nN20 $A_OUT[4]=1\nN30 $A_DBB[10]=255\n"
           "N40 G0 X=$AC_MARKER[1] Y=$AC_PARAM[0] Z=$A_IN[2]*10+$A_IN[1]\nM30\n", control)
    assert (last(r)["X"], last(r)["Y"], last(r)["Z"]) == (3.0, 2.5, 10.0)
    sets = [(c.name, c.value, c.source.line) for c in r.commands if isinstance(c, SetVariable)]
    assert sets == [("$A_OUT[4]", 1, 2), ("$A_DBB[10]", 255, 3)]
    assert not [f for f in r.findings if f.kind == "machine_data_default"]


def test_tool_data_from_the_library_and_written_by_the_program(tmp_path):
    """$TC_DP6[T,D] is the radius, $TC_DP3 the length; a program that writes $TC_DP6 sets the
    radius tool radius compensation uses."""
    data = {("1", 1): {"name": "1", "type": "ball", "length": 80.0, "radius": 5.0}}
    opts = RunOptions(tool_radius=lambda t, d: data[(t, d)]["radius"] if (t, d) in data else None,
                      tool_data=lambda t, d: data.get((t, d)))
    r = run(tmp_path, "T1 D1\nR1=$TC_DP6[1,1] R2=$TC_DP3[1,1] R3=$TC_DP1[1,1]\n"
            "$TC_DP6[1,1]=2\nG0 X0 Y0\nG41 G1 X20 Y0 F100\nG40 G0 X=R1 Y=R2 Z=R3\nM30\n", options=opts)
    assert r.completed, r.findings
    m = moves(r)
    assert m[1].axes["Y"] == pytest.approx(2.0)                  # offset by the written radius
    assert (last(r)["X"], last(r)["Y"], last(r)["Z"]) == (5.0, 80.0, 110.0)


def test_program_state_of_a_subprogram_call(tmp_path):
    """$P_SUBPAR[n] tells whether the call gave parameter n (SUB(1,,3))."""
    r = ok(tmp_path, "SUB(1,,3)\nM30\n",
           SUB_DOT_SPF="PROC SUB(REAL A, REAL B, REAL C)\nG0 X=$P_SUBPAR[1] Y=$P_SUBPAR[2] "
           "Z=$P_SUBPAR[3]+$P_STACK*10\nRET\n")
    assert (last(r)["X"], last(r)["Y"], last(r)["Z"]) == (1.0, 0.0, 11.0)


def test_a_run_is_never_a_search_test_or_dry_run(tmp_path):
    r = ok(tmp_path, "IF $P_SEARCH OR $P_DRYRUN OR $P_ISTEST\nG0 X1\nELSE\nG0 X2\nENDIF\n"
           "F250 S1200 M3\nG0 Y=$P_F Z=$P_S[1]\nM30\n")
    assert (last(r)["X"], last(r)["Y"], last(r)["Z"]) == (2.0, 250.0, 1200.0)


def test_read_only_and_unknown_variables_in_check(tmp_path):
    """Writing a read-only variable is read_only; an unknown system variable is unsupported,
    the same kind whether read or written."""
    found = check(tmp_path, "N10 $P_EP[X]=1\nN20 R1=$P_NOSUCH\nN30 $P_NOSUCH=1\nN40 R2=$P_GG\nM30\n")
    assert kinds(found, "error") == [("read_only", 1), ("unsupported", 2), ("unsupported", 3), ("syntax", 4)]


@pytest.mark.parametrize("expr", ["$P_UIFR[1]+1", "$P_UIFR[1]", "ABS($P_UIFR[1])", "2/$P_UIFR[1]",
                                  "$P_UIFR[1] MOD 2", "NOT $P_UIFR[1]", "-$P_UIFR[1]", "1:2",
                                  "CTRANS(X,1):2", "SIN($P_UIFR[1])", "$AC_MARKER[$P_UIFR[1]]"])
def test_a_frame_is_no_number(tmp_path, expr):
    """A frame where a number belongs (or ':' between numbers) is the control's type error,
    never a traceback."""
    f = error_of(run(tmp_path, f"N10 R1={expr}\nM30\n"))
    assert (f.kind, f.line) == ("type_error", 1)


def test_writing_the_programmable_frame_moves_like_trans_and_rot(tmp_path):
    """$P_PFRAME=CTRANS(X,10):CROT(Z,90) is TRANS X10 followed by AROT Z90."""
    a = ok(tmp_path, "$P_PFRAME=CTRANS(X,10):CROT(Z,90)\nG0 X5 Y0\nR1=$P_PFRAME[X,TR]\nG0 X=R1 Y1\nM30\n")
    b = ok(tmp_path, "TRANS X10\nAROT Z90\nG0 X5 Y0\nG0 X10 Y1\nM30\n")
    for ma, mb in zip(moves(a), moves(b), strict=True):
        assert [ma.axes[k] for k in "XYZ"] == pytest.approx([mb.axes[k] for k in "XYZ"], abs=1e-12)
    assert moves(a)[0].axes["X"] == pytest.approx(10.0) and moves(a)[0].axes["Y"] == pytest.approx(5.0)


def test_workpiece_counter_clock_and_active_tool_data(tmp_path):
    """A shop program counts parts ($AC_ACTUAL_PARTS); the clock reads a fixed instant;
    $P_AD[6] and $P_TOOLL[1] are the active edge's radius and length; $AA_S the speed."""
    data = {("3", 2): {"name": "3", "type": "flat", "length": 95.0, "radius": 4.0}}
    opts = RunOptions(tool_data=lambda t, d: data.get((t, d)))
    r = run(tmp_path, "$AC_ACTUAL_PARTS=$AC_ACTUAL_PARTS+1\nT3 D2\nS800 M3\n"
            "G0 X=$AC_ACTUAL_PARTS*1000+$A_YEAR Y=$P_AD[6]*100+$P_TOOLL[1] Z=$AA_S[1]+$P_TOOLP\n"
            "M5\nG0 X=$AA_S\nM30\n", options=opts)
    assert r.completed, r.findings
    m = moves(r)
    assert (m[0].axes["X"], m[0].axes["Y"], m[0].axes["Z"]) == (3000.0, 495.0, 803.0)
    assert m[1].axes["X"] == 0.0


def test_the_active_settable_frame_is_written_at_once(tmp_path):
    """Writing $P_IFRAME acts at once (no G54 needed) and leaves $P_UIFR[1] as it was; the
    next G54 selects the stored frame again (Function Manual K2, settable frames)."""
    control = ControlSpec(zero_offsets={"G54": {"X": 100.0}})
    r = ok(tmp_path, "G54 G0 X0\n$P_IFRAME[X,TR]=50\nG0 X0\nG0 Y=$P_UIFR[1,X,TR]\nG54 G0 X0\nM30\n", control)
    assert [m.axes["X"] for m in moves(r)] == [100.0, 50.0, 50.0, 100.0]
    assert moves(r)[2].axes["Y"] == 100.0


def test_crpl_rotates_in_the_working_plane(tmp_path):
    """CRPL(0, 30) under G18 turns about Y; CRPL(1, 45) about Z."""
    r = ok(tmp_path, "G18\n$P_UIFR[1]=CRPL(0,30)\n$P_UIFR[2]=CTRANS(X,1):CRPL(1,45)\n"
           "G17 G0 X=$P_UIFR[1,Y,RT] Y=$P_UIFR[2,Z,RT] Z=$P_UIFR[1,Z,RT]\nM30\n")
    assert [last(r)[a] for a in "XYZ"] == pytest.approx([30.0, 45.0, 0.0])


def test_axis_indices_by_name_number_and_loose_letter(tmp_path):
    """$AA_IM[AX2] and $AA_IM[2] are the second machine axis; without a machine any axis letter
    is an axis, with one an axis it lacks is unknown_axis."""
    r = ok(tmp_path, "G0 X1 Y2 Z3\nG0 X=$AA_IM[AX2] Y=$AA_IM[3] Z=$P_EP[B]\nM30\n")
    assert [last(r)[a] for a in "XYZ"] == [2.0, 3.0, 0.0]
    strict = replace(DEFAULT_CONTROL, strict_axes=True)                  # X Y Z only
    f = error_of(run(tmp_path, "N10 G0 X1\nN20 R1=$P_EP[B]\nM30\n", strict))
    assert (f.kind, f.line) == ("unknown_axis", 2)


def test_a_warm_up_program_waiting_on_a_timer_ends(tmp_path):
    """Spindle warm-up: start $AC_TIMER[1], dwell 10 s per pass until 60 s have passed — six
    passes (the timer runs on the dwells and moves the run has made)."""
    r = ok(tmp_path, "S1000 M3\n$AC_TIMER[1]=0\nR1=0\nWARM:\nG4 F10\nR1=R1+1\n"
           "IF $AC_TIMER[1]<60 GOTOB WARM\nM5\nG0 X=R1 Y=$AC_CYCLE_TIME\n$AC_TIMER[1]=-1\n"
           "G4 F5\nG0 Z=$AC_TIMER[1]\nM30\n")
    assert last(r)["X"] == 6.0 and last(r)["Y"] == pytest.approx(60.0) and last(r)["Z"] == -1.0


def test_the_clock_counts_feeds_rapids_and_spindle_revolutions(tmp_path):
    """G1 100 mm at F600 = 10 s; a rapid of 100 mm at $MA_MAX_AX_VELO 6000 mm/min = 1 s; G95 F0.1
    at S600 = 60 mm/min, 20 mm = 20 s; a quarter circle of radius 10 at F600 ≈ 1.571 s; G4 S5 at
    S600 = 0.5 s."""
    control = ControlSpec(machine_data={"$MA_MAX_AX_VELO": {"X": 6000.0, "Y": 6000.0, "Z": 6000.0}})
    r = ok(tmp_path, "S600 M3\n$AC_TIMER[2]=0\nG1 X100 F600\nR1=$AC_TIMER[2]\nG0 X0\n"
           "R2=$AC_TIMER[2]-R1\nG95 G1 X20 F0.1\nR3=$AC_TIMER[2]-R1-R2\nG94 G3 X10 Y10 CR=10 F600\n"
           "R4=$AC_CUTTING_TIME\nG4 S5\nR5=$AC_CYCLE_TIME-$AC_CUTTING_TIME\n"
           "G0 X=R1 Y=R2 Z=R3\nG0 X=R4 Y=R5\nM30\n", control)
    m = moves(r)
    assert [m[-2].axes[a] for a in "XYZ"] == pytest.approx([10.0, 1.0, 20.0])
    assert m[-1].axes["X"] == pytest.approx(10.0 + 20.0 + math.pi * 10 / 2 / 10)
    assert m[-1].axes["Y"] == pytest.approx(1.0 + 0.5)


def test_a_datum_vmach_does_not_list_is_read_from_the_model_or_is_unsupported(tmp_path):
    """$MA_MAKERS_OFFSET is no datum vmach knows a default for: the model's [machine_data] gives
    it (here per axis), else the run stops with unsupported there; check accepts both."""
    text = "N10 R1=$MA_MAKERS_OFFSET[Z]\nN20 G0 X=R1\nM30\n"
    given = ControlSpec(machine_data={"$MA_MAKERS_OFFSET": {"Z": 12.5}})
    assert last(ok(tmp_path, text, given))["X"] == 12.5
    f = error_of(run(tmp_path, text))
    assert (f.kind, f.line, f.source.column) == ("unsupported", 1, 5)     # the assignment
    assert kinds(check(tmp_path, text), "error") == []


def test_a_save_subprogram_restores_a_plain_settable_frame_after_a_rotated_one(tmp_path):
    """PROC ... SAVE selects a rotated G55; back in the caller G54 (a plain offset) holds again."""
    r = ok(tmp_path, "$P_UIFR[1]=CTRANS(X,100)\n$P_UIFR[2]=CROT(Z,90)\nG54 G0 X1 Y0\nSUB\nG0 X1 Y0\nM30\n",
           SUB_DOT_SPF="PROC SUB SAVE\nG55 G0 X1 Y0\nRET\n")
    got = [(m.axes["X"], m.axes["Y"]) for m in moves(r)]
    assert got == [pytest.approx((101.0, 0.0)), pytest.approx((0.0, 1.0)), pytest.approx((101.0, 0.0))]
