"""The setup file ``vmach.toml`` (issue 31): a key it cannot hold is an error at its line with the
closest key as a hint (as model files), and its ``[parameters]`` set the machine model's set-up,
which ``postcheck`` reads so the correct post fixture checks clean without ``--set``."""

from __future__ import annotations

import json

import pytest
from catalog import FIXTURES

from vmach.cli import main
from vmach.setup import read_setup

POST = FIXTURES / "postcheck"


@pytest.mark.parametrize("text, line, hint", [
    ('machine = "turnmill"\nstok = "cylinder:d=30,l=60"\n', 2, "'stock'"),
    ('machine = "turnmill"\n[programs.P]\nprofle = "P3G:50"\n', 3, "'profile'"),
    ('machine = "turnmill"\naccurcy = "fine"\n', 2, "'accuracy'"),
    ('[zero_offset.G54]\nX = 1\n', 1, "'zero_offsets'"),
    ('machine = "turnmill"\ncolour = "red"\n', 2, None),
])
def test_an_unknown_setup_key_is_an_error_at_its_line(tmp_path, capsys, text, line, hint):
    (tmp_path / "vmach.toml").write_text(text)
    p = tmp_path / "P.MPF"
    p.write_text("G0 X1\nM30\n")
    for cmd in (["check", str(p)], ["verify", str(p), "--no-images", "--out", str(tmp_path / "o")]):
        assert main(cmd) == 2
        err = capsys.readouterr().err
        (first,) = [ln for ln in err.splitlines() if "error[" in ln]
        assert first.startswith(f"{tmp_path / 'vmach.toml'}:{line}:1: error[unknown_key]")
        if hint:
            assert f"did you mean {hint}" in first
        assert not (tmp_path / "o").exists()


def test_every_unknown_key_is_reported_at_once(tmp_path, capsys):
    (tmp_path / "vmach.toml").write_text('machin = "s5d"\ntool = "t.toml"\n[programs.P]\nstok = "x"\n')
    (tmp_path / "P.MPF").write_text("M30\n")
    assert main(["check", str(tmp_path / "P.MPF")]) == 2
    err = capsys.readouterr().err
    assert [ln.split(":")[1] for ln in err.splitlines() if "error[unknown_key]" in ln] == ["1", "2", "4"]


def test_setup_parameters_are_read(tmp_path):
    (tmp_path / "vmach.toml").write_text('machine = "s5d"\n[parameters]\nrotation_centre = [1, 2.5, -30]\n')
    assert read_setup(tmp_path / "P.MPF").parameters == {"rotation_centre": (1.0, 2.5, -30.0)}
    (tmp_path / "vmach.toml").write_text('machine = "s5d"\n[parameters]\nrotation_centre = ["a"]\n')
    assert main(["check", str(tmp_path / "P.MPF")]) == 2


def test_postcheck_reads_the_set_up_beside_the_program(capsys):
    """The correct post output checks clean with no option but --cl: the machine and its rotation
    centre come from fixtures/postcheck/vmach.toml (were 28 false errors without --set)."""
    cl = str(POST / "s5d_chamfer.cl")
    assert main(["postcheck", str(POST / "s5d_chamfer.mpf"), "--cl", cl, "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["summary"]["beyond_tolerance"] == 0 and out["summary"]["paired"] == 36
    assert "rotation_centre = 0,0,-30" in out["setup"] and "vmach.toml" in out["setup"]
    # the wrong post that ignores the rotation centre is still caught, every tilted pose of it
    assert main(["postcheck", str(POST / "s5d_chamfer_no_centre.mpf"), "--cl", cl, "--format", "json"]) == 1
    bad = json.loads(capsys.readouterr().out)["summary"]["beyond_tolerance"]
    # --set wins over the file: the model's own set-up (0, 0, 0) makes the correct post wrong
    assert main(["postcheck", str(POST / "s5d_chamfer.mpf"), "--cl", cl, "--set", "rotation_centre=0,0,0",
                 "--format", "json"]) == 1
    out = json.loads(capsys.readouterr().out)
    assert out["summary"]["beyond_tolerance"] == bad > 0 and "(--set)" in out["setup"]


@pytest.mark.parametrize("setting, kind", [
    ('stock = "box:x=60,y=40"', "stock_spec"), ('profile = "P3G:5O"', "profile_spec"),
    ('accuracy = "fien"', "usage"), ('default_tool = "em10"', "usage"),
    ('profile = "P3G:50"\nprofile_z = "-35:x"', None)])
def test_a_bad_setting_value_is_an_error_at_its_line(tmp_path, capsys, setting, kind):
    """Read before anything runs, with or without a tool library; a command-line option with
    the same bad value is an error of its own (no line in the file)."""
    (tmp_path / "vmach.toml").write_text(f'machine = "s5d"\n{setting}\n')
    p = tmp_path / "P.MPF"
    p.write_text('T="EM10" D1\nG0 X1\nM30\n')
    assert main(["verify", str(p), "--no-images", "--out", str(tmp_path / "o")]) == 2
    (line,) = [ln for ln in capsys.readouterr().err.splitlines() if "error[" in ln]
    n = setting.count("\n") + 2
    assert line.startswith(f"{tmp_path / 'vmach.toml'}:{n}:1: error[{kind or ''}")
    assert not (tmp_path / "o").exists()
