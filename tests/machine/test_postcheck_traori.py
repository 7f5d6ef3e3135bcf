"""The post-processor check turned around (#35): the CL data of fixtures/postcheck written as a
TRAORI program (no post) passes ``vmach postcheck`` like the correct post output, and both
programs move the machine to the same poses block for block — the domain §2 formalism used in
both directions (the post's closed form, and vmach's transformation)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from machine.machine_helpers import model

import interpreters
from vmach.canon import RunOptions
from vmach.cli import main
from vmach.machine.oriented import resolve
from vmach.machine.postcheck import moves_from_commands

FIX = Path(__file__).resolve().parents[2] / "fixtures" / "postcheck"
CL = FIX / "s5d_chamfer.cl"


def moves(program: str, name: str):
    m = model(name).with_parameters(rotation_centre=(0.0, 0.0, -30.0))
    path = FIX / program
    res = interpreters.dialect_for(path).run(str(path), m.control, RunOptions())
    assert res.completed and not [f for f in res.findings if f.severity != "info"]
    cmds, found = resolve(res.commands, m, ends_only=True)
    assert found == []
    return m, moves_from_commands(cmds, m.axes, m.home)


def test_postcheck_accepts_the_traori_program(capsys):
    assert main(["postcheck", str(FIX / "s5d_chamfer_traori.mpf"), "--cl", str(CL), "--machine", "s5d",
                 "--set", "rotation_centre=0,0,-30", "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["summary"]["paired"] == 36 and out["summary"]["beyond_tolerance"] == 0
    assert out["summary"]["max_position_mm"] < 1e-4          # the program's 4 decimals only
    assert out["summary"]["max_angle_deg"] < 1e-3


@pytest.mark.parametrize("name", ["s5d", "h5d"])
def test_traori_and_post_output_move_the_machine_alike(name):
    m, post = moves("s5d_chamfer.mpf", name)
    _, tra = moves("s5d_chamfer_traori.mpf", name)
    # the post's program has a safety move before (B0 C0 Z100) and the same retract after
    assert len(post.q) == len(tra.q) == 38
    a, b = m.fk(post.q[1:-1]), m.fk(tra.q[1:-1])
    assert np.abs(a.tip - b.tip).max() < 1e-3 and np.abs(a.axis - b.axis).max() < 1e-5
    # axis values: the post's (domain §2: B ≥ 0) or the mirrored root (−B, C + 180°) that the
    # transformation's rule takes when it moves the rotary axes less (the swarf pass)
    ib, ic = m.axes.index("B"), m.axes.index("C")
    pb, pc, tb, tc = post.q[1:-1, ib], post.q[1:-1, ic], tra.q[1:-1, ib], tra.q[1:-1, ic]
    same = (np.abs(pb - tb) < 1e-3) & (np.abs((pc - tc + 180.0) % 360.0 - 180.0) < 1e-3)
    mirrored = (np.abs(pb + tb) < 1e-3) & (np.abs((pc - tc) % 360.0 - 180.0) < 1e-3)
    assert (same | mirrored).all()
    # the three swarf poses, and the last (vertical: the pole, C kept from the swarf pass)
    assert pb[mirrored].tolist() == [20.0, 20.0, 20.0, 0.0]
