"""Turning tools (#34): ISO inserts by their designation's sizes, the cutting edge position,
grooving, threading and boring tools, the bundled library and its errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from vmach.errors import ModelError
from vmach.tooling import load_tools
from vmach.tooling.turning import EDGE_POSITIONS, TurningTool

ROOT = Path(__file__).resolve().parents[2]
LIB = ROOT / "fixtures" / "tools" / "turning.toml"


@pytest.fixture(scope="module")
def lib():
    return load_tools(LIB)


def test_the_bundled_library_holds_cnmg120408_grooving_threading_and_a_boring_bar(lib):
    cnmg = lib.lookup("CNMG120408")
    assert (cnmg.kind, cnmg.shape, cnmg.inscribed, cnmg.nose_radius, cnmg.edge_position) == \
        ("turning", "C", 12.7, 0.8, 3)
    assert {t.kind for t in lib.tools} == {"turning", "grooving", "threading", "boring"}
    assert lib.lookup(5).kind == "boring" and lib.lookup(5).bar_diameter == 16.0
    # tool nose radius compensation reads the nose radius as the tool's radius
    assert lib.radius("CNMG120408", 1) == 0.8
    assert lib.data("CNMG120408", 1)["type"] == "turning"


def test_cnmg_section_has_p_at_the_corner_of_its_nose_circle_and_an_80_degree_rhombus(lib):
    t = lib.lookup("CNMG120408")
    sec = t.section(0.0005)
    # SL 3: P is the nose circle's lowest X and lowest Z: the section's bounding corner
    assert sec.min(axis=0) == pytest.approx([0.0, 0.0], abs=1e-12)
    s = t.nose_centre()
    assert s == pytest.approx([0.8, 0.8])
    near = sec[np.linalg.norm(sec - s, axis=1) < 0.8 + 1e-9]
    assert len(near) > 8                                   # the arc's points lie on the circle
    assert np.linalg.norm(near - s, axis=1) == pytest.approx(0.8, abs=1e-12)
    # the inscribed circle 12.7 of an 80° rhombus: sides 12.7 / sin 80°; area side² sin 80°
    side = 12.7 / math.sin(math.radians(80))
    x, z = sec[:, 0], sec[:, 1]
    area = 0.5 * abs(np.sum(x * np.roll(z, -1) - np.roll(x, -1) * z))
    corner_loss = (0.8 ** 2) * (1 / math.tan(math.radians(40)) - math.radians(100) / 2) * 2 / 2
    assert area == pytest.approx(side ** 2 * math.sin(math.radians(80)) - corner_loss, rel=1e-4)


@pytest.mark.parametrize("sl", range(1, 10))
def test_each_edge_position_puts_p_where_the_table_says(sl):
    t = TurningTool("X", "turning", shape="V", inscribed=9.525, nose_radius=0.4, edge_position=sl)
    sec = t.section(0.0005)
    dx, dz = EDGE_POSITIONS[sl]
    s = t.nose_centre()
    assert s == pytest.approx([-0.4 * dx, -0.4 * dz])
    # the nose circle touches P's sides: no point of the insert lies beyond P in its directions
    if dx:
        assert (dx * sec[:, 0]).max() == pytest.approx(0.0, abs=1e-9)
    if dz:
        assert (dz * sec[:, 1]).max() == pytest.approx(0.0, abs=1e-9)


def test_grooving_insert_is_its_width_with_rounded_cutting_corners(lib):
    g = lib.lookup("GROOVE3")
    sec = g.section(0.0005)
    assert np.ptp(sec[:, 1]) == pytest.approx(3.0)
    assert sec.min(axis=0) == pytest.approx([0.0, 0.0], abs=1e-12)
    assert g.radius == 0.2


def test_threading_insert_is_a_60_degree_v_pointing_at_the_centre(lib):
    t = lib.lookup("THREAD60")
    sec = t.section(0.0005)
    assert sec[:, 0].min() == pytest.approx(0.0, abs=1e-12)        # SL 8: P at the nose's -X
    tip = sec[sec[:, 0] > 3.0]
    half = np.degrees(np.arctan2(np.abs(tip[:, 1]).max(), tip[:, 0].max()))
    assert 2 * half == pytest.approx(60.0, abs=2.0)


def test_bad_turning_entries_are_reported_at_their_lines(tmp_path):
    path = tmp_path / "lib.toml"
    path.write_text(
        "[[tool]]\n"                      # 1
        'name = "A"\n'                    # 2
        'type = "turning"\n'              # 3
        'shape = "Q"\n'                   # 4
        "[[tool]]\n"                      # 5
        'name = "B"\n'                    # 6
        'type = "turning"\n'              # 7
        "edge_position = 12\n"            # 8
        "[[tool]]\n"                      # 9
        'name = "C"\n'                    # 10
        'type = "grooving"\n'             # 11
        "width = 3\n"                     # 12
        "corner_radius = 2\n"             # 13
        "[[tool]]\n"                      # 14
        'name = "D"\n'                    # 15
        'type = "turning"\n'              # 16
        "colour = 1\n",                   # 17
        encoding="utf-8")
    with pytest.raises(ModelError) as exc:
        load_tools(path)
    assert sorted((f.kind, f.line) for f in exc.value.findings()) == [
        ("tool_library", 4), ("tool_library", 8), ("tool_library", 13), ("tool_library", 17)]
