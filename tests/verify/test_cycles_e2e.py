"""Siemens milling and boring cycles through the whole pipeline (verify, stock, export) on the
three-axis mill: the exported part's pockets, spigots, slots and faces have the sizes, depths
and corner radii the cycles' parameters give, within the simulation's bound (the tool polygon's
0.01 mm on sides); the cycles fixture (fixtures/cycles/SHOP.MPF) verifies clean, and a
mistake in one of its cycles is reported at that cycle's line, naming the part of the cycle."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
import trimesh
from catalog import FIXTURES

from vmach.cli import main

#: a Ø10 end mill, 22 mm flutes, in a Ø32 holder
TOOLS = ('[[tool]]\nname = "EM10"\ntype = "flat"\ndiameter = 10.0\ncutting_length = 22.0\n'
         'shank = { diameter = 10.0, length = 28.0 }\nholder = { diameter = 32.0, length = 45.0 }\n'
         'd = { 1 = { radius = 5.0, length = 0.0 } }\n')
#: the tool polygon's bound on sides (mm), and on flat faces
SIDE, FLAT = 0.011, 1e-6


def cut(tmp_path, body: str, stock: str = "box:xmin=0,xmax=60,ymin=0,ymax=50,zmin=-12,zmax=0"):
    """Verify ``body`` with the Ø10 end mill; the exported part's mesh (the run must be clean)."""
    (tmp_path / "tools.toml").write_text(TOOLS)
    prog = tmp_path / "CYC.MPF"
    prog.write_text('T="EM10" D1\nG17 G90 G0 X0 Y0 Z30\nS3000 M3 F500\n' + body + "\nG0 Z50\nM30\n")
    part = tmp_path / "part.stl"
    code = main(["verify", str(prog), "--dialect", "sinumerik", "--machine", "mill3", "--tools",
                 str(tmp_path / "tools.toml"), "--stock", stock, "--export", str(part),
                 "--out", str(tmp_path / "o"), "--no-images", "--quiet"])
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert code == 0, [(f["kind"], f["line"], f["message"]) for f in report["findings"]]
    return trimesh.load(part)


def loops(mesh, z: float) -> list[np.ndarray]:
    """The (n, 2) outlines of the part's section at height z."""
    section = mesh.section(plane_origin=[0, 0, z], plane_normal=[0, 0, 1])
    return [] if section is None else [loop[:, :2] for loop in section.discrete]


def inner(mesh, z: float, near) -> np.ndarray:
    """The section's outline around the point ``near`` that is not the block's outside."""
    cands = [lp for lp in loops(mesh, z) if lp[:, 0].min() < near[0] < lp[:, 0].max()
             and lp[:, 1].min() < near[1] < lp[:, 1].max()]
    return min(cands, key=lambda lp: np.ptp(lp[:, 0]))


def assert_box(loop: np.ndarray, lo, hi) -> None:
    """The outline spans lo … hi (x, y) within the bound on sides."""
    assert loop.min(0) == pytest.approx(lo, abs=SIDE) and loop.max(0) == pytest.approx(hi, abs=SIDE)


def test_pocket3_rectangular_pocket_size_depth_and_corner_radius(tmp_path):
    """POCKET3 40 × 24 R6 at (30, 25), 6 deep: roughed with helical insertion (FAL 0.5,
    FALD 0.2), then finished (VARI 2)."""
    mesh = cut(tmp_path,
               "POCKET3(10, 0, 2, -6, 40, 24, 6, 30, 25, 0, 3, 0.5, 0.2, 600, 200, 0, 11, 8, , , , 3, 2)\n"
               "POCKET3(10, 0, 2, -6, 40, 24, 6, 30, 25, 0, 3, 0, 0, 600, 200, 0, 2, 8)")
    for z in (-0.5, -5.9):
        p = inner(mesh, z, (30, 25))
        assert_box(p, [10, 13], [50, 37])
        corner = p[(p[:, 0] < 16) & (p[:, 1] < 19)]                 # the corner about (16, 19)
        assert corner.size and np.abs(np.hypot(corner[:, 0] - 16, corner[:, 1] - 19) - 6).max() < SIDE
    assert not any(np.ptp(lp[:, 0]) < 59 for lp in loops(mesh, -6.05))  # the floor at −6
    pocket = (40 * 24 - (4 - np.pi) * 6**2) * 6
    assert mesh.is_watertight and mesh.volume == pytest.approx(60 * 50 * 12 - pocket, rel=2e-4)


def test_pocket4_circular_pocket(tmp_path):
    mesh = cut(tmp_path, "POCKET4(10, 0, 2, -5, 18, 30, 25, 2.5, 0, 0, 600, 200, 0, 11, 7, 0, 0, 4, 2)")
    p = inner(mesh, -4.9, (30, 25))
    assert np.abs(np.hypot(p[:, 0] - 30, p[:, 1] - 25) - 18).max() < SIDE
    assert not any(np.ptp(lp[:, 0]) < 59 for lp in loops(mesh, -5.05))


def test_cycle76_rectangular_spigot(tmp_path):
    """A 24 × 16 R4 spigot 5 high at (30, 25) from a 40 × 30 blank (the block is larger: a
    groove about the spigot)."""
    mesh = cut(tmp_path, "CYCLE76(10, 0, 2, -5, , 24, 16, 4, 30, 25, 0, 2.5, 0, 0, 600, 200, 0, 1, 40, 30)")
    spigot = inner(mesh, -2.5, (30, 25))
    assert_box(spigot, [18, 17], [42, 33])
    corner = spigot[(spigot[:, 0] > 38) & (spigot[:, 1] > 29)]
    assert corner.size and np.abs(np.hypot(corner[:, 0] - 38, corner[:, 1] - 29) - 4).max() < SIDE
    assert max(np.ptp(lp[:, 0]) for lp in loops(mesh, -5.05)) == pytest.approx(60)   # the foot at −5


def test_cycle77_circular_spigot_with_dpr(tmp_path):
    mesh = cut(tmp_path, "CYCLE77(10, 0, 2, , 4, 20, 30, 25, 2, 0, 0, 600, 200, 0, 1, 32)")
    spigot = min(loops(mesh, -3.9), key=lambda lp: np.ptp(lp[:, 0]))
    assert np.abs(np.hypot(spigot[:, 0] - 30, spigot[:, 1] - 25) - 10).max() < SIDE
    assert len(loops(mesh, -4.05)) == 1


def test_slot1_slot2_and_longhole(tmp_path):
    """SLOT1: two 20 × 12 slots at 0° and 180° on R15 about (30, 35); SLOT2: one slot 12 wide
    on R15 about (30, 35) from 200° over 60° (between its ends' centres); LONGHOLE: one hole
    18 long at 270° on R25 about it; all 3 deep."""
    mesh = cut(tmp_path,
               "SLOT1(10, 0, 2, -3, , 2, 20, 12, 30, 35, 15, 0, 180, 100, 400, 3, 2, 0.3, 0, 0, 300)\n"
               "LONGHOLE(10, 0, 2, -3, , 1, 18, 30, 35, 25, 270, 0, 100, 400, 1.5)")
    right = inner(mesh, -2.9, (45, 35))
    assert_box(right, [35, 29], [55, 41])
    hole = inner(mesh, -2.9, (30, 10))
    assert_box(hole, [25, 1], [35, 19])
    assert not any(np.ptp(lp[:, 0]) < 59 for lp in loops(mesh, -3.05))
    mesh = cut(tmp_path,
               "SLOT2(10, 0, 2, -3, , 1, 60, 12, 30, 35, 15, 200, 0, 100, 400, 3, 3, 0.3, 0, 0, 300)")
    p = inner(mesh, -2.9, (30 + 15 * np.cos(np.radians(230)), 35 + 15 * np.sin(np.radians(230))))
    r = np.hypot(p[:, 0] - 30, p[:, 1] - 35)
    assert r.min() == pytest.approx(9, abs=SIDE) and r.max() == pytest.approx(21, abs=SIDE)


def test_cycle71_faces_the_area_to_the_depth(tmp_path):
    """The 60 × 50 block's top at Z1 faced to Z0 (VARI 31: roughing to and fro along X,
    FALD 0, the passes 2 mm beyond the sides): the part is 12 high, its top flat."""
    mesh = cut(tmp_path, "CYCLE71(10, 1, 2, 0, 0, 0, 60, 50, 0, 1, 8, 2, 0, 800, 31, 2)",
               stock="box:xmin=0,xmax=60,ymin=0,ymax=50,zmin=-12,zmax=1")
    assert mesh.bounds[1][2] == pytest.approx(0, abs=FLAT)
    assert mesh.volume == pytest.approx(60 * 50 * 12, rel=1e-6)


@pytest.fixture(scope="module")
def shop(tmp_path_factory):
    job = tmp_path_factory.mktemp("cycles") / "cycles"
    shutil.copytree(FIXTURES / "cycles", job)
    return job


def _verify(job, name="SHOP.MPF"):
    out = job / ("o_" + name)
    code = main(["verify", str(job / name), "--out", str(out), "--no-images", "--quiet",
                 "--export", str(out / "part.stl")])
    return code, json.loads((out / "report.json").read_text()), out / "part.stl"


@pytest.mark.slow
def test_the_cycles_fixture_verifies_clean_and_cuts_its_drawing(shop):
    code, report, part = _verify(shop)
    assert code == 0 and [f for f in report["findings"] if f["severity"] != "info"] == []
    mesh = trimesh.load(part)
    assert mesh.bounds[1][2] == pytest.approx(0, abs=FLAT)                  # CYCLE71: faced to Z0
    pocket = inner(mesh, -7.9, (30, 40))                                    # POCKET3 40 × 30 R8
    assert_box(pocket, [10, 25], [50, 55])
    round_ = inner(mesh, -5.9, (75, 58))                                    # POCKET4 R14
    assert np.abs(np.hypot(round_[:, 0] - 75, round_[:, 1] - 58) - 14).max() < SIDE
    spigot = inner(mesh, -4.9, (78, 14))                                    # CYCLE77 Ø20
    assert np.abs(np.hypot(spigot[:, 0] - 78, spigot[:, 1] - 14) - 10).max() < SIDE
    slot = inner(mesh, -3.9, (42, 12))                                      # SLOT1 16 × 10
    assert_box(slot, [34, 7], [50, 17])
    for centre, radius, z in (((8, 66), 4, -11.9), ((55, 66), 4, -11.9), ((30, 68), 5, -9.9)):
        hole = inner(mesh, z, centre)                                       # CYCLE84 M8, CYCLE85 Ø10
        assert np.abs(np.hypot(hole[:, 0] - centre[0], hole[:, 1] - centre[1]) - radius).max() < SIDE


@pytest.mark.parametrize("line, old, new, kind, phase", [
    # the slots' depth typed −20 for −4: below its 16 mm flutes the Ø8 cutter's Ø12 shank
    # runs into the 10 mm slot, at the SLOT1 line
    (21, "SLOT1(10, 0, 2, -4,", "SLOT1(10, 0, 2, -20,", "holder_collision", "slot 1/2 roughing depth 5/5"),
    # the circular pocket's reference plane −4 for 0: the approach rapids into the block
    (17, "POCKET4(10, 0, 2, -6,", "POCKET4(10, -4, 2, -6,", "rapid_into_stock", "approach"),
])
@pytest.mark.slow
def test_a_mistake_in_a_cycle_is_caught_at_its_line(shop, line, old, new, kind, phase):
    text = (shop / "SHOP.MPF").read_text()
    assert text.count(old) == 1
    (shop / "BAD.MPF").write_text(text.replace(old, new))
    code, report, _ = _verify(shop, "BAD.MPF")
    errors = [f for f in report["findings"] if f["severity"] == "error"]
    assert code == 1 and errors
    assert {(f["kind"], f["line"]) for f in errors} == {(kind, line)}
    assert any(f["phase"].startswith(phase) for f in errors)


def test_cycle79_hexagon_across_flats_and_corners(tmp_path):
    """A hexagon 24 across flats, R2 corners, 4 high at (30, 25) from a Ø40 blank: the flats
    12 from the centre along X, the corners (12 − 2)/cos 30° + 2 from it along Y."""
    mesh = cut(tmp_path, "CYCLE79(10, 0, 2, -4, 30, 25, 40, 0, 6, 24, 2, 2, 0, 0, 600, 200, 0, 1)")
    hexagon = inner(mesh, -2, (30, 25))
    corner = (12 - 2) / np.cos(np.pi / 6) + 2
    assert_box(hexagon, [18, 25 - corner], [42, 25 + corner])
    assert mesh.bounds[0][2] == pytest.approx(-12) and len(loops(mesh, -4.05)) == 1


@pytest.mark.slow
def test_the_operate_cycles_fixture_verifies_clean_and_a_wrong_depth_is_caught(shop):
    """fixtures/cycles/SHOP2.MPF: CYCLE79, CYCLE802 with MCALL CYCLE81, CYCLE60, CYCLE977 and
    CYCLE978 (a probe measuring the hexagon and the block's side) verify clean;
    the hexagon's flats are 20 from its centre; its depth typed −25 for −6 runs the Ø12 end
    mill's shank (above its 20 mm flutes) into the block at the CYCLE79 line."""
    code, report, part = _verify(shop, "SHOP2.MPF")
    assert code == 0 and [f for f in report["findings"] if f["severity"] != "info"] == []
    mesh = trimesh.load(part)
    hexagon = inner(mesh, -3, (30, 40))
    assert [hexagon[:, 0].min(), hexagon[:, 0].max()] == pytest.approx([10, 50], abs=SIDE)
    for x, y in ((75, 12), (88, 25), (75, 38)):                             # CYCLE802's holes
        hole = inner(mesh, -7, (x, y))                                      # above the point
        assert np.abs(np.hypot(hole[:, 0] - x, hole[:, 1] - y) - 3.4).max() < SIDE
    assert mesh.bounds[1][2] == pytest.approx(1, abs=FLAT)
    assert len(loops(mesh, 0.8)) > len(loops(mesh, 0.6))                     # the text, 0.3 deep
    text = (shop / "SHOP2.MPF").read_text()
    line = text[:text.index("N50 CYCLE79")].count("\n") + 1
    (shop / "BAD2.MPF").write_text(text.replace("CYCLE79(10, 1, 2, -6,", "CYCLE79(10, 1, 2, -25,"))
    code, report, _ = _verify(shop, "BAD2.MPF")
    errors = [f for f in report["findings"] if f["severity"] == "error"]
    assert code == 1 and {(f["kind"], f["line"]) for f in errors} == {("holder_collision", line)}
    # the hexagon measured as a web 30 wide: the probe goes down onto its flat, at CYCLE977
    line = text[:text.index("N180 CYCLE977")].count("\n") + 1
    (shop / "BAD3.MPF").write_text(text.replace("CYCLE977(104, , , 1, 40,", "CYCLE977(104, , , 1, 30,"))
    code, report, _ = _verify(shop, "BAD3.MPF")
    errors = [f for f in report["findings"] if f["severity"] == "error"]
    assert code == 1 and {(f["kind"], f["line"]) for f in errors} == {("probe_collision", line)}


def test_cycle72_mills_round_an_island_to_its_contour(tmp_path):
    """A 30 × 20 island, its contour a section of the program run clockwise with G41 (the tool
    outside), finished 4 deep in two levels: the island measures 30 × 20 below the top."""
    mesh = cut(tmp_path, 'CYCLE72("ISL:ISL_E", 10, 0, 2, -4, 2, 0, 0, 500, 100, 112, 41, 1, 8, 800, 1, 8)\n'
               "G0 Z50\nM30\nISL: G1 X15 Y15\nY35\nX45\nY15\nISL_E: X15")
    island = inner(mesh, -2, (30, 25))
    assert_box(island, [15, 15], [45, 35])
    assert len(loops(mesh, -4.05)) == 1 and mesh.bounds[1][2] == pytest.approx(0, abs=FLAT)
