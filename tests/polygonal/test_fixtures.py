"""The polygonal-turning fixture programs (#34) verify on the turn-mill: the tool spindle coupled
to the main spindle by COUPDEF/COUPON, each program's part shows its shape family; and the
flywheel's own findings (uncoupled, rapid into the stock, the cutter's body in the stock)."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import pytest

from vmach.checks.flats import flanks
from vmach.verify import VerifyOptions, verify

ROOT = Path(__file__).resolve().parents[2]
FIX = ROOT / "fixtures" / "polygon_turning"


@pytest.fixture(scope="module")
def parts():
    return {name: verify(FIX / f"{name}.MPF", VerifyOptions(images=False))
            for name in ("SQUARE", "HEXAGON", "ARCS", "CONCAVE")}


@pytest.mark.parametrize("name, flats, across, shape", [
    ("SQUARE", 4, 22.0, "slight"), ("HEXAGON", 6, 24.0, "slight"), ("ARCS", 3, 20.0, "strong"),
    ("CONCAVE", 6, 24.0, "concave"),
])
def test_each_fixture_cuts_its_shape_without_findings(parts, name, flats, across, shape):
    rep = parts[name]
    assert [(f.kind, f.line) for f in rep.findings if f.severity != "info"] == []
    assert rep.skipped == {}
    fl = flanks(max(rep.part.section(-10.0), key=len))
    assert len(fl) == flats
    for f in fl:
        assert 2.0 * f.radius == pytest.approx(across, abs=0.004)         # X is the diameter across the flats
        if shape == "slight":
            assert 0.0 < f.bulge < 0.005 * across
        elif shape == "strong":
            assert f.bulge > 0.05 * across
        else:
            assert f.bulge < 0.0


def test_coupon_offset_turns_the_polygon(parts):
    # HEXAGON: COUPON(S2, S1, 15) at 2:1 puts the flats' middles at -15/2 deg + 60 deg steps;
    # SQUARE (offset 0) at 0, 90, 180, 270
    hexa = flanks(max(parts["HEXAGON"].part.section(-10.0), key=len))
    assert all(abs((f.angle + 7.5 + 30.0) % 60.0 - 30.0) < 0.1 for f in hexa)
    square = flanks(max(parts["SQUARE"].part.section(-10.0), key=len))
    assert all(abs((f.angle + 45.0) % 90.0 - 45.0) < 0.1 for f in square)


def test_the_part_keeps_the_bar_where_the_cutter_did_not_reach(parts):
    sec = parts["SQUARE"].part.section(-30.0)             # below the pass: z -25 and the edges above it
    assert len(flanks(sec[0])) == 0
    assert max(math.hypot(*p) for p in sec[0]) == pytest.approx(16.0, abs=0.01)


def _program(tmp_path: Path, body: str) -> Path:
    for f in ("vmach.toml", "tools.toml"):
        shutil.copy(FIX / f, tmp_path / f)
    p = tmp_path / "TEST.MPF"
    p.write_text("G18 G90 G54 DIAMON\nT=\"FLY2\" D1\nG0 X90 Z5\nSETMS(1)\nCOUPDEF(S2, S1, 2, 1)\n"
                 "G95 S800 M3\n" + body + "M30\n", encoding="utf-8")
    return p


def test_a_flywheel_in_the_stock_without_the_coupling_cuts_nothing_and_says_so(tmp_path):
    rep = verify(_program(tmp_path, "G0 X22 Z2\nG1 Z-10 F0.1\nG0 X60\n"), VerifyOptions(images=False))
    assert [(f.kind, f.line) for f in rep.findings if f.severity == "warning"] == [("flywheel_uncoupled", 8)]
    assert len(flanks(rep.part.section(-5.0)[0])) == 0      # the bar as it was


def test_a_coupled_rapid_through_the_bar_is_a_rapid_into_stock(tmp_path):
    rep = verify(_program(tmp_path, "COUPON(S2, S1)\nG0 X22 Z2\nG0 Z-10\nG0 X60\nCOUPOF(S2, S1)\n"),
                 VerifyOptions(images=False))
    assert [(f.kind, f.line) for f in rep.findings if f.severity == "error"] == [("rapid_into_stock", 9)]


def test_the_cutters_body_in_the_bar_is_a_holder_collision(tmp_path):
    # FLY2's body is Ø34 inside its R25 inserts: at X52 (radius 26) it reaches 26 + 25 - 17 = 34 mm
    # from the axis, while the square's corners (where two inserts' ellipses cross, 34.8 mm out)
    # stand inside the Ø70 bar: the inserts never sweep them, the body does
    body = "COUPON(S2, S1)\nG0 X90 Z-5\nG1 X52 F0.05\nG0 X90\nCOUPOF(S2, S1)\n"
    rep = verify(_program(tmp_path, body), VerifyOptions(images=False, stock="cylinder:d=70,l=40"))
    hits = [(f.kind, f.line, f.data.get("part")) for f in rep.findings if f.severity == "error"]
    # the plunge, and the retract from where the plunge ended (the body removes nothing)
    assert hits == [("holder_collision", 9, "flywheel_body"), ("holder_collision", 10, "flywheel_body")]
    # at X60 the body stays 38 mm out, beyond the bar: nothing
    rep = verify(_program(tmp_path, body.replace("X52", "X60")),
                 VerifyOptions(images=False, stock="cylinder:d=70,l=40"))
    assert [f.kind for f in rep.findings if f.severity == "error"] == []


def test_a_feed_too_coarse_for_the_edges_and_a_ratio_that_never_closes_are_said(tmp_path):
    # 2:1 closes after one work turn: 12 mm per turn along Z is more than the 10 mm edges cover
    rep = verify(_program(tmp_path, "COUPON(S2, S1)\nG0 X22 Z2\nG1 Z-20 F12\nG0 X90\nCOUPOF(S2, S1)\n"),
                 VerifyOptions(images=False))
    assert [(f.kind, f.line) for f in rep.findings if f.severity == "warning"] == [("polygon_feed_coarse", 9)]
    # 2.0001:1 is no p/q with q <= 12
    text = "COUPDEF(S2, S1, 2.0001, 1)\nCOUPON(S2, S1)\nG0 X22 Z2\nG1 Z-20 F0.1\nG0 X90\nCOUPOF(S2, S1)\n"
    rep = verify(_program(tmp_path, text), VerifyOptions(images=False))
    assert [(f.kind, f.line) for f in rep.findings if f.severity == "warning"] == [("coupling_ratio", 8)]
    # 0.1 mm per turn at 3:2 (two work turns a period) is fine; 4/3 no warning either
    text = "COUPDEF(S2, S1, 4, 3)\nCOUPON(S2, S1)\nG0 X22 Z2\nG1 Z-20 F0.1\nG0 X90\nCOUPOF(S2, S1)\n"
    rep = verify(_program(tmp_path, text), VerifyOptions(images=False))
    assert [f.kind for f in rep.findings if f.severity != "info"] == []


def test_the_polygon_does_not_depend_on_where_c1_stood(tmp_path, parts):
    # the coupling fixes the cutter to the spindle's zero, not to the last C1 position
    for f in ("vmach.toml", "tools.toml"):
        shutil.copy(FIX / f, tmp_path / f)
    text = (FIX / "HEXAGON.MPF").read_text(encoding="utf-8").replace("N30 G0 X60 Z5", "N30 G0 X60 Z5 C1=40")
    (tmp_path / "HEXC.MPF").write_text(text, encoding="utf-8")
    rep = verify(tmp_path / "HEXC.MPF", VerifyOptions(images=False))
    here = [round(f.angle, 2) for f in flanks(max(rep.part.section(-10.0), key=len))]
    assert here == [round(f.angle, 2) for f in flanks(max(parts["HEXAGON"].part.section(-10.0), key=len))]
