"""``verify --design``: the milling fixture (fixtures/milling/PLATE.MPF) against its own
exported part, and two variants with a real programming slip each: the outline milled 0.2 mm
too deep (Z-6.2 for Z-6) and the bolt-circle holes drilled 1 mm short (CYCLE81 depth -7 for
-8). The design is the part of the original program, written by ``--export``: the three runs
cut the same walls, so the only regions are the slips."""

from __future__ import annotations

import json
import math
import shutil

import numpy as np
import pytest
from catalog import FIXTURES

from vmach.cli import main

PLATE = FIXTURES / "milling"


def _lines_of(text: str, *blocks: str) -> list[int]:
    """1-based line numbers of the blocks starting with the given N words."""
    found = {}
    for i, line in enumerate(text.splitlines(), start=1):
        word = line.split(" ", 1)[0]
        if word in blocks:
            found[word] = i
    return [found[b] for b in blocks]


def _program(directory, replace: tuple[str, str] | None = None):
    directory.mkdir(parents=True, exist_ok=True)
    for name in ("vmach.toml", "tools.toml"):
        shutil.copy(PLATE / name, directory / name)
    text = (PLATE / "PLATE.MPF").read_text()
    if replace is not None:
        assert replace[0] in text
        text = text.replace(*replace)
    prog = directory / "PLATE.MPF"
    prog.write_text(text)
    return prog, text


def _verify(prog, out, *extra) -> tuple[int, dict]:
    rc = main(["verify", str(prog), "--out", str(out), "--quiet", *extra])
    return rc, json.loads((out / "report.json").read_text())


@pytest.fixture(scope="module")
def design(tmp_path_factory):
    """The fixture's own part, exported, and the report of that run checked against it."""
    root = tmp_path_factory.mktemp("plate")
    prog, _ = _program(root / "own")
    part = root / "plate.stl"
    rc, _ = _verify(prog, root / "export", "--no-images", "--export", str(part))
    assert rc == 0 and part.is_file()
    return root, part


def _design_findings(report: dict) -> list[dict]:
    return [f for f in report["findings"] if f["kind"].startswith("design_")]


def _check(design, name: str, *extra, replace=None) -> tuple[int, dict, str]:
    """Verify the fixture (``replace``: (old, new) text) in ``name`` against the exported part."""
    root, part = design
    prog, text = _program(root / name, replace)
    rc, report = _verify(prog, root / f"out_{name}", "--design", str(part), *extra)
    return rc, report, text


def test_the_fixture_against_its_own_part_has_no_design_findings(design):
    root, _ = design
    rc, report, _ = _check(design, "again", "--no-images", "--design-tolerance", "+0.05/-0.02")
    assert rc == 0
    assert _design_findings(report) == []
    d = report["design"]
    assert d["tolerance_mm"] == [-0.02, 0.05]
    assert d["gouges"] == 0 and d["excess"] == 0
    assert d["max_gouge_mm"] < 1e-4 and d["max_excess_mm"] < 1e-4      # float32 rounding of the STL
    assert d["within_band"] == 1.0
    arrays = np.load(root / "out_again" / d["deviation_file"])
    assert arrays["deviation"].shape == (d["vertices"],)
    assert arrays["faces"].max() < len(arrays["vertices"])
    assert not arrays["region"].any()


def test_an_outline_milled_too_deep_is_one_gouge_naming_the_outline(design):
    root, _ = design
    rc, report, text = _check(design, "deep", replace=("N50 G1 Z-6 F300", "N50 G1 Z-6.2 F300"))
    assert rc == 1
    found = _design_findings(report)
    assert [f["kind"] for f in found] == ["design_gouge"]
    g = found[0]
    assert g["depth_mm"] == pytest.approx(0.2, abs=0.01)
    # the ring between the 70 x 50 blank and the 60 x 40 outline with R6 corners, 0.2 mm thick
    ring = 70 * 50 - (60 * 40 - (4 - math.pi) * 36)
    assert g["volume_mm3"] == pytest.approx(0.2 * ring, rel=0.01)
    assert g["bbox_mm"][0][2] == pytest.approx(-6.2, abs=1e-3)
    assert g["bbox_mm"][1][2] == pytest.approx(-6.0, abs=1e-3)
    outline = _lines_of(text, "N60", "N70", "N80", "N90", "N100", "N110", "N120")
    assert sorted({x["line"] for x in g["lines"]}) == outline
    assert g["line"] in outline and g["lines_touch"] is True
    # the picture is drawn and listed
    assert report["images"]["design_deviation"] == "design_deviation.png"
    assert (root / "out_deep" / "design_deviation.png").stat().st_size > 10_000
    arrays = np.load(root / "out_deep" / "design_deviation.npz")
    floor = np.abs(arrays["vertices"][:, 2] + 6.2) < 1e-6
    assert floor.sum() > 10
    dev, (x, y) = arrays["deviation"][floor], arrays["vertices"][floor, :2].T
    assert dev.min() == pytest.approx(-0.2, abs=1e-6) and dev.max() < 1e-6
    # farther than 0.2 mm from the walls (whose feet lie on the design's), 0.2 mm below the design
    ring = (np.abs(x) < 34.75) & (np.abs(y) < 24.75) & ((np.abs(x) > 30.25) | (np.abs(y) > 20.25))
    assert ring.sum() > 10 and np.allclose(dev[ring], -0.2, atol=1e-6)
    assert set(np.unique(arrays["region"][floor][ring])) == {1}


def test_holes_drilled_short_are_excess_at_each_hole_naming_the_cycle(design):
    rc, report, text = _check(design, "short", "--no-images",
                              replace=("CYCLE81(5, 0, 2, -8)", "CYCLE81(5, 0, 2, -7)"))
    assert rc == 1
    found = _design_findings(report)
    assert [f["kind"] for f in found] == ["design_excess"] * 4
    (holes,) = _lines_of(text, "N170")
    centres = []
    for f in found:
        # the drill's rim 1 mm above where it should be: 1 mm from the design's rim; the 118°
        # point is 1 mm · sin 59° from the design's cone
        assert f["depth_mm"] == pytest.approx(1.0, abs=0.01)
        assert f["volume_mm3"] == pytest.approx(math.pi * 3.4 ** 2 * 1.0, rel=0.02)
        assert f["bbox_mm"][0][2] == pytest.approx(-8.0, abs=0.01)
        assert [x["line"] for x in f["lines"]] == [holes] and f["line"] == holes
        centres.append(f["centroid_mm"][:2])
    angles = sorted(round(math.degrees(math.atan2(y, x))) % 360 for x, y in centres)
    assert angles == [45, 135, 225, 315]
    assert all(math.hypot(x, y) == pytest.approx(12.0, abs=0.01) for x, y in centres)
    part_dev = report["design"]["max_excess_mm"]
    assert part_dev == pytest.approx(math.sin(math.radians(59.0)), abs=0.01)


def test_a_design_moved_off_the_part_says_so(design):
    rc, report, _ = _check(design, "moved", "--no-images", "--design-offset", "0,0,0.3")
    assert rc == 1
    kinds = [f["kind"] for f in _design_findings(report)]
    assert "design_placement" in kinds and "design_gouge" in kinds and "design_excess" in kinds
    assert report["design"]["offset_mm"] == [0.0, 0.0, 0.3]
    placement = next(f for f in report["findings"] if f["kind"] == "design_placement")
    assert placement["beyond_mm"] == pytest.approx(0.3, abs=1e-3)


def test_report_html_colours_the_part_by_its_distance_to_the_design(design):
    """report.html's 3-D view shows the comparison (#38): the part coloured by its signed
    distance to the design against the design's band, the gouge in the gouge colour."""
    import base64
    import re

    root, _ = design
    rc, report, _ = _check(design, "deep_html", "--no-images", "--design-tolerance", "+0.05/-0.02",
                           replace=("N50 G1 Z-6 F300", "N50 G1 Z-6.2 F300"))
    assert rc == 1
    page = (root / "out_deep_html" / "report.html").read_text()
    scene = json.loads(re.search(r"<script type='application/json' id='scene-data'>(.*?)</script>",
                                 page, re.S).group(1).replace("<\\/", "</"))
    assert scene["band"]["what"] == "design" and "deviation from the design" in page
    assert (scene["band"]["lo_um"], scene["band"]["hi_um"]) == pytest.approx((-20.0, 50.0))
    rgb = np.frombuffer(base64.b64decode(scene["part"]["colours"]), np.uint8).reshape(-1, 3)
    assert len(rgb) == report["design"]["vertices"]
    arrays = np.load(root / "out_deep_html" / report["design"]["deviation_file"])
    dev = arrays["deviation"]
    assert len(rgb) == len(dev)
    blue = rgb[:, 2].astype(int) > rgb[:, 0].astype(int) + 40       # the gouge colour
    grey = np.ptp(rgb.astype(int), axis=1) < 8                        # within the band
    assert blue.sum() > 10 and np.array_equal(blue, dev < -0.02)
    assert np.array_equal(grey, (dev >= -0.02) & (dev <= 0.05))
    # the region's label stands at its deepest point
    gouge = next(f for f in report["findings"] if f["kind"] == "design_gouge")
    assert [p["at"] for p in scene["places"] if p["kind"] == "design_gouge"] == [
        pytest.approx(gouge["deepest_mm"], abs=1e-4)]
