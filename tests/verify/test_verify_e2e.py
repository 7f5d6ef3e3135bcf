"""Broken variants of our own fixture program: each yields exactly the expected finding kind at
the expected line (issue 5 acceptance), and the clean program yields none."""

from __future__ import annotations

import json
import re
import shutil

import numpy as np
import pytest
from catalog import FIXTURES, POLYGON_TOOLS

from vmach.cli import main
from vmach.verify import VerifyOptions, verify

FLATS = FIXTURES / "turnmill"


def variant(tmp_path, old: str | None = None, new: str | None = None, tools: str | None = None):
    d = tmp_path / "job"
    shutil.copytree(FLATS, d)
    text = (d / "FLATS.MPF").read_text()
    if old is not None:
        assert old in text
        text = text.replace(old, new)
        (d / "FLATS.MPF").write_text(text)
    if tools is not None:
        (d / "tools.toml").write_text(tools)       # the fixture's own library, replaced
    lines = text.splitlines()

    def line_of(prefix: str) -> int:
        return next(i + 1 for i, ln in enumerate(lines) if ln.startswith(prefix))

    return d / "FLATS.MPF", line_of


def errors(report):
    return sorted((f.kind, f.line) for f in report.findings if f.severity == "error")


def test_clean_fixture_verifies_without_findings(tmp_path):
    prog, _ = variant(tmp_path)
    report = verify(prog, VerifyOptions(images=False))
    assert report.findings == []
    assert report.part.volume < 3.141592653589793 * 15**2 * 60  # the flats removed material


def test_g0_through_the_stock_is_a_rapid_into_stock(tmp_path):
    prog, line_of = variant(tmp_path, "N130 G1 Z-7.5 F400", "N130 G0 Z-7.5 F400")
    report = verify(prog, VerifyOptions(images=False))
    assert errors(report) == [("rapid_into_stock", line_of("N130"))]
    f = next(f for f in report.findings if f.kind == "rapid_into_stock")
    # what the plunge removes, computed independently: beyond the plane x = 12 inside the Ø30
    # shaft, from the end face z = 0 down to the cutter's round edge z = -7.5 - sqrt(12.5² - y²)
    y = np.linspace(-9.0, 9.0, 200001)
    depth = np.sqrt(15.0**2 - y**2) - 12.0
    length = 7.5 + np.sqrt(12.5**2 - y**2)
    assert f.data["volume_mm3"] == pytest.approx(np.trapezoid(depth * length, y), rel=0.002)
    # ... and where: the chip's centre of mass, by the same integrals (C = 0: the work frame's
    # X is the machine's; the chip is symmetric about y = 0)
    vol = np.trapezoid(depth * length, y)
    x_bar = np.trapezoid((np.sqrt(15.0**2 - y**2) ** 2 - 12.0**2) / 2 * length, y) / vol
    z_bar = np.trapezoid(depth * -(length**2) / 2, y) / vol
    assert f.data["at_mm"] == pytest.approx([x_bar, 0.0, z_bar], abs=0.005)


def test_tool_too_short_so_the_holder_touches_the_shoulder(tmp_path):
    tools = (
        POLYGON_TOOLS.read_text()
        .replace("cutting_length = 38.0", "cutting_length = 2.0")
        .replace("shank = { diameter = 25.0, length = 40.0 }", "shank = { diameter = 25.0, length = 0.5 }")
    )
    prog, line_of = variant(tmp_path, tools=tools)
    report = verify(prog, VerifyOptions(images=False))
    assert {k for k, _ in errors(report)} == {"holder_collision"}
    hits = [f for f in report.findings if f.kind == "holder_collision"]
    # the Ø50 holder, 2.5 mm behind the face at X = 14.5 < 15, meets the shaft's end already on
    # the approach to X12 (it reaches 25 mm below Z15), reaches below the shoulder at z = -20
    # while the tool plunges, and still touches it as the feed retract starts
    assert {f.line for f in hits} == {line_of(n) for n in ("N120", "N130", "N140", "N170", "N180", "N190")}
    # the 0.5 mm shank behind the 2 mm cutter rubs the material the cutter could not reach
    assert {f.data["part"] for f in hits} == {"holder", "shank"}
    retract = [f for f in hits if f.data["part"] == "holder" and f.line == line_of("N140")]
    assert retract and retract[0].data["at_mm"][2] < -20  # what it touches is below the shoulder


def test_x_beyond_travel_is_an_axis_limit(tmp_path):
    prog, line_of = variant(tmp_path, "N110 G0 X40 Y0 Z15", "N110 G0 X340 Y0 Z15")
    report = verify(prog, VerifyOptions(images=False))
    assert errors(report) == [("axis_limit", line_of("N110"))]


def test_rapid_into_the_chuck_jaws_is_a_fixture_collision(tmp_path):
    prog, line_of = variant(tmp_path, "N140 G1 X40\n", "N140 G1 X40\nN145 G0 Z-72\n")
    report = verify(prog, VerifyOptions(images=False))
    errs = errors(report)
    assert {k for k, _ in errs} == {"fixture_collision"}
    assert errs[0][1] == line_of("N145")  # going down; the next rapid starts inside the jaw
    assert {f.data["obstacle"] for f in report.findings if f.kind == "fixture_collision"} == {"jaw_1"}


def test_cli_writes_report_and_pictures(tmp_path, capsys):
    prog, line_of = variant(tmp_path, "N130 G1 Z-7.5 F400", "N130 G0 Z-7.5 F400")
    out = tmp_path / "out"
    assert main(["verify", str(prog), "--out", str(out), "--format", "json"]) == 1
    data = json.loads((out / "report.json").read_text())
    assert data == json.loads(capsys.readouterr().out)
    assert [(f["kind"], f["line"]) for f in data["findings"]] == [("rapid_into_stock", line_of("N130"))]
    assert set(data) >= {"program", "machine", "findings", "simulation", "profile", "cycle_time_s", "images",
                         "timings_s"}
    assert data["simulation"]["cutters"] > 0 and data["simulation"]["error_bounds_mm"]["tool_polygon"] == 0.01
    assert data["cycle_time_s"] > 0 and data["cycle_time"]["per_tool"]
    for name in ("toolpath", "collision_1"):
        assert (out / data["images"][name]).stat().st_size > 1000


def test_accuracy_fine_simulates_to_its_finer_bounds_and_says_so(tmp_path, capsys):
    prog, _ = variant(tmp_path)
    out = tmp_path / "out"
    assert main(["verify", str(prog), "--out", str(out), "--no-images", "--accuracy", "fine"]) == 0
    text = capsys.readouterr().out
    sim = json.loads((out / "report.json").read_text())["simulation"]
    assert sim["accuracy"] == "fine"
    assert (sim["error_bounds_mm"]["tool_polygon"], sim["error_bounds_mm"]["side_cusps"]) == (0.004, 0.0035)
    assert re.search(r"stock \(fine accuracy\): \d+ cutters .* 0\.004 mm on sides", text)
    standard = verify(prog, VerifyOptions(images=False))
    fine = verify(prog, VerifyOptions(images=False, accuracy="fine"))
    assert standard.simulation()["accuracy"] == "standard" and fine.part.chord == 0.004
    assert fine.findings == standard.findings == []
    # the same part to within the two simulations' bounds (tool polygons of 0.01 and 0.004 mm)
    v, f = fine.part.mesh()
    area = 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1).sum()
    assert 0 < abs(standard.part.volume - fine.part.volume) < 0.014 * area
    with pytest.raises(SystemExit) as e:
        main(["verify", str(prog), "--accuracy", "coarse"])
    assert e.value.code == 2 and "invalid choice: 'coarse'" in capsys.readouterr().err
    # the setup file beside the program may ask for it; a name it does not know is an error
    setup = prog.parent / "vmach.toml"
    setup.write_text('accuracy = "fine"\n' + setup.read_text())
    assert verify(prog, VerifyOptions(images=False)).simulation()["accuracy"] == "fine"
    assert verify(prog, VerifyOptions(images=False, accuracy="standard")).part.chord == 0.01
    setup.write_text(setup.read_text().replace('"fine"', '"ultra"'))
    assert main(["verify", str(prog), "--out", str(out)]) != 0
    err = capsys.readouterr().err
    assert f"{setup}:1:1: error[usage]" in err      # at the setting's line in the file
    assert "Traceback" not in err


def test_stock_from_the_programs_workpiece_block(tmp_path):
    prog, _ = variant(tmp_path, "N10 TRANS\n", 'N5 WORKPIECE(,"",,"CYLINDER",192,0,-60,-80,30)\nN10 TRANS\n')
    setup = prog.parent / "vmach.toml"
    setup.write_text("\n".join(ln for ln in setup.read_text().splitlines() if not ln.startswith("stock")))
    report = verify(prog, VerifyOptions(images=False))
    assert report.stock_spec == "cylinder:d=30,l=60,z=0"
    assert report.findings == [] and report.part is not None
    # the text summary says what the simulation did and how far it may be off
    from vmach.commands.verify import summary

    lines = summary(report, tmp_path).splitlines()
    line = [ln for ln in lines if ln.startswith("stock (standard accuracy):")]
    want = r"\d+ cutters \(\d+ fans\); simulation error within 0\.\d{4} mm on flat faces, 0\.01 mm on sides"
    assert len(line) == 1 and re.search(want, line[0])


def test_unknown_workpiece_form_is_a_clear_error(tmp_path, capsys):
    prog, line_of = variant(
        tmp_path, "N10 TRANS\n", 'N5 WORKPIECE(,"",,"CONE",192,0,-60,-80,30)\nN10 TRANS\n'
    )
    setup = prog.parent / "vmach.toml"
    setup.write_text("\n".join(ln for ln in setup.read_text().splitlines() if not ln.startswith("stock")))
    assert main(["verify", str(prog), "--out", str(tmp_path / "o"), "--no-images"]) == 2
    err = capsys.readouterr().err
    assert f"FLATS.MPF:{line_of('N5')}:1: error[workpiece]" in err and "Traceback" not in err


def test_rapid_close_to_the_stock_is_a_near_miss(tmp_path):
    # the approach stops 0.4 mm above the end face: the cutter's round edge at Z15 - 12.5 = 2.5
    # would clear it by 2.5 mm; at Z12.9 it passes 0.4 mm over the face at z = 0
    prog, line_of = variant(
        tmp_path, "N110 G0 X40 Y0 Z15\n", "N110 G0 X40 Y0 Z15\nN115 G0 X12 Z12.9\nN116 G0 X40\n"
    )
    report = verify(prog, VerifyOptions(images=False))
    near = [f for f in report.findings if f.kind == "near_miss"]
    # in, out, and in again (the original approach N120 now runs at Z12.9 too)
    assert [(f.line, f.severity) for f in near] == [(line_of(n), "warning") for n in ("N115", "N116", "N120")]
    assert near[0].data["distance_mm"] == pytest.approx(0.4, abs=0.02)
    assert report.errors == 0
    # with a smaller clearance it is not reported
    report = verify(prog, VerifyOptions(images=False, clearance=0.3))
    assert [f for f in report.findings if f.kind == "near_miss"] == []
