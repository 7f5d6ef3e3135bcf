"""The machines real Sinumerik programs are written for (issue 32): a three-axis vertical mill,
a table-table A/C five-axis mill (WCAVXYZT) and a two-axis lathe with C — data only, each with
its description, limits, rates and [machine_data]; FK/IK hold and programs run on them."""

from __future__ import annotations

import numpy as np
import pytest
from machine.machine_helpers import model, random_q
from machine.test_machine_fk import MODELS, rot

from interpreters import sinumerik
from vmach.canon import MOTIONS, RunOptions
from vmach.machine import load_model
from vmach.machine.loader import load_model_control

NEW = ("mill3", "mill5ac", "lathe")


@pytest.mark.parametrize("name", NEW)
def test_each_new_machine_loads_with_a_description_limits_and_rates(name):
    m = model(name)
    assert m.spec.description and "\n" not in m.spec.description
    assert m.control.dialect == "sinumerik"
    md = m.control.machine_data
    for a in m.axes:
        if m.control.axis(a).modulo is None:   # an endless table has no travel limit
            assert md["$MA_POS_LIMIT_MINUS"][a] < md["$MA_POS_LIMIT_PLUS"][a]
        assert md["$MA_MAX_AX_VELO"][a] > 0
    assert md["$MN_SCALING_SYSTEM_IS_METRIC"] == 1


def test_mill3_tip_is_the_slides():
    m = model("mill3")
    q = random_q(m, 50, np.random.default_rng(3))
    pose = m.fk(q)
    assert np.allclose(pose.tip, q, atol=1e-9)
    assert np.allclose(pose.axis, [0.0, 0.0, 1.0])
    sol = m.ik(pose.tip, pose.axis)
    assert sol.ok.all() and np.allclose(sol.q, q, atol=1e-6)


def test_mill5ac_fk_is_the_table_table_geometry_and_ik_returns_the_pose():
    """Tip in the workpiece: Rot(k, −C)·Rot(i, −A)·(p − r_R) + r_R, as s5d with A for B."""
    r_R = np.array([10.0, -20.0, 30.0])
    m = model("mill5ac").with_parameters(rotation_centre=tuple(r_R))
    rng = np.random.default_rng(7)
    q = random_q(m, 60, rng)
    q[:, m.axes.index("A")] = rng.uniform(5.0, 100.0, 60)
    X, Y, Z, A, C = q.T
    R = rot([0, 0, 1], -C) @ rot([1, 0, 0], -A)
    tip = r_R + (R @ (np.stack([X, Y, Z], axis=1) - r_R)[:, :, None])[:, :, 0]
    pose = m.fk(q)
    assert np.allclose(pose.tip, tip, atol=1e-9)
    assert np.allclose(pose.axis, R[:, :, 2], atol=1e-12)
    sol = m.ik(pose.tip, pose.axis, previous=q[0])
    assert sol.ok.all()
    back = m.fk(sol.q)
    assert np.abs(back.tip - pose.tip).max() < 1e-6
    assert np.abs(back.axis - pose.axis).max() < 1e-9


def carr(md, *ks):
    return [md[f"$TC_CARR{k}"][1] for k in ks]


def test_mill5ac_swivel_record_is_derived_from_the_chain():
    """Swivel table (P), CYCLE800's record: rotary axis 1 A (C sits on it), vectors reversed
    because the axes turn the part; l2 from the machine reference (the tip at zero) to the
    pivot, l3 pivot to pivot, l4 closes the chain."""
    md = load_model("mill5ac", {"rotation_centre": (10.0, -20.0, 30.0)}).control.machine_data
    assert carr(md, 7, 8, 9) == [-1.0, 0.0, 0.0] and carr(md, 10, 11, 12) == [0.0, 0.0, -1.0]
    assert md["$TC_CARR23"][1] == "P"
    assert carr(md, 4, 5, 6) == [10.0, -20.0, 30.0]              # the rotation centre
    assert carr(md, 15, 16, 17) == [0.0, 0.0, 0.0]               # the axes intersect
    assert carr(md, 18, 19, 20) == [-10.0, 20.0, -30.0]
    assert (md["$TC_CARR30"][1], md["$TC_CARR32"][1]) == (-120.0, 120.0)
    assert (md["$TC_CARR35"][1], md["$TC_CARR36"][1]) == ("A", "C")
    assert md["$MC_TRAFO_TYPE_1"] == 24


def test_a_swivel_head_record_closes_its_chain():
    """Swivel head (T, hybrid5's B/C head): l3 tool reference → pivot of axis 2 (B), l2 → pivot
    of axis 1 (C), l1 = −(l2 + l3); head vectors as the joints turn."""
    md = model("hybrid5").control.machine_data
    assert md["$TC_CARR23"][1] == "T" and (md["$TC_CARR35"][1], md["$TC_CARR36"][1]) == ("C", "B")
    l1, l2, l3 = carr(md, 1, 2, 3), carr(md, 4, 5, 6), carr(md, 15, 16, 17)
    assert [a + b + c for a, b, c in zip(l1, l2, l3, strict=True)] == [0.0, 0.0, 0.0]
    assert l3[2] > 0                                            # the pivot is above the tip
    assert carr(md, 7, 8, 9) == [0.0, 0.0, 1.0] and carr(md, 10, 11, 12) == [0.0, 1.0, 0.0]


def test_lathe_is_x_radius_z_and_c():
    m = model("lathe")
    assert m.axes == ("X", "Z", "C") and m.control.transverse == "X"
    pose = m.fk(np.array([[100.0, 50.0, 0.0]]))
    assert np.allclose(pose.tip, [[100.0, 0.0, 50.0]], atol=1e-9)


PROGRAMS = {
    "mill3": "G17 G54 G90 T1 D1 M6\nS3000 M3\nG0 X=-300 Y=-150 Z=100\nG1 Z=-20 F500\n"
             "G2 X=-280 Y=-150 CR=10\nG0 Z=$MA_POS_LIMIT_PLUS[Z]-10\nM30\n",
    "mill5ac": "G54 G90\nG0 X0 Y0 Z100 A0 C0\nG0 A=$MA_POS_LIMIT_PLUS[A]-30 C=90\n"
               "G1 X10 Z50 F1000\nG0 A0 C0\nM30\n",
    "lathe": "G18 G54 G90 DIAMON\nT1 D1\nS1000 M3\nG0 X80 Z5\nG1 Z-40 F0.2\nG0 X200 Z300\nM30\n",
}


@pytest.mark.parametrize("name", NEW)
def test_a_program_runs_on_each_new_machine(tmp_path, name):
    p = tmp_path / "P.MPF"
    p.write_text(PROGRAMS[name])
    control = load_model_control(MODELS / f"{name}.toml")
    result = sinumerik.run(p, control, RunOptions())
    assert result.completed, result.findings
    moves = [c for c in result.commands if isinstance(c, MOTIONS)]
    assert moves and set(moves[-1].axes) == set(model(name).axes) | ({"Y"} if name == "lathe" else set())
    if name == "mill5ac":
        assert any(c.axes["A"] == 90.0 for c in moves)


SLOT = """T="EM10" D1
G17 G90 G0 Z50
{turn}G0 X-30 Y0
G0 Z5
S3000 M3
G1 Z=$MA_POS_LIMIT_MINUS[Z]/10 F500
G1 X30
G0 Z50
M30
"""


@pytest.mark.parametrize("name, turn, along", [("mill3", "", 0), ("mill5ac", "G0 C90\n", 1)])
def test_verify_cuts_a_slot_on_the_mills(tmp_path, name, turn, along):
    """A 60 mm slot, Ø10, 5 mm deep (the depth read from machine data: Z travel −50 on mill3;
    mill5ac's C is endless so the depth comes from Z's −200 → 20 mm, limited by the stock to its
    10 mm): on mill5ac after C90 the table has turned, so the slot runs along the part's Y."""
    import trimesh

    from vmach.cli import main

    (tmp_path / "tools.toml").write_text('[[tool]]\nname = "EM10"\ntype = "flat"\ndiameter = 10.0\n'
                                         'cutting_length = 30.0\n')
    prog = tmp_path / "SLOT.MPF"
    prog.write_text(SLOT.format(turn=turn))
    removed = tmp_path / "removed.stl"
    code = main(["verify", str(prog), "--machine", name, "--tools", str(tmp_path / "tools.toml"),
                 "--stock", "box:xmin=-50,xmax=50,ymin=-50,ymax=50,zmin=-10,zmax=0",
                 "--export", str(removed), "--out", str(tmp_path / "o"), "--no-images", "--quiet"])
    assert code == 0
    mesh = trimesh.load(removed)
    lo, hi = mesh.bounds
    depth = 5.0 if name == "mill3" else 10.0
    assert hi[along] - lo[along] == pytest.approx(70.0, abs=0.02)      # 60 mm + the Ø10
    assert hi[1 - along] - lo[1 - along] == pytest.approx(10.0, abs=0.02)
    assert lo[2] == pytest.approx(-depth, abs=1e-6)
