"""Model files: every shipped model loads; bad files report every problem with its line."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from machine.machine_helpers import ALL_MODELS, model

from vmach.errors import InputError, ModelError
from vmach.machine import load_control, load_model
from vmach.machine.formula import FormulaError, formula_axes, parse_formula
from vmach.machine.loader import load_model_control
from vmach.machine.tomlpos import KeyLines

MODELS = Path(__file__).resolve().parents[2] / "models"


@pytest.mark.parametrize("name", ALL_MODELS)
def test_every_shipped_model_loads_and_its_control_matches_load_control(name):
    m = model(name)
    # load_control reads the control part alone; the machine data need the kinematic part
    assert replace(m.control, machine_data={}) == load_control(MODELS / f"{name}.toml")
    assert m.control == load_model_control(MODELS / f"{name}.toml")
    assert m.control.machine_data["$MN_SCALING_SYSTEM_IS_METRIC"] == 1
    assert m.axes == tuple(a.name for a in m.control.axes)
    assert np.all(np.isnan(m.limits) | (m.limits[:, :1] <= m.limits[:, 1:]))


def test_turnmill_keeps_its_control_contract():
    c = load_control(MODELS / "turnmill.toml")
    assert [a.name for a in c.axes] == ["X", "Y", "Z", "C1"]
    assert c.axis("C1").modulo == 360.0 and c.axis("C1").kind == "rotary"
    assert c.transverse == "X" and c.strict_axes
    assert {"C_AXIS_ON", "C_AXIS_OFF"} <= c.cycles and "G971" in c.gcodes
    assert c.spindles == (1, 2) and c.master_spindle == 1
    assert c.axis("X").home == 325.0 and c.axis("Z").home == 300.0


def test_turnmill_tool_change_position_is_inside_travel():
    m = model("turnmill")
    tc = m.spec.positions["tool_change"]
    assert tc == {"X": 325.0, "Y": 0.0}
    for axis, value in tc.items():
        lo, hi = m.limits[m.axes.index(axis)]
        assert lo <= value <= hi
    assert {g.name for g in m.spec.geometry} >= {"chuck_body", "jaw_1", "jaw_2", "jaw_3"}


BAD = """\
name = "bad"
[parameters]
r = [0.0, 0.0, 0.0]

[[joints]]
name = "X"
type = "prismatic"
parent = "nowhere"
child = "x"
axis = [1.0, 0.1, 0.0]
limits = [10.0, -10.0]

[[joints]]
name = "Y"
type = "sliding"
parent = "x"
child = "y"
origin = "-q"

[work]
link = "base"

[tool]
link = "y"

[[geometry]]
name = "m"
link = "x"
shape = "mesh"
path = "nope.stl"
"""


def test_every_problem_is_reported_at_once_with_its_line(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(BAD)
    with pytest.raises(ModelError) as exc:
        load_model(f)
    got = {(p.kind, p.line) for p in exc.value.findings()}
    assert got == {
        ("unknown_link", 8),
        ("non_unit_axis", 10),
        ("inverted_limits", 11),
        ("bad_value", 15),
        ("unknown_parameter", 18),
        ("missing_mesh", 30),
    }
    assert all(p.source.path == str(f) for p in exc.value.findings())


def test_existing_mesh_is_accepted_and_resolved_beside_the_model(tmp_path):
    (tmp_path / "part.stl").write_text("solid x\nendsolid x\n")
    f = tmp_path / "ok.toml"
    f.write_text(BAD.replace("nowhere", "base").replace("1.0, 0.1, 0.0", "1.0, 0.0, 0.0")
                 .replace("10.0, -10.0", "-10.0, 10.0").replace("sliding", "prismatic")
                 .replace('"-q"', '"-r"').replace("nope.stl", "part.stl"))
    m = load_model(f)
    assert m.axes == ("X", "Y")
    assert m.spec.geometry[0].path == str(tmp_path / "part.stl")


def test_formula_problems_point_at_the_formula_line(tmp_path):
    f = tmp_path / "f.toml"
    f.write_text('name = "f"\n\nformula = "WCBXYZT"\n')
    with pytest.raises(ModelError) as exc:
        load_model(f)
    assert [(p.kind, p.line) for p in exc.value.findings()] == [("bad_formula", 3)]


@pytest.mark.parametrize("bad", ["", "CBXYZ", "WCBXYZT", "TCBVXYZW", "WCBVXYZVT", "WCCVXYZT",
                                 "WCVXYZB'T", "WCQVXYZT"])
def test_invalid_formulas_are_refused(bad):
    with pytest.raises(FormulaError):
        parse_formula(bad)


def test_formula_reading():
    c = parse_formula("WC'BVXYZT")
    assert [(j.token, j.parent, j.child, j.side) for j in c.joints] == [
        ("B", "base", "b", "work"), ("C", "b", "c", "work"), ("X", "base", "x", "tool"),
        ("Y", "x", "y", "tool"), ("Z", "y", "z", "tool")]
    assert c.work_link == "c" and c.tool_link == "z"
    assert formula_axes("C'VZXYB") == ("X", "Y", "Z", "B", "C")
    assert formula_axes("WC1VXZT") == ("X", "Z", "C1")


def test_formula_model_without_axes_gets_them_from_the_formula(tmp_path):
    f = tmp_path / "g.toml"
    f.write_text('formula = "WC\'A\'VXYZT"\n')
    c = load_control(f)
    assert [(a.name, a.kind) for a in c.axes] == [
        ("X", "linear"), ("Y", "linear"), ("Z", "linear"), ("A", "rotary"), ("C", "rotary")]
    assert load_model(f).axes == ("X", "Y", "Z", "A", "C")


def test_key_lines_follow_nested_arrays_of_tables():
    text = (MODELS / "hybrid5.toml").read_text()
    kl = KeyLines.scan(text, "h")
    lines = text.splitlines()
    ref = kl.find(("parallel", 0, "legs", 2, "guide_point"))
    assert lines[ref.line - 1].startswith("guide_point") and "259.807" in lines[ref.line - 1]
    assert "-150.0" in lines[ref.line - 1]
    # the third leg's guide point is the last guide_point in the file
    assert ref.line == max(i for i, s in enumerate(lines, 1) if s.startswith("guide_point"))
    origin_c = lines[kl.find(("dimensions", "C", "origin")).line - 1]
    assert origin_c.startswith('origin = [0.0, 0.0, "-l1"]')


def test_toml_syntax_error_has_line_and_column(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text('name = "s"\n[control\n')
    with pytest.raises(ModelError) as exc:
        load_model(f)
    (p,) = exc.value.findings()
    assert p.kind == "model_syntax" and p.line == 2


def test_unknown_model_name_is_an_input_error():
    with pytest.raises(InputError):
        load_model("no_such_machine")


def test_parameters_can_be_changed_but_not_invented():
    m = model("s5d")
    m2 = m.with_parameters(rotation_centre=(10.0, -2.0, 5.0))
    assert m2.spec.parameters["rotation_centre"] == (10.0, -2.0, 5.0)
    assert m.spec.parameters["rotation_centre"] == (0.0, 0.0, 0.0)
    with pytest.raises(InputError):
        m.with_parameters(rotation_center=(1, 2, 3))
    with pytest.raises(InputError):
        m.with_parameters(rotation_centre=(1, 2))


def test_a_closed_form_that_does_not_fit_the_chain_is_refused(tmp_path):
    text = (MODELS / "s5d.toml").read_text().replace(
        'name = "C"\ntype = "revolute"\nparent = "b"\nchild = "c"\naxis = [0.0, 0.0, 1.0]',
        'name = "C"\ntype = "revolute"\nparent = "b"\nchild = "c"\naxis = [0.0, 0.0, -1.0]')
    assert "axis = [0.0, 0.0, -1.0]" in text
    f = tmp_path / "wrong.toml"
    f.write_text(text)
    with pytest.raises(ModelError) as exc:
        load_model(f)
    (p,) = exc.value.findings()
    assert p.kind == "closed_form_mismatch"
    assert text.splitlines()[p.line - 1].startswith("ik = ")


# Found by fuzzing the model files (each used to end in a traceback, a NaN in the trace or a
# 24 GB collision mesh): (model, text replaced, replacement, kind, line of the problem).
FUZZED = [
    ("turnmill", 'cycles = ["C_AXIS_ON", "C_AXIS_OFF"]', "cycles = 5", "bad_value", 16),
    ("turnmill", 'dialect = "sinumerik"', 'dialect = "fanuc"', "bad_value", 12),
    ("turnmill", 'transverse = "X"', 'transverse = ["X"]', "bad_value", 14),
    ("turnmill", "spindles = [1, 2]", "spindles = [1, 128]", "bad_value", 19),
    ("turnmill", "home = 325.0", "home = inf", "bad_value", 28),
    ("turnmill", "home = 325.0", "home = 1e308", "bad_value", 28),
    ("s5d", "modulo = 360.0", "modulo = nan", "bad_value", 44),
    ("s5d", "max_rate = 5400.0", "max_rate = 1e-320", "bad_value", 61),
    ("s5d", "radius = 50.0", "radius = 20000.0", "bad_value", 118),
    ("s5d", "size = [160.0, 120.0, 20.0]", "size = [200000.0, 120.0, 20.0]", "bad_value", 126),
    ("h5d", "root = -1", 'root = "x"', "bad_value", 93),
    ("s5d", 'geometry = ["X", "Y", "Z"]', 'geometry = ["X", "Y", "Q"]', "bad_value", 21),
    ("s5d", 'geometry = ["X", "Y", "Z"]', 'geometry = ["X", "X", "Z"]', "bad_value", 21),
    ("h5d", 'virtual = ["Y", "Z"]', 'virtual = ["Y", "Y"]', "bad_value", 83),
    # misspelt keys are errors at their line, not silently ignored (a rate limit would be lost)
    ("turnmill", "max_rate = 30000.0          # assumption: 30 m/min rapid\n",
     "max_rat = 30000.0\n", "unknown_key", 104),
    ("turnmill", 'dialect = "sinumerik"', 'dialekt = "sinumerik"', "unknown_key", 12),
    ("s5d", 'ik = "table_table"', 'ik = "table_table"\nik_method = "numeric"', "unknown_key", 52),
    ("h5d", "root = -1", "root = -1\nrooot = 1", "unknown_key", 94),
    ("hybrid5", 'direction = [0.0, 0.0, 1.0]', 'directon = [0.0, 0.0, 1.0]', "unknown_key", 79),
    ("turnmill", "[control]", "colour = 1\n[control]", "unknown_key", 11),
]


def model_problems(tmp_path, text: str) -> set[tuple[str, int]]:
    """(kind, line) of the problems a model text raises (it must raise)."""
    f = tmp_path / "m.toml"
    f.write_text(text)
    with pytest.raises(ModelError) as exc:
        load_model(f)
    return {(p.kind, p.line) for p in exc.value.findings()}


@pytest.mark.parametrize("name, old, new, kind, line", FUZZED)
def test_fuzzed_model_values_are_findings_at_their_line(tmp_path, name, old, new, kind, line):
    text = (MODELS / f"{name}.toml").read_text()
    assert old in text
    assert (kind, line) in model_problems(tmp_path, text.replace(old, new, 1))


def test_deeply_nested_toml_is_a_syntax_error(tmp_path):
    assert model_problems(tmp_path, "a = " + "[" * 1000 + "]" * 1000 + "\n") == {("model_syntax", 1)}
