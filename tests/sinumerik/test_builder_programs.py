"""Machine builders' archives, warm-up and axis test programs, shop programs (issue 32): files
named as the control's file system names them, machine axis names in machine data, interrupts
and synchronised actions as such programs use them. Programs written for these tests after the
Programming Manuals' descriptions (Fundamentals; Job planning: "Flexible NC programming",
"Motion-synchronous actions"; Operating Manual: "Formats for saving and importing data")."""

from __future__ import annotations

from catalog import MODELS
from nc import check, error_of, moves, ok, run

from interpreters import dialect_for, sinumerik
from vmach.machine.loader import load_model_control

MILL3 = load_model_control(MODELS / "mill3.toml")


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
