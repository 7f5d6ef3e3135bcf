"""Post-processor check (domain §2): CL reader, pairing, deviations, wrong posts caught."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from machine.machine_helpers import model

import interpreters
from vmach.canon import RunOptions
from vmach.cli import main
from vmach.machine.cl import parse_cl, read_cl
from vmach.machine.postcheck import Moves, moves_from_commands, postcheck

FIX = Path(__file__).resolve().parents[2] / "fixtures" / "postcheck"
CL = FIX / "s5d_chamfer.cl"
CENTRE = (0.0, 0.0, -30.0)


def check(program: str, name: str = "s5d"):
    m = model(name).with_parameters(rotation_centre=CENTRE)
    path = FIX / program
    res = interpreters.dialect_for(path).run(str(path), m.control, RunOptions())
    assert res.completed and not res.findings
    return postcheck(m, read_cl(CL), moves_from_commands(res.commands, m.axes, m.home))


def words(program: str, letter: str) -> dict[int, float]:
    """Line → value of an axis word in the motion blocks of a fixture program."""
    out = {}
    for no, line in enumerate((FIX / program).read_text().splitlines(), 1):
        m = re.search(rf"\b{letter}(-?\d+\.\d+)", line.split(";")[0])
        if line.startswith(("G0 X", "G1 X")) and m:
            out[no] = float(m.group(1))
    return out


def goto_lines() -> list[int]:
    return [no for no, s in enumerate(CL.read_text().splitlines(), 1) if s.startswith("GOTO/")]


def flagged(pc):
    return {f.line: f.data["cl_line"] for f in pc.findings if f.kind == "post_deviation"}


def test_fixtures_are_what_the_generator_writes(tmp_path):
    subprocess.run([sys.executable, str(FIX / "make_fixtures.py"), str(tmp_path)], check=True)
    for f in tmp_path.iterdir():
        assert f.read_text() == (FIX / f.name).read_text(), f.name


@pytest.mark.parametrize("name", ["s5d", "h5d"])
def test_correct_post_passes_and_every_pose_is_paired_in_order(name):
    pc = check("s5d_chamfer.mpf", name)
    assert [f for f in pc.findings if f.severity != "info"] == []
    assert (pc.move >= 0).all() and (np.diff(pc.move) > 0).all()
    assert pc.position.max() < 1e-3 and pc.angle.max() < 1e-3  # 4-decimal rounding only
    assert [pc.cl.sources[i].line for i in range(len(pc.cl))] == goto_lines()
    nc_lines = [pc.moves.sources[j].line for j in pc.move]
    assert nc_lines == sorted(words("s5d_chamfer.mpf", "X"))  # every block written per pose
    unpaired = [pc.moves.sources[j].text for j in pc.unpaired]
    assert unpaired == ["G0 X0 Y0 Z100 B0 C0", "G0 Z120"]
    # expected axes (IK of the CL pose) equal the programmed ones within the rounding
    assert np.abs(pc.expected - pc.programmed).max() < 1e-3


def test_wrong_c_sign_is_caught_exactly_where_c_matters():
    pc = check("s5d_chamfer_c_sign.mpf")
    c = words("s5d_chamfer_c_sign.mpf", "C")
    matters = {no for no, v in c.items() if abs(np.sin(np.radians(v))) > 1e-6}
    b = words("s5d_chamfer_c_sign.mpf", "B")
    matters = {no for no in matters if abs(b[no]) > 1e-9}
    assert set(flagged(pc)) == matters and len(matters) > 10
    assert all(cl in goto_lines() for cl in flagged(pc).values())


def test_ignored_rotation_centre_is_caught_on_every_tilted_pose():
    pc = check("s5d_chamfer_no_centre.mpf")
    b = words("s5d_chamfer_no_centre.mpf", "B")
    assert set(flagged(pc)) == {no for no, v in b.items() if abs(v) > 1e-9}
    # the deviation is the r_R shift turned by B: |Δ| = 30·|(sB·cC, −sB·sC, cB − 1)|·…
    dev = next(f for f in pc.findings if f.kind == "post_deviation")
    assert dev.data["angle_deg"] < 1e-3 and dev.data["position_mm"] > 1.0


def test_single_typo_is_the_only_finding_with_both_lines():
    pc = check("s5d_chamfer_typo.mpf")
    text = (FIX / "s5d_chamfer_typo.mpf").read_text().splitlines()
    typo_line = next(i for i, s in enumerate(text, 1) if "deliberate error" in s)
    (f,) = [f for f in pc.findings if f.severity == "error"]
    assert f.kind == "post_deviation" and f.line == typo_line
    i = list(pc.move).index(f.move_index)
    assert f.data["cl_line"] == pc.cl.sources[i].line == goto_lines()[i]
    assert set(f.data["programmed_minus_expected"]) == {"Y"}


def test_truncated_program_leaves_missing_poses():
    pc = check("s5d_chamfer_truncated.mpf")
    missing = [f.line for f in pc.findings if f.kind == "missing_pose"]
    assert missing == goto_lines()[-3:]
    assert [f for f in pc.findings if f.kind == "post_deviation"] == []


def test_mirrored_solution_is_the_same_pose():
    """(−B, C + 180°) puts the tool where (B, C) does: the check compares poses, not axes."""
    m = model("s5d")
    rng = np.random.default_rng(2)
    q = np.column_stack([rng.uniform(-20, 20, (20, 3)), rng.uniform(5, 80, 20),
                         rng.uniform(-170, 170, 20)])
    pose = m.fk(q)
    text = "MULTAX\n" + "".join(f"GOTO/{','.join(f'{v:.12f}' for v in (*t, *a))}\n"
                                for t, a in zip(pose.tip, pose.axis, strict=True))
    cl = parse_cl(text, "x.cl")
    mirror = q.copy()
    mirror[:, 3] *= -1
    mirror[:, 4] += 180.0
    # X, Y, Z for the mirrored angles: p = Rot(j, B)·Rot(k, C)·r_T (r_R = 0), domain §2
    b, c = np.radians(mirror[:, 3]), np.radians(mirror[:, 4])
    t = pose.tip
    rc = np.stack([np.cos(c) * t[:, 0] - np.sin(c) * t[:, 1],
                   np.sin(c) * t[:, 0] + np.cos(c) * t[:, 1], t[:, 2]], axis=1)
    mirror[:, 0] = np.cos(b) * rc[:, 0] + np.sin(b) * rc[:, 2]
    mirror[:, 1] = rc[:, 1]
    mirror[:, 2] = -np.sin(b) * rc[:, 0] + np.cos(b) * rc[:, 2]
    assert np.abs(mirror[:, :3] - q[:, :3]).max() > 1.0  # really another solution
    src = tuple(cl.sources)
    pc = postcheck(m, cl, Moves(mirror, np.zeros(20, bool), np.full(20, np.nan), src))
    assert pc.position.max() < 1e-9 and pc.angle.max() < 1e-9 and not pc.findings


def test_cl_reader_statements():
    cl = parse_cl(
        "PARTNO/T\n$$ comment\nUNITS/INCHES\nMULTAX\nLOADTL/7\nRAPID\nGOTO/1,2,3,0,0,2\n"
        "FEDRAT/10,IPM\nGOTO/1,$\n 0 , 0\nCIRCLE/0,0,0,0,0,1,5\nGOTO/1,2\nGOTO/a,b,c\n"
        "MULTAX/OFF\nGOTO/0,0,0\nFOO/1\nFINI\n", "t.cl")
    assert len(cl) == 3
    assert np.allclose(cl.tip, [[25.4, 50.8, 76.2], [25.4, 0, 0], [0, 0, 0]])
    assert np.allclose(cl.axis, [[0, 0, 1]] * 3)
    assert cl.rapid.tolist() == [True, False, False]
    assert np.isnan(cl.feed[0]) and cl.feed[1] == pytest.approx(254.0)
    assert cl.tool.tolist() == [7, 7, 7]
    assert [s.line for s in cl.sources] == [7, 9, 15]
    assert [(f.kind, f.severity, f.line) for f in cl.findings] == [
        ("cl_unsupported", "warning", 11), ("cl_syntax", "error", 12),
        ("cl_syntax", "error", 13), ("cl_unsupported", "warning", 16)]


def test_postcheck_cli_json_and_exit_codes(capsys):
    base = ["postcheck", "--cl", str(CL), "--machine", "s5d", "--set",
            "rotation_centre=0,0,-30", "--format", "json"]
    assert main([*base[:1], str(FIX / "s5d_chamfer.mpf"), *base[1:]]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["summary"]["beyond_tolerance"] == 0 and out["summary"]["paired"] == 36
    assert len(out["poses"]) == 36 and out["poses"][0]["cl_line"] == goto_lines()[0]
    assert main([*base[:1], str(FIX / "s5d_chamfer_typo.mpf"), *base[1:]]) == 1
    out = json.loads(capsys.readouterr().out)
    (f,) = [f for f in out["findings"] if f["kind"] == "post_deviation"]
    assert f["cl_file"] == str(CL) and f["line"] > 0 and f["cl_line"] in goto_lines()
    assert main(["postcheck", str(FIX / "nope.mpf"), "--cl", str(CL), "--machine", "s5d"]) == 2
    assert main(["postcheck", str(FIX / "s5d_chamfer.mpf"), "--cl", str(CL), "--machine",
                 "s5d", "--tol-angle", "x"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "error[" in err


def test_loadtl_beyond_an_integer_is_a_syntax_error_and_keeps_the_tool():
    """Found by fuzzing: LOADTL/inf raised OverflowError, LOADTL/1e300 overflowed the tool
    column."""
    cl = parse_cl("LOADTL/3\nGOTO/1,2,3\nLOADTL/inf,IN,1\nGOTO/1,2,4\nLOADTL/1e300\nGOTO/1,2,5\n", "t.cl")
    assert cl.tool.tolist() == [3, 3, 3]
    assert [(f.kind, f.line) for f in cl.findings] == [("cl_syntax", 3), ("cl_syntax", 5)]
    # an axis of 1e308 components overflowed its norm and matched any pose; a NaN feed passed;
    # CL data without a pose "passed" every move
    cl = parse_cl("GOTO/-10,-10,0,1e308,1e308,1e308\nFEDRAT/nan\nGOTO/1,2,3\n", "t.cl")
    assert len(cl) == 1 and [(f.kind, f.line) for f in cl.findings] == [("cl_syntax", 1), ("cl_syntax", 2)]
    empty = parse_cl("$$ nothing\n", "t.cl")
    assert [(f.kind, f.severity) for f in empty.findings] == [("cl_syntax", "error")]
