"""Parallel mechanisms (domain §3): the strut equation, both roots, forward solutions, reach."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from machine.machine_helpers import model

from vmach.machine import axis_limit_findings
from vmach.machine import parallel as par
from vmach.machine.spec import Leg, Parallel

seeds = st.integers(0, 2**32 - 1)


def strut_lengths(mech, virtual, drives):
    """|P + b_i − (g_i + p_i·u_i)| for each leg — must equal L_i."""
    P = virtual + np.asarray(mech.origin)
    out = []
    for i, leg in enumerate(mech.legs):
        s = np.asarray(leg.guide_point) + drives[:, i, None] * np.asarray(leg.guide_dir)
        out.append(np.linalg.norm(P + np.asarray(leg.attach) - s, axis=1))
    return np.stack(out, axis=1)


@settings(max_examples=20, deadline=None)
@given(seeds)
def test_h5d_planar_drives_satisfy_the_strut_equation_and_invert_in_closed_form(seed):
    m = model("h5d")
    (mech,) = m.spec.parallel
    rng = np.random.default_rng(seed)
    v = np.column_stack([rng.uniform(-60, 60, 300), rng.uniform(-50, 80, 300)])
    p, ok = par.inverse(mech, v)
    assert ok.all()
    assert np.allclose(strut_lengths(mech, v, p), [leg.length for leg in mech.legs], atol=1e-9)
    assert (p[:, 0] < v[:, 0]).all() and (p[:, 1] > v[:, 0]).all()  # the sliders splay outward
    back, ok = par.forward(mech, p)
    assert ok.all() and np.abs(back - v).max() <= 1e-9


@settings(max_examples=10, deadline=None)
@given(seeds)
def test_hybrid5_spatial_forward_by_newton_inverts_the_drives(seed):
    m = model("hybrid5")
    (mech,) = m.spec.parallel
    rng = np.random.default_rng(seed)
    v = np.column_stack([rng.uniform(-400, 400, 300), rng.uniform(-120, 120, 300),
                         rng.uniform(-100, 60, 300)])
    p, ok = par.inverse(mech, v)
    assert ok.all()
    assert np.allclose(strut_lengths(mech, v, p), 450.0, atol=1e-9)
    back, ok = par.forward(mech, p)
    assert ok.all() and np.abs(back - v).max() <= 1e-9


def test_both_roots_are_assembly_modes_of_the_same_pose():
    legs = (Leg("p1", (0.0, 0.0), (1.0, 0.0), 100.0, (0.0, 0.0), -1),
            Leg("p2", (0.0, 50.0), (1.0, 0.0), 100.0, (0.0, 0.0), 1))
    low = Parallel("m", ("Y", "Z"), (0.0, 0.0), legs, assembly=-1)
    high = Parallel("m", ("Y", "Z"), (0.0, 0.0), tuple(
        Leg(g.drive, g.guide_point, g.guide_dir, g.length, g.attach, -g.root) for g in legs), -1)
    v = np.array([[10.0, -30.0], [-5.0, 20.0]])
    p_low, ok1 = par.inverse(low, v)
    p_high, ok2 = par.inverse(high, v)
    assert ok1.all() and ok2.all()
    assert not np.allclose(p_low, p_high)
    for mech, p in ((low, p_low), (high, p_high)):
        assert np.allclose(strut_lengths(mech, v, p), 100.0)
    # the other root of each leg differs from the first by 2·√disc, symmetric about u·d
    assert np.allclose(p_low + p_high, 2 * v[:, :1], atol=1e-12)


def test_no_real_root_is_unreachable_never_clipped():
    m = model("h5d")
    (mech,) = m.spec.parallel
    v = np.array([[0.0, 0.0], [0.0, 100.0], [0.0, -60.0]])  # P_z = 0: still reachable (|z| < L)
    v[1, 1] = 280.0  # P_z = 170 mm above the guideway: farther than the 160 mm struts
    v[2, 1] = -51.0 - 110.0 - 10.0  # P_z = −271: farther than 160 below
    p, ok = par.inverse(mech, v)
    assert ok.tolist() == [True, False, False]
    assert np.isnan(p[1:]).all() and np.isfinite(p[0]).all()
    q = m.q(n=3)
    q[:, m.axes.index("Z")] = v[:, 1]
    found = axis_limit_findings(m, q, move_index=[7, 8, 9])
    unreachable = [f for f in found if f.kind == "unreachable"]
    assert [f.move_index for f in unreachable] == [8, 9]
    sol = m.ik(m.fk(q).tip, m.fk(q).axis)
    assert sol.ok.tolist() == [True, False, False]
    assert np.allclose(sol.q[:, m.axes.index("Z")], v[:, 1])  # the virtual value, not clipped


def test_fk_command_path_from_drives_back_to_axes():
    m = model("h5d")
    q = m.q({"X": 3.0, "Y": 12.0, "Z": -30.0, "B": 20.0, "C": 10.0})
    drives, ok = m.drive_values(q)
    assert ok.all()
    q2, ok = m.axes_from_drives(m.q({"X": 3.0, "B": 20.0, "C": 10.0}), drives)
    assert ok.all() and np.allclose(q2, q, atol=1e-9)
