"""The machine-builder archive and shop program fixtures (fixtures/sinumerik_archive/, #32)
through the command line: ``check`` finds nothing, ``run`` ends, ``verify`` cuts the shop
program's outline and holes on the three-axis mill where the program puts them."""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh
from catalog import FIXTURES, MODELS

from interpreters import sinumerik
from vmach.cli import main
from vmach.machine.loader import load_model_control

DIR = FIXTURES / "sinumerik_archive"


def test_service_archive_checks_and_runs(tmp_path, capsys):
    # the warm-up archive: its GUD section gives the stage speeds, its R-parameter section
    # the number of axis runs; the axis runs reach the software limits less the margin
    assert main(["check", str(DIR / "SERVICE.ARC"), "--machine", "mill3", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out) == []
    trace = tmp_path / "trace.txt"
    assert main(["run", str(DIR / "SERVICE.ARC"), "--machine", "mill3", "-o", str(trace)]) == 0
    assert trace.read_text().count("program_end") == 1
    r = sinumerik.run(DIR / "SERVICE.ARC", load_model_control(MODELS / "mill3.toml"))
    assert r.completed
    speeds = [c.speed for c in r.commands if c.kind == "spindle" and c.direction == "cw"]
    assert speeds == [1500.0, 3000.0, 6000.0, 9000.0]
    feeds = [c for c in r.commands if c.kind == "feed"]
    assert len(feeds) == 4 * 2 * 7                                      # stages x R20 runs x moves
    xs = {c.axes["X"] for c in feeds}
    assert (min(xs), max(xs)) == (-480.0, 480.0)                        # mill3's X ±500, margin 20
    assert min(c.axes["Z"] for c in feeds) == -30.0                     # Z from -50
    kinds = {f.kind for f in r.findings}
    assert "synchronized_action" in kinds and "archive_section" not in kinds


def test_shop_program_saved_from_the_control_verifies_and_cuts(tmp_path, capsys):
    part = tmp_path / "part.stl"
    code = main(["verify", str(DIR / "_N_FLANGE_MPF"), "--out", str(tmp_path / "o"), "--no-images",
                 "--quiet", "--export", str(part)])
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert code == 0, [(f["kind"], f["line"], f["message"]) for f in report["findings"]]
    mesh = trimesh.load(part)
    holes = [lp for lp in loops(mesh, -6.0) if np.ptp(lp[:, 0]) < 20]
    centres = sorted((round(float(lp[:, 0].mean())), round(float(lp[:, 1].mean()))) for lp in holes)
    assert centres == [(20, 20), (20, 60), (80, 20), (80, 60)]       # four Ø8 holes through z=-6
    for lp in holes:
        assert np.ptp(lp[:, 0]) == pytest.approx(8.0, abs=0.05)
    assert [lp for lp in loops(mesh, -13.5) if np.ptp(lp[:, 0]) < 20] == []   # below the holes
    outer = max(loops(mesh, -1.0), key=lambda lp: np.ptp(lp[:, 0]))
    assert outer.min(0) == pytest.approx([1.0, 1.0], abs=0.011)       # sides milled 1 mm in,
    assert outer.max(0) == pytest.approx([99.0, 79.0], abs=0.011)
    below = max(loops(mesh, -3.0), key=lambda lp: np.ptp(lp[:, 0]))
    assert below.max(0) == pytest.approx([100.0, 80.0], abs=1e-6)      # 2 mm deep


def loops(mesh, z: float) -> list[np.ndarray]:
    """The (n, 2) outlines of the part's section at height z."""
    section = mesh.section(plane_origin=[0, 0, z], plane_normal=[0, 0, 1])
    return [] if section is None else [loop[:, :2] for loop in section.discrete]
