"""Sinumerik milling words through the whole pipeline (verify, stock, export) on the
table-table mill with B = C = 0: a 40 × 40 mm boss milled with G41 and an Ø10 end mill has its
walls where the drawing puts them (without G41 they lie 5 mm inside); MCALL CYCLE81 drills
its holes where the program puts them."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from shapely.geometry import Polygon

from vmach.cli import main

TOOLS = """
[[tool]]
name = "EM10"
type = "flat"
diameter = 10.0
cutting_length = 20.0
shank = { diameter = 10.0, length = 30.0 }
holder = { diameter = 30.0, length = 40.0 }
[tool.d.1]
length = 0.0
"""

DRILL = """
[[tool]]
name = "DR8"
type = "drill"
diameter = 8.0
point_angle = 118.0
cutting_length = 30.0
shank = { diameter = 8.0, length = 20.0 }
holder = { diameter = 30.0, length = 40.0 }
"""

BOSS = """T="EM10" D1
G17 G90 G0 X-30 Y-30 Z5
S3000 M3
G1 Z-5 F500
{comp} X0 Y20
Y40
X40
Y0
X0
Y20
G40 X-30 Y-30
G0 Z5
M30
"""


@pytest.mark.parametrize("comp, wall", [("G41", 0.0), ("", 5.0)])
def test_a_g41_contour_mills_the_boss_to_the_drawing(tmp_path, comp, wall):
    (tmp_path / "tools.toml").write_text(TOOLS)
    prog = tmp_path / "BOSS.MPF"
    prog.write_text(BOSS.format(comp=comp or "G1"))
    part = tmp_path / "part.stl"
    code = main(["verify", str(prog), "--dialect", "sinumerik", "--machine", "s5d",
                 "--tools", str(tmp_path / "tools.toml"), "--stock",
                 "box:xmin=-20,xmax=60,ymin=-20,ymax=60,zmin=-20,zmax=0",
                 "--export", str(part), "--out", str(tmp_path / "o"), "--no-images", "--quiet"])
    assert code == 0
    section = trimesh.load(part).section(plane_origin=[0, 0, -2.5], plane_normal=[0, 0, 1])
    boss = min(section.discrete, key=lambda loop: np.ptp(loop[:, 0]))[:, :2]
    lo, hi = wall, 40.0 - wall
    # mid-side the walls are exact (the side sweeps them across its travel); elsewhere within
    # the tool polygon's 0.01 mm
    for y in (10.0, 30.0):
        xs = boss[np.abs(boss[:, 1] - y) < 5.0, 0]
        on = xs[np.abs(xs - lo) < 0.02]
        assert on.size and np.abs(on - lo).max() < 1e-6
    assert boss.min(0) == pytest.approx([lo, lo], abs=0.01)
    assert boss.max(0) == pytest.approx([hi, hi], abs=0.01)


def test_mcall_cycle81_drills_a_hole_at_each_position(tmp_path):
    """MCALL CYCLE81 after two positioning blocks: the exported part has two Ø8 holes where
    the program put them (none at the start position), their 118° points ending at DP = −10:
    0.5 mm above it the hole is the cone's 0.5·tan 59° wide."""
    (tmp_path / "tools.toml").write_text(TOOLS + DRILL)
    prog = tmp_path / "HOLES.MPF"
    prog.write_text('T="DR8" D1\nG17 G90 G0 X0 Y0 Z20\nS2000 M3 F200\n'
                    "MCALL CYCLE81(10, 0, 2, -10)\nX10 Y10\nX30\nMCALL\nG0 Z50\nM30\n")
    part = tmp_path / "part.stl"
    assert main(["verify", str(prog), "--dialect", "sinumerik", "--machine", "s5d",
                 "--tools", str(tmp_path / "tools.toml"), "--stock",
                 "box:xmin=-5,xmax=45,ymin=-5,ymax=25,zmin=-20,zmax=0",
                 "--export", str(part), "--out", str(tmp_path / "o"), "--no-images", "--quiet"]) == 0
    mesh = trimesh.load(part)
    for z, radius, tol in ((-5.0, 4.0, 0.011), (-9.5, 0.5 * math.tan(math.radians(59)), 0.011)):
        section = mesh.section(plane_origin=[0, 0, z], plane_normal=[0, 0, 1])
        holes = sorted((loop[:, :2] for loop in section.discrete if np.ptp(loop[:, 0]) < 10),
                       key=lambda loop: loop[:, 0].mean())
        assert len(holes) == 2
        for loop, centre in zip(holes, [(10, 10), (30, 10)], strict=True):
            r = np.hypot(loop[:, 0] - centre[0], loop[:, 1] - centre[1])
            assert r.min() > radius - tol and r.max() < radius + tol
    below = mesh.section(plane_origin=[0, 0, -10.05], plane_normal=[0, 0, 1])
    assert all(np.ptp(loop[:, 0]) > 10 for loop in below.discrete)   # the point ends at −10


def test_a_tracyl_groove_on_the_turn_mill(tmp_path):
    """TRACYL(60): the D25 end mill, radial, runs 30 mm along the unwrapped surface of a Ø60
    shaft 3 mm deep; the part's section through the groove is at radius 27 over the arc that
    30 mm unwraps to (57.3° at Ø60), and at the blank's 30 elsewhere."""
    from catalog import POLYGON_TOOLS

    prog = tmp_path / "GROOVE.MPF"
    prog.write_text('T="GLOD D25" D1\nG54 G19 G90\nSETMS(2)\nG94 S2=1500 M2=3\nC_AXIS_ON\nC1=0\n'
                    "G0 X40 Y0 Z-20\nTRACYL(60)\nG1 X27 F300\nY30\nG0 X40\nTRAFOOF\nM2=5\nM30\n")
    part = tmp_path / "part.stl"
    assert main(["verify", str(prog), "--machine", "turnmill", "--tools", str(POLYGON_TOOLS),
                 "--stock", "cylinder:d=60,l=60", "--export", str(part), "--out", str(tmp_path / "o"),
                 "--no-images", "--quiet"]) == 0
    loops = trimesh.load(part).section(plane_origin=[0, 0, -20], plane_normal=[0, 0, 1]).discrete
    pts = np.concatenate([loop[:, :2] for loop in loops])
    r = np.hypot(pts[:, 0], pts[:, 1])
    ang = np.degrees(np.arctan2(pts[:, 1], pts[:, 0])) % 360
    sweep = math.degrees(30 / 30)                    # 30 mm of arc at radius 30: 57.3°
    inside = (ang > 5) & (ang < sweep - 5)
    assert inside.any() and np.abs(r[inside] - 27).max() < 0.02
    outside = (ang > sweep + 40) & (ang < 360 - 40)
    assert outside.any() and np.abs(r[outside] - 30).max() < 0.01


def test_the_milling_fixture_verifies_clean_and_makes_its_drawing(tmp_path):
    """fixtures/milling/PLATE.MPF (G41 outline with RND corners, MCALL CYCLE81 on a HOLES2
    bolt circle) verifies without a finding — the drill's rapid retracts out of its holes are
    no near misses — and its part is the drawing: a 60 × 40 R6 outline (area 2400 − (4 − π)·36)
    and four Ø6.8 holes on Ø24 at 45°, 135°, 225°, 315°."""
    import json
    import shutil

    from catalog import FIXTURES

    job = tmp_path / "milling"
    shutil.copytree(FIXTURES / "milling", job)
    part = tmp_path / "part.stl"
    assert main(["verify", str(job / "PLATE.MPF"), "--export", str(part), "--out", str(tmp_path / "o"),
                 "--no-images", "--quiet"]) == 0
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert report["summary"] == {"errors": 0, "warnings": 0, "infos": 0}
    section = trimesh.load(part).section(plane_origin=[0, 0, -3], plane_normal=[0, 0, 1])
    loops = sorted((Polygon(loop[:, :2]) for loop in section.discrete), key=lambda poly: -poly.length)
    outline, inner = loops[0], loops[1:]
    assert len(inner) == 4 and all(outline.contains(h) for h in inner)
    assert outline.bounds == pytest.approx((-30, -20, 30, 20), abs=0.01)
    assert outline.area == pytest.approx(2400 - (4 - math.pi) * 36, abs=0.5)
    holes = sorted(((h.centroid.x, h.centroid.y), h.area) for h in inner)
    want = sorted((12 * math.cos(math.radians(a)), 12 * math.sin(math.radians(a)))
                  for a in (45, 135, 225, 315))
    assert [c for c, _ in holes] == [pytest.approx(w, abs=1e-3) for w in want]
    assert all(area == pytest.approx(math.pi * 3.4 ** 2, rel=0.01) for _, area in holes)


def test_a_rapid_retract_along_the_axis_is_no_near_miss_only_for_a_tool_that_does_not_widen(tmp_path):
    from vmach.checks.stock_events import retracts
    from vmach.tooling.library import load_tools

    (tmp_path / "t.toml").write_text(TOOLS + DRILL + """
[[tool]]
name = "FACE"
type = "face"
diameter = 40.0
cutting_length = 5.5
shank = { diameter = 36.0, length = 35.0 }
""")
    lib = load_tools(tmp_path / "t.toml")
    up = np.array([[0, 0, -8.0], [0, 0, 5.0]])
    axis = np.array([[0, 0, 1.0], [0, 0, 1.0]])
    assert retracts(lib["DR8"], up, axis) and retracts(lib["EM10"], up, axis)
    assert not retracts(lib["FACE"], up, axis)                   # its body is narrower
    assert not retracts(lib["DR8"], up[::-1], axis)               # a plunge
    assert not retracts(lib["DR8"], np.array([[0, 0, 5.0], [10, 0, 6.0]]), axis)   # sideways


def test_an_rs274_g41_boss_takes_the_radius_from_the_tool_library(tmp_path):
    """The same boss as an RS274/NGC program: under verify, G41 compensates with the library's
    EM10 (tool 1, 5 mm) — not rs274's built-in T1 of 1/8 in — so the walls land on the drawing."""
    (tmp_path / "tools.toml").write_text(TOOLS.replace('name = "EM10"', 'name = "EM10"\nnumber = 1'))
    prog = tmp_path / "boss.ngc"
    prog.write_text("G21 G17 G90\nT1 M6\nS3000 M3\nG0 X-30 Y20 Z5\nG1 Z-5 F500\nG41 G1 X0 Y20\n"
                    "Y40\nX40\nY0\nX0\nY20\nG40 G1 X-30\nG0 Z5\nM2\n")
    part = tmp_path / "part.stl"
    assert main(["verify", str(prog), "--machine", "s5d", "--tools", str(tmp_path / "tools.toml"),
                 "--stock", "box:xmin=-20,xmax=60,ymin=-20,ymax=60,zmin=-20,zmax=0",
                 "--export", str(part), "--out", str(tmp_path / "o"), "--no-images", "--quiet"]) == 0
    from shapely.geometry import LineString

    section = trimesh.load(part).section(plane_origin=[0, 0, -2.5], plane_normal=[0, 0, 1])
    boss = Polygon(min(section.discrete, key=lambda loop: np.ptp(loop[:, 0]))[:, :2])
    # across the boss at heights the compensated sides run past (LinuxCNC's entry move, from
    # the left to y = 25, leaves the wall below that to the last side's way back)
    for y in (10.0, 30.0, 35.0):
        xmin, _, xmax, _ = boss.intersection(LineString([(-50, y), (100, y)])).bounds
        assert (xmin, xmax) == pytest.approx((0.0, 40.0), abs=1e-6)


def test_the_turn_mill_groove_fixture_verifies_clean_and_cuts_its_groove(tmp_path):
    """fixtures/turnmill/GROOVE.MPF (TRACYL(40), the D25 radial, 3 mm deep over 90°; two
    countersinks by CYCLE81 along X): no finding, and through the groove the part lies at
    radius 17 (the countersinks below it at 30° and 60°), at the blank's 20 elsewhere."""
    import json
    import shutil

    from catalog import FIXTURES

    job = tmp_path / "turnmill"
    shutil.copytree(FIXTURES / "turnmill", job)
    part = tmp_path / "part.stl"
    assert main(["verify", str(job / "GROOVE.MPF"), "--export", str(part), "--out", str(tmp_path / "o"),
                 "--no-images", "--quiet"]) == 0
    assert json.loads((tmp_path / "o" / "report.json").read_text())["summary"]["warnings"] == 0
    section = trimesh.load(part).section(plane_origin=[0, 0, -25], plane_normal=[0, 0, 1])
    pts = np.concatenate([loop[:, :2] for loop in section.discrete])
    r = np.hypot(pts[:, 0], pts[:, 1])
    ang = np.degrees(np.arctan2(pts[:, 1], pts[:, 0])) % 360
    floor = ((ang > 3) & (ang < 20)) | ((ang > 70) & (ang < 87))
    assert floor.any() and np.abs(r[floor] - 17).max() < 0.02
    sinks = (np.abs(ang - 30) < 1) | (np.abs(ang - 60) < 1)
    assert sinks.any() and r[sinks].min() < 16
    blank = (ang > 125) & (ang < 325)    # the flat face's chords reach 31.8° beyond 0 and 90
    assert blank.any() and np.abs(r[blank] - 20).max() < 0.01
