"""LinuxCNC's lathe cycles G70/G71/G72 (and .1/.2): the traces against rs274 are the golden
programs ``fixtures/rs274ngc/lathe_g7x_*``; here what the moves mean and that LinuxCNC's own
lathe examples (``../shared/corpus/rs274ngc``) run and verify on the lathe model."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from catalog import MODELS, ROOT, shared_or_skip

from interpreters import rs274ngc
from vmach.canon import ArcFeed, LinearFeed, Traverse
from vmach.machine.control import load_control
from vmach.verify import VerifyOptions, verify

CORPUS = ROOT.parent / "shared" / "corpus" / "rs274ngc"
LATHE_PROGRAMS = ["linuxcnc_lathe_g70_71_demo.ngc", "linuxcnc_lathe_g7x_face_boring.ngc",
                  "linuxcnc_lathe_g7x_quadrants.ngc"]
TOOLS = str(ROOT / "fixtures" / "tools" / "turning.toml")

#: a stepped shaft (diameters 20, 30) in G7: radius 10 to Z-15, a 45° cone, radius 15 to Z-30
STEP = """G7 G18 G21 G90
T1 M6
S600 M3 F200
O10 SUB
  G1 X20 Z0
  Z-15
  X30 Z-20
  Z-30
O10 ENDSUB
{cycles}
G0 X60 Z20
M2
"""


def _moves(tmp_path: Path, cycles: str, name: str = "step.ngc"):
    prog = tmp_path / name
    prog.write_text(STEP.format(cycles=cycles))
    r = rs274ngc.run(prog, load_control(MODELS / "lathe.toml"))
    assert r.completed, [f.render() for f in r.findings]
    return r.commands


def _contour_radius(z: float) -> float:
    """The step contour's radius at z (the solid of revolution it bounds)."""
    if z > -15.0:
        return 10.0
    if z > -20.0:
        return 10.0 + (-15.0 - z)
    return 15.0


def test_g71_roughing_stays_outside_the_allowance_and_reaches_it(tmp_path):
    """G71 D0.3 I2: horizontal passes 2 mm apart from X 26 (radius) down; no feed point lies
    closer to the contour than D, and the passes end on the contour + D."""
    cmds = _moves(tmp_path, "G71 Q10 X52 Z2 D0.3 I2 R0.5")
    feeds = [c for c in cmds if isinstance(c, (LinearFeed, ArcFeed))]
    assert len(feeds) > 10
    assert all(c.source.line == 10 for c in feeds)  # the moves carry the cycle's line
    ends = [(c.axes["X"], c.axes["Z"]) for c in feeds]
    for x, z in ends:  # never inside contour + allowance (X is a radius in the stream)
        if -30 < z < 0:
            assert x >= _contour_radius(z) + 0.3 - 1e-6 - (0.3 * (math.sqrt(2) - 1))
    # the pass levels: 2 mm apart (I2) down from the start radius 26
    levels = sorted({round(x, 4) for x, z in ends if z > 1.9}, reverse=True)
    steps = np.diff(levels)
    assert np.allclose(steps[steps < -1e-6][:-1], -2.0)


def test_g70_finishing_with_no_allowance_follows_the_contour(tmp_path):
    cmds = _moves(tmp_path, "G70 Q10 X52 Z2")
    pts = [(type(c).__name__, round(c.axes["X"], 6), round(c.axes["Z"], 6)) for c in cmds
           if isinstance(c, (LinearFeed, Traverse)) and c.source.line == 10]
    assert pts == [("Traverse", 26.0, 2.0), ("Traverse", 26.0, 2.0), ("Traverse", 10.0, 0.0),
                   ("LinearFeed", 10.0, -15.0), ("LinearFeed", 15.0, -20.0),
                   ("LinearFeed", 15.0, -30.0)]


def test_g70_two_passes_from_d_to_e(tmp_path):
    """P2 passes from D0.4 to E0: the first along the contour at 0.4 off, the last on it."""
    cmds = _moves(tmp_path, "G70 Q10 X52 Z2 D0.4 E0 P2")
    feeds = [(c.axes["X"], c.axes["Z"]) for c in cmds if isinstance(c, LinearFeed)]
    on_first_diameter = [x for x, z in feeds if -14 < z < -1]
    assert on_first_diameter == []  # feeds end at corners only
    radii = sorted({round(x, 6) for x, z in feeds if abs(z + 30) < 1e-6})
    assert radii == [15.0, 15.2]


def test_an_endless_contour_stops_with_an_error_at_the_cycle(tmp_path):
    """LinuxCNC 2.9 loops for ever on this contour (its test g71-endless-loop); vmach stops
    after MAX_MOVES moves with an error at the cycle's line."""
    prog = tmp_path / "loop.ngc"
    prog.write_text("G21 G18 G8 G91.1\nO200 SUB\nG01 X10 Z0\nG01 X10 Z-14\nG01 X3\n"
                    "G01 X7 Z-22\nO200 ENDSUB\nF225\nG71.2 Q200 X15.0 Z0 D0.04 I0.5 R1\nM2\n")
    r = rs274ngc.run(prog, load_control(MODELS / "lathe.toml"))
    assert not r.completed
    assert (r.findings[-1].kind, r.findings[-1].source.line) == ("g7x_too_many_moves", 9)


def test_a_cycle_that_loops_without_moving_stops_too(tmp_path):
    """This G72.2 makes LinuxCNC 2.9 loop for ever without a move; vmach stops after
    MAX_STEPS turns of its pocket loop, at the cycle's line."""
    prog = tmp_path / "still.ngc"
    prog.write_text("G18 G21 G90 G7\nF300\nO10 SUB\n  G1 X3.039 Z0.000\n  G1 X3.717 Z-3.865\n"
                    "  G2 X7.517 Z-6.460 R4.433\nO10 ENDSUB\n"
                    "G72.2 Q10 X9.316 Z2.876 D0.17 I0.97 R0.66\nM2\n")
    r = rs274ngc.run(prog, load_control(MODELS / "lathe.toml"))
    assert not r.completed
    assert (r.findings[-1].kind, r.findings[-1].source.line) == ("g7x_too_many_moves", 8)


def test_fillet_and_chamfer_words_on_a_contour_are_not_axes_for_check(tmp_path):
    prog = tmp_path / "fc.ngc"
    prog.write_text("G18 G21 F100\nO5 SUB\nG1 X10 Z0 C1\nZ-10 A2\nX20\nO5 ENDSUB\n"
                    "G70 Q5 X22 Z2\nG1 X10 A3\nM2\n")
    found = rs274ngc.check(prog, load_control(MODELS / "lathe.toml"))
    assert [(f.kind, f.line) for f in found] == [("unknown_axis", 8)]


@pytest.mark.parametrize("name", LATHE_PROGRAMS)
def test_linuxcnc_lathe_examples_run(name, tmp_path):
    path = shared_or_skip(CORPUS / name, "LinuxCNC lathe example")
    prog = tmp_path / name
    prog.write_text(path.read_text().replace("T10M6", "T2M6"))  # rs274's table has T1..T3
    r = rs274ngc.run(prog, load_control(MODELS / "lathe.toml"))
    assert r.completed, [f.render() for f in r.findings]
    moves = [c for c in r.commands if isinstance(c, (LinearFeed, ArcFeed))]
    assert len(moves) > 30


@pytest.mark.parametrize("name", LATHE_PROGRAMS)
def test_linuxcnc_lathe_examples_verify_on_the_lathe(name, tmp_path):
    """In verify on the lathe model the cycles run end to end; what is reported is about
    the machine (travel below X-5 in the quadrants demo) or the tools, never the program."""
    path = shared_or_skip(CORPUS / name, "LinuxCNC lathe example")
    prog = tmp_path / name
    prog.write_text(path.read_text())
    rep = verify(prog, VerifyOptions(machine="lathe", tools=TOOLS, default_tool="flat:d=1",
                                     images=False))
    assert rep.result.completed, [f.render() for f in rep.findings if f.is_error]
    kinds = {f.kind for f in rep.findings if f.is_error}
    assert kinds <= {"axis_limit"}
    assert len(rep.table.kind) > 100
