"""A touch probe in verify (vmach/checks/probing.py): its stylus ball swept exactly against the
stock as cut so far; a measuring move stops at contact, no contact on the measuring path is
probe_no_contact, any other move that touches the part probe_collision — at the line of the
cycle that made the move; a probe removes no material."""

from __future__ import annotations

import json

import numpy as np
import pytest

from vmach.checks.probing import sweep_contact
from vmach.cli import main

#: a unit square's two triangles in the plane z = 0
SQUARE = np.array([[[0, 0, 0], [1, 0, 0], [1, 1, 0]], [[0, 0, 0], [1, 1, 0], [0, 1, 0]]], float)
TOOLS = ('[[tool]]\nname = "PROBE"\ntype = "probe"\ndiameter = 6.0\ncutting_length = 30.0\n'
         'shank = { diameter = 6.0, length = 20.0 }\nholder = { diameter = 40.0, length = 60.0 }\n'
         '[[tool]]\nname = "EM10"\ntype = "flat"\ndiameter = 10.0\ncutting_length = 22.0\n'
         'shank = { diameter = 10.0, length = 28.0 }\nholder = { diameter = 32.0, length = 45.0 }\n')


@pytest.mark.parametrize("c0, d, t", [
    ((0.5, 0.5, 3), (0, 0, -4), 0.5),           # onto the face: the ball's bottom at z 0 after 2
    ((3, 0.5, 0), (-2, 0, 0), 0.5),             # sideways onto the edge x = 1 (ball radius 1)
    ((2, 2, 0), (-1, -1, 0), 1 - 1 / np.sqrt(2)),  # onto the corner (1, 1, 0)
    ((0.5, 0.5, 0.5), (0, 0, 1), 0.0),          # already overlapping
    ((0.5, 0.5, 3), (0, 0, 1), None),           # moving away
    ((3, 3, 0), (0, 1, 0), None),               # passing by
])
def test_sweep_contact_faces_edges_corners(c0, d, t):
    got = sweep_contact(np.array(c0, float), np.array(d, float), 1.0, SQUARE)
    assert (got is None) if t is None else got == pytest.approx(t)


def _verify(tmp_path, body: str):
    (tmp_path / "tools.toml").write_text(TOOLS)
    prog = tmp_path / "PR.MPF"
    prog.write_text(body + "\nG0 Z50\nM30\n")
    out = tmp_path / "o"
    code = main(["verify", str(prog), "--dialect", "sinumerik", "--machine", "mill3", "--tools",
                 str(tmp_path / "tools.toml"), "--stock", "box:xmin=0,xmax=60,ymin=0,ymax=50,zmin=-12,zmax=0",
                 "--out", str(out), "--no-images", "--quiet", "--export", str(out / "part.stl")])
    report = json.loads((out / "report.json").read_text())
    return code, [(f["kind"], f["line"]) for f in report["findings"] if f["severity"] != "info"], out


EDGE = 'T="PROBE" D1\nG17 G90 G0 X-20 Y25 Z30\nG0 Z-5\nCYCLE978(0, , , 1, {}, 2, 1, 1, 1, 1)'
POCKET = ('T="EM10" D1\nS3000 M3 F500\nG17 G90 G0 X30 Y25 Z30\n'
          'POCKET4(10, 0, 2, -8, 15, 30, 25, 4, 0, 0, 600, 200, 0, 11, 7, , , 4, 2)\n'
          'T="PROBE" D1\nM5\nG0 X30 Y25 Z30\nG0 Z-5\nCYCLE977(101, , , 1, {}, , , 2, 1, 0)')


def test_an_edge_and_a_milled_hole_measured_clean(tmp_path):
    code, found, out = _verify(tmp_path, EDGE.format(0) + "\nG0 Z30\n" + POCKET.format(30))
    assert code == 0 and found == []
    volume = 60 * 50 * 12 - np.pi * 15**2 * 8
    import trimesh
    assert trimesh.load(out / "part.stl").volume == pytest.approx(volume, rel=1e-3)   # no probe cut


@pytest.mark.parametrize("body, kind, line", [
    (EDGE.format(-10), "probe_no_contact", 4),        # the edge expected 10 mm before it is
    (EDGE.format(10), "probe_collision", 4),          # positioning runs into the block's side
    (POCKET.format(20), "probe_no_contact", 9),       # the hole expected Ø20, it is Ø30
    (POCKET.format(40), "probe_collision", 9),        # Ø40 expected: positioning into the wall
    (EDGE.format(0).replace("G0 Z-5", "G0 X10 Z-5"), "probe_collision", 3),   # a rapid into it
])
def test_a_probe_meeting_nothing_or_hitting_the_part_is_caught_at_its_line(tmp_path, body, kind, line):
    code, found, _ = _verify(tmp_path, body)
    assert code == 1 and (kind, line) in found
    assert {k for k, _ in found} <= {"probe_no_contact", "probe_collision"}


def test_linuxcnc_g38_stops_at_contact_with_the_stock(tmp_path):
    """G38.2 toward the block's side from X −20 to X 5 stops at X −3 (a Ø6 ball): the rapid
    back starts there, clean; G38.2 that meets nothing is probe_no_contact at its line,
    G38.3 (no error without contact) is not."""
    (tmp_path / "tools.toml").write_text(TOOLS.replace('name = "PROBE"', 'name = "PROBE"\nnumber = 1'))
    prog = tmp_path / "p.ngc"
    prog.write_text("G21 G17 G90\nT1 M6 G43\nG0 X-20 Y25 Z30\nG0 Z-5\nG38.2 X5 F300\nG0 X-20\n"
                    "G38.3 X-15 F300\nG38.2 X-16 F300\nG0 Z30\nM2\n")
    out = tmp_path / "o"
    code = main(["verify", str(prog), "--machine", "mill3", "--tools", str(tmp_path / "tools.toml"),
                 "--stock", "box:xmin=0,xmax=60,ymin=0,ymax=50,zmin=-12,zmax=0", "--out", str(out),
                 "--no-images", "--quiet"])
    report = json.loads((out / "report.json").read_text())
    assert code == 1
    assert [(f["kind"], f["line"]) for f in report["findings"] if f["severity"] != "info"] == [
        ("probe_no_contact", 8)]
