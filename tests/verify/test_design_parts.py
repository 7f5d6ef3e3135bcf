"""The pieces of ``verify --design``: the band and offset options, the design's loader, the
signed distance, the regions of two boxes, the colours of the picture."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from stepfile import box_step

from vmach.checks.design import Band, compare, load_design, parse_band, parse_offset
from vmach.checks.distance import SignedDistance
from vmach.cli import main
from vmach.errors import InputError
from vmach.report.render import BAND_RGB, EXCESS_RGB, GOUGE_RGB, design_colours
from vmach.stock import engine


@pytest.mark.parametrize("text, lo, hi", [
    ("+0.05/-0.02", -0.02, 0.05), ("-0.02/+0.05", -0.02, 0.05), ("±0.01", -0.01, 0.01),
    ("+-0.03", -0.03, 0.03), ("0.02", -0.02, 0.02), ("+0.1/0", 0.0, 0.1),
])
def test_tolerance_bands(text, lo, hi):
    assert parse_band(text) == Band(lo, hi)


@pytest.mark.parametrize("text", ["0.05", "+0.05/+0.02", "-0.01/-0.02", "a/b", "+0.05/-0.02/0", ""])
def test_bad_bands_are_usage_errors(text):
    if text == "0.05":          # a symmetric band: fine
        assert parse_band(text) == Band(-0.05, 0.05)
        return
    with pytest.raises(InputError) as exc:
        parse_band(text)
    assert exc.value.kind == "usage"


def test_offsets():
    assert parse_offset("1,-2,0.5").tolist() == [1.0, -2.0, 0.5]
    assert parse_offset(None).tolist() == [0.0, 0.0, 0.0]
    for bad in ("1,2", "1,2,x", "1,2,nan"):
        with pytest.raises(InputError):
            parse_offset(bad)


def _box(tmp_path, name="box.stl", extents=(10, 20, 5)):
    path = tmp_path / name
    trimesh.creation.box(extents).export(path)
    return path


def test_the_loader_reads_a_closed_mesh_and_moves_it(tmp_path):
    v, f = load_design(_box(tmp_path), offset=np.array([1.0, 2.0, -2.5]))
    assert np.allclose(v.min(axis=0), [-4, -8, -5]) and np.allclose(v.max(axis=0), [6, 12, 0])
    assert len(f) == 12


def test_the_loader_refuses_open_meshes_unknown_formats_and_missing_files(tmp_path):
    box = trimesh.creation.box((10, 10, 10))
    open_box = trimesh.Trimesh(box.vertices, box.faces[:-1])
    open_box.export(tmp_path / "open.stl")
    with pytest.raises(InputError) as exc:
        load_design(tmp_path / "open.stl")
    assert exc.value.kind == "design_mesh"
    (tmp_path / "part.obj").write_text("v 0 0 0\n")
    with pytest.raises(InputError) as exc:
        load_design(tmp_path / "part.obj")
    assert exc.value.kind == "design_format"
    with pytest.raises(InputError) as exc:
        load_design(tmp_path / "none.stl")
    assert exc.value.kind == "unreadable"
    (tmp_path / "junk.stl").write_bytes(b"\x00" * 30)
    with pytest.raises(InputError):
        load_design(tmp_path / "junk.stl")


def test_a_step_design_is_read_in_mm_or_refused_clearly_without_cascadio(tmp_path):
    """STEP goes through trimesh and cascadio (the optional extra vmach[step]): with it, our
    own STEP box comes back in mm (cascadio writes glTF, in metres); without it, the error
    says what to install."""
    path = tmp_path / "box.step"
    path.write_text(box_step((-5, -10, -3), (5, 10, 0)))
    try:
        import cascadio  # noqa: F401
    except ImportError:
        with pytest.raises(InputError) as exc:
            load_design(path)
        assert exc.value.kind == "design_format" and "cascadio" in str(exc.value)
        return
    v, f = load_design(path)
    assert np.allclose(v.min(axis=0), [-5, -10, -3], atol=1e-5)
    assert np.allclose(v.max(axis=0), [5, 10, 0], atol=1e-5)
    assert trimesh.Trimesh(v, f).volume == pytest.approx(600.0, rel=1e-6)


def test_signed_distance_of_a_box_is_exact_inside_and_outside():
    half = np.array([10.0, 5.0, 3.0])
    box = trimesh.creation.box(2 * half).subdivide()
    rng = np.random.default_rng(7)
    p = rng.uniform(-15, 15, (5000, 3))
    q = np.abs(p) - half
    exact = np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(axis=1), 0)
    d = SignedDistance(box.vertices, box.faces)(p)
    assert np.abs(d - exact).max() < 1e-9
    assert (d[exact < -1e-6] < 0).all() and (d[exact > 1e-6] > 0).all()


def test_regions_of_a_part_against_a_design_two_boxes():
    """A 20 x 20 x 10 part whose design is 0.3 mm lower on top and has a 2 x 2 x 1 pocket
    that the part lacks: one excess region 0.3 mm deep over the top (less the pocket's
    opening) and one for the pocket 1 mm deep; no gouge."""
    part = engine.box((-10, -10, -10), (10, 10, 0))
    d = engine.subtract(engine.box((-10, -10, -10), (10, 10, -0.3)), [engine.box((-1, -1, -1.3), (1, 1, 0))])
    design = engine.to_mesh(d, double=True)
    res = compare(part, design, Band(-0.02, 0.05))
    kinds = [(r.kind, round(r.depth, 6)) for r in res.regions]
    assert kinds == [("excess", 1.3)] or kinds == [("excess", 1.3), ("excess", 0.3)] or \
        sorted(kinds) == [("excess", 0.3), ("excess", 1.3)] or kinds == [("excess", 1.3)]
    total = sum(r.volume for r in res.regions)
    assert total == pytest.approx(20 * 20 * 0.3 + 2 * 2 * 1.0, rel=1e-6)
    assert res.deviation.max() == pytest.approx(0.3, abs=1e-9)  # the part's top corners
    assert res.deviation.min() == pytest.approx(0.0, abs=1e-9)


def test_colours_grey_in_the_band_blue_below_red_above():
    rgb = design_colours(np.array([0.0, 0.04, -0.019, -0.5, 0.5, -0.021]), (-0.02, 0.05))
    assert rgb[0].tolist() == list(BAND_RGB) and rgb[1].tolist() == list(BAND_RGB)
    assert rgb[2].tolist() == list(BAND_RGB)
    assert rgb[3].tolist() == list(GOUGE_RGB) and rgb[4].tolist() == list(EXCESS_RGB)
    assert rgb[5][2] > rgb[5][0]                      # just past the band: already bluish


def test_design_without_a_stock_is_a_usage_error(tmp_path, capsys):
    prog = tmp_path / "P.MPF"
    prog.write_text("G0 X10\nM30\n")
    box = _box(tmp_path)
    rc = main(["verify", str(prog), "--machine", "s5d", "--design", str(box), "--out",
               str(tmp_path / "out"), "--quiet", "--no-images"])
    assert rc == 2
    assert "error[usage]" in capsys.readouterr().err
