"""Forward kinematics: fast path = matrix path; formula = hand-written chain; domain formulas."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from machine.machine_helpers import ALL_MODELS, model, random_q
from scipy.spatial.transform import Rotation

from vmach.machine import load_model

MODELS = Path(__file__).resolve().parents[2] / "models"


def rot(axis, deg):
    """(n, 3, 3) rotations about a fixed axis (scipy, independent of vmach)."""
    return Rotation.from_rotvec(np.outer(np.radians(deg), axis)).as_matrix()


@pytest.mark.parametrize("name", ALL_MODELS)
def test_fast_path_equals_the_link_pose_path(name):
    m = model(name)
    q = random_q(m, 200, np.random.default_rng(1))
    pose = m.fk(q)
    t2w = m.tool2work(q)
    assert np.allclose(pose.tip, t2w[:, :3, 3], atol=1e-9)
    assert np.allclose(pose.axis, t2w[:, :3, 2], atol=1e-12)
    assert np.allclose(np.linalg.norm(pose.axis, axis=1), 1.0, atol=1e-12)
    frames = m.link2base(q)
    assert {"base", "work", "tool", "tool_mount"} <= set(frames)
    assert all(f.shape == (200, 4, 4) for f in frames.values())
    length = m.spec.tool.length
    assert np.allclose(frames["tool_mount"][:, :3, 3],
                       frames["tool"][:, :3, 3] + length * frames["tool"][:, :3, 2], atol=1e-9)


def s5d_direct(q, r_R):
    """Domain §2 direct geometry, matrices written out: Tr(r_R)·Rot(k,−C)·Rot(j,−B)·Tr(p)."""
    X, Y, Z, B, C = q.T
    R = rot([0, 0, 1], -C) @ rot([0, 1, 0], -B)
    p = np.stack([X, Y, Z], axis=1) - r_R
    tip = np.asarray(r_R) + (R @ p[:, :, None])[:, :, 0]
    return tip, R[:, :, 2]


@settings(max_examples=25, deadline=None)
@given(st.tuples(*[st.floats(-50, 50)] * 3), st.integers(0, 2**32 - 1))
def test_table_table_fk_is_the_domain_direct_geometry(r_R, seed):
    for name in ("s5d", "h5d"):
        m = model(name).with_parameters(rotation_centre=r_R)
        q = random_q(m, 50, np.random.default_rng(seed), b_range=(-25, 135))
        pose = m.fk(q)
        tip, axis = s5d_direct(q, np.array(r_R))
        assert np.allclose(pose.tip, tip, atol=1e-9)
        assert np.allclose(pose.axis, axis, atol=1e-12)


def test_formula_built_model_agrees_with_hand_written_s5d(tmp_path):
    hand = (MODELS / "s5d.toml").read_text()
    head = hand.split("[kinematics]")[0]  # name, control, axes, parameters
    (tmp_path / "s5d_formula.toml").write_text('formula = "WCBVXYZT"\n' + head + """
[kinematics]
ik = "table_table"
[dimensions.B]
limits = [-25.0, 135.0]
[dimensions.W]
origin = "-rotation_centre"
[dimensions.X]
origin = "-rotation_centre"
[dimensions.T]
length = "tool_length"
""")
    built = load_model(tmp_path / "s5d_formula.toml")
    assert built.spec.formula == "WCBVXYZT" and built.axes == model("s5d").axes
    rng = np.random.default_rng(7)
    for r_R in ((0.0, 0.0, 0.0), (12.5, -3.0, 40.0)):
        a = model("s5d").with_parameters(rotation_centre=r_R)
        b = built.with_parameters(rotation_centre=r_R)
        q = random_q(a, 500, rng, b_range=(-25, 135))
        pa, pb = a.fk(q), b.fk(q)
        assert np.allclose(pa.tip, pb.tip, atol=1e-10) and np.allclose(pa.axis, pb.axis, atol=1e-14)
        la, lb = a.link2base(q), b.link2base(q)
        for link in ("b", "c", "x", "y", "z", "work", "tool", "tool_mount"):
            assert np.allclose(la[link], lb[link], atol=1e-10)
    # the hybrid H5D is the same formula: its virtual serial chain is the S5D chain
    q = random_q(model("s5d"), 300, rng, b_range=(-25, 135))
    assert np.allclose(model("h5d").fk(q).tip, model("s5d").fk(q).tip, atol=1e-10)


def test_hybrid5_head_follows_domain_section_3():
    m = model("hybrid5")
    q = random_q(m, 300, np.random.default_rng(3), b_range=(-10, 100))
    X, Y, Z, B, C = q.T
    b, c = np.radians(B), np.radians(C)
    k = np.stack([np.cos(c) * np.sin(b), np.sin(c) * np.sin(b), np.cos(b)], axis=1)
    l1, l2 = m.spec.parameters["l1"], m.spec.parameters["l2"]
    p2 = np.stack([X, Y, Z], axis=1)  # home P2 at the machine origin
    work_z = -160.0  # work frame origin in the machine frame (hybrid5.toml)
    tip = p2 - l2 * k - np.array([0.0, 0.0, l1 + work_z])
    pose = m.fk(q)
    assert np.allclose(pose.axis, k, atol=1e-12)
    assert np.allclose(pose.tip, tip, atol=1e-9)


def test_turnmill_c1_convention_on_the_polygon_finishing_moves():
    """X = d1/2 − e1·sin(3·C1): the tool face sits at radial distance X from the workpiece axis,
    facing the workpiece-frame polar angle +C1 (the chosen sign: the workpiece turns by −C1)."""
    m = model("turnmill")
    d1, e1 = 50.0, 1.8  # size 50, domain §4/§5
    c1 = np.arange(0.0, 720.0, 1.713)  # two revolutions, 1.713° per point (domain §4)
    x = d1 / 2 - e1 * np.sin(np.radians(3 * c1))
    sector = np.mod(c1, 120.0)
    y = np.where(sector < 60, 0.2305 * sector - 6.763, -0.229 * sector + 20.771)
    z = -0.01 * np.arange(c1.size)
    q = m.q(n=c1.size)
    q[:, 0], q[:, 1], q[:, 2], q[:, 3] = x, y, z, c1
    pose = m.fk(q)
    phi = np.radians(c1)
    radial = np.stack([np.cos(phi), np.sin(phi), 0 * phi], axis=1)
    tangent = np.stack([-np.sin(phi), np.cos(phi), 0 * phi], axis=1)
    assert np.allclose(pose.axis, radial, atol=1e-12)  # tool axis radial, at polar angle C1
    assert np.allclose(np.einsum("ij,ij->i", pose.tip, radial), x, atol=1e-9)  # face at X
    assert np.allclose(np.einsum("ij,ij->i", pose.tip, tangent), y, atol=1e-9)
    assert np.allclose(pose.tip[:, 2], z, atol=1e-12)  # end face at Z = 0, material at −Z
    on_axis = q.copy()
    on_axis[:, 1] = 0.0  # with Y = 0 the tip itself is at radius X, polar angle C1
    tip = m.fk(on_axis).tip
    assert np.allclose(np.hypot(tip[:, 0], tip[:, 1]), x, atol=1e-9)
    ang = np.degrees(np.arctan2(tip[:, 1], tip[:, 0]))
    assert np.allclose(np.mod(ang - c1 + 180.0, 360.0) - 180.0, 0.0, atol=1e-9)


def test_turnmill_chuck_turns_with_c1_and_the_turret_sits_behind_the_tool():
    m = model("turnmill")
    q = m.q({"X": 40.0, "Y": 0.0, "Z": 10.0, "C1": 90.0})
    f = m.link2base(q)
    jaw = next(g for g in m.spec.geometry if g.name == "jaw_1")
    centre = f[jaw.link][0] @ np.append(jaw.origin.xyz, 1.0)
    # jaw_1 at +X of the chuck; the workpiece turned by −90° puts it at machine −Y
    assert np.allclose(centre[:3], [0.0, -50.0, -100.0 + 17.5], atol=1e-9)
    assert np.allclose(f["tool_mount"][0, :3, 3], [40.0 + m.spec.tool.length, 0.0, 10.0])
