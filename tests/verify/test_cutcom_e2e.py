"""Tool radius compensation through the whole pipeline: a Sinumerik program mills a 40 × 40 mm
boss with G41 and an Ø10 end mill on the table-table mill (B = C = 0); the exported part's
section has its walls where the drawing puts them — without G41 they lie 5 mm inside."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

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
