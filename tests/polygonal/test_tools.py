"""Flywheel cutters in the tool library (#34): insert count, cutting radius, insert shape; the
bundled fixtures/tools/polygon.toml and the library's errors for a bad entry."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from vmach.errors import ModelError
from vmach.tooling import load_tools
from vmach.tooling.flywheel import FlywheelTool

ROOT = Path(__file__).resolve().parents[2]
LIB = ROOT / "fixtures" / "tools" / "polygon.toml"


def test_the_bundled_library_holds_two_and_three_insert_flywheels():
    lib = load_tools(LIB)
    two, three = lib.lookup("FLY2"), lib.lookup(22)
    assert isinstance(two, FlywheelTool) and three.name == "FLY3"
    assert (two.inserts, two.radius, two.shape, two.width, two.teeth) == (2, 25.0, "T", 10.0, 2)
    assert (three.inserts, three.diameter, three.body_diameter) == (3, 50.0, 34.0)
    # the fixture directory's copy is the same library
    copy = load_tools(ROOT / "fixtures" / "polygon_turning" / "tools.toml")
    assert [t.geometry_key() for t in copy.tools] == [t.geometry_key() for t in lib.tools]


def test_the_insert_section_ends_in_its_nose_arc_at_the_cutting_radius():
    t = FlywheelTool("FW", inserts=3, radius=25.0, shape="T", inscribed=8.0, nose_radius=0.4)
    sec = t.insert_section(0.0005)
    r = np.hypot(sec[:, 0], sec[:, 1])
    assert r.max() == pytest.approx(25.0, abs=1e-12)                   # the tip on the cutting circle
    near = sec[np.hypot(sec[:, 0] - 24.6, sec[:, 1]) < 0.4 + 1e-9]
    assert len(near) > 6                                                 # arc points on the nose circle
    # a 60° corner: the edges leave the nose at ±30° from the radial line, 8 mm back
    back = sec[np.argmax(sec[:, 1])]                                    # the upper edge's end, 8 mm back
    tangent = np.array([24.6 + 0.4 * math.cos(math.radians(60)), 0.4 * math.sin(math.radians(60))])
    edge = tangent - back
    assert np.linalg.norm(edge) == pytest.approx(8.0)
    assert math.degrees(math.atan2(-edge[1], edge[0])) == pytest.approx(30.0, abs=1e-9)
    # a round insert is a circle of its nose radius
    rnd = FlywheelTool("R", inserts=1, radius=20.0, shape="R", inscribed=6.0, nose_radius=2.0)
    rnd = rnd.insert_section(0.001)
    assert np.hypot(rnd[:, 0] - 18.0, rnd[:, 1]) == pytest.approx(2.0, abs=1e-12)
    assert math.isclose(rnd[:, 0].max(), 20.0, abs_tol=1e-12)


def test_bad_flywheel_entries_are_errors_at_their_lines(tmp_path):
    path = tmp_path / "tools.toml"
    path.write_text(
        '[[tool]]\nname = "A"\ntype = "flywheel"\ninserts = 0\nradius = 20.0\n'          # 1-5: inserts 0
        '[[tool]]\nname = "B"\ntype = "flywheel"\ninserts = 2\n'                          # 6-9: no radius
        '[[tool]]\nname = "C"\ntype = "flywheel"\ninserts = 2\nradius = 5.0\ninscribed = 6.0\n'   # 10-15
        '[[tool]]\nname = "D"\ntype = "flywheel"\ninserts = 2\nradius = 20.0\nshape = "Q"\n',     # 16-21
        encoding="utf-8")
    with pytest.raises(ModelError) as exc:
        load_tools(path)
    assert sorted((f.kind, f.line) for f in exc.value.findings()) == [
        ("tool_library", 4), ("tool_library", 6), ("tool_library", 15), ("tool_library", 21)]
