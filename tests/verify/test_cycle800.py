"""CYCLE800 (swivel plane, #35): the frame and the rotary positioning the control makes, then a
pocket milled in the swivelled plane lands where the plane says — checked on the exported part
on the table-table mills s5d (B/C) and mill5ac (A/C)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh
from nc import error_of, run
from scipy.spatial.transform import Rotation

from vmach.canon import MOTIONS, OrientedMove, SetFrame, Transformation
from vmach.cli import main
from vmach.machine import load_model
from vmach.machine.oriented import resolve

#: the five-axis fixtures' Ø6 flat end mill "EM6"
TOOLS = Path(__file__).resolve().parents[2] / "fixtures" / "five_axis" / "tools.toml"

# a 10 x 10 pocket 3 mm deep below the plane turned 20° about X through (0, 4, 0)
POCKET = """G17 G90 G0 X0 Y0 Z60 {rot0} C0
T="EM6" D1
S6000 M3
CYCLE800(1,"TC1",0,57,0,4,0,20,0,0,0,0,0,{dir},100,1)
G0 X0 Y0 Z5
G1 Z-3 F300
X-2 Y-2
X2
Y2
X-2
Y-2
G0 Z10
CYCLE800()
M5
M30
"""


#: the swivelled plane of the pocket programs: turned 20° about X through (0, 4, 0)
RX20 = Rotation.from_euler("x", 20, degrees=True).as_matrix()
ORIGIN = np.array([0.0, 4.0, 0.0])


def exported(tmp_path, name: str, body: str, machine: str):
    """The part ``vmach verify`` exports for the program ``body`` (clean: exit 0)."""
    prog = tmp_path / name
    prog.write_text(body)
    part = tmp_path / "part.stl"
    assert main(["verify", str(prog), "--machine", machine, "--tools", str(TOOLS),
                 "--stock", "box:x=40,y=40,z=30", "--export", str(part), "--out", str(tmp_path / "o"),
                 "--no-images", "--quiet"]) == 0
    return trimesh.load(part)


def plane_loops(mesh, depth: float, reach: float) -> list:
    """The part's section loops in the swivelled plane z' = depth, in the plane's coordinates,
    those within ``reach`` of its origin."""
    sec = mesh.section(plane_origin=ORIGIN + RX20 @ (0, 0, depth), plane_normal=RX20 @ (0, 0, 1))
    found = [(lp - ORIGIN) @ RX20 for lp in (sec.discrete if sec is not None else [])]
    return [lp for lp in found if np.abs(lp[:, :2]).max() < reach]


def swivelled(machine: str, body: str, tmp_path):
    m = load_model(machine)
    r = run(tmp_path, body, m.control)
    assert r.completed, [f.render() for f in r.findings]
    cmds, found = resolve(r.commands, m)
    return m, r, cmds, found


@pytest.mark.parametrize("machine, rot0", [("s5d", "B0"), ("mill5ac", "A0")])
def test_the_tool_stands_normal_to_the_swivelled_plane(tmp_path, machine, rot0):
    m, r, cmds, found = swivelled(machine, POCKET.format(rot0=rot0, dir=-1), tmp_path)
    assert found == []
    marks = [(c.name, c.source.line) for c in r.commands if isinstance(c, Transformation)]
    assert marks == [("CYCLE800", 4), ("TRAFOOF", 13)]
    frame = [c for c in r.commands if isinstance(c, SetFrame) and c.source.line == 4][-1]
    rx = Rotation.from_euler("x", 20, degrees=True).as_matrix()
    assert np.allclose(np.reshape(frame.rotation, (3, 3)), rx, atol=1e-12)
    assert frame.origin["Y"] == pytest.approx(4.0)
    normal = rx @ (0, 0, 1)
    for line in range(5, 13):               # every move in the plane: tool along its normal
        q = np.array([[c.axes[a] for a in m.axes] for c in cmds
                      if isinstance(c, MOTIONS) and c.source.line == line])
        pose = m.fk(q)
        assert np.abs(pose.axis - normal).max() < 1e-9
    # the plane's point (2, 2, -3) is where the tip goes on line 9
    q = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 9][-1]
    tip = m.fk(np.array([[q.axes[a] for a in m.axes]])).tip[0]
    assert np.abs(tip - ((0, 4, 0) + rx @ (2, 2, -3))).max() < 1e-9
    # the retraction before swivelling: Z to its travel's end, the others still
    retract = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 4][0]
    assert retract.axes["Z"] == m.limits[m.axes.index("Z")][1]


def test_direction_and_direct_mode(tmp_path):
    """_DIR −1/+1 chooses the lower/higher value of rotary axis 1 (A on mill5ac: −20 or +20 —
    both tilt the tool onto the plane's normal); mode 192 positions the rotary axes directly."""
    m = load_model("mill5ac")
    a = {}
    for d in (-1, 1):
        _, _, cmds, _ = swivelled("mill5ac", POCKET.format(rot0="A0", dir=d), tmp_path)
        a[d] = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 4][-1].axes
    assert a[-1]["A"] == pytest.approx(-20) and a[1]["A"] == pytest.approx(20)
    assert a[-1]["C"] % 360 == pytest.approx(0) and a[1]["C"] % 360 == pytest.approx(180)
    body = 'G0 X0 Y0 Z60 A0 C0\nCYCLE800(0,"TC1",0,192,0,0,0,30,45,0,0,0,0,1,100,1)\nG0 X0 Y0 Z20\nM30\n'
    _, r, cmds, _ = swivelled("mill5ac", body, tmp_path)
    end = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 2][-1].axes
    assert (end["A"], end["C"]) == (pytest.approx(30), pytest.approx(45))
    q = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 3][-1]
    pose = m.fk(np.array([[q.axes[x] for x in m.axes]]))
    frame = [c for c in r.commands if isinstance(c, SetFrame)][-1]
    rot = np.reshape(frame.rotation, (3, 3))
    assert np.abs(pose.axis[0] - rot[:, 2]).max() < 1e-9          # the tool along the frame's Z
    assert np.abs(pose.tip[0] - rot @ (0, 0, 20)).max() < 1e-9
    assert any(isinstance(c, OrientedMove) and c.hold_axes for c in r.commands)


def test_solid_and_projection_angles(tmp_path):
    s5d = load_model("s5d").control
    for mode, args, expect in (
            (64, "30,40,0", Rotation.from_euler("ZY", [30, 40], degrees=True).as_matrix()),
            (128 + 57, "0,30,0", Rotation.from_euler("Y", 30, degrees=True).as_matrix())):
        body = f'G0 X0 Y0 Z50 B0 C0\nCYCLE800(0,"",0,{mode},0,0,0,{args},0,0,0,0,100,1)\nM30\n'
        r = run(tmp_path, body, s5d)
        frame = [c for c in r.commands if isinstance(c, SetFrame)][-1]
        assert np.allclose(np.reshape(frame.rotation, (3, 3)), expect, atol=1e-12), mode


def test_errors(tmp_path):
    r = run(tmp_path, 'G0 X0 Y0 Z10 B0 C0\nCYCLE800(5,"",0,57,0,0,0,10,0,0,0,0,0,1,25,1)\nM30\n',
            load_model("s5d").control)                           # table-table: +Z by _FR_I
    assert [c.axes["Z"] for c in r.commands if isinstance(c, MOTIONS)] == [10, 35]
    f = error_of(run(tmp_path, 'CYCLE800(1,"",0,57,0,0,0,10,0,0,0,0,0,1,100,1)\nM30\n',
                     load_model("turnmill").control))
    assert (f.kind, f.line) == ("unsupported", 1)


@pytest.mark.parametrize("machine, rot0", [("s5d", "B0"), ("mill5ac", "A0")])
def test_a_pocket_in_the_swivelled_plane_lands_where_the_plane_says(tmp_path, machine, rot0):
    mesh = exported(tmp_path, "POCKET.MPF", POCKET.format(rot0=rot0, dir=-1), machine)

    def walls(depth):
        """The pocket's loops in the plane z' = depth, in the plane's coordinates."""
        return plane_loops(mesh, depth, 8)

    (loop,) = walls(-2.0)                               # 10 x 10 walls, at z' = −2 exactly
    assert np.abs(loop[:, 2] + 2.0).max() < 1e-6
    lo, hi = loop[:, :2].min(axis=0), loop[:, :2].max(axis=0)
    assert lo == pytest.approx([-5.0, -5.0], abs=0.02) and hi == pytest.approx([5.0, 5.0], abs=0.02)
    assert walls(-3.2) == []                            # the floor at z' = −3


# POCKET3 in the same swivelled plane: 12 x 10, corner radius 3.5, floor 3 mm below the plane's
# reference plane _RFP 0, vertical insertion, 1.5 mm per cut; then a G2 half circle in the plane
POCKET3_SWIVELLED = """G17 G90 G0 X0 Y0 Z60 {rot0} C0
T="EM6" D1
S6000 M3
CYCLE800(1,"TC1",0,57,0,4,0,20,0,0,0,0,0,-1,100,1)
POCKET3(10, 0, 2, -3, 12, 10, 3.5, 0, 0, 0, 1.5, 0, 0, 300, 150, 0, 1, 3)
G0 X5 Y-11 Z8
G1 Z-1 F300
G2 X-5 Y-11 I-5 J0
G1 X-4
G0 Z10
CYCLE800()
M5
M30
"""


@pytest.mark.parametrize("machine, rot0", [("s5d", "B0"), ("mill5ac", "A0")])
def test_pocket3_and_a_circle_in_the_swivelled_plane(tmp_path, machine, rot0):
    """The milling cycle runs in the swivelled frame (its moves are the tip in the plane) and a
    G2 lies in the plane: both land where the plane says on the exported part."""
    mesh = exported(tmp_path, "SWIVEL3.MPF", POCKET3_SWIVELLED.format(rot0=rot0), machine)

    def loops(depth):
        return plane_loops(mesh, depth, 19.5)

    pocket = [lp for lp in loops(-2.0) if lp[:, 0].max() < 7]
    (loop,) = pocket
    lo, hi = loop[:, :2].min(axis=0), loop[:, :2].max(axis=0)
    assert lo == pytest.approx([-6, -5], abs=0.02) and hi == pytest.approx([6, 5], abs=0.02)
    corner = loop[(loop[:, 0] > 4) & (loop[:, 1] > 3)]    # the 3.5 corner radius about (2.5, 1.5)
    assert np.abs(np.hypot(corner[:, 0] - 2.5, corner[:, 1] - 1.5) - 3.5).max() < 0.02
    assert [lp for lp in loops(-3.2) if lp[:, 0].max() < 7] == []        # the floor at z' = −3
    # the half circle of radius 5 about (0, −11), tool Ø6: a groove from r 2 to r 8 below y' −11
    (groove,) = [lp for lp in loops(-0.5) if lp[:, 1].max() < -6]
    r = np.hypot(groove[:, 0], groove[:, 1] + 11)
    assert r.max() == pytest.approx(8, abs=0.02) and groove[:, 1].min() == pytest.approx(-19, abs=0.02)
    inner = (np.abs(groove[:, 0]) < 1) & (groove[:, 1] < -12) & (groove[:, 1] > -14)   # wall r 2
    assert inner.any() and np.abs(r[inner] - 2).max() < 0.02
    assert [lp for lp in loops(-1.2) if lp[:, 1].max() < -6] == []     # the groove's floor


@pytest.mark.parametrize("machine, rot0", [("s5d", "B0"), ("mill5ac", "A0")])
def test_tool_follow_up_keeps_the_tip(tmp_path, machine, rot0):
    """_ST tens digit 1 (tool follow-up, the control's tracking with TRAORI): the rotary axes
    turn with the tool tip kept where it is on the part; 0 holds the linear axes (the tip moves
    with the part)."""
    m = load_model(machine)
    tips = {}
    for st in (0, 10):
        body = (f"G0 X10 Y-5 Z40 {rot0} C0\n"
                f'CYCLE800(0,"TC1",{st},57,0,0,0,25,0,0,0,0,0,-1,100,1)\nG0 Z30\nM30\n')
        _, _, cmds, found = swivelled(machine, body, tmp_path)
        assert found == []
        rows = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 2]
        q = np.array([[rows[-1].axes[a] for a in m.axes]])
        pose = m.fk(q)
        rx = Rotation.from_euler("x", 25, degrees=True).as_matrix()
        assert np.abs(pose.axis[0] - rx @ (0, 0, 1)).max() < 1e-9
        tips[st] = pose.tip[0]
        held = [r.axes[g] for g in "XYZ" for r in rows[-1:]]
        assert (held == pytest.approx([10, -5, 40])) == (st == 0)
    assert np.abs(tips[10] - (10, -5, 40)).max() < 1e-9
    assert np.abs(tips[0] - (10, -5, 40)).max() > 1


def test_a_settable_frame_selected_under_cycle800_keeps_the_swivel(tmp_path):
    """G55 after CYCLE800: the swivel stays, about its reference point on the new zero (the
    control keeps it in a system frame after the settable frame); CYCLE800() then goes back
    to G55 alone."""
    body = ('$P_UIFR[2]=CTRANS(X,10,Y,-4,Z,0)\nG54 G0 X0 Y0 Z60 B0 C0\n'
            'CYCLE800(1,"TC1",0,57,0,2,0,20,0,0,0,0,0,-1,100,1)\nG0 X0 Y0 Z5\nG55\nG0 X0 Y0 Z5\n'
            'G1 X3 F300\nCYCLE800()\nG0 Z40\nM30\n')
    m, r, cmds, found = swivelled("s5d", body, tmp_path)
    assert found == []
    rx = Rotation.from_euler("x", 20, degrees=True).as_matrix()
    g54, g55 = (0, 2, 0), (10, -2, 0)
    for line, zero, p in ((4, g54, (0, 0, 5)), (6, g55, (0, 0, 5)), (7, g55, (3, 0, 5))):
        q = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == line][-1]
        pose = m.fk(np.array([[q.axes[a] for a in m.axes]]))
        assert np.abs(pose.tip[0] - (np.array(zero) + rx @ p)).max() < 1e-9, line
        assert np.abs(pose.axis[0] - rx @ (0, 0, 1)).max() < 1e-9
    frame = [c for c in r.commands if isinstance(c, SetFrame)][-1]     # CYCLE800(): G55 alone
    assert np.allclose(np.reshape(frame.rotation, (3, 3)), np.eye(3)) and frame.origin["X"] == 10


def test_projection_angles_x_y(tmp_path):
    """_MODE 128 + 57 (Xα, Yα): the new Z's projections make _A with Z in the Y/Z plane and _B
    in the Z/X plane, the new X stays in the old Z/X plane; another projection position is
    unsupported at its line."""
    body = 'G0 X0 Y0 Z50 B0 C0\nCYCLE800(0,"",0,185,0,0,0,25,-35,0,0,0,0,0,100,1)\nM30\n'
    r = run(tmp_path, body, load_model("s5d").control)
    rot = np.reshape([c for c in r.commands if isinstance(c, SetFrame)][-1].rotation, (3, 3))
    x, z = rot[:, 0], rot[:, 2]
    assert np.allclose(rot.T @ rot, np.eye(3), atol=1e-12) and np.linalg.det(rot) == pytest.approx(1)
    assert np.degrees(np.arctan2(-z[1], z[2])) == pytest.approx(25)
    assert np.degrees(np.arctan2(z[0], z[2])) == pytest.approx(-35)
    assert abs(x[1]) < 1e-12
    f = error_of(run(tmp_path, body.replace(",185,", ",158,"), load_model("s5d").control))
    assert (f.kind, f.line) == ("unsupported", 2)


@pytest.mark.parametrize("fr", [4, 5])
def test_retraction_along_a_tilted_tool(tmp_path, fr):
    """hybrid5's B/C head tilted 30°: _FR 5 retracts 25 mm along the tool, 4 as far as the
    travel allows (one axis at its end), before the swivel turns it."""
    m = load_model("hybrid5")
    body = f'G0 X0 Y0 Z10 B30 C60\nCYCLE800({fr},"",0,57,0,0,0,10,0,0,0,0,0,1,25,1)\nM30\n'
    r = run(tmp_path, body, m.control)
    assert r.completed, [f.render() for f in r.findings]
    moves = [c for c in r.commands if isinstance(c, MOTIONS)]
    q = np.array([[c.axes[a] for a in m.axes] for c in moves[:2]])
    pose = m.fk(q)
    step = pose.tip[1] - pose.tip[0]
    assert np.abs(np.cross(step, pose.axis[0])).max() < 1e-9 and step @ pose.axis[0] > 0
    if fr == 5:
        assert np.linalg.norm(step) == pytest.approx(25, abs=1e-9)
    else:
        at_end = [abs(moves[1].axes[g] - m.limits[m.axes.index(g)][1 if d > 0 else 0]) < 1e-9
                  for g, d in zip("XYZ", q[1, :3] - q[0, :3], strict=True) if abs(d) > 1e-9]
        assert any(at_end) and np.linalg.norm(step) > 25
