"""The blank's hull for the screening tests (vmach/stock/hull.py) and the mesh blank's cells
(Stock.blank_meets): reduced for a finely meshed blank, looser than exact but never wrong."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from vmach.stock import Stock, engine
from vmach.stock import hull as hull_module
from vmach.stock.clip import shape
from vmach.stock.hull import BANDS, MAX_PLANES, SECTORS, blank_hull, directions


def _inside(planes: np.ndarray, p: np.ndarray, slack: float = 0.0) -> np.ndarray:
    """(k,) bool: points (k, 3) within ``slack`` of the region n·x <= d (in blocks: a fine
    hull's planes times many points would not fit in memory)."""
    return np.concatenate([np.all(p[i : i + 500] @ planes[:, :3].T - planes[:, 3] <= slack, axis=1)
                           for i in range(0, len(p), 500)] or [np.zeros(0, bool)])


@pytest.fixture(scope="module")
def sphere():
    m = trimesh.creation.icosphere(subdivisions=5, radius=30.0)        # 20,480 triangles
    return np.asarray(m.vertices, float), np.asarray(m.faces, np.int64)


def test_a_coarse_hull_is_used_as_it_is(sphere):
    m = trimesh.creation.cylinder(radius=30.0, height=100.0, sections=64)
    h = blank_hull(m.vertices, m.faces)
    assert h.exact
    assert np.array_equal(h.outer, shape(m.vertices, m.faces).planes)
    assert np.array_equal(h.outer, h.inner)


def test_a_fine_hull_is_reduced_to_outer_inner_and_corners_that_bracket_it(sphere):
    v, f = sphere
    exact = shape(v, f).planes
    h = blank_hull(v, f)
    assert not h.exact
    assert len(exact) > 10 * MAX_PLANES
    assert len(h.outer) <= BANDS * SECTORS + 6
    # outer: every vertex of the blank is inside (supporting planes)
    assert _inside(h.outer, v, 1e-9).all()
    # inner: inside the blank — random points inside the inner region are inside the hull
    rng = np.random.default_rng(3)
    p = rng.uniform(-31, 31, (20_000, 3))
    inner = _inside(h.inner, p)
    assert inner.sum() > 8_000
    assert _inside(exact, p[inner], 1e-9).all()
    # ... and close to it: points 0.05 mm inside the sphere are inside the inner region
    shell = directions(5000) * (30.0 * np.cos(np.pi / 320) - 0.05)   # icosphere's own facets
    assert _inside(h.inner, shell).all()
    # corners: the region's vertices reach at least as far as the blank in every direction
    u = directions(2000)
    assert np.all((u @ h.corners.T).max(axis=1) >= (u @ v.T).max(axis=1) - 1e-9)
    assert np.all((u @ h.corners.T).max(axis=1) <= (u @ v.T).max(axis=1) + 1.0)


def test_a_fine_mesh_blank_is_met_cell_by_cell_as_the_whole_blank_would_be(tmp_path, sphere, monkeypatch):
    v, f = sphere
    trimesh.Trimesh(v, f).export(tmp_path / "ball.stl")
    stock = Stock.from_spec(f"mesh:{tmp_path / 'ball.stl'}")
    monkeypatch.setattr(Stock, "BLANK_CELL", 2_000)                   # 11 cells a side
    rng = np.random.default_rng(5)
    agree = hits = 0
    for _ in range(60):
        c = rng.uniform(-33, 33, 3)
        size = rng.uniform(0.2, 4.0, 3)
        q = engine.box(c - size, c + size)
        whole = engine.volume(engine.intersect(stock.initial, q)) > 0.0
        assert stock.blank_meets(q) == whole
        agree += 1
        hits += whole
    assert 10 < hits < 50                      # both answers were asked for
    assert len(stock.blank.cells) > 8         # the cells were made, and only where asked
    assert len(stock.blank.cells) < 11 ** 3


def test_reduced_hull_keeps_the_blank_holds_answers_safe(tmp_path, sphere, monkeypatch):
    v, f = sphere
    trimesh.Trimesh(v, f).export(tmp_path / "ball.stl")
    stock = Stock.from_spec(f"mesh:{tmp_path / 'ball.stl'}")
    p = np.random.default_rng(7).uniform(-31, 31, (20_000, 3))
    held = stock.blank_holds(p)
    exact = _inside(shape(*engine.to_mesh(engine.hull(v), double=True)).planes, p, -1e-6)
    assert not (held & ~exact).any()           # never inside when it is not
    assert held.sum() > 0.99 * exact.sum()
    monkeypatch.setattr(hull_module, "MAX_PLANES", 100_000)
    exact_stock = Stock.from_spec(f"mesh:{tmp_path / 'ball.stl'}")
    assert np.array_equal(exact_stock.blank_holds(p), exact)


def _ringed_cylinder(radius: float = 30.0, length: float = 100.0, sections: int = 400, rings: int = 10):
    """A closed Ø2r cylinder, end face at z = 0, as a CAD export meshes one: side strips cut
    into ``rings - 1`` bands along its length (vertices (p, 3), faces (f, 3), outward)."""
    ang = 2.0 * np.pi * np.arange(sections) / sections
    z = np.linspace(0.0, -length, rings)
    ring = np.column_stack([radius * np.cos(ang), radius * np.sin(ang)])
    v = np.vstack([np.column_stack([ring, np.full(sections, zi)]) for zi in z]
                  + [[[0.0, 0.0, 0.0], [0.0, 0.0, -length]]])
    top, bottom = len(v) - 2, len(v) - 1
    f = []
    for k in range(rings - 1):
        for i in range(sections):
            a, b = k * sections + i, k * sections + (i + 1) % sections
            f += [[a, b + sections, b], [a, a + sections, b + sections]]
    for i in range(sections):
        f += [[top, i, (i + 1) % sections],
              [bottom, (rings - 1) * sections + (i + 1) % sections, (rings - 1) * sections + i]]
    mesh = trimesh.Trimesh(v, np.array(f), process=False)
    assert mesh.is_watertight and mesh.volume > 0
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def test_a_convex_mesh_blank_is_taken_as_its_hull_and_a_dented_one_as_it_is(tmp_path):
    """A cylinder meshed as CAD exports do (side strips cut along its length: 8,000
    triangles) is loaded as its hull — the same solid, a quarter of the triangles — which the
    stock's booleans pay for. The same mesh with one vertex pushed in by 0.001 mm (ten times
    tol.blank_hull) stays as it is."""
    from vmach.stock.spec import parse_stock
    from vmach.tol import tol

    v, f = _ringed_cylinder()
    trimesh.Trimesh(v, f, process=False).export(tmp_path / "cyl.stl")
    notes: list = []
    solid = parse_stock(f"mesh:{tmp_path / 'cyl.stl'}", notes=notes)
    assert engine.num_triangles(solid) < len(f) / 4
    # said (verify reports it as a blank_hull info finding)
    assert [d for _, d in notes] == [{"triangles": len(f), "hull_triangles": engine.num_triangles(solid),
                                      "within_mm": tol.blank_hull}]
    stl = trimesh.load(tmp_path / "cyl.stl", force="mesh")                # its float32 corners
    exact = engine.from_mesh(np.asarray(stl.vertices), np.asarray(stl.faces))
    assert abs(engine.volume(solid) - engine.volume(exact)) < 1e-9 * engine.volume(exact)
    assert engine.volume(engine.subtract(solid, [exact])) < 1e-6          # no material added
    dented = v.copy()
    dented[4 * 400 + 7, :2] *= 1.0 - 10 * tol.blank_hull / 30.0           # on the side, mid-length
    trimesh.Trimesh(dented, f, process=False).export(tmp_path / "dent.stl")
    notes = []
    assert engine.num_triangles(parse_stock(f"mesh:{tmp_path / 'dent.stl'}", notes=notes)) == len(f)
    assert notes == []


def test_a_mesh_whose_vertices_all_lie_on_its_hull_is_not_taken_for_it_when_a_face_folds_in():
    """A box whose top has one corner raised by 0.01 mm: triangulated along the raised corner's
    diagonal, every triangle lies on a hull face; along the other diagonal the top folds inward
    (a valley) while every vertex still lies on the hull — lies_on_hull tells them apart, the
    vertices alone could not."""
    from vmach.stock.hull import lies_on_hull

    box = trimesh.creation.box((10.0, 10.0, 10.0))
    v = np.asarray(box.vertices, float).copy()
    top = np.nonzero(v[:, 2] > 0)[0]
    corner = top[np.argmax(v[top, 0] + v[top, 1])]                       # (+5, +5, +5)
    v[corner, 2] += 0.01
    others = [i for i in top if i != corner]
    opposite = others[int(np.argmin([v[i, 0] + v[i, 1] for i in others]))]
    sides = [i for i in others if i != opposite]
    keep = [list(t) for t in np.asarray(box.faces) if not all(i in top for i in t)]

    def with_top(diagonal):
        a, b = diagonal
        c, d = [i for i in top if i not in diagonal]
        faces = np.array(keep + [[a, b, c], [a, d, b]])
        m = trimesh.Trimesh(v, faces, process=False)
        m.fix_normals()
        return np.asarray(m.vertices), np.asarray(m.faces)

    # along the raised corner's diagonal the top is a ridge (convex); along the other, a valley
    for diagonal, convex in (((corner, opposite), True), ((sides[0], sides[1]), False)):
        mv, mf = with_top(diagonal)
        hv, hf = engine.hull_mesh(mv)
        assert lies_on_hull(mv, mf, hv, hf, 1e-4) == convex
    # a triangle of no area is judged by its corners: on the hull, or 5 mm inside it
    bv, bf = np.asarray(box.vertices, float), np.asarray(box.faces)
    hv, hf = engine.hull_mesh(bv)
    assert lies_on_hull(bv, np.vstack([bf, [[0, 0, 1]]]), hv, hf, 1e-4)
    inner = np.vstack([bv, [[0.0, 0.0, 0.0]]])
    assert not lies_on_hull(inner, np.vstack([bf, [[8, 8, 1]]]), hv, hf, 1e-4)
