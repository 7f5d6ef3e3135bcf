"""Inverse kinematics: round trips, domain §2 term by term, §3 head, singularity strategies."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from machine.machine_helpers import FIVE_AXIS, model, random_q, tilted_axes

from vmach.machine import axis_limit_findings
from vmach.machine.closed_form import head_bc_ik, head_platform_point, table_table_ik

seeds = st.integers(0, 2**32 - 1)
centres = st.tuples(*[st.floats(-40, 40)] * 3)


def angle_between(a, b):
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))


def assert_same_pose(p, q):
    assert np.abs(p.tip - q.tip).max() <= 1e-9  # mm
    assert angle_between(p.axis, q.axis).max() <= 1e-9  # rad


@settings(max_examples=20, deadline=None)
@given(seeds)
@pytest.mark.parametrize("name", FIVE_AXIS)
def test_fk_of_ik_is_the_pose_and_ik_of_fk_is_q(name, seed):
    m = model(name)
    rng = np.random.default_rng(seed)
    q = random_q(m, 200, rng, b_range=(1.0, 100.0))
    pose = m.fk(q)
    sol = m.ik(pose.tip, pose.axis)
    assert sol.ok.all()
    assert_same_pose(m.fk(sol.q), pose)
    # unique where B ∈ (0°, 180°), up to whole turns of C: the principal solution is q itself
    c = m.axes.index("C")
    assert np.allclose(np.delete(sol.q, c, axis=1), np.delete(q, c, axis=1), atol=1e-9)
    assert np.allclose(np.mod(sol.q[:, c] - q[:, c] + 180.0, 360.0) - 180.0, 0.0, atol=1e-9)
    assert np.all(np.abs(sol.q[:, c]) <= 180.0)


@settings(max_examples=15, deadline=None)
@given(seeds, centres)
def test_table_table_round_trip_for_any_rotation_centre(seed, r_R):
    m = model("s5d").with_parameters(rotation_centre=r_R)
    rng = np.random.default_rng(seed)
    tip = rng.uniform(-30, 30, (100, 3))
    axis = tilted_axes(rng.uniform(0, 135, 100), rng.uniform(-180, 180, 100))
    sol = m.ik(tip, axis)
    back = m.fk(sol.q)
    assert np.abs(back.tip - tip).max() <= 1e-9
    assert angle_between(back.axis, axis).max() <= 1e-9


@settings(max_examples=25, deadline=None)
@given(seeds, centres)
def test_table_table_inverse_is_domain_section_2_term_by_term(seed, r_R):
    rng = np.random.default_rng(seed)
    n = 200
    tip = rng.uniform(-50, 50, (n, 3))
    a = tilted_axes(rng.uniform(0.5, 179.5, n), rng.uniform(-180, 180, n))
    got, singular = table_table_ik(tip, a, r_R)
    assert not singular.any()
    # domain §2, written out literally
    B = np.arccos(a[:, 2])
    sB, cB = np.sin(B), np.cos(B)
    C = np.arctan2(a[:, 1] / sB, -a[:, 0] / sB)
    sC, cC = np.sin(C), np.cos(C)
    xT, yT, zT = tip.T
    xR, yR, zR = r_R
    px = (xT - xR) * cB * cC - (yT - yR) * cB * sC + (zT - zR) * sB
    py = (xT - xR) * sC + (yT - yR) * cC
    pz = -(xT - xR) * sB * cC + (yT - yR) * sB * sC + (zT - zR) * cB
    assert np.allclose(got["B"], np.degrees(B), atol=1e-7)  # arccos loses digits near 0 and π
    assert np.allclose(got["C"], np.degrees(C), atol=1e-7)
    assert np.allclose(got["X"], xR + px, atol=1e-7)
    assert np.allclose(got["Y"], yR + py, atol=1e-7)
    assert np.allclose(got["Z"], zR + pz, atol=1e-7)
    # the programmed tool axis turned by C (about k) then B (about j) is a0 = (0, 0, 1)
    b, c = np.radians(got["B"]), np.radians(got["C"])
    rc = np.stack([np.cos(c) * a[:, 0] - np.sin(c) * a[:, 1],
                   np.sin(c) * a[:, 0] + np.cos(c) * a[:, 1], a[:, 2]], axis=1)
    rb = np.stack([np.cos(b) * rc[:, 0] + np.sin(b) * rc[:, 2], rc[:, 1],
                   -np.sin(b) * rc[:, 0] + np.cos(b) * rc[:, 2]], axis=1)
    assert np.allclose(rb, [0.0, 0.0, 1.0], atol=1e-12)


def test_b_zero_singularity_strategies():
    m = model("s5d")
    tips = np.zeros((6, 3))
    tilt = np.array([30.0, 0.0, 0.0, 45.0, 0.0, 20.0])
    az = np.array([100.0, 0.0, 0.0, -170.0, 0.0, 175.0])
    axis = tilted_axes(tilt, az)
    axis[tilt == 0] = [0.0, 0.0, 1.0]
    prev = m.q({"C": 33.0})[0]
    keep = m.ik(tips, axis, previous=prev, strategy="keep")
    c = keep.q[:, m.axes.index("C")]
    assert keep.singular.tolist() == [False, True, True, False, True, False]
    # C = atan2(a_y, −a_x): an axis at azimuth φ gives C = 180° − φ
    assert np.allclose(c, [80.0, 80.0, 80.0, -10.0, -10.0, 5.0])
    first = m.ik(tips[1:3], axis[1:3], previous=prev, strategy="keep")
    assert np.allclose(first.q[:, m.axes.index("C")], 33.0)  # keeps the C before the block
    short = m.ik(tips, axis, previous=m.q({"C": 350.0})[0], strategy="shortest")
    cs = short.q[:, m.axes.index("C")]
    assert np.allclose(np.mod(cs - c, 360.0), 0.0, atol=1e-9)  # same poses, other turns
    assert np.allclose(cs, [440.0, 440.0, 440.0, 350.0, 350.0, 365.0])
    assert np.abs(np.diff(np.concatenate([[350.0], cs]))).max() <= 180.0
    for sol in (keep, short):
        assert np.allclose(m.fk(sol.q).tip, tips, atol=1e-12)
        assert angle_between(m.fk(sol.q).axis, axis).max() < 1e-12


def test_head_formulas_of_section_3():
    rng = np.random.default_rng(5)
    B, C = rng.uniform(1, 120, 300), rng.uniform(-179, 179, 300)
    k = np.stack([np.cos(np.radians(C)) * np.sin(np.radians(B)),
                  np.sin(np.radians(C)) * np.sin(np.radians(B)), np.cos(np.radians(B))], axis=1)
    b, c, singular = head_bc_ik(k)
    assert np.allclose(b, B) and np.allclose(c, C) and not singular.any()
    b2, c2, _ = head_bc_ik(k, b_sign=-1)  # the other root: −B, C + 180°
    assert np.allclose(b2, -B) and np.allclose(np.mod(c2 - C, 360.0), 180.0)
    tip = rng.uniform(-20, 20, (300, 3))
    p2 = head_platform_point(tip, B, C, 60.0, 100.0)
    assert np.allclose(p2[:, 0], tip[:, 0] + 100.0 * np.cos(np.radians(C)) * np.sin(np.radians(B)))
    assert np.allclose(p2[:, 2], tip[:, 2] + 60.0 + 100.0 * np.cos(np.radians(B)))


@pytest.mark.parametrize("name", FIVE_AXIS)
def test_workspace_holds_a_40mm_cube_with_tilts_up_to_60_degrees(name):
    m = model(name)
    rng = np.random.default_rng(11)
    n = 4000
    home = m.fk(m.home[None]).tip[0]
    tip = home + rng.uniform(-20, 20, (n, 3))
    corners = np.array(np.meshgrid([-20, 20], [-20, 20], [-20, 20])).reshape(3, -1).T
    tip[: 8 * 12] = home + np.repeat(corners, 12, axis=0)
    tilt = np.where(np.arange(n) % 2 == 0, 60.0, rng.uniform(0, 60, n))
    axis = tilted_axes(tilt, rng.uniform(-180, 180, n))
    sol = m.ik(tip, axis)
    assert sol.ok.all()
    assert axis_limit_findings(m, sol.q) == []
    back = m.fk(sol.q)
    assert np.abs(back.tip - tip).max() <= 1e-9
    assert angle_between(back.axis, axis).max() <= 1e-9


@settings(max_examples=10, deadline=None)
@given(seeds)
def test_turnmill_numeric_ik_round_trips(seed):
    m = model("turnmill")
    rng = np.random.default_rng(seed)
    q = np.column_stack([rng.uniform(0.5, 320, 60), rng.uniform(-60, 60, 60),
                         rng.uniform(-450, 350, 60), rng.uniform(-720, 720, 60)])
    pose = m.fk(q)
    sol = m.ik(pose.tip, pose.axis)
    assert sol.ok.all()
    assert_same_pose(m.fk(sol.q), pose)
    # unique up to whole turns of the modulo axis C1
    assert np.allclose(sol.q[:, :3], q[:, :3], atol=1e-8)
    dc = np.mod(sol.q[:, 3] - q[:, 3] + 180.0, 360.0) - 180.0
    assert np.allclose(dc, 0.0, atol=1e-8)


def test_turnmill_pose_with_an_axial_tool_is_unreachable_not_clipped():
    m = model("turnmill")
    sol = m.ik([[20.0, 0.0, -5.0], [20.0, 0.0, -5.0]], [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    assert sol.ok.tolist() == [False, True]
