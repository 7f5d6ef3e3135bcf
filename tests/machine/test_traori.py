"""The orientation transformation's solver (vmach/machine/traori.py) on the four bundled
five-axis models: FK of the solution equals the programmed tip and vector to 1e-9, the
solution rule, the pole, and the domain §2 closed form on the table-table machine."""

from __future__ import annotations

import numpy as np
import pytest

from vmach.machine import load_model
from vmach.machine.closed_form import table_table_ik
from vmach.machine.traori import orienter

MODELS = ("s5d", "h5d", "hybrid5", "mill5ac")


def _poses(seed: int, n: int = 300):
    rng = np.random.default_rng(seed)
    t = rng.normal(size=(n, 3))
    t[:, 2] = np.abs(t[:, 2]) + 0.4            # tilts the machines reach (below 70° or so)
    t /= np.linalg.norm(t, axis=1)[:, None]
    return rng.uniform(-30.0, 30.0, (n, 3)), t


@pytest.mark.parametrize("name", MODELS)
def test_fk_of_the_solution_is_the_programmed_pose(name):
    m = load_model(name)
    o = orienter(m)
    tip, t = _poses(7)
    outer, inner, reach, pole = o.rotaries(t, (0.0, 0.0))
    assert reach.all() and not pole.any()
    q = m.q(n=len(t))
    q[:, o.outer], q[:, o.inner] = outer, inner
    q = o.linear_axes(q, tip)
    pose = m.fk(q)
    assert np.abs(pose.tip - tip).max() < 1e-9
    assert np.abs(pose.axis - t).max() < 1e-9
    assert np.abs(o.vector(q) - t).max() < 1e-12


@pytest.mark.parametrize("name", MODELS)
def test_both_roots_give_the_vector(name):
    m = load_model(name)
    o = orienter(m)
    _, t = _poses(3, 50)
    outer, inner, reach, _ = o.candidates(t)
    for j in (0, 1):
        q = m.q(n=len(t))
        q[:, o.outer], q[:, o.inner] = outer[:, j], inner[:, j]
        assert np.abs(o.vector(q) - t).max() < 1e-12


def test_table_table_matches_the_domain_closed_form():
    """On s5d, coming from near the domain's B ∈ [0°, 180°] branch the rule stays on it: the
    same axis values as domain §2's formula; from home the mirrored root (−B, C − 180°) moves
    the axes less and is chosen (it lies inside the B travel)."""
    m = load_model("s5d").with_parameters(rotation_centre=(10.0, 0.0, -5.0))
    o = orienter(m)
    tip = np.array([[5.0, -3.0, 12.0]])
    t = np.array([[0.3, 0.2, 0.9]]) / np.linalg.norm([0.3, 0.2, 0.9])
    ref, _ = table_table_ik(tip, t, (10.0, 0.0, -5.0))
    outer, inner, _, _ = o.rotaries(t, (0.0, 0.0))
    assert inner[0] == pytest.approx(-ref["B"][0]) and outer[0] == pytest.approx(ref["C"][0] - 180.0)
    outer, inner, _, _ = o.rotaries(t, (140.0, 20.0))
    assert o.rotary_names == ("C", "B")
    assert outer[0] == pytest.approx(ref["C"][0], abs=1e-9)
    assert inner[0] == pytest.approx(ref["B"][0], abs=1e-9)
    q = m.q(n=1)
    q[:, o.outer], q[:, o.inner] = outer, inner
    q = o.linear_axes(q, tip)
    for name in ("X", "Y", "Z"):
        assert q[0, m.axes.index(name)] == pytest.approx(ref[name][0], abs=1e-9)


def test_the_pole_keeps_the_outer_axis():
    """The tool along the outer axis (B = 0 on s5d): C is free and keeps its previous value."""
    o = orienter(load_model("s5d"))
    outer, inner, reach, pole = o.rotaries(np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]), (123.0, 10.0))
    assert pole.all() and reach.all()
    assert outer.tolist() == [123.0, 123.0] and inner == pytest.approx([0.0, 0.0], abs=1e-12)


def test_the_rule_moves_the_rotary_axes_least():
    """The root inside the travel wins; a modulo C is unwrapped to the nearest turn (C = 540
    from 530); between two roots inside, the one with less rotary travel."""
    o = orienter(load_model("s5d"))
    t = np.array([[-1.0, 0.0, 1.0]]) / np.sqrt(2)
    outer, inner, _, _ = o.rotaries(t, (170.0, 40.0))
    # B −45 lies outside s5d's B travel (−25…135): the root inside wins although C moves 170°
    assert inner[0] == pytest.approx(45.0) and outer[0] == pytest.approx(0.0, abs=1e-9)
    outer, _, _, _ = o.rotaries(np.array([[1.0, 0.0, 1.0]]) / np.sqrt(2), (530.0, 40.0))
    assert outer[0] == pytest.approx(540.0)
    t = np.array([[0.0, np.sin(np.radians(20)), np.cos(np.radians(20))]])
    outer, inner, _, _ = o.rotaries(t, (85.0, 5.0))         # roots (20, 90) and (−20, −90)
    assert (outer[0], inner[0]) == (pytest.approx(90.0), pytest.approx(20.0))
    outer, inner, _, _ = o.rotaries(t, (-85.0, -5.0))
    assert (outer[0], inner[0]) == (pytest.approx(-90.0), pytest.approx(-20.0))


def test_a_vector_out_of_reach():
    """mill5ac turns A about X and C about Z: every direction is reachable geometrically, but a
    machine whose inner axis is at 45° to the tool reaches only a cone: built by turning the
    inner axis of s5d's orienter (the rule's reach flag)."""
    o = orienter(load_model("s5d"))
    tilted = type(o)(o.model, o.outer, o.inner, o.u_outer, np.array([0.0, -1.0, 1.0]) / np.sqrt(2),
                     o.v0, o.linear, o.limits, o.modulo)
    _, _, reach, _ = tilted.candidates(np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]))
    assert reach.tolist() == [False, True]


def test_a_machine_without_two_rotary_axes_has_no_orienter():
    assert orienter(load_model("turnmill")) is None
    assert orienter(load_model("mill3")) is None
