"""A five-axis job as Sinumerik CAM posts write it (#35; fixtures/cam5/CAM5AX.MPF, written by
make_cam.py): header resets, CYCLE832 per operation, a 3+2 slot under CYCLE800, a chamfer under
TRAORI with ORIWKS, ORIAXES then ORIVECT, A3= B3= C3= with ten decimals on every block, G642,
TRAFOOF; and HM5AX.MPF in hyperMILL's post style. They run and verify clean on the table-table
mills s5d (B/C) and mill5ac (A/C) and the hybrid h5d; every TRAORI block ends where it says (FK
to 1e-9), and the exported part has the slot's floor and the face in their swivelled planes and
the chamfer and bevel where the tool vector puts them."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation
from shapely.geometry import Point, Polygon

from interpreters import sinumerik
from vmach.canon import MOTIONS, OrientedMove, RunOptions
from vmach.cli import main
from vmach.machine import load_model
from vmach.machine.oriented import resolve

FIX = Path(__file__).resolve().parents[2] / "fixtures" / "cam5"
PROG = FIX / "CAM5AX.MPF"
MACHINES = ("s5d", "mill5ac", "h5d")


def test_the_program_is_what_the_generator_writes(tmp_path):
    subprocess.run([sys.executable, str(FIX / "make_cam.py"), str(tmp_path)], check=True)
    assert (tmp_path / "CAM5AX.MPF").read_text() == PROG.read_text()


@pytest.mark.parametrize("machine", MACHINES)
def test_every_traori_block_ends_at_its_tip_and_vector(machine):
    m = load_model(machine)
    r = sinumerik.run(PROG, m.control, RunOptions())
    assert r.completed, [f.render() for f in r.findings if f.severity == "error"]
    cmds, found = resolve(r.commands, m)
    assert [f.kind for f in found] == []
    blocks = [c for c in r.commands if isinstance(c, OrientedMove) and c.vector is not None
              and c.frame is None and not c.hold_axes and c.source.line > 40]
    assert len(blocks) > 60
    ends = {}
    for c in cmds:
        if isinstance(c, MOTIONS):
            ends[c.source.line] = c
    for b in blocks:
        q = np.array([[ends[b.source.line].axes[a] for a in m.axes]])
        pose = m.fk(q)
        tip = [b.axes[g] for g in "XYZ"]
        assert np.abs(pose.tip[0] - tip).max() < 1e-9, b.source.line
        v = np.asarray(b.vector) / np.linalg.norm(b.vector)
        assert np.abs(pose.axis[0] - v).max() < 1e-9, b.source.line


@pytest.mark.parametrize("machine", MACHINES)
@pytest.mark.parametrize("program, blocks", [("CAM5AX.MPF", 80), ("HM5AX.MPF", 18)])
def test_it_runs_end_to_end(tmp_path, machine, program, blocks, capsys):
    assert main(["run", str(FIX / program), "--machine", machine, "--format", "json"]) == 0
    lines = [json.loads(s) for s in capsys.readouterr().out.splitlines() if s.startswith("{")]
    assert sum(d.get("kind") == "oriented_move" for d in lines) > blocks


@pytest.mark.parametrize("machine", MACHINES)
def test_it_verifies_clean_and_cuts_what_the_program_says(tmp_path, machine):
    part = tmp_path / "part.stl"
    out = tmp_path / "o"
    assert main(["verify", str(PROG), "--machine", machine, "--tools", str(FIX / "tools.toml"),
                 "--stock", "box:x=40,y=40,z=25", "--export", str(part), "--out", str(out),
                 "--no-images", "--quiet"]) == 0
    report = json.loads((out / "report.json").read_text())
    assert [f["kind"] for f in report["findings"] if f["severity"] != "info"] == []
    mesh = trimesh.load(part)
    # operation 1: the slot (16 x 8 path, Ø6 tool: 22 x 14) 1.5 mm deep in the plane turned
    # 15° about X through (0, 0, -2)
    rx = Rotation.from_euler("x", 15, degrees=True).as_matrix()
    origin = np.array([0.0, 0.0, -2.0])

    def slot(depth):
        sec = mesh.section(plane_origin=origin + rx @ (0, 0, depth), plane_normal=rx @ (0, 0, 1))
        loops = [(lp - origin) @ rx for lp in (sec.discrete if sec is not None else [])]
        return [lp for lp in loops if np.abs(lp[:, :2]).max() < 12.5]

    (loop,) = slot(-1.0)
    lo, hi = loop[:, :2].min(axis=0), loop[:, :2].max(axis=0)
    assert lo == pytest.approx([-11, -7], abs=0.02) and hi == pytest.approx([11, 7], abs=0.02)
    assert slot(-1.6) == []                               # the floor at z' = -1.5
    # operation 2: the chamfer plane through the edge's middle line (±19, z -1) normal to the
    # tool vector (45°): at z = -0.5 the part's outline is ±18.5 along the sides
    sec = mesh.section(plane_origin=(0, 0, -0.5), plane_normal=(0, 0, 1))
    outer = max(sec.discrete, key=lambda lp: np.ptp(lp[:, 0]))
    mid_x = outer[np.abs(outer[:, 1]) < 10]
    mid_y = outer[np.abs(outer[:, 0]) < 10]
    assert np.abs(np.abs(mid_x[:, 0]) - 18.5).max() < 0.02
    assert np.abs(np.abs(mid_y[:, 1]) - 18.5).max() < 0.02


@pytest.mark.parametrize("machine", MACHINES)
def test_a_hypermill_style_job_verifies_clean_and_cuts_its_planes(tmp_path, machine):
    """fixtures/cam5/HM5AX.MPF (hyperMILL post style: Operate's integer CYCLE800 _ST and
    CYCLE832 codes, CYCLE800 retraction _FR 4, TRAORI(1), ORIAXES lead-in, SOFT FFWON COMPCAD
    G645): clean on the three machines; the 3+2 face lies on z' = 1 of the plane turned −20°
    about Y through (10, 0, −3), and the tilted pass bevels the front edge."""
    part = tmp_path / "part.stl"
    out = tmp_path / "o"
    assert main(["verify", str(FIX / "HM5AX.MPF"), "--machine", machine, "--export", str(part),
                 "--out", str(out), "--no-images", "--quiet"]) == 0
    report = json.loads((out / "report.json").read_text())
    assert [f["kind"] for f in report["findings"] if f["severity"] != "info"] == []
    mesh = trimesh.load(part)
    ry = Rotation.from_euler("y", -20, degrees=True).as_matrix()

    def material(origin, rot, points):
        """Which plane points (x', y') are in the part, on the plane through ``origin`` whose
        axes are ``rot``'s columns."""
        sec = mesh.section(plane_origin=origin, plane_normal=rot[:, 2])
        loops = [Polygon(((lp - origin) @ rot)[:, :2]) for lp in sec.discrete]
        # even-odd: a point inside an odd number of loops is in the material
        return np.array([sum(lp.contains(Point(p)) for lp in loops) % 2 == 1 for p in points])

    grid = np.array([(x, y) for x in np.linspace(-5, 5, 6) for y in np.linspace(-3, 3, 4)])
    for depth, want in ((1.05, False), (0.95, True)):
        origin = np.array((10.0, 0.0, -3.0)) + ry @ (0, 0, depth)
        world = origin + np.c_[grid, np.zeros(len(grid))] @ ry.T
        inside = (np.abs(world[:, :2]) < 19.9).all(axis=1) & (world[:, 2] < -0.1)
        assert inside.sum() >= 6
        assert (material(origin, ry, grid[inside]) == want).all(), depth
    # the tilted pass's bevel: removed at the edge's top, kept below the tool's bottom
    assert material((0, 0, -0.1), np.eye(3), [(0, -19.95)]).tolist() == [False]
    assert material((0, 0, -0.5), np.eye(3), [(0, -19.8)]).tolist() == [True]
