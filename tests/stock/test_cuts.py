"""Stock removal against answers known in closed form, and the sweep's error bounds."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.stock.conftest import turnmill
from vmach.stock import Stock, engine
from vmach.stock.plan import WITHOUT
from vmach.stock.sweep import hull_overcut, plan, scallop_bound
from vmach.tooling import frames, place, tool_solid
from vmach.tooling.solid import RIM_SAG


def radii(stock: Stock, z: float) -> np.ndarray:
    """Distances from the work axis of the section contour around the axis (vertices)."""
    from vmach.checks.profile import axis_contour

    c = axis_contour(stock.section(z))
    return np.hypot(c[:, 0], c[:, 1])


def edge_distance(contour: np.ndarray) -> np.ndarray:
    """Distance of each edge of a closed contour from the origin (nearest point of the edge)."""
    a, b = contour, np.roll(contour, -1, axis=0)
    d = b - a
    t = np.clip(-np.einsum("ij,ij->i", a, d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
    return np.linalg.norm(a + t[:, None] * d, axis=1)


def test_straight_slot_removes_exactly_the_minkowski_sum(flat10):
    stock = Stock.from_spec("box:xmin=-50,xmax=50,ymin=-20,ymax=20,zmin=-10,zmax=0")
    v0 = stock.volume
    x = np.array([-20.0, 0.0, 20.0])
    tips = np.column_stack([x, np.zeros(3), np.full(3, -3.0)])
    axes = np.tile([0.0, 0.0, 1.0], (3, 1))
    assert plan(tips, axes).runs.tolist() == [[0, 2]]  # collinear steps coalesced into one hull
    stock.cut(flat10, tips, axes)
    ts = tool_solid(flat10)
    ring = ts.pieces[0][np.abs(ts.pieces[0][:, 2]) < 1e-12, :2]
    ring = ring[np.hypot(*ring.T) > 0]
    ring = ring[np.argsort(np.arctan2(ring[:, 1], ring[:, 0]))]
    # the polygon (its vertices straddle the circle, with arcs of it about the laterals)
    area = 0.5 * abs(np.sum(ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1]))
    assert abs(area - math.pi * flat10.radius ** 2) <= 2 * math.pi * flat10.radius * ts.deviation
    # the polygon is turned so that it reaches exactly the true radius to both sides of its
    # travel (tooling.solid.spun): the slot is the tool's true width, 2r, not the polygon's
    width = 2.0 * flat10.radius
    expected = 3.0 * (area + width * 40.0)     # depth x (polygon + swept band)
    assert v0 - stock.volume == pytest.approx(expected, rel=2e-6)
    engine.check(stock.solid)


@pytest.mark.parametrize("fans", [False, True])
def test_rotary_face_cut_leaves_the_tangent_polygon_and_never_overcuts(face40, fans):
    """A face mill at X = h turned a full turn in steps of delta: the section is the polygon
    of tangents to the circle of radius h; its corners stand h(sec(delta/2) - 1) proud —
    with placed poses and with fan cutters alike (M of vmach/stock/fan.py is that polygon)."""
    h, delta = 26.0, 2.0
    c = np.arange(0.0, 360.0 + 1e-9, delta)
    tips, axes = turnmill(h, 0.0, -30.0, c)
    stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01, fans=fans)
    stock.cut(face40, tips, axes)
    assert (stock.stats.fans > 0) == fans
    from vmach.checks.profile import axis_contour

    contour = axis_contour(stock.section(-30.0))
    r = radii(stock, -30.0)
    bound = float(scallop_bound(h, delta))
    assert bound == pytest.approx(h * (1 / math.cos(math.radians(delta / 2)) - 1))
    assert edge_distance(contour).min() >= h - 1e-4  # no overcut
    assert r.max() <= h + bound + 1e-4              # scallops within the bound ...
    assert r.max() >= h + 0.9 * bound               # ... and the bound is what is left


def test_hull_of_two_rotated_poses_overcuts_by_about_r_sin_half_delta(library):
    """Why rotary steps are not hulled (issue 4): 0.19 mm for the D25 cutter at 1.713 deg."""
    tool = library.lookup("GLOD D25")
    h, delta = 25.0, 1.713
    tips, axes = turnmill(h, 0.0, 0.0, [0.0, delta])
    ts = tool_solid(tool)
    pts = place(ts.pieces[0], frames(tips, axes)).reshape(-1, 3)
    section = engine.slice_polygons(engine.hull(pts), 0.0)[0]
    expected = hull_overcut(tool.radius, h, delta)
    assert expected == pytest.approx(tool.radius * math.sin(math.radians(delta / 2)), rel=0.03)
    assert expected > 0.18
    depth = h - edge_distance(section).min()
    assert depth == pytest.approx(expected, abs=ts.deviation + 1e-4)


@pytest.mark.parametrize("fans", [False, True])
def test_stock_stays_valid_and_part_plus_removed_is_the_blank(face40, tmp_path, fans):
    stock = Stock.from_spec("cylinder:d=60,l=40", batch=8 if not fans else 1, chord=0.01, fans=fans)
    tips, axes = turnmill(27.0, np.linspace(-5, 5, 30), -10.0, np.linspace(0, 90, 30))
    stock.cut(face40, tips, axes)
    part = stock.solid
    engine.check(part)
    assert stock.stats.batches >= 4
    removed = engine.volume(stock.removed())
    assert removed > 0
    assert engine.volume(part) + removed == pytest.approx(engine.volume(stock.initial), rel=1e-6)


@pytest.mark.parametrize("suffix", [".stl", ".3mf", ".ply"])
def test_export_round_trips_through_trimesh(face40, tmp_path, suffix):
    import trimesh

    stock = Stock.from_spec("cylinder:d=60,l=40", chord=0.01)
    tips, axes = turnmill(27.0, 0.0, -10.0, [0.0, 10.0, 20.0])
    stock.cut(face40, tips, axes)
    for which in ("part", "removed"):
        path = stock.export(tmp_path / f"{which}{suffix}", which=which)
        mesh = trimesh.load(path, force="mesh")
        want = engine.volume(stock.solid if which == "part" else stock.removed())
        assert mesh.is_watertight
        assert abs(mesh.volume) == pytest.approx(want, rel=1e-4)


def test_paths_away_from_the_stock_are_culled(face40):
    stock = Stock.from_spec("cylinder:d=60,l=40")
    tips, axes = turnmill(325.0, 0.0, 50.0, [0.0, 90.0, 180.0])
    n = stock.cut(face40, tips, axes)
    assert n == 0 and stock.stats.culled == 3   # trimmed to nothing: the box misses them
    assert stock.volume == pytest.approx(engine.volume(stock.initial))


def test_bad_poses_are_input_errors(face40):
    from vmach.errors import InputError

    stock = Stock.from_spec("cylinder:d=60,l=40")
    with pytest.raises(InputError):
        stock.cut(face40, np.zeros((2, 3)), np.zeros((3, 3)))
    with pytest.raises(InputError):
        stock.cut(face40, np.full((1, 3), np.nan), np.array([[1.0, 0, 0]]))


def test_spread_batches_remove_exactly_what_queue_order_does(face40):
    """Batches spread over a window of queued cutters (vmach/stock/batch.py) only change the
    order of the subtraction, which commutes."""
    c = np.arange(0.0, 120.0, 1.713)
    tips, axes = turnmill(26.5, np.linspace(-6, 6, len(c)), -15.0 - 0.01 * np.arange(len(c)), c)
    vols = []
    for spread in (1, 4):
        stock = Stock.from_spec("cylinder:d=60,l=40", chord=0.01, batch=8, spread=spread, fans=False)
        stock.cut(face40, tips, axes)
        vols.append(stock.volume)
        assert stock.stats.batches >= 8
    assert vols[1] == pytest.approx(vols[0], rel=1e-12)


@pytest.mark.parametrize("arcs", [False, True])
@pytest.mark.parametrize("fans", [False, True])
def test_side_made_floor_is_where_the_true_tool_puts_it(library, fans, arcs):
    """The D25 end mill turned a full revolution about the work axis at X = 26: its flat face
    makes the round flank (exact for any polygon) and its side makes the floor at Z = zc - R.
    The side is a polygon (within tol.tool_chord of the circle), but every pose is turned about
    its axis so that the polygon reaches exactly R across its travel (tooling.solid.spun):
    the floor is the true one (fans), or the true one up to the cusps between sampled copies
    (placed poses), not merely within the polygon's deviation of it."""
    from vmach.checks.profile import axis_contour
    from vmach.tol import tol

    tool = library.lookup("GLOD D25")
    zc, h = -20.0, 26.0
    c = np.arange(0.0, 360.0 + 1e-9, 1.0)
    tips, axes = turnmill(h, 0.0, zc, c)
    ts = tool_solid(tool, tol.tool_chord, arcs=arcs)
    assert ts.deviation <= tol.tool_chord
    stock = Stock.from_spec("cylinder:d=60,l=60", fans=fans, arcs=arcs)
    stock.cut(tool, tips, axes)
    assert (stock.stats.fans > 0) == fans
    removed = stock.removed()
    floor = []
    for phi in np.radians(np.arange(0.5, 360.0, 7.0)):     # midway between two poses
        for r in (h + 0.5, 27.5, 29.0):
            x, y = r * np.cos(phi), r * np.sin(phi)
            floor.append(removed.ray_cast((x, y, -60.0), (x, y, 0.0))[0].position[2])
    assert ts.deviation > 0.005                    # the polygon is coarse ...
    err = np.array(floor) - (zc - tool.radius)     # > 0: material left
    if fans:
        assert np.abs(err).max() <= 1e-6           # ... the floor exact: the hull fills it
    else:
        # ... placed poses leave only the cusps between the side's copies, s²/(8R) with the
        # side moving s = r·delta between poses at the outermost ray (the rays lie midway
        # between poses, where the cusps peak), and never cut below
        # — plus, midway between two poses, what the side's outline there leaves inside the
        # circle: with arcs (solid.RIM_ARC) its chords, within RIM_SAG; the plain polygon only
        # reaches the true radius at the lateral itself, and a degree off it lies inside by up
        # to its deviation (measured 0.0044 mm against a cusp of 0.0026)
        cusp = (29.0 * math.radians(1.0)) ** 2 / (8 * tool.radius)
        assert err.min() >= -1e-6 and err.max() <= cusp + (RIM_SAG if arcs else ts.deviation) + 1e-6
        assert err.max() > 0.8 * cusp
    # the flank made by the face is the tangent polygon of radius h, whatever the chord
    edge = edge_distance(axis_contour(stock.section(zc)))
    assert edge.min() >= h - 1e-4 and edge.max() <= h + float(scallop_bound(h, 1.0)) + 1e-4


def test_chamfer_cone_walls_are_the_true_cone(library):
    """The 150-degree chamfer mill drawn straight along X at a tilt-free axis: its cone makes
    two bevelled walls at +-Y whose half width at height z above the tip is (z - z_tip)·tan 75°
    — the true cone's, to 1e-6 mm, though its polygon is coarse (every ring of the cone is
    turned alike, exact across the travel)."""
    tool = library.lookup("GLOD D16_15")
    ts = tool_solid(tool)
    assert ts.deviation > 0.001
    z_tip = -1.5
    tips = np.array([[-30.0, 0.0, z_tip], [30.0, 0.0, z_tip]])
    axes = np.tile([0.0, 0.0, 1.0], (2, 1))
    stock = Stock.from_spec("box:xmin=-20,xmax=20,ymin=-20,ymax=20,zmin=-10,zmax=0")
    stock.cut(tool, tips, axes)
    half = math.tan(math.radians(tool.point_angle / 2))
    for z in (-1.2, -0.7, -0.1):
        for x in (-10.0, 3.0, 15.0):
            for sign in (1.0, -1.0):
                hit = stock.solid.ray_cast((x, 0.0, z), (x, sign * 25.0, z))
                assert abs(abs(hit[0].position[1]) - (z - z_tip) * half) <= 1e-6


def test_a_plunge_along_the_axis_reaches_the_true_depth(face40):
    """The Ø40 face mill, radial, driven along its own axis (no side of travel to turn the
    polygon to): the polygon is turned to the work Z instead, so the deepest point of the
    floor its side leaves 20 mm below the axis is the true tool's, though the 72-gon deviates
    by up to 0.0095 mm (between its vertices the floor follows the polygon)."""
    ts = tool_solid(face40)
    assert ts.deviation > 0.005
    tips = np.array([[40.0, 0.0, -20.0], [22.0, 0.0, -20.0]])
    axes = np.tile([1.0, 0.0, 0.0], (2, 1))
    stock = Stock.from_spec("cylinder:d=60,l=60")
    stock.cut(face40, tips, axes)
    removed = stock.removed()
    for x in (24.0, 27.0, 29.0):
        z = [removed.ray_cast((x, y, -70.0), (x, y, 0.0))[0].position[2] for y in np.arange(-1.0, 1.0, 0.005)]
        assert abs(min(z) - (-40.0)) <= 1e-4         # the polygon's slope near its vertex: 0.013


def test_centroid_is_the_centre_of_mass():
    """Two boxes, 1 and 8 mm³: the centre of mass lies 8/9 of the way to the bigger one's
    centre, wherever the boxes are; an empty solid has none."""
    a = engine.box((0, 0, 0), (1, 1, 1))
    b = engine.box((10, -3, 5), (12, -1, 7))
    c = engine.centroid(engine.union([a, b]))
    assert c == pytest.approx((np.array([0.5, 0.5, 0.5]) + 8 * np.array([11.0, -2.0, 6.0])) / 9, abs=1e-12)
    assert engine.centroid(engine.empty()) is None


def test_blank_holds_answers_for_a_convex_blank_only(tmp_path):
    """Stock.blank_holds: points 1e-6 mm or more inside a convex blank (the cylinder's polygon
    lies within tol.blank_chord of the true circle); a non-convex blank answers nothing, so its
    callers meet solids instead."""
    import trimesh

    stock = Stock.from_spec("cylinder:d=60,l=40")
    pts = np.array([[0, 0, -20], [29.99, 0, -20], [0, 0, -0.001], [30.1, 0, -20], [0, 0, 0], [0, 0, -40.5]])
    assert stock.blank_holds(pts).tolist() == [True, True, True, False, False, False]
    ell = trimesh.boolean.union([trimesh.creation.box((20, 20, 10)),                 # an L
                                 trimesh.creation.box((10, 10, 30)).apply_translation((5, 5, 10))],
                                engine="manifold")
    path = tmp_path / "ell.stl"
    ell.export(path)
    bent = Stock.from_spec(f"mesh:{path}")
    assert engine.volume(bent.initial) < engine.volume(engine.hull(engine.to_mesh(bent.initial)[0]))
    assert not bent.blank_holds(np.array([[0.0, 0.0, 0.0], [5.0, 5.0, 15.0]])).any()


@pytest.mark.parametrize("spec", ["cylinder:d=1e9,l=100", "cylinder:d=60,l=2e4", "box:x=10,y=10,z=1e12",
                                  "box:xmin=0,xmax=1,ymin=0,ymax=1,zmin=-1e300,zmax=0"])
def test_a_stock_larger_than_any_machine_is_a_spec_error(spec):
    """Found by fuzzing: d=1e9 asked numpy for 11 PiB (the round blank's polygon to
    tol.blank_chord); the 1 mm trim bins of a kilometre-tall box would follow."""
    from vmach.errors import InputError
    from vmach.tol import tol

    with pytest.raises(InputError) as exc:
        Stock.from_spec(spec)
    assert exc.value.kind == "stock_spec"
    top = tol.max_size
    assert np.ptp(engine.bounds(Stock.from_spec(f"box:x={top},y=1,z=1").solid), axis=0).max() == top


def test_a_mesh_stock_larger_than_any_machine_is_a_spec_error(tmp_path):
    import trimesh

    from vmach.errors import InputError

    path = tmp_path / "huge.stl"
    trimesh.creation.box(extents=(20_000.0, 10.0, 10.0)).export(path)
    with pytest.raises(InputError) as exc:
        Stock.from_spec(f"mesh:{path}")
    assert exc.value.kind == "stock_spec"


def test_a_blank_too_small_for_a_hull_is_not_taken_for_convex(face40):
    """Found by fuzzing: a 1e-6 mm box stock has no hull planes, and the verify checks'
    screening reduced over none (ValueError)."""
    stock = Stock.from_spec("box:x=1e-6,y=1e-6,z=1e-6")
    assert stock.blank_planes() is None
    assert not stock.blank_holds(np.zeros((1, 3))).any()
    assert len(Stock.from_spec("box:x=10,y=10,z=10").blank_planes()) == 6


def _plunges(xs, c=10.0, top=25.0, bottom=-20.0, retract=10.0):
    """Roughing plunges of a radial face mill at C1 = c: for each X in ``xs``, down along Z
    from ``top`` to ``bottom``, then out along the tool's axis by ``retract`` and up again
    (turn-mill poses: tips and axes)."""
    x, z = [], []
    for xv in xs:
        x += [xv, xv, xv + retract, xv + retract]
        z += [top, bottom, bottom, top]
    return turnmill(np.array(x), 0.0, np.array(z), np.full(len(x), c))


def test_a_retract_along_the_tool_removes_what_the_tool_at_its_inner_pose_does(face40):
    """A plunge and its retract out along the tool's axis: the stock lies in front of the
    tool's back where it retracts, so the retract is cut as the tool at its inner pose (which
    the plunge's hull holds) — the same part as with the retract's own hull, to round-off.
    A tool whose back lies in the stock (X so small that the back face is inside it) keeps the
    retract's hull."""
    for xs, replaced in (([26.0], True), ([10.0], False)):
        parts = []
        for axial in (True, False):
            with pytest.MonkeyPatch.context() as mp:
                if not axial:
                    mp.setenv(WITHOUT, "axial")
                stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01)
                stock.cut(face40, *_plunges(xs))
                parts.append(stock)
        assert (parts[0].stats.axial_runs > 0) == replaced
        assert parts[0].volume == pytest.approx(parts[1].volume, rel=1e-10)
        if replaced:
            assert parts[0].stats.cutters < parts[1].stats.cutters


def test_a_cutter_beyond_the_stock_along_its_tool_axis_is_culled(face40):
    """After the retract, the move up at X + 10 lies wholly beyond the stock along the tool's
    axis (its face 36 mm out, the stock 30) though its box meets the stock's box: it is
    culled, and the part is the same as with it cut."""
    from vmach.stock.view import View

    parts = []
    for cull in (True, False):
        with pytest.MonkeyPatch.context() as mp:
            if not cull:
                mp.setattr(View, "apart",
                           lambda self, points, axes: np.zeros(len(points), bool))
            stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01)
            stock.cut(face40, *_plunges([26.0], c=45.0))       # at 45°: its box meets the stock's
            parts.append(stock)
    assert parts[0].stats.culled == parts[1].stats.culled + 1
    assert parts[0].volume == pytest.approx(parts[1].volume, rel=1e-12)
