"""Global user data (GUD) definition files beside the program (issue 32): their variables
exist in every program of the directory with their types, initial values and arrays; nothing is
read from outside the directory. Programs after the manuals' GUD examples, written anew."""

from __future__ import annotations

from pathlib import Path

from nc import check, error_of, kinds, linked_from_outside, moves, ok, run

from interpreters import sinumerik
from vmach.canon import DEFAULT_CONTROL, RunOptions

UGUD = """%_N_UGUD_DEF
;$PATH=/_N_DEF_DIR
DEF NCK REAL SAFE_Z=50.5
DEF CHAN INT PARTS
DEF NCK APR 7 APW 2 REAL DEPTHS[3]=SET(1.5, 2.5, 3.5)
DEF CHAN STRING[16] LABEL="ABC"
M30
"""


def test_gud_variables_are_global_with_initial_values_and_arrays(tmp_path):
    """A main program and its subprogram share the GUD: what the subprogram writes, the main
    program reads back (unlike a DEF inside a program, which belongs to its level)."""
    r = ok(tmp_path, "N10 G0 Z=SAFE_Z\nN20 PARTS=PARTS+1\nN30 SUB1\nN40 G1 X=PARTS Y=DEPTHS[2] F100\n"
           "N50 IF LABEL==\"ABC\" GOTOF DONE\nN60 G0 X999\nDONE:\nM30\n",
           _N_UGUD_DEF=UGUD, SUB1_DOT_SPF="PROC SUB1\nPARTS=PARTS+10\nDEPTHS[2]=7\nRET\n")
    m = moves(r)
    assert m[0].axes["Z"] == 50.5
    assert (m[1].axes["X"], m[1].axes["Y"]) == (11.0, 7.0)
    assert len(m) == 2


def test_pc_names_of_definition_files_and_activation_order(tmp_path):
    """``SGUD.DEF`` and ``_N_MGUD_DEF.DEF`` are read too; check finds no undefined variable."""
    found = check(tmp_path, "G0 X=MAKER_X Y=USER_Y\nM30\n", SGUD_DOT_DEF="DEF NCK REAL MAKER_X=3\n",
                  _N_MGUD_DEF_DOT_DEF="DEF CHAN REAL USER_Y=4\n")
    assert kinds(found, "error") == []
    r = ok(tmp_path, "G0 X=MAKER_X Y=USER_Y\nM30\n")
    assert (moves(r)[0].axes["X"], moves(r)[0].axes["Y"]) == (3.0, 4.0)


def test_without_the_definition_file_the_name_is_undefined(tmp_path):
    found = check(tmp_path, "G0 X=SAFE_Z\nM30\n")
    assert kinds(found, "error") == [("undefined_variable", 1)]


def test_an_error_in_a_definition_file_names_its_line(tmp_path):
    found = check(tmp_path, "M30\n", _N_UGUD_DEF="%_N_UGUD_DEF\nDEF NCK REAL A\nG1 X10\nDEF NCK BANANA B\n"
                  "DEF NCK FRAME F\n")
    errs = [(f.kind, f.severity, Path(f.source.path).name, f.line) for f in found]
    assert errs == [("syntax", "error", "_N_UGUD_DEF", 3), ("syntax", "error", "_N_UGUD_DEF", 4),
                    ("unsupported_definition", "warning", "_N_UGUD_DEF", 5)]
    assert Path(found[0].source.path).parent == tmp_path


def test_a_local_definition_of_a_gud_name_is_a_duplicate(tmp_path):
    found = check(tmp_path, "DEF REAL SAFE_Z\nM30\n", _N_UGUD_DEF=UGUD)
    assert kinds(found, "error") == [("duplicate_definition", 1)]


def test_a_definition_file_linked_from_outside_is_not_read(tmp_path):
    job = linked_from_outside(tmp_path, "_N_UGUD_DEF", UGUD)
    (job / "P.MPF").write_text("G0 Z=SAFE_Z\nM30\n")
    r = sinumerik.run(job / "P.MPF", DEFAULT_CONTROL, RunOptions())
    assert (error_of(r).kind, error_of(r).line) == ("undefined_variable", 1)


def test_a_bad_initial_value_stops_the_run_at_its_definition(tmp_path):
    r = run(tmp_path, "M30\n", _N_GUD5_DEF="DEF NCK REAL Q=1/0\n")
    f = error_of(r)
    assert (f.kind, Path(f.source.path).name, f.line) == ("division_by_zero", "_N_GUD5_DEF", 1)


def test_definition_files_named_by_the_machine_or_the_setup(tmp_path):
    # a machine maker keeps its GUD under its own name; the model (or vmach.toml) names it,
    # and it is read from the program's directory (or below) only
    from dataclasses import replace

    (tmp_path / "GUD").mkdir()
    (tmp_path / "GUD" / "MAKER.DEF").write_text("DEF NCK REAL TC_Z=-20\nM30\n", encoding="utf-8")
    control = replace(DEFAULT_CONTROL, definitions=("GUD/MAKER.DEF", "ABSENT.DEF"))
    text = "G0 Z=TC_Z\nM30\n"
    assert [m.axes["Z"] for m in moves(ok(tmp_path, text, control))] == [-20.0]
    assert check(tmp_path, text, control) == []
    assert kinds(check(tmp_path, text)) == [("undefined_variable", 1)]
    job = linked_from_outside(tmp_path, "OUT.DEF", "DEF NCK REAL TC_Z=-5\n")
    outside = replace(DEFAULT_CONTROL, definitions=("OUT.DEF",))
    r = run(job, text, outside)
    assert ("file_outside", 1) in kinds(r.findings) and not r.completed


def test_the_setup_file_names_definition_files_inside_its_directory(tmp_path):
    import pytest

    from vmach.errors import InputError
    from vmach.setup import control_for

    job = tmp_path / "job"
    job.mkdir()
    for d in (tmp_path, job):
        (d / "MAKER.DEF").write_text("DEF NCK INT TOOLS=3\n", encoding="utf-8")
    prog = job / "P.MPF"
    prog.write_text("R1=TOOLS\nM30\n", encoding="utf-8")
    (job / "vmach.toml").write_text('definitions = ["MAKER.DEF"]\n', encoding="utf-8")
    control, _ = control_for(prog, "mill3")
    assert control.definitions == ("MAKER.DEF",)
    assert sinumerik.run(prog, control, RunOptions()).completed
    (job / "vmach.toml").write_text('definitions = ["../MAKER.DEF"]\n', encoding="utf-8")
    with pytest.raises(InputError) as exc:
        control_for(prog, "mill3")
    assert (exc.value.kind, exc.value.source.line) == ("file_outside", 1)
