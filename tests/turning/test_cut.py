"""The revolved cut of a turning tool (#34): exact diameters and nose fillets, the spindle
axis crossed by a facing cut, rapids into the stock and the holder in it, turning and milling
on one stock."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vmach.stock import Stock, engine
from vmach.tooling import load_tools
from vmach.verify import VerifyOptions, verify

ROOT = Path(__file__).resolve().parents[2]
TOOLS = ROOT / "fixtures" / "tools" / "turning.toml"


@pytest.fixture(scope="module")
def lib():
    return load_tools(TOOLS)


def radius_at(stock: Stock, z: float) -> float:
    area = sum(0.5 * abs(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))
               for p in stock.section(z))
    return float(np.sqrt(area / np.pi))


def test_a_straight_pass_leaves_its_diameter_and_the_nose_fillet_at_the_shoulder(lib):
    stock = Stock.from_spec("cylinder:d=60,l=100")
    tips = np.array([[35, 0, 2], [25, 0, 2], [25, 0, -30], [35, 0, -30]], float)
    assert stock.turn(lib.lookup("CNMG120408"), tips, np.arange(4)) == 1     # one pass, one cutter
    for z in (-0.5, -10.0, -29.0):
        assert radius_at(stock, z) == pytest.approx(25.0, abs=0.001)
    # the nose circle (centre 25.8, -29.2, radius 0.8) at z = -29.5: 25.8 - sqrt(0.64 - 0.09)
    assert radius_at(stock, -29.5) == pytest.approx(25.8 - np.sqrt(0.55), abs=0.001)
    assert radius_at(stock, -30.5) == pytest.approx(30.0, abs=0.001)


def test_a_facing_cut_across_the_axis_faces_the_centre(lib):
    stock = Stock.from_spec("cylinder:d=60,l=100")
    stock.turn(lib.lookup("CNMG120408"), np.array([[32, 0, -1], [-0.8, 0, -1], [-0.8, 0, 2]], float))
    hi = engine.bounds(stock.solid)[1, 2]
    assert hi == pytest.approx(-1.0, abs=1e-6)                         # nothing left above Z-1


def run(tmp_path, text, machine="lathe", stock="cylinder:d=60,l=100"):
    prog = tmp_path / "T.MPF"
    prog.write_text(text)
    return verify(prog, VerifyOptions(machine=machine, tools=str(TOOLS), stock=stock, images=False))


def test_a_rapid_into_the_bar_is_reported_at_its_line(tmp_path):
    r = run(tmp_path, "G18 G90 DIAMON\nT=\"CNMG120408\" D1\nG97 S1000 M3\nG0 X64 Z2\nX50\nG0 Z-10\n"
                      "G0 Z2\nG0 X70\nM30\n")
    hits = [(f.kind, f.line) for f in r.findings if f.severity == "error"]
    assert hits == [("rapid_into_stock", 6)]


def test_a_groove_deeper_than_the_blade_runs_its_holder_into_the_bar(tmp_path):
    # GROOVE3 reaches 12 mm: a plunge from Ø60 to Ø30 is 15 mm deep
    r = run(tmp_path, "G18 G90 DIAMON\nT=\"GROOVE3\" D1\nG97 S800 M3\nG0 X64 Z-20\nG95 G1 X30 F0.05\n"
                      "G0 X70\nM30\n")
    hits = [(f.kind, f.line, f.data.get("part")) for f in r.findings if f.severity == "error"]
    # the plunge, and the retract (the 25 mm holder is wider than its 3 mm groove)
    assert hits == [("holder_collision", 5, "holder"), ("holder_collision", 6, "holder")]
    ok = run(tmp_path, "G18 G90 DIAMON\nT=\"GROOVE3\" D1\nG97 S800 M3\nG0 X64 Z-20\nG95 G1 X40 F0.05\n"
                       "G0 X70\nM30\n")
    assert [f for f in ok.findings if f.severity == "error"] == []
