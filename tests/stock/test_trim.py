"""Cutters trimmed to the box around the stock (vmach/stock/clip.py): exact, and the trimmed
faces lie exactly in the box's planes."""

from __future__ import annotations

import numpy as np
import pytest

from tests.stock.conftest import turnmill
from vmach.stock import Stock, engine
from vmach.stock.clip import clip, shape
from vmach.stock.fan import prism
from vmach.stock.slabs import GRID, JITTER, Slabs
from vmach.stock.view import View
from vmach.tol import tol
from vmach.tooling import frames, tool_solid


@pytest.fixture(scope="module")
def d25_shape(library):
    ts = tool_solid(library.lookup("GLOD D25"), 0.01)
    return ts, shape(*engine.hull_mesh(ts.pieces[0]))


@pytest.mark.parametrize("arcs", [False, True])
def test_shape_planes_contain_the_piece_and_edges_are_the_real_ones(library, arcs):
    ts = tool_solid(library.lookup("GLOD D25"), 0.01, arcs=arcs)
    sh = shape(*engine.hull_mesh(ts.pieces[0]))
    n = len(prism(ts.pieces[0]).ring)       # the polygon's vertices (and its arcs' points)
    assert (n > ts.segments) if arcs else (n == ts.segments)
    assert (sh.vertices @ sh.planes[:, :3].T - sh.planes[:, 3]).max() < 1e-12
    # a prism: n side faces and two caps; 3n edges (the caps' and sides' diagonals left out)
    assert len(sh.planes) == n + 2 and len(sh.edges) == 3 * n


def test_trimmed_copies_are_the_copies_cut_by_the_box(d25_shape):
    ts, sh = d25_shape
    rng = np.random.default_rng(4)
    c = rng.uniform(0, 360, 40)
    tips, axes = turnmill(rng.uniform(15, 40, 40), rng.uniform(-8, 8, 40), rng.uniform(-30, 5, 40), c)
    axes = axes + rng.normal(0, 0.2, axes.shape)          # not only radial: any orientation
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    # one copy wholly inside the box (pointing down the Z axis), one far outside
    tips = np.vstack([tips, [[0.0, 0.0, -1.0], [100.0, 100.0, 100.0]]])
    axes = np.vstack([axes, [[0.0, 0.0, -1.0], [1.0, 0.0, 0.0]]])
    fr = frames(tips, axes)
    lo, hi = np.array([-30.5, -30.5, -40.5]), np.array([30.5, 30.5, 0.5])
    pts, inside = clip(sh, fr, lo, hi)
    box = engine.box(lo, hi)
    whole = engine.hull(ts.pieces[0])
    seen = {"cut": 0, "inside": 0, "missed": 0}
    for k, q in enumerate(pts):
        exact = engine.intersect(engine.transform(whole, fr[k]), box)
        if q is None:
            assert engine.volume(exact) < 1e-9
            seen["missed"] += 1
            continue
        got = engine.hull(q)
        assert engine.volume(got) == pytest.approx(engine.volume(exact), rel=1e-9, abs=1e-9)
        # same solid: the symmetric difference is empty
        assert engine.volume(engine.subtract(got, [exact])) < 1e-7
        assert engine.volume(engine.subtract(exact, [got])) < 1e-7
        if inside[k]:
            seen["inside"] += 1
            continue
        seen["cut"] += 1
        on = np.isclose(q, lo, atol=1e-9) | np.isclose(q, hi, atol=1e-9)
        # points on a box face carry the face's coordinate exactly
        assert np.all(np.isin(q[on], np.r_[lo, hi]))
    assert seen["cut"] > 10 and seen["inside"] > 0 and seen["missed"] > 0


@pytest.mark.parametrize("delta", [2.0, 1.713])
def test_trimming_and_covered_poses_do_not_change_the_cut(face40, delta):
    """Rotary steps (placed poses) and translation steps (hulls) in turn, as the facing pass
    of the polygon program: the trimmed cut, with the placed poses that the hulls contain left
    out, removes exactly what the untrimmed one does. (Fan cutters, which only the trimmed
    stock makes, are off: they remove more than placed poses, by design.)"""
    c = np.repeat(np.arange(0.0, 40.0, delta), 2)[1:]
    y = np.repeat(np.linspace(-6, 6, len(c) // 2 + 1), 2)[: len(c)]
    tips, axes = turnmill(27.0 + 0.02 * np.arange(len(c)), y, -20.0, c)
    vols = []
    for trim in (False, True):
        stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01, trim=trim, batch=16, fans=False)
        stock.cut(face40, tips, axes)
        vols.append(stock.volume)
        if trim:
            assert stock.stats.covered > 10
    assert vols[1] == pytest.approx(vols[0], rel=1e-10)
    assert vols[0] < engine.volume(Stock.from_spec("cylinder:d=60,l=60").initial) - 100


def test_local_stock_is_the_stock_inside_the_box(face40):
    """Stock.local (what the verify checks measure against) is the stock now, pending cutters
    subtracted, inside the box — with one cell and with several."""
    c = np.arange(0.0, 60.0, 1.713)
    tips, axes = turnmill(26.0, np.linspace(-5, 5, len(c)), -12.0, c)
    lo, hi = np.array([0.0, 0.0, -40.0]), np.array([31.0, 31.0, 1.0])
    got = []
    for cells in ((1, 1, 1), (2, 2, 2)):
        stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01, cells=cells)
        stock.cut(face40, tips, axes)
        local = stock.local(lo, hi)                  # before stock.solid: cutters still queued
        want = engine.intersect(stock.solid, engine.box(lo, hi))
        assert engine.volume(local) == pytest.approx(engine.volume(want), rel=1e-9)
        got.append(engine.volume(local))
    assert got[0] == pytest.approx(got[1], rel=1e-9)
    assert got[0] < 0.25 * np.pi * 30 ** 2 * 41 - 100   # material was removed inside the box


def test_trimming_to_the_stock_within_each_cutters_z_range_does_not_change_the_cut(face40):
    """Slab boxes (vmach/stock/slabs.py): a shaft turned down to R 24 over its first 20 mm,
    then cut across the step by a radial face mill. Each cutter is trimmed to the stock's
    extent within its own Z range — tighter than one box where the shaft is thinner — and
    the cut is the same as with one box. A retake of the slabs reads the stock as the retake
    before it found it (Stock's docstring): the one after the turning still sees the blank,
    the next the turned shaft."""
    c = np.arange(0.0, 360.0, 3.0)
    turn_tips, turn_axes = turnmill(24.0, 0.0, -10.0 + 0.0 * c, c)      # D40 face: z -30..10
    tips, axes = turnmill(22.0, np.linspace(-4, 4, 40), np.linspace(-12, -30, 40), np.linspace(0, 70, 40))
    vols = []
    for slabs in (False, True):
        View.SLABS = slabs
        try:
            # small batches: enough of them that the next path takes the slabs again
            stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01, fans=False, batch=8)
            zlo, zhi = np.array([-15.0, -50.0]), np.array([-5.0, -40.0])
            stock.cut(face40, turn_tips, turn_axes)
            stock.flush()
            first = stock.view.boxes(zlo, zhi, fresh=True)
            stock.cut(face40, turn_tips, turn_axes)        # again: cutters, nothing removed
            box = stock.view.boxes(zlo, zhi, fresh=True)
            stock.cut(face40, tips, axes)
            vols.append(stock.volume)
        finally:
            View.SLABS = True
        if slabs:
            assert first[0, 1, 0] > 29.9 + tol.trim_margin         # the blank, as it was
            # thinner where it was turned, the whole stock's width beyond the step (each
            # box then moved out by its own jitter)
            assert box[0, 1, 0] <= 24.0 + tol.trim_margin + GRID + JITTER < stock.trim_box()[1, 0]
            assert stock.trim_box()[1, 0] <= box[1, 1, 0] <= stock.trim_box()[1, 0] + JITTER
    assert vols[1] == pytest.approx(vols[0], rel=1e-10)


def test_a_translation_sweeps_written_down_shape_clips_like_its_hull(d25_shape):
    """sweep_shape (vmach/stock/clip.py) gives the hull of a piece at two poses of one axis
    without building it: clipped to a box, the same solid as the built hull clipped — also for
    travels along the axis, across it (parallel to the caps) and the like, where the planes of
    edges the travel does not see edge-on are left out."""
    from vmach.stock.clip import Shape, sweep_shape

    ts, sh = d25_shape
    every_edge = Shape(sh.vertices, sh.edges, sh.planes)      # no normals: every edge's planes
    rng = np.random.default_rng(7)
    lo, hi = np.array([-30.5, -30.5, -40.5]), np.array([30.5, 30.5, 0.5])
    seen = 0
    fewer = 0
    for i in range(40):
        c = rng.uniform(0, 360)
        a_tips, axes = turnmill(rng.uniform(15, 35), rng.uniform(-8, 8), rng.uniform(-45, 5), c)
        fa = frames(a_tips, axes)[0]
        ax, across = fa[:, 2], fa[:, 0]                       # the tool's axis and a lateral
        d = [rng.normal(0, 15, 3), 9.0 * ax, -7.0 * across, 5.0 * (ax + across),
             6.0 * np.cross(ax, across)][i % 5]
        fb = frames(a_tips + d, axes)[0]
        ident = np.hstack([np.eye(3), np.zeros((3, 1))])[None]
        w = sweep_shape(sh, fa, fb)
        fewer += len(w.planes) < len(sweep_shape(every_edge, fa, fb).planes)
        mine = clip(w, ident, lo, hi)[0][0]
        both = np.concatenate([sh.vertices @ fa[:, :3].T + fa[:, 3], sh.vertices @ fb[:, :3].T + fb[:, 3]])
        built = clip(shape(*engine.hull_mesh(both)), ident, lo, hi)[0][0]
        assert (mine is None) == (built is None)
        if mine is None:
            continue
        seen += 1
        # every point on the hull, and the same solid
        hb = shape(*engine.hull_mesh(both))
        assert (mine @ hb.planes[:, :3].T - hb.planes[:, 3]).max() < 1e-9
        assert engine.volume(engine.hull(mine)) == pytest.approx(engine.volume(engine.hull(built)), rel=1e-9)
    assert seen > 15 and fewer >= 30


def test_slab_boxes_hold_the_stock_and_share_no_plane():
    """Neighbouring cutters' boxes (vmach/stock/slabs.py): each holds the stock's extent in its
    Z range grown by the margin (up to GRID + JITTER more), no two of a thousand share a
    plane, and the same Z range always gets the same box."""
    rng = np.random.default_rng(3)
    v = rng.uniform(-20.0, 20.0, (3000, 3))
    f = rng.integers(0, len(v), (1000, 3))
    slabs = Slabs.from_mesh(v, f)
    outer = np.array([[-30.0, -30.0, -30.0], [30.0, 30.0, 30.0]])
    zlo = np.sort(rng.uniform(-20.0, 15.0, 1000))
    zhi = zlo + np.where(np.arange(1000) % 2, rng.uniform(0.5, 5.0, 1000), rng.uniform(5.0, 40.0, 1000))
    box = slabs.boxes(zlo, zhi, outer)
    tri = v[f]
    t0 = np.floor((tri[:, :, 2].min(axis=1) - slabs.z0) / slabs.step)      # each triangle's bins
    t1 = np.floor((tri[:, :, 2].max(axis=1) - slabs.z0) / slabs.step)
    for k in range(0, 1000, 23):
        # the triangles that meet the cutter's Z range: their extent, grown by the margin, is in
        meet = (tri[:, :, 2].max(axis=1) >= zlo[k]) & (tri[:, :, 2].min(axis=1) <= zhi[k])
        lo, hi = tri[meet][:, :, :2].min(axis=(0, 1)), tri[meet][:, :, :2].max(axis=(0, 1))
        assert np.all(box[k, 0, :2] <= lo - tol.trim_margin) and np.all(box[k, 1, :2] >= hi + tol.trim_margin)
        # ... and the box is no more than GRID + JITTER beyond the extent of the bins it meets
        b0, b1 = np.floor((np.array([zlo[k], zhi[k]]) - slabs.z0) / slabs.step)
        bins = (t0 <= b1) & (t1 >= b0)
        lo, hi = tri[bins][:, :, :2].min(axis=(0, 1)), tri[bins][:, :, :2].max(axis=(0, 1))
        assert np.all(box[k, 0, :2] >= np.maximum(lo - tol.trim_margin - GRID, outer[0, :2]) - JITTER - 1e-12)
        assert np.all(box[k, 1, :2] <= np.minimum(hi + tol.trim_margin + GRID, outer[1, :2]) + JITTER + 1e-12)
    for side in range(2):
        for axis in range(3):
            planes = box[:, side, axis]
            assert len(np.unique(planes)) == len(planes)
    assert np.array_equal(slabs.boxes(zlo[:10], zhi[:10], outer), box[:10])


def test_slab_boxes_take_the_extent_of_every_bin_their_range_meets():
    """Ranges over 1 to 60 bins of a surface whose extent changes with Z (a cone, lop-sided):
    each box is its bins' extent, taken bin by bin, grown and rounded (slabs.py)."""
    from vmach.stock.slabs import jitter

    t = np.linspace(0.0, 2 * np.pi, 48, endpoint=False)
    z = np.linspace(-60.0, 0.0, 241)
    r = 5.0 + 0.3 * (z + 60.0) + 4.0 * np.sin(z / 7.0) ** 2
    v = np.concatenate([np.column_stack([rk * np.cos(t) + 0.1 * zk, rk * np.sin(t), np.full(48, zk)])
                        for rk, zk in zip(r, z, strict=True)])
    i, j = np.meshgrid(np.arange(240), np.arange(48), indexing="ij")
    a, b = (i * 48 + j).ravel(), (i * 48 + (j + 1) % 48).ravel()
    f = np.concatenate([np.column_stack([a, b, a + 48]), np.column_stack([b, b + 48, a + 48])])
    slabs = Slabs.from_mesh(v, f)
    outer = np.array([[-100.0] * 3, [100.0] * 3])
    rng = np.random.default_rng(5)
    zlo = rng.uniform(-62.0, 2.0, 400)
    zhi = zlo + rng.uniform(-0.5, 60.0, 400)
    box = slabs.boxes(zlo, zhi, outer)
    nb = len(slabs.lo)
    b0 = np.clip(np.floor((zlo - slabs.z0) / slabs.step).astype(int), 0, nb - 1)
    b1 = np.maximum(np.clip(np.floor((zhi - slabs.z0) / slabs.step).astype(int), 0, nb - 1), b0)
    u = jitter(zlo, zhi)
    for k in range(len(zlo)):
        lo = slabs.lo[b0[k] : b1[k] + 1].min(axis=0)
        hi = slabs.hi[b0[k] : b1[k] + 1].max(axis=0)
        want_lo = np.floor((lo - tol.trim_margin) / GRID) * GRID - u[k, :2] * JITTER
        want_hi = np.ceil((hi + tol.trim_margin) / GRID) * GRID + u[k, 3:5] * JITTER
        assert np.array_equal(box[k, 0, :2], want_lo) and np.array_equal(box[k, 1, :2], want_hi)


def test_slabs_are_each_bins_extent_over_the_triangles_that_meet_it():
    """Slabs.from_mesh against the definition, bin by bin: random triangles — short ones and
    ones that span tens of bins (a CAD blank's cylinder side spans all of them) — and the X/Y
    extent and largest radius of those that meet each bin."""
    rng = np.random.default_rng(11)
    for _ in range(30):
        n = int(rng.integers(1, 300))
        v = rng.normal(size=(3 * n, 3)) * [10.0, 10.0, rng.uniform(0.1, 40.0)]
        f = np.arange(3 * n).reshape(n, 3)
        slabs = Slabs.from_mesh(v, f, step=float(rng.choice([0.5, 1.0, 3.0])))
        tri = v[f]
        b0 = np.floor((tri[:, :, 2].min(axis=1) - slabs.z0) / slabs.step).astype(int)
        b1 = np.floor((tri[:, :, 2].max(axis=1) - slabs.z0) / slabs.step).astype(int)
        for b in range(len(slabs.lo)):
            meet = (b0 <= b) & (b <= b1)
            if not meet.any():
                assert np.all(slabs.lo[b] == np.inf) and slabs.rmax[b] == -np.inf
                continue
            t = tri[meet]
            assert np.array_equal(slabs.lo[b], t[:, :, :2].min(axis=(0, 1)))
            assert np.array_equal(slabs.hi[b], t[:, :, :2].max(axis=(0, 1)))
            assert slabs.rmax[b] == np.hypot(t[:, :, 0], t[:, :, 1]).max()


def test_slab_support_bounds_the_solid_in_a_z_range_along_any_direction():
    """Slabs.support: a lop-sided, twisting solid (a stack of offset, rotated polygons): for
    random Z ranges and directions, the support is at least that of the solid's part in the
    range (its triangles clipped to the range, exactly: corners and edge crossings) — a
    bound — and no more than the support of the bins' boxes it meets."""
    solid = engine.union([engine.transform(engine.cylinder(8.0 + k, -3.0 * k - 3.0, -3.0 * k, 12),
                                           np.hstack([np.eye(3), [[0.4 * k], [0.2 * k * k], [0.0]]]))
                          for k in range(10)])
    v, f = engine.to_mesh(solid, double=True)
    slabs = Slabs.from_mesh(v, f)
    rng = np.random.default_rng(8)
    tri = v[f]
    edges = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])     # (e, 2, 3)
    for _ in range(200):
        zlo = rng.uniform(-32.0, 2.0)
        zhi = zlo + rng.uniform(0.0, 12.0)
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        got = slabs.support(np.array([zlo]), np.array([zhi]), d[None])[0]
        # the solid's points in the range: vertices within it and edges crossing its planes
        pts = [v[(v[:, 2] >= zlo) & (v[:, 2] <= zhi)]]
        for zc in (zlo, zhi):
            a, b = edges[:, 0], edges[:, 1]
            rise = b[:, 2] - a[:, 2]
            t = (zc - a[:, 2]) / np.where(rise != 0, rise, 1.0)
            ok = (rise != 0) & (t >= 0) & (t <= 1)
            pts.append(a[ok] + t[ok, None] * (b[ok] - a[ok]))
        p = np.concatenate(pts)
        if len(p) == 0:
            continue
        assert got >= (p @ d).max() - 1e-9
        b0, b1 = (int(np.floor((z - slabs.z0) / slabs.step)) for z in (zlo, zhi))
        bins = np.arange(max(b0, 0), min(b1, len(slabs.lo) - 1) + 1)
        corners = [np.array([x, y, z]) for k in bins for x in (slabs.lo[k, 0], slabs.hi[k, 0])
                   for y in (slabs.lo[k, 1], slabs.hi[k, 1])
                   for z in (slabs.z0 + k * slabs.step, slabs.z0 + (k + 1) * slabs.step)]
        assert got <= max(c @ d for c in corners) + 1e-9


def test_copies_clipped_each_to_its_own_box_are_clipped_as_one_by_one(d25_shape):
    """clip with a box per copy (lo, hi (m, 3)) gives each copy what clipping it alone to its
    box gives; an empty box (lo > hi) culls its copy."""
    ts, sh = d25_shape
    rng = np.random.default_rng(11)
    c = rng.uniform(0, 360, 40)
    tips, axes = turnmill(rng.uniform(15, 35, 40), rng.uniform(-8, 8, 40), rng.uniform(-45, 5, 40), c)
    fr = frames(tips, axes)
    lo = rng.uniform(-31, -15, (40, 3))
    hi = rng.uniform(15, 31, (40, 3))
    hi[::5, 2] = lo[::5, 2] - 1.0
    together, inside = clip(sh, fr, lo, hi)
    assert all(together[k] is None for k in range(0, 40, 5))
    compared = 0
    for k in range(40):
        if k % 5 == 0:
            continue
        alone, alone_inside = clip(sh, fr[k : k + 1], lo[k], hi[k])
        assert (alone[0] is None) == (together[k] is None) and alone_inside[0] == inside[k]
        if alone[0] is not None:
            compared += 1
            assert np.array_equal(alone[0], together[k])
    assert compared > 10

