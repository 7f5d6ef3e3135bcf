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
    assert len(stock._blank_cells) > 8         # the cells were made, and only where asked
    assert len(stock._blank_cells) < 11 ** 3


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
