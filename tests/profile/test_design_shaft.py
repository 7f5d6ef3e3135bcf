"""The polygon shaft's design, made from its profile (``vmach profile P3G 50 --design-stl``),
and ``verify --design`` against it agreeing with the profile check where both apply (the
flanks between the profile check's stations)."""

from __future__ import annotations

import json
import math
import shutil

import numpy as np
import pytest
import trimesh
from catalog import POLYGON_DIR, POLYGON_TOOLS

from vmach.checks.nominal import ShaftDesign, parse_pair, shaft_mesh
from vmach.checks.polygon import parse_profile
from vmach.cli import main
from vmach.errors import InputError

P3G50 = parse_profile("P3G:50")


def test_the_plain_polygon_prism_has_the_profiles_area_times_its_length():
    v, f = shaft_mesh(P3G50, ShaftDesign(length=40))
    mesh = trimesh.Trimesh(v, f, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    # 1440 chords inside the curve, each at most 0.1 µm from it: 4e-6 of the area
    assert mesh.volume == pytest.approx(P3G50.area * 40, rel=1e-5)
    assert mesh.volume < P3G50.area * 40
    assert v[:, 2].max() == 0.0 and v[:, 2].min() == -40.0


def test_the_shaft_end_with_chamfer_and_shoulder():
    design = ShaftDesign(length=40, chamfer=(15, 3), shoulder=(60, 60), phase_deg=30)
    v, f = shaft_mesh(P3G50, design)
    mesh = trimesh.Trimesh(v, f, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert v[:, 2].min() == -100.0
    # the flanks' edges below the chamfer and at the shoulder lie on the profile turned by the phase
    flank = np.isin(v[:, 2], (-3.0, -40.0)) & (np.hypot(v[:, 0], v[:, 1]) < 28)
    assert flank.sum() == 2 * 1440
    d = P3G50.signed_distance(v[flank, :2], math.radians(30))
    assert np.abs(d).max() < 1e-9
    # the end face: the profile moved in by 3·tan 15°
    top = (v[:, 2] == 0.0) & (np.hypot(v[:, 0], v[:, 1]) > 1)
    assert np.allclose(P3G50.signed_distance(v[top, :2], math.radians(30)), -3 * math.tan(math.radians(15)))
    # shoulder cylinder Ø60 from Z -40 to -100, the polygon, and the chamfer: parallel curves
    # δ inside (Steiner: area A − Lδ + πδ², L = π·d1 for a curve of constant width d1), δ
    # falling linearly from 3·tan 15° to 0 over 3 mm
    d0 = 3 * math.tan(math.radians(15))
    chamfer = 3 * (P3G50.area - math.pi * 50 * d0 / 2 + math.pi * d0 ** 2 / 3)
    body = math.pi * 30 ** 2 * 60 + P3G50.area * 37 + chamfer
    assert mesh.volume == pytest.approx(body, rel=1e-5)


def test_bad_design_options():
    with pytest.raises(InputError):
        parse_pair("15", "--chamfer")
    with pytest.raises(InputError):
        parse_pair("15x-3", "--chamfer")
    with pytest.raises(InputError):
        shaft_mesh(P3G50, ShaftDesign(length=40, shoulder=(50, 10)))      # inside the profile
    with pytest.raises(InputError):
        shaft_mesh(P3G50, ShaftDesign(length=2, chamfer=(15, 3)))


def test_the_profile_command_writes_the_design(tmp_path, capsys):
    out = tmp_path / "shaft.stl"
    rc = main(["profile", "P3G", "50", "--design-stl", str(out), "--length", "40", "--chamfer", "15x3",
               "--shoulder", "60:60", "--phase", "30", "--format", "json"])
    assert rc == 0
    data = json.loads(capsys.readouterr().out)
    mesh = trimesh.load(out)
    assert mesh.is_watertight and len(mesh.faces) == data["design"]["triangles"]
    assert main(["profile", "P3G", "50", "--design-stl", str(tmp_path / "x.stl")]) == 2   # no --length


@pytest.mark.slow
def test_verify_design_agrees_with_the_profile_check(tmp_path):
    """The fixture's subprogram with one roughing and one facing pass and 0.1 mm Z steps (to
    keep the test short), its flanks finished 40 µm inside the nominal profile (R59 = -0.04):
    the profile check fails and so does the design (±0.02 mm), by the same numbers."""
    shutil.copy(POLYGON_DIR / "P3G_SHAFT.SPF", tmp_path / "P3G_SHAFT.SPF")
    text = (POLYGON_DIR / "POLY50.MPF").read_text()
    for old, new in (("R65=0.01", "R65=0.1"), ("R66=3", "R66=1"), ("R68=2", "R68=1"),
                     ("R59=-0.0085", "R59=-0.04")):
        assert old in text
        text = text.replace(old, new)
    prog = tmp_path / "POLYR.MPF"
    prog.write_text(text)
    design = tmp_path / "shaft.stl"
    assert main(["profile", "P3G", "50", "--design-stl", str(design), "--length", "40", "--chamfer", "15x3",
                 "--shoulder", "60:60", "--phase", "30"]) == 0
    out = tmp_path / "out"
    rc = main(["verify", str(prog), "--machine", "turnmill", "--tools", str(POLYGON_TOOLS), "--stock",
               "cylinder:d=60,l=100", "--profile", "P3G:50", "--profile-z", "-35:-5", "--design", str(design),
               "--design-tolerance", "+-0.02", "--out", str(out), "--quiet", "--no-images"])
    assert rc == 1
    report = json.loads((out / "report.json").read_text())
    profile = report["profile"]
    assert profile["pass"] is False and profile["phase_deg"] == pytest.approx(30.0, abs=0.05)
    gouges = [f for f in report["findings"] if f["kind"] == "design_gouge"]
    assert len(gouges) == 1 and not [f for f in report["findings"] if f["kind"] == "design_excess"]
    assert gouges[0]["depth_mm"] == pytest.approx(0.04, abs=0.002)
    # the finishing and edge lines made it
    spf = (POLYGON_DIR / "P3G_SHAFT.SPF").read_text().splitlines()
    finishing = [i for i, s in enumerate(spf, start=1) if s.startswith(("N990", "N1160"))]
    assert set(finishing) <= {x["line"] for x in gouges[0]["lines"]}
    arrays = np.load(out / report["design"]["deviation_file"])
    v, dev = arrays["vertices"], arrays["deviation"]
    flank = (v[:, 2] >= -35) & (v[:, 2] <= -5) & (np.hypot(v[:, 0], v[:, 1]) < 28)
    lo = min(s["min_deviation_mm"] for s in profile["stations"])
    hi = max(s["max_deviation_mm"] for s in profile["stations"])
    # the profile check samples its sections' edges every 0.02 mm, the design the part's
    # vertices: the same flank, the same deviation to 1 µm
    assert dev[flank].min() == pytest.approx(lo, abs=1e-3)
    assert dev[flank].max() == pytest.approx(hi, abs=1e-3)
