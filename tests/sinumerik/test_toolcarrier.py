"""TCARR, PAROT, TOROT (#35; toolcarrier.py): the orientable tool carrier on the model's swivel
data. Under TCARR=1 the rotary axes are programmed directly and X Y Z are machine-parallel with
the zero on the turned part; PAROT turns the workpiece coordinates with the table (X Y Z on the
part again), TOROT puts Z along the turned tool. Checked with the model's FK to 1e-9."""

from __future__ import annotations

import numpy as np
import pytest
from nc import error_of, run
from scipy.spatial.transform import Rotation

from vmach.canon import MOTIONS, SetFrame, Transformation
from vmach.machine import load_model
from vmach.machine.oriented import resolve


def solved(tmp_path, model, body):
    m = load_model(model)
    r = run(tmp_path, body, m.control)
    assert r.completed, [f.render() for f in r.findings]
    cmds, found = resolve(r.commands, m)
    assert found == []
    return m, r, cmds


def end(m, cmds, line):
    row = [c for c in cmds if isinstance(c, MOTIONS) and c.source.line == line][-1]
    q = np.array([[row.axes[a] for a in m.axes]])
    return row.axes, m.fk(q)


@pytest.mark.parametrize("model, b, c, turn", [("s5d", "B", "C", "yz"), ("mill5ac", "A", "C", "xz")])
def test_parot_on_a_swivel_table(tmp_path, model, b, c, turn):
    body = (f"G0 X0 Y0 Z80 {b}0 {c}0\nTCARR=1\nG0 {b}30 {c}40\nG0 X10 Y5 Z20\nPAROT\nG0 X10 Y5 Z20\n"
            f"G1 Z-1 F200\nPAROTOF\nTCARR=0\nM30\n")
    m, r, cmds = solved(tmp_path, model, body)
    assert [(t.name, t.source.line) for t in r.commands if isinstance(t, Transformation)] == [
        ("TCARR", 2), ("TRAFOOF", 9)]
    axes, _ = end(m, cmds, 3)                       # the rotary axes as programmed, nothing else
    assert (axes[b], axes[c]) == (pytest.approx(30), pytest.approx(40))
    assert (axes["X"], axes["Y"], axes["Z"]) == (0, 0, 80)
    # the tool relative to the part: the table's turn undone (machine +Z seen from the part)
    _, pose = end(m, cmds, 6)
    tool = pose.axis[0]
    # without PAROT, machine-parallel coordinates: the tip is the programmed point turned back
    # with the table, so that the distance to the part's zero and the height along the tool
    # stay what the program says
    _, before = end(m, cmds, 4)
    assert np.linalg.norm(before.tip[0]) == pytest.approx(np.linalg.norm([10, 5, 20]), abs=1e-9)
    assert before.tip[0] @ tool == pytest.approx(20, abs=1e-9)
    # with PAROT: X Y Z on the part
    assert np.abs(pose.tip[0] - (10, 5, 20)).max() < 1e-9
    _, pose = end(m, cmds, 7)
    assert np.abs(pose.tip[0] - (10, 5, -1)).max() < 1e-9
    frame = [f for f in r.commands if isinstance(f, SetFrame) and f.source.line == 5][-1]
    rot = np.reshape(frame.rotation, (3, 3))
    assert np.abs(rot.T @ (0, 0, 1) - tool).max() < 1e-9      # the frame turned with the part
    assert np.abs(Rotation.from_matrix(rot).magnitude() - 0) > 0.1


def test_torot_on_a_swivel_head(tmp_path):
    """hybrid5's B/C head (kinematic type T): TOROT makes Z the tool's direction."""
    body = "G0 X0 Y0 Z150 B0 C0\nTCARR=1\nG0 B30 C45\nTOROT\nG0 X0 Y0 Z20\nG1 X5 F300\nTOROTOF\nM30\n"
    m, r, cmds = solved(tmp_path, "hybrid5", body)
    _, pose = end(m, cmds, 5)
    k = pose.axis[0]
    assert k[2] == pytest.approx(np.cos(np.radians(30)), abs=1e-9)
    assert np.abs(pose.tip[0] - 20 * k).max() < 1e-9           # 20 mm along the tool from zero
    _, pose6 = end(m, cmds, 6)
    step = pose6.tip[0] - pose.tip[0]
    assert abs(step @ k) < 1e-9 and np.linalg.norm(step) == pytest.approx(5, abs=1e-9)


@pytest.mark.parametrize("body, line", [
    ("TCARR=2\nM30\n", 1),                                         # record 1 only
    ("PAROT\nM30\n", 1),                                           # without TCARR
    ("TCARR=1\nTOROTX\nM30\n", 2),
    ("TRAORI\nG0 X0 Y0 Z10 A3=0 B3=0 C3=1\nTRAFOOF\nTCARR=1\nPAROT\nM30\n", 5),   # B, C unknown
    ("G0 B0 C0\nTCARR=1\nG1 X0 Y0 Z5 A3=0 B3=0 C3=1 F100\nM30\n", 3)])         # a vector
def test_errors(tmp_path, body, line):
    f = error_of(run(tmp_path, body, load_model("s5d").control))
    assert (f.kind, f.line) == ("unsupported", line)


def test_a_machine_without_swivel_data(tmp_path):
    f = error_of(run(tmp_path, "G0 X1\nTCARR=1\nM30\n"))      # the default three-axis control
    assert (f.kind, f.line) == ("unsupported", 2)
