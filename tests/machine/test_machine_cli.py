"""``vmach fk`` / ``vmach ik``: JSON contract, hybrids' drives, clear errors (exit 2)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from machine.machine_helpers import model

from vmach.cli import main


def run_json(capsys, *argv):
    code = main([*argv, "--format", "json"])
    out = capsys.readouterr()
    return code, json.loads(out.out), out.err


def test_fk_json_matches_the_library(capsys):
    code, out, _ = run_json(capsys, "fk", "s5d", "--axes", "X=10,Y=5,Z=-10,B=30,C=40")
    assert code == 0
    pose = model("s5d").fk(model("s5d").q({"X": 10, "Y": 5, "Z": -10, "B": 30, "C": 40}))
    assert np.allclose(out["tip"], pose.tip[0], atol=1e-8)
    assert np.allclose(out["axis"], pose.axis[0], atol=1e-8)
    assert out["findings"] == []


def test_ik_then_fk_round_trip_through_the_cli_with_a_rotation_centre(capsys):
    code, out, _ = run_json(capsys, "ik", "s5d", "--tip", "5,-3,12", "--axis", "0.3,0.2,0.9",
                            "--set", "rotation_centre=10,0,-5")
    assert code == 0 and out["reachable"] is True
    axes = ",".join(f"{k}={v!r}" for k, v in out["axes"].items())
    code, back, _ = run_json(capsys, "fk", "s5d", "--axes", axes, "--set",
                             "rotation_centre=10,0,-5")
    a = np.array([0.3, 0.2, 0.9])
    assert np.allclose(back["tip"], [5, -3, 12], atol=1e-7)
    assert np.allclose(back["axis"], a / np.linalg.norm(a), atol=1e-8)


def test_hybrids_report_their_drives(capsys):
    code, out, _ = run_json(capsys, "ik", "hybrid5", "--tip", "1,2,3", "--axis", "0,0.5,0.8")
    assert code == 0 and set(out["drives"]) == {"p1", "p2", "p3"}
    code, fk, _ = run_json(capsys, "fk", "h5d", "--axes", "X=1,Y=2,Z=3,B=10,C=20")
    drives = fk["drives"]
    assert set(drives) == {"p1", "p2"}
    given = f"X=1,p1={drives['p1']!r},p2={drives['p2']!r},B=10,C=20"
    code, again, _ = run_json(capsys, "fk", "h5d", "--axes", given)
    assert np.allclose(again["tip"], fk["tip"], atol=1e-7)


def test_turnmill_ik_by_bare_name(capsys):
    code, out, _ = run_json(capsys, "ik", "turnmill", "--tip", "20,3,-5", "--axis", "0,1,0")
    assert code == 0
    assert np.allclose([out["axes"][k] for k in ("X", "Y", "Z", "C1")], [3, -20, -5, 90])


def test_limits_and_unreachable_exit_1(capsys):
    code, out, _ = run_json(capsys, "fk", "s5d", "--axes", "X=99")
    assert code == 1 and out["findings"][0]["kind"] == "axis_limit"
    code, out, _ = run_json(capsys, "ik", "turnmill", "--tip", "20,0,0", "--axis", "0,0,1")
    assert code == 1 and out["reachable"] is False
    assert out["findings"][0]["kind"] == "unreachable"


@pytest.mark.parametrize("argv", [
    ["fk", "s5d", "--axes", "Q=1"],
    ["fk", "s5d", "--axes", "X=abc"],
    ["fk", "s5d", "--axes", "X"],
    ["ik", "s5d", "--tip", "1,2", "--axis", "0,0,1"],
    ["ik", "s5d", "--tip", "1,2,3", "--axis", "0,0,0"],
    ["ik", "s5d", "--tip", "1,2,3", "--axis", "0,0,1", "--set", "rotation_centre=1,2"],
    ["ik", "s5d", "--tip", "1,2,3", "--axis", "0,0,1", "--set", "nope=1"],
    ["fk", "no_such_model", "--axes", "X=1"],
    ["fk", "h5d", "--axes", "p1=-100"],
])
def test_bad_input_is_a_clear_error_with_exit_2(capsys, argv):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "error[" in err and "Traceback" not in err


def test_broken_model_file_lists_its_problems(tmp_path, capsys):
    f = tmp_path / "m.toml"
    f.write_text('[[joints]]\nname = "X"\ntype = "prismatic"\nparent = "a"\nchild = "x"\n'
                 '[work]\nlink = "base"\n[tool]\nlink = "x"\n')
    assert main(["fk", str(f), "--axes", "X=1"]) == 2
    err = capsys.readouterr().err
    assert f"{f}:4:1: error[unknown_link]" in err
