"""The collision close-up's highlighted volume: where the tool overlaps the other body, as a
mesh (manifold3d's exact boolean through vmach.stock.engine)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from vmach.checks.collisions import Cylinder
from vmach.machine.spec import Geometry
from vmach.report.pictures import _move_path, _overlap, box_mesh


def test_the_overlap_of_a_holder_and_a_body_is_the_shared_volume():
    holder = Cylinder("holder", 0.0, 10.0, 5.0)        # z 0..10, r 5, at the origin
    v, f = box_mesh((20.0, 20.0, 20.0))
    v = v + [0.0, 0.0, 15.0]                           # a body from z = 5 to 25: half the holder
    mesh = _overlap([(holder, np.eye(4))], [(v, f)])
    polygon = 0.5 * 48 * math.sin(2 * math.pi / 48) * 25.0      # the 48-gon's area
    assert trimesh.Trimesh(*mesh).volume == pytest.approx(polygon * 5.0, rel=1e-6)
    # a fixture given as its geometry and pose gives the same
    jaw = Geometry("jaw", "base", "box", size=(20.0, 20.0, 20.0))
    pose = np.eye(4)
    pose[2, 3] = 15.0
    assert trimesh.Trimesh(*_overlap([(holder, np.eye(4))], [(jaw, pose)])).volume == pytest.approx(
        polygon * 5.0, rel=1e-6)
    # apart: nothing to highlight
    assert _overlap([(holder, np.eye(4))], [(v + [0.0, 0.0, 30.0], f)]) is None
    assert _overlap([], [(v, f)]) is None


def test_a_rotary_moves_tip_path_is_its_arc(tmp_path):
    from catalog import TURNMILL
    from nc import ok

    from vmach.machine import load_model
    from vmach.motion import build

    model = load_model(TURNMILL)
    r = ok(tmp_path, "C_AXIS_ON\nG0 X30 Y0 Z-10 C1=0\nG0 C1=90\nM30\n", model.control)
    table = build(r.commands, model.control)
    row = len(table) - 1
    seg = _move_path(table, model, row)
    pts = np.vstack([seg[:, 0], seg[-1:, 1]])
    radius = np.hypot(pts[:, 0], pts[:, 1])
    assert len(seg) >= 45 and np.allclose(radius, radius[0], atol=1e-9)   # on the circle, not a chord
