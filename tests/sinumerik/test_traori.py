"""TRAORI programs (orientation.py → vmach.machine.oriented): every block's last row of axis
values puts the tool tip and vector where the program says (FK to 1e-9) on s5d, h5d, hybrid5
and mill5ac; vector, Euler and RPY orientation (the Job Planning manual's definitions),
rotary axes programmed directly, ORIWKS/ORIMKS under a rotated frame, ORIVECT on the great
circle and ORIAXES linear in the axes within tol.angle_step; the pole; flips; TRAFOOF."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from nc import error_of, run
from scipy.spatial.transform import Rotation

from vmach.canon import MOTIONS, OrientedMove, Transformation
from vmach.machine import load_model
from vmach.machine.oriented import resolve
from vmach.tol import tol

MODELS = ("s5d", "h5d", "hybrid5", "mill5ac")


def solved(tmp_path, model, body):
    m = load_model(model)
    r = run(tmp_path, body + "M30\n", m.control)
    assert r.completed, [f.render() for f in r.findings]
    cmds, found = resolve(r.commands, m)
    return m, cmds, found


def rows(m, cmds, line):
    got = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == line]
    q = np.array([[c.axes[a] for a in m.axes] for c in got])
    return q, m.fk(q)


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


@pytest.mark.parametrize("model", MODELS)
def test_vector_programming_reaches_tip_and_vector(tmp_path, model):
    poses = [((5, -3, 12), (0.3, 0.2, 0.9)), ((-10, 4, 2), (0, -1, 2)), ((0, 0, 20), (0.1, 0, 1)),
             ((8, 8, -4), (-0.4, 0.4, 1))]
    rot = "A" if model == "mill5ac" else "B"
    body = f"TRAORI\nG0 X0 Y0 Z30 {rot}10 C0\n" + "".join(
        f"G1 X{p[0]} Y{p[1]} Z{p[2]} A3={v[0]} B3={v[1]} C3={v[2]} F1000\n" for p, v in poses) + "TRAFOOF\n"
    m, cmds, found = solved(tmp_path, model, body)
    assert found == []
    for line, (p, v) in enumerate(poses, 3):
        q, pose = rows(m, cmds, line)
        assert np.abs(pose.tip[-1] - p).max() < 1e-9
        assert np.abs(pose.axis[-1] - unit(v)).max() < 1e-9
        ok = m.drive_values(q)[1]                 # hybrids: the drives follow, all reachable
        assert ok.all()


def test_euler_and_rpy_angles_as_the_manual_defines_them(tmp_path):
    """ORIEULER: Z, then the new X (A2, B2; C2 leaves the vector); ORIRPY: C2 about Z, B2 about
    the new Y, A2 about the new X (the manual's example C2=90 B2=45 A2=30)."""
    m, cmds, _ = solved(tmp_path, "s5d", "TRAORI\nG1 X0 Y0 Z10 A2=30 B2=40 C2=77 F500\n"
                                         "ORIRPY\nG1 A2=30 B2=45 C2=90\nTRAFOOF\n")
    _, pose = rows(m, cmds, 2)
    euler = Rotation.from_euler("ZXZ", [30, 40, 77], degrees=True).apply([0, 0, 1])
    assert np.abs(pose.axis[-1] - euler).max() < 1e-9
    _, pose = rows(m, cmds, 4)
    rpy = Rotation.from_euler("ZYX", [90, 45, 30], degrees=True).apply([0, 0, 1])
    assert np.abs(pose.axis[-1] - rpy).max() < 1e-9
    assert np.abs(pose.tip[-1] - (0, 0, 10)).max() < 1e-9


def test_rotary_axes_programmed_directly_keep_the_tip(tmp_path):
    m, cmds, _ = solved(tmp_path, "mill5ac", "TRAORI\nG1 X10 Y-5 Z20 A0 C0 F500\nA30 C45\nTRAFOOF\n")
    q, pose = rows(m, cmds, 3)
    assert q[-1, m.axes.index("A")] == pytest.approx(30) and q[-1, m.axes.index("C")] == pytest.approx(45)
    assert np.abs(pose.tip - (10, -5, 20)).max() < 1e-9          # every row: the tip stays put
    a = Rotation.from_euler("ZX", [-45, -30], degrees=True).apply([0, 0, 1])   # table: part turns
    assert np.abs(pose.axis[-1] - a).max() < 1e-9


def test_oriwks_turns_the_vector_with_the_frame_orimks_does_not(tmp_path):
    body = ("G0 X0 Y0 Z0\nROT Z90\nTRAORI\nG1 X10 Y0 Z5 A3=1 B3=0 C3=1 F500\nORIMKS\n"
            "G1 A3=1 B3=0 C3=1\nTRAFOOF\n")
    m, cmds, _ = solved(tmp_path, "s5d", body)
    _, pose = rows(m, cmds, 4)
    assert np.abs(pose.tip[-1] - (0, 10, 5)).max() < 1e-9                    # X10 turned by 90°
    assert np.abs(pose.axis[-1] - unit((0, 1, 1))).max() < 1e-9
    _, pose = rows(m, cmds, 6)
    assert np.abs(pose.axis[-1] - unit((1, 0, 1))).max() < 1e-9


def test_orivect_turns_on_the_great_circle_oriaxes_moves_the_axes_linearly(tmp_path):
    head = "TRAORI\nG1 X0 Y0 Z10 A3=0 B3=-1 C3=2 F500\n"
    m, cmds, _ = solved(tmp_path, "s5d", head + "G1 X20 A3=1 B3=0 C3=1\nTRAFOOF\n")
    q, pose = rows(m, cmds, 3)
    t0, t1 = unit((0, -1, 2)), unit((1, 0, 1))
    normal = unit(np.cross(t0, t1))
    assert np.abs(pose.axis @ normal).max() < 1e-9                           # on the great circle
    steps = np.degrees(np.arccos(np.clip(np.sum(pose.axis[1:] * pose.axis[:-1], axis=1), -1, 1)))
    assert steps.max() <= tol.angle_step + 1e-9
    assert np.abs(pose.tip[:, 1:] - (0, 10)).max() < 1e-9                    # the tip on its line
    m, cmds, _ = solved(tmp_path, "s5d", head + "ORIAXES\nG1 X20 A3=1 B3=0 C3=1\nTRAFOOF\n")
    q, pose = rows(m, cmds, 4)
    rot = q[:, [m.axes.index("B"), m.axes.index("C")]]
    assert np.abs(np.diff(rot, 2, axis=0)).max() < 1e-9                     # linear in the axes
    assert np.abs(np.diff(rot, axis=0)).max() <= tol.angle_step + 1e-9
    assert np.abs(pose.axis @ normal).max() > 1e-3                           # not the great circle
    assert np.abs(pose.tip[:, 1:] - (0, 10)).max() < 1e-9


def test_the_pole_keeps_c(tmp_path):
    m, cmds, found = solved(tmp_path, "s5d", "TRAORI\nG1 X0 Y0 Z10 B20 C30 F500\nA3=0 B3=0 C3=1\n"
                                             "A3=0 B3=0.2 C3=1\nTRAFOOF\n")
    q, pose = rows(m, cmds, 3)
    assert q[-1, m.axes.index("C")] == pytest.approx(30) and q[-1, m.axes.index("B")] == pytest.approx(0)
    assert found == []


def test_passing_by_the_pole_is_an_orientation_flip(tmp_path):
    s, c = math.sin(math.radians(10)), math.cos(math.radians(10))
    body = (f"TRAORI\nG1 X0 Y0 Z10 A3={s} B3=0.001 C3={c} F500\nG1 A3={-s} B3=0.001 C3={c}\n"
            "G1 A3=0.3 B3=0.1 C3=1\nTRAFOOF\n")
    m, cmds, found = solved(tmp_path, "s5d", body)
    assert [(f.kind, f.severity, f.line) for f in found] == [("orientation_flip", "warning", 3)]
    assert found[0].data["axis"] == "C" and found[0].data["step"] > 10
    assert found[0].data["vector_turn"] == pytest.approx(20, abs=0.1)


def test_trafoof_leaves_the_axes_where_the_transformation_put_them(tmp_path):
    m, cmds, _ = solved(tmp_path, "s5d", "TRAORI\nG1 X10 Y5 Z10 A3=1 B3=0 C3=1 F500\nTRAFOOF\nG0 Z50\n")
    last = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 2][-1]
    after = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 4][0]
    assert after.axes["Z"] == 50
    for a in ("X", "Y", "B", "C"):
        assert after.axes[a] == last.axes[a]
    assert any(isinstance(c, Transformation) and c.name == "TRAFOOF" for c in cmds)
    assert sum(isinstance(c, OrientedMove) for c in cmds) == 1


def test_errors_at_their_lines(tmp_path):
    s5d = load_model("s5d").control
    f = error_of(run(tmp_path, "G0 X0\nG1 A3=1 F100\nM30\n", s5d))
    assert (f.kind, f.line) == ("no_transformation", 2)
    f = error_of(run(tmp_path, "G0 X0\nG1 X5 C2=1 F100\nM30\n", s5d))
    assert (f.kind, f.line) == ("no_transformation", 2)
    f = error_of(run(tmp_path, "TRAORI\nG91 G1 X1 F100\nM30\n", s5d))
    assert (f.kind, f.line) == ("unsupported", 2)
    f = error_of(run(tmp_path, "TRAORI\nG1 X0 Y0 Z0 F100\nTRAFOOF\nG91 Z5\nM30\n", s5d))
    assert (f.kind, f.line) == ("unsupported", 4)
    f = error_of(run(tmp_path, "TRAORI\nG1 X0 Y0 Z0 B10 A3=1 F100\nM30\n", s5d))
    assert (f.kind, f.line) == ("syntax", 2)
    f = error_of(run(tmp_path, "TRAORI\nM30\n", load_model("turnmill").control))
    assert (f.kind, f.line) == ("unsupported", 1)
    f = error_of(run(tmp_path, "ORICURVE\nM30\n", s5d))
    assert (f.kind, f.line) == ("unsupported", 1)


def test_traori_n_and_left_active(tmp_path):
    r = run(tmp_path, "TRAORI(2)\nG1 X0 Y0 Z5 F100\nM30\n", load_model("s5d").control)
    marks = [c for c in r.commands if isinstance(c, Transformation)]
    assert [(c.name, c.number) for c in marks] == [("TRAORI", 2)]
    assert ("left_active", 3) in [(f.kind, f.line) for f in r.findings]


def test_cycle832_tolerance_is_recorded_and_used_for_the_path(tmp_path):
    """CYCLE832(0.05, …) stays in the stream with its tolerance, and a TRAORI circle after it is
    written within 0.05 mm (the control's compressor may leave the path by that much) instead of
    tol.chord; CYCLE832(0) goes back."""
    from vmach.canon import PathTolerance

    arc = "G1 X10 Y0 Z0 A3=0 B3=0 C3=1 F500\nG3 X-10 Y0 I-10 J0\n"
    body = f"CYCLE832(0.05,_FINISH,1)\nTRAORI\n{arc}CYCLE832(0)\n{arc}TRAFOOF\n"
    m, cmds, _ = solved(tmp_path, "s5d", body)
    (c832, c0) = [c for c in cmds if isinstance(c, PathTolerance)]
    assert (c832.tolerance, c832.setting, c832.source.line) == (0.05, ("_FINISH", 1), 1)
    assert (c0.tolerance, c0.source.line) == (0.0, 5)
    coarse, pose = rows(m, cmds, 4)
    fine, _ = rows(m, cmds, 7)
    assert np.abs(np.hypot(pose.tip[:, 0], pose.tip[:, 1]) - 10).max() < 1e-9   # on the circle
    r = 10.0
    assert len(coarse) == math.ceil(math.pi / (2 * math.acos(1 - 0.05 / r)))
    assert len(fine) == math.ceil(math.pi / (2 * math.acos(1 - tol.chord / r)))


def test_run_json_writes_unknown_positions_as_null(tmp_path, capsys):
    import json

    from vmach.cli import main

    prog = tmp_path / "T.MPF"
    prog.write_text("TRAORI\nG1 X1 Y2 Z3 A3=0 B3=0 C3=1 F100\nTRAFOOF\nG0 Z50\nM30\n")
    assert main(["run", str(prog), "--machine", "h5d", "--format", "json"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert rows[1]["kind"] == "oriented_move" and rows[1]["axes"]["B"] is None
    assert rows[3]["axes"]["X"] is None and rows[3]["axes"]["Z"] == 50.0


def test_the_domain_worked_case_as_a_traori_program(tmp_path):
    """Domain §2 on s5d with r_R = (10, 0, −5): the TRAORI block's axis values are the closed
    form's term by term (coming from the B ≥ 0 branch, as the rule keeps it)."""
    from vmach.machine.closed_form import table_table_ik

    m = load_model("s5d").with_parameters(rotation_centre=(10.0, 0.0, -5.0))
    r = run(tmp_path, "TRAORI\nG0 X0 Y0 Z40 B20 C140\nG1 X5 Y-3 Z12 A3=0.3 B3=0.2 C3=0.9 F500\n"
            "TRAFOOF\nM30\n", m.control)
    cmds, found = resolve(r.commands, m)
    end = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 3][-1].axes
    ref, _ = table_table_ik(np.array([[5.0, -3.0, 12.0]]), np.array([[0.3, 0.2, 0.9]]), (10.0, 0.0, -5.0))
    for name in ("X", "Y", "Z", "B", "C"):
        assert end[name] == pytest.approx(float(ref[name][0]), abs=1e-9), name
    assert found == []


def test_a_vector_out_of_reach_is_unreachable_at_its_line(tmp_path):
    """A table whose tilt axis leans 45° (a nutating table) reaches only tool vectors within 90°
    of its axis: (0, −1, −1) is not, the block is an unreachable error and does not move."""
    from pathlib import Path

    from vmach.machine.oriented import resolve as solve

    text = (Path(__file__).resolve().parents[2] / "models" / "s5d.toml").read_text()
    leaning = "axis = [0.0, 0.70710678118654757, 0.70710678118654757]"
    text = text.replace('ik = "table_table"', 'ik = "numeric"').replace(
        "axis = [0.0, 1.0, 0.0]\nlimits = [-25.0, 135.0]", leaning)
    (tmp_path / "nutate.toml").write_text(text)
    m = load_model(tmp_path / "nutate.toml")
    r = run(tmp_path, "TRAORI\nG0 X0 Y0 Z40 A3=0 B3=0 C3=1\nG1 X5 A3=0 B3=-1 C3=-1 F500\n"
            "G1 X6 A3=0.2 B3=0 C3=1\nTRAFOOF\nM30\n", m.control)
    cmds, found = solve(r.commands, m)
    assert [(f.kind, f.severity, f.line) for f in found] == [("unreachable", "error", 3)]
    assert not [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == 3]
    q, pose = rows(m, cmds, 4)
    assert np.abs(pose.axis[-1] - unit((0.2, 0, 1))).max() < 1e-9


def test_hybrid_drives_follow_under_traori(tmp_path, capsys):
    """On hybrid5 (p1..p3 carry the platform) ``vmach run --format json`` gives every TRAORI
    block the drive values of its solved end pose, as for an axis program: the drives' inverse
    of the virtual axes that put the tip and vector where the block says."""
    import json

    from vmach.cli import main

    m = load_model("hybrid5")
    body = ("TRAORI\nG1 X5 Y-3 Z12 A3=0.3 B3=0.2 C3=0.9 F500\nG1 X-8 Y4 Z6 A3=-0.2 B3=0.1 C3=1\n"
            "TRAFOOF\nG0 Z60\nM30\n")
    prog = tmp_path / "T.MPF"
    prog.write_text(body)
    assert main(["run", str(prog), "--machine", "hybrid5", "--format", "json"]) == 0
    lines = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    cmds, _ = resolve(run(tmp_path, body, m.control).commands, m)
    for line in (2, 3):
        (row,) = [r for r in lines if r["kind"] == "oriented_move" and r["line"] == line]
        q, pose = rows(m, cmds, line)
        assert set(row["drives"]) == {"p1", "p2", "p3"}
        drives, ok = m.drive_values(q[-1:])
        assert ok[0]
        for d in ("p1", "p2", "p3"):
            assert row["drives"][d] == pytest.approx(float(drives[d][0]), abs=1e-9)
        assert np.abs(pose.tip[-1] - [(5, -3, 12), (-8, 4, 6)][line - 2]).max() < 1e-9
    after = [r for r in lines if r["kind"] != "oriented_move" and r["line"] == 5][-1]
    assert after["drives"]["p1"] is not None        # the position TRAFOOF left, known again


@pytest.mark.parametrize("model", ["s5d", "mill5ac"])
def test_orirpy2_and_the_virtual_orientation_axes(tmp_path, model):
    """G group 50 of the manual: ORIRPY2 is the RPY angles in the rotation sequence Z, Y, X
    (C2 about Z first, then B2 about Y, then A2 about X, fixed axes: Rx(A2)·Ry(B2)·Rz(C2)·e_z);
    ORIVIRT1/ORIVIRT2 turn about the axes MD21120/MD21130 $MC_ORIAX_TURN_TAB_1/2 name in
    order (1 X, 2 Y, 3 Z; the model's data, here TAB_2 = Z, X, Z: the Euler angles of
    virtual axes), default X, Y, Z (= ORIRPY). FK of the solution = the vector to 1e-9."""
    m = load_model(model)
    md = dict(m.control.machine_data)
    md["$MC_ORIAX_TURN_TAB_2"] = [3, 1, 3]
    control = replace(m.control, machine_data=md)
    body = ("TRAORI\nORIRPY2\nG1 X0 Y0 Z10 A2=20 B2=-35 C2=50 F500\nORIVIRT1\nG1 A2=-25 B2=15 C2=40\n"
            "ORIVIRT2\nG1 A2=30 B2=40 C2=10\nTRAFOOF\nM30\n")
    r = run(tmp_path, body, control)
    assert r.completed, [f.render() for f in r.findings]
    cmds, found = resolve(r.commands, m)
    assert found == []
    ez = np.array([0.0, 0.0, 1.0])
    rpy2 = Rotation.from_euler("XYZ", [20, -35, 50], degrees=True).apply(ez)    # intrinsic X Y Z
    virt1 = Rotation.from_euler("xyz", [-25, 15, 40], degrees=True).apply(ez)   # fixed X, Y, Z
    virt2 = Rotation.from_euler("zxz", [30, 40, 10], degrees=True).apply(ez)    # fixed Z, X, Z
    for line, want in ((3, rpy2), (5, virt1), (7, virt2)):
        _, pose = rows(m, cmds, line)
        assert np.abs(pose.axis[-1] - want).max() < 1e-9, line
        assert np.abs(pose.tip[-1] - (0, 0, 10)).max() < 1e-9


def cone_rows(tmp_path, model, mode, words):
    m, cmds, found = solved(tmp_path, model, "TRAORI\nORIVECT\nG1 X0 Y0 Z10 A3=1 B3=0 C3=1 F500\n"
                            f"{mode}\nG1 X10 {words} A3=0 B3=1 C3=1\nTRAFOOF\n")
    assert found == []
    q, pose = rows(m, cmds, 5)
    return pose


@pytest.mark.parametrize("model", ["s5d", "mill5ac", "h5d"])
def test_cone_interpolation_oriconccw_oriconcw_oriconio(tmp_path, model):
    """Interpolation on a cone's surface (G group 51): from 45° toward +X to 45° toward +Y on
    the cone about Z (A6=0 B6=0 C6=1) — ORICONCCW the quarter turn, ORICONCW the other three
    quarters; ORICONIO through the intermediate orientation A7 B7 C7 (toward −X: three
    quarters again). Every row: 45° from the axis; the azimuth monotonic at most
    tol.angle_step apart; FK of the end = the programmed vector and tip to 1e-9."""
    ez = np.array([0.0, 0.0, 1.0])
    for mode, words, sweep in (("ORICONCCW", "A6=0 B6=0 C6=1", 90.0),
                               ("ORICONCW", "A6=0 B6=0 C6=1", -270.0),
                               ("ORICONIO", "A7=-1 B7=0 C7=1", -270.0)):
        pose = cone_rows(tmp_path, model, mode, words)
        assert np.abs(pose.axis @ ez - math.cos(math.radians(45))).max() < 1e-9, mode
        az = np.degrees(np.unwrap(np.arctan2(pose.axis[:, 1], pose.axis[:, 0])))
        steps = np.diff(az)
        assert (np.sign(steps) == np.sign(sweep)).all(), mode
        assert az[-1] - az[0] + steps[0] == pytest.approx(sweep, abs=tol.angle_step)
        turned = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", pose.axis[1:], pose.axis[:-1]), -1, 1)))
        assert turned.max() <= tol.angle_step * (1 + 1e-9), mode
        assert np.abs(pose.axis[-1] - unit((0, 1, 1))).max() < 1e-9
        assert np.abs(pose.tip[-1] - (10, 0, 10)).max() < 1e-9


@pytest.mark.parametrize("model", ["s5d", "mill5ac"])
def test_oriconto_goes_on_tangentially(tmp_path, model):
    """ORICONTO: the cone leaves the start orientation in the direction the orientation turned
    at the end of the block before. After ORIVECT from Z to 45° toward +X (a turn in the X/Z
    plane, ending toward +X), ORICONTO to 45° toward +Y: the first step leaves along +X (the
    tangent), the circle through both on the unit sphere, FK of the end to 1e-9."""
    m, cmds, found = solved(tmp_path, model, "TRAORI\nORIVECT\nG1 X0 Y0 Z10 A3=0 B3=0 C3=1 F500\n"
                            "G1 A3=1 B3=0 C3=1\nORICONTO\nG1 X5 A3=0 B3=1 C3=1\nTRAFOOF\n")
    assert found == []
    _, pose = rows(m, cmds, 6)
    a = pose.axis
    first = a[0] - unit((1, 0, 1))
    assert first[0] > 0 and abs(first[1]) > 0            # leaves on, then off, the X/Z plane
    assert np.dot(unit(first), unit((1, 0, -1))) > 0.99  # along the previous turn's tangent
    centre = a.mean(axis=0)                               # one circle: a plane cuts the sphere
    normal = np.linalg.svd(a - centre)[2][-1]
    assert np.abs((a - centre) @ normal).max() < 1e-9
    assert np.abs(a[-1] - unit((0, 1, 1))).max() < 1e-9
    assert np.abs(pose.tip[-1] - (5, 0, 10)).max() < 1e-9
    _, _, found = solved(tmp_path, model, "TRAORI\nG0 X0 Y0 Z10 A3=0 B3=0 C3=1\nORICONTO\n"
                         "G1 A3=0 B3=1 C3=1 F100\nTRAFOOF\n")
    assert [(x.kind, x.line) for x in found] == [("invalid_value", 4)]


@pytest.mark.parametrize("model", ["s5d", "mill5ac", "h5d"])
def test_lead_and_tilt_relative_to_the_path(tmp_path, model):
    """LEAD: the surface normal (Z) turned toward the path tangent; TILT: then about the tangent
    (the manual's definitions); modal; under ORIPATH every path block takes its orientation from
    its own tangent (an arc's at its end), under ORIVECT only a block that programs them."""
    body = ("TRAORI\nG1 X0 Y0 Z10 A3=0 B3=0 C3=1 F500\nORIPATH\nG1 X20 LEAD=10\nG1 Y20\n"
            "G3 X0 Y40 I-20 J0\nG1 X-20 TILT=20\nORIVECT\nG1 X-30\nG1 Y30 LEAD=0 TILT=0\n"
            "G1 Y20 A5=1 B5=0 C5=1 LEAD=15\nTRAFOOF\n")
    m, cmds, found = solved(tmp_path, model, body)
    assert found == []
    s10, c10 = math.sin(math.radians(10)), math.cos(math.radians(10))
    tilted = Rotation.from_rotvec(np.radians(20) * np.array([-1, 0, 0])).apply((-s10, 0, c10))
    n5 = unit((1, 0, 1))
    lead15 = math.cos(math.radians(15)) * n5 + math.sin(math.radians(15)) * np.array([0, -1, 0])
    for line, want, tip in ((4, (s10, 0, c10), (20, 0, 10)), (5, (0, s10, c10), (20, 20, 10)),
                            (6, (-s10, 0, c10), (0, 40, 10)), (7, tilted, (-20, 40, 10)),
                            (9, tilted, (-30, 40, 10)), (10, (0, 0, 1), (-30, 30, 10)),
                            (11, lead15, (-30, 20, 10))):
        _, pose = rows(m, cmds, line)
        assert np.abs(pose.axis[-1] - want).max() < 1e-9, line
        assert np.abs(pose.tip[-1] - tip).max() < 1e-9, line
    s5d = load_model("s5d").control
    f = error_of(run(tmp_path, "TRAORI\nG1 X0 Y0 Z10 LEAD=5 F100\nM30\n", s5d))
    assert (f.kind, f.line) == ("unsupported", 2)           # its start only the machine knows
    f = error_of(run(tmp_path, "TRAORI\nG1 X0 Y0 Z10 F100\nG1 X5 LEAD=5 A3=0 B3=0 C3=1\nM30\n", s5d))
    assert (f.kind, f.line) == ("syntax", 3)
    f = error_of(run(tmp_path, "TRAORI\nG1 X0 Y0 Z10 F100\nG1 X5 A4=0 B4=0 C4=1 LEAD=5\nM30\n", s5d))
    assert (f.kind, f.line) == ("unsupported", 3)


def test_oripaths_says_what_it_does_not_smooth(tmp_path):
    r = run(tmp_path, "TRAORI\nORIPATHS\nG1 X0 Y0 Z10 A3=0 B3=0 C3=1 F100\nG1 X10\nORIPATHS\nTRAFOOF\nM30\n",
            load_model("s5d").control)
    assert r.completed
    assert [(f.kind, f.severity, f.line) for f in r.findings if f.kind == "orientation_simplified"] == [
        ("orientation_simplified", "info", 2)]
