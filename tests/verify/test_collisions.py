"""Tool against chuck and jaws: analytic geometry, sampled motion, bounded error."""

from __future__ import annotations

import numpy as np
import pytest
from catalog import TURNMILL
from nc import ok

from vmach.checks.collisions import (
    Cylinder,
    fixture_collisions,
    signed_distance,
    surface_points,
    tool_cylinders,
)
from vmach.machine import load_model
from vmach.machine.spec import Geometry
from vmach.motion import build
from vmach.tooling.model import Tool

MODEL = load_model(TURNMILL)
D25 = Tool(
    name="D25",
    kind="flat",
    diameter=25.0,
    cutting_length=30.0,
    shank_diameter=25.0,
    shank_length=30.0,
    holder_diameter=50.0,
    holder_length=40.0,
)


def test_signed_distance_of_box_and_cylinder():
    box = Geometry("b", "base", "box", size=(2.0, 4.0, 6.0))
    p = np.array([[0, 0, 0], [2, 0, 0], [0, 0, 4], [2, 3, 3]], float)
    assert signed_distance(p, box) == pytest.approx([-1, 1, 1, np.hypot(1, 1)])
    cyl = Geometry("c", "base", "cylinder", radius=2.0, length=4.0)
    p = np.array([[0, 0, 0], [3, 0, 0], [0, 0, 3], [3, 0, 3], [1.5, 0, 0]], float)
    assert signed_distance(p, cyl) == pytest.approx([-2, 1, 1, np.hypot(1, 1), -0.5])


def test_surface_points_cover_the_tool_within_the_step():
    parts = tool_cylinders(D25)
    assert [c.part for c in parts] == ["cutter", "shank", "holder"]
    assert parts[2] == Cylinder("holder", 60.0, 100.0, 25.0)
    pts, part = surface_points(parts, 2.0)
    r = np.hypot(pts[:, 0], pts[:, 1])
    assert r.max() == pytest.approx(25.0) and pts[:, 2].min() == 0 and pts[:, 2].max() == 100
    # neighbouring points on the holder mantle are at most one step apart
    ring = pts[(part == 2) & np.isclose(r, 25.0) & np.isclose(pts[:, 2], 80.0)]
    ang = np.sort(np.arctan2(ring[:, 1], ring[:, 0]))
    assert (np.diff(ang) * 25.0).max() <= 2.0 + 1e-9


def _moves(tmp_path, text):
    r = ok(tmp_path, 'T="D25" D1\nSETMS(2)\nS2=1000 M2=3\n' + text + "M30\n", MODEL.control)
    return build(r.commands, MODEL.control)


def test_rapid_into_the_jaws_is_a_fixture_collision_at_its_line(tmp_path):
    # the jaws clamp the blank between radius 30 and 70 over z = -100..-65 (models/turnmill.toml)
    t = _moves(tmp_path, "G0 X60 Y0 Z10 C1=0\nG0 Z-80\nG0 Z10\n")
    f = fixture_collisions(MODEL, t, {0: tool_cylinders(D25)})
    hits = sorted((x.line, x.data["obstacle"], x.data["part"]) for x in f if x.kind == "fixture_collision")
    # the rapid down drives the cutter into jaw 1 and the Ø50 holder onto the chuck face
    # (z = -100); the rapid back up starts inside both: collisions as well
    assert hits == [
        (5, "chuck_body", "holder"),
        (5, "jaw_1", "cutter"),
        (6, "chuck_body", "holder"),
        (6, "jaw_1", "cutter"),
    ]
    depth = {x.data["obstacle"]: x.data["depth_mm"] for x in f if x.line == 5}
    # jaw top at z = -65, cutter bottom at -80 - 12.5; holder bottom at -80 - 25 vs chuck face -100
    # deepest cutter point in the jaw: the tip face centre (60, 0, -80), 10 mm from the jaw's
    # outer face at radius 70
    assert depth["jaw_1"] == pytest.approx(10.0, abs=1e-6)
    assert depth["chuck_body"] == pytest.approx(5.0, abs=0.05)


def test_clear_path_has_no_finding_and_a_close_rapid_is_a_near_miss(tmp_path):
    # the radial tool's cutter (radius 12.5) stops 1.5 mm above the jaw's face at z = -65
    t = _moves(tmp_path, "G0 X60 Y0 Z10\nG0 Z-51\nG0 Z10\nG0 X150\n")
    f = fixture_collisions(MODEL, t, {0: tool_cylinders(D25)}, clearance=2.0)
    # down to 1.5 mm above the jaw, and up again from there: two near misses, no collision
    assert [(x.kind, x.line) for x in f] == [("near_miss", 5), ("near_miss", 6)]
    assert f[0].data["distance_mm"] == pytest.approx(1.5, abs=1e-6)


def test_turning_the_chuck_under_a_tool_finds_the_jaw_it_meets(tmp_path):
    # tool tip at radius 40 between the jaws' z range, then C1 turns the jaws into it
    t = _moves(tmp_path, "G0 X150 Y0 Z10 C1=60\nG0 Z-80\nG0 X40\nG1 C1=0 F1000\n")
    f = fixture_collisions(MODEL, t, {0: tool_cylinders(D25)})
    assert [(x.kind, x.line) for x in f if x.kind == "fixture_collision"][0][1] == 6


def test_turret_against_chuck_is_a_machine_collision(tmp_path):
    from vmach.checks.collisions import machine_collisions

    # the VDI turret disc (axis along Z, ±40 mm around the tool's Z, from X + 100 outward)
    # meets the Ø250 chuck (z < -100) when the tool comes down to Z-70 at X20
    t = _moves(tmp_path, "G0 X150 Y0 Z10\nG0 Z-70\nG0 X20\nG0 X150\n")
    f = machine_collisions(MODEL, t)
    assert sorted({(x.line, x.data["part"], x.data["obstacle"]) for x in f}) == [
        (6, "turret_disc", "chuck_body"),
        (7, "turret_disc", "chuck_body"),
    ]
    # the disc's rim reaches radius 20 + 100 = 120 into the chuck's 125: about 5 mm
    assert max(x.data["depth_mm"] for x in f) == pytest.approx(5.0, abs=0.6)
    # machining the polygon end stays clear of it
    t = _moves(tmp_path, "G0 X40 Y0 Z10\nG1 X26 Z-20 F500\nG1 C1=360\nG0 X150\n")
    assert machine_collisions(MODEL, t) == []


def test_rigid_inverse_is_the_matrix_inverse_of_rigid_frames():
    from vmach.checks.collisions import rigid_inverse

    rng = np.random.default_rng(7)
    q, _ = np.linalg.qr(rng.normal(size=(50, 3, 3)))
    m = np.zeros((50, 4, 4))
    m[:, :3, :3], m[:, :3, 3], m[:, 3, 3] = q, rng.normal(scale=300.0, size=(50, 3)), 1.0
    assert np.allclose(rigid_inverse(m), np.linalg.inv(m), atol=1e-12)
    assert np.allclose(rigid_inverse(m[7]) @ m[7], np.eye(4), atol=1e-12)


def test_the_balls_that_screen_samples_hold_every_surface_point():
    """fixture_collisions skips a sample when every ball of sphere_cover lies farther than the
    clearance from the obstacle: sound only if the balls hold the points it would measure."""
    from vmach.checks.collisions import Cylinder, sphere_cover, surface_points

    parts = [Cylinder("cutter", 0.0, 5.5, 20.0), Cylinder("shank", 5.5, 45.0, 18.0),
             Cylinder("holder", 45.0, 110.0, 31.5), Cylinder("pin", 110.0, 111.0, 0.5)]
    centres, radii = sphere_cover(parts)
    pts, _ = surface_points(parts, 0.5)
    d = np.linalg.norm(pts[:, None, :3] - centres[None, :, :3], axis=2) - radii[None, :]
    assert d.min(axis=1).max() <= 1e-9
    # and no ball reaches farther than 1.12 of its cylinder's radius from the axis (1 mm
    # pieces for the needle: sqrt(0.5² + 0.5²))
    assert np.all(radii <= np.repeat([20.0, 18.0, 31.5, 0.71], [1, 3, 3, 1]) * 1.12)
    # a needle-thin cutter (found by fuzzing: radius 5e-10 mm asked for 5.5e9 balls) is held
    # by balls around 1 mm pieces
    needle = [Cylinder("cutter", 0.0, 5.5, 5e-10)]
    centres, radii = sphere_cover(needle)
    assert len(radii) == 6
    pts, _ = surface_points(needle, 0.05)
    d = np.linalg.norm(pts[:, None, :3] - centres[None, :, :3], axis=2) - radii[None, :]
    assert d.min(axis=1).max() <= 1e-9
