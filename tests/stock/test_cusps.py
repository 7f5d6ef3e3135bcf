"""Cusps between placed poses (vmach/stock/cusps.py): measured against geometry known on its
own — the gap between two circles, a side's curvature, the floor a round side sweeps
continuously — and the poses that cut them down."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.stock.conftest import turnmill
from tests.stock.test_fans import floor_hits, true_floor
from vmach.stock import Stock, engine
from vmach.stock.cusps import AROUND, cusp_height, side, step_cusps, substeps
from vmach.stock.plan import WITHOUT
from vmach.tol import ACCURACY
from vmach.tooling import Tool, frames, tool_solid


def test_cusp_height_is_the_gap_between_two_imprints():
    # two circles of radius R whose centres lie s apart on a line meet R - sqrt(R^2 - s^2/4)
    # above the line they both touch
    for radius, s in ((5.0, 1.0), (12.5, 0.8), (1.0, 1.9)):
        centres = np.array([[-s / 2, radius], [s / 2, radius]])
        meet_y = centres[0, 1] - math.sqrt(radius**2 - (s / 2) ** 2)
        assert cusp_height(np.array(s), np.array(1.0 / radius)) == pytest.approx(meet_y, abs=1e-12)
    assert cusp_height(np.array(3.0), np.array(1.0)) == pytest.approx(1.0)   # at most the radius
    assert cusp_height(np.array(3.0), np.array(0.0)) == 0.0                  # flat: none


def test_side_curvatures_are_the_tools(library):
    cone = side(library.lookup("GLOD D16_15"))       # edge 15 deg to the end plane
    r = np.hypot(cone.points[:, 0], cone.points[:, 1])
    on_cone = cone.points[:, 2] < 8.0 * math.tan(math.radians(15.0)) - 1e-9
    assert on_cone.any()
    assert cone.across[on_cone] == pytest.approx(math.cos(math.radians(75.0)) / r[on_cone])
    assert np.all(cone.down == 0.0)                  # straight generators
    mill = side(library.lookup("GLOD D25"))
    assert mill.across == pytest.approx(1.0 / 12.5)  # the cylinder; its end face is not sampled
    assert mill.points[:, 2].min() == 0.0
    assert np.hypot(mill.points[:, 0], mill.points[:, 1]) == pytest.approx(12.5)
    ball = side(Tool(name="ball", kind="ball", diameter=10.0, cutting_length=20.0))
    assert ball.down.max() == pytest.approx(0.2)


def test_a_side_moved_across_its_axis_leaves_the_two_circle_cusp():
    tool = Tool(name="flat10", kind="flat", diameter=10.0, cutting_length=20.0)
    sd = side(tool)
    tips = np.array([[0.0, 0.0, 0.0], [0.8, 0.0, 0.0], [0.0, 0.0, 0.0]])
    axes = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    fr = frames(tips, axes)
    everywhere = lambda p: np.ones(p.shape[:-1], bool)   # noqa: E731
    nowhere = lambda p: np.zeros(p.shape[:-1], bool)     # noqa: E731
    c = step_cusps(sd, fr[:1], fr[1:2], everywhere)
    # the samples around lie 360/AROUND deg apart, the nearest pi/AROUND off the side that
    # faces across the travel, and its travel across is taken 1/cos(pi/AROUND) larger: the
    # whole spacing, as the side facing across sees it
    sampled = 0.8 * math.cos(math.pi / AROUND)
    assert c[0] == pytest.approx(cusp_height(np.array(sampled / math.cos(math.pi / AROUND)), np.array(0.2)))
    assert c[0] == pytest.approx(cusp_height(np.array(0.8), np.array(0.2)))
    assert step_cusps(sd, fr[:1], fr[2:3], everywhere)[0] == 0.0     # no travel
    assert step_cusps(sd, fr[:1], fr[1:2], nowhere)[0] == 0.0        # not in the material
    assert list(substeps(np.array([0.0, 0.01, 0.0101, 0.04, 0.041, 10.0]), 0.01)) == [1, 1, 2, 2, 3, 8]


def _turned_flat10():
    """A Ø10 end mill radial at X = 12, tip Z -2, turned 6 deg per step about the work axis
    over 60 deg: (tool, C1 degrees, tips, axes, the control's poses between steps — C
    interpolated)."""
    tool = Tool(name="flat10", kind="flat", diameter=10.0, cutting_length=20.0)
    c = np.arange(0.0, 61.0, 6.0)
    tips, axes = turnmill(12.0, 0.0, -2.0, c)

    def between(steps, parts):
        at = np.concatenate([s + np.arange(1, p) / p for s, p in zip(steps, parts, strict=True)])
        t, a = turnmill(12.0, 0.0, -2.0, np.interp(at, np.arange(len(c)), c))
        return t, a, at

    return tool, c, tips, axes, between


@pytest.mark.parametrize("accuracy", ["standard", "fine"])
def test_placed_poses_get_the_poses_between_that_keep_the_side_made_floor_within_the_cusp(accuracy):
    """A Ø10 end mill, radial at X = 12, turned 6 deg per step about the work axis: its side
    cuts a shoulder floor 5 mm below the tip's height, and placed poses leave cusps on it of
    R - sqrt(R² - (r·sin 3°)²), 0.06 mm at r = 15. With the poses between from the control's
    motion (here: C interpolated), the floor is within the stock's ``cusp`` (``tol.sweep_cusp``,
    or the ``fine`` preset's) of the true floor the continuous motion cuts, plus the tool
    polygon's deviation, and never below it. (Fans off: a flat end mill's rotary run is
    otherwise one fan cutter, whose hull leaves no cusp — and gets no poses added but for the
    steps left to placed poses.)"""
    acc = ACCURACY[accuracy]
    tool, c, tips, axes, between = _turned_flat10()

    plain = Stock.from_spec("cylinder:d=30,l=20", fans=False)
    plain.cut(tool, tips, axes)
    refined = Stock.from_spec("cylinder:d=30,l=20", fans=False, **acc.stock)
    refined.cut(tool, tips, axes, between)
    fanned = Stock.from_spec("cylinder:d=30,l=20", **acc.stock)
    fanned.cut(tool, tips, axes, between)
    # fans take runs of up to tol.fan_angle (3 steps here); the one step left over is placed
    assert fanned.stats.fans > 0 and 0 < fanned.stats.cusp_poses < refined.stats.cusp_poses
    assert plain.stats.cusp_poses == 0 and refined.stats.cusp_poses > 0
    phis = np.radians(np.linspace(1.0, 59.0, 117))
    rs = np.linspace(12.2, 14.8, 14)
    truth = true_floor(phis, rs, 12.0, 5.0, c, np.full(len(c), -2.0))
    dev = tool_solid(tool, refined.chord).deviation
    left_plain = floor_hits(plain.solid, phis, rs) - truth
    left = floor_hits(refined.solid, phis, rs) - truth
    assert np.nanmax(left_plain) > 0.05                       # 5 - sqrt(25 - (15 sin 3°)²) = 0.062
    assert np.nanmax(left) <= acc.sweep_cusp + dev
    assert np.nanmin(left) >= -dev - 1e-6                     # placed poses: never below
    assert np.nanmax(left) < 0.3 * np.nanmax(left_plain)
    left_fanned = floor_hits(fanned.solid, phis, rs) - truth
    assert np.nanmax(left_fanned) <= acc.sweep_cusp + dev
    if accuracy == "fine":   # the preset asks for more poses, and they bring the floor closer
        standard = Stock.from_spec("cylinder:d=30,l=20", fans=False, chord=acc.tool_chord, arcs=acc.rim_arcs)
        standard.cut(tool, tips, axes, between)
        assert refined.stats.cusp_poses > standard.stats.cusp_poses
        assert np.nanmax(left) < np.nanmax(floor_hits(standard.solid, phis, rs) - truth) - 0.001
    # what the added poses remove is material the plain cut left
    assert refined.volume < plain.volume


CHAMFER = """N10 G0 G53 X325 Y0 D0
N20 T="GLOD D16_15" D1
N30 G54 G19 G90
N40 DIAMOF
N50 SETMS(2)
N60 G94 S2=1350 M2=3
N70 C_AXIS_ON
N80 C1=0
N90 G0 X40 Y0 Z1
N100 G1 X29 F400
N110 R1=0
N120 WHILE R1<90
N130 R1=R1+6
N140 G1 C1=R1
N150 ENDWHILE
N160 G1 X40
N170 M30
"""


def test_simulate_adds_the_controls_own_poses_where_a_cone_tip_would_leave_cusps(tmp_path):
    """The chamfer mill, its sharp tip 1 mm in front of a Ø60 shaft's end face and 1 mm
    inside its radius, turned 6 deg per block: rows are sampled to 2 deg (the tip travels
    1 mm), and the cone, 1 mm from its tip at the end face, would leave cusps of about 0.03 mm
    between them. The poses added lie on the control's motion (machine axes interpolated linearly,
    through the kinematics), in plain and in checked runs alike, which cut the same part."""
    from catalog import POLYGON_TOOLS

    from interpreters import sinumerik
    from vmach.machine import load_model
    from vmach.motion.table import build
    from vmach.stock.simulate import _between, simulate
    from vmach.tooling import load_tools

    path = tmp_path / "CHAMFER.MPF"
    path.write_text(CHAMFER)
    model = load_model("turnmill")
    table = build(sinumerik.run(str(path), model.control).commands, model.control)
    lib = load_tools(POLYGON_TOOLS)
    stocks = {}
    for checks in (False, True):
        stocks[checks] = Stock.from_spec("cylinder:d=60,l=20")
        simulate(table, model, lib, stocks[checks], checks=checks)
        assert stocks[checks].stats.cusp_poses > 0
    assert stocks[True].volume == pytest.approx(stocks[False].volume, abs=1e-6)
    # the poses between: fk of the machine axes interpolated, placed at step + fraction
    q = np.array([[10.0, 0.0, 1.0, 0.0], [14.0, 2.0, 1.0, 6.0], [14.0, 2.0, 1.0, 12.0]])
    cols = list(model.axes)
    full = np.tile(np.asarray(model.home, dtype=float), (3, 1))
    for j, a in enumerate(("X", "Y", "Z", "C1")):
        full[:, cols.index(a)] = q[:, j]
    tips, axes, at = _between(full, model.fk)(np.array([0, 1]), np.array([2, 3]))
    assert list(at) == pytest.approx([0.5, 1 + 1 / 3, 1 + 2 / 3])
    want = model.fk(np.vstack([(full[0] + full[1]) / 2, full[1] + (full[2] - full[1]) / 3,
                               full[1] + 2 * (full[2] - full[1]) / 3]))
    assert tips == pytest.approx(want.tip) and axes == pytest.approx(want.axis)
    shifted = _between(full, model.fk, offset=1)(np.array([0]), np.array([2]))
    assert shifted[2][0] == pytest.approx(0.5)
    assert shifted[0] == pytest.approx(model.fk(full[1:2] + (full[2] - full[1]) / 2).tip)


def test_steps_are_measured_in_blocks_and_above_a_least_cusp_with_the_same_result(monkeypatch):
    import vmach.stock.cusps as cusps_module

    tool = Tool(name="flat10", kind="flat", diameter=10.0, cutting_length=20.0)
    sd = side(tool)
    tips, axes = turnmill(12.0, 0.0, -2.0, np.arange(0.0, 60.0, 3.0))
    fr = frames(tips, axes)
    everywhere = lambda p: np.ones(p.shape[:-1], bool)   # noqa: E731
    whole = step_cusps(sd, fr[:-1], fr[1:], everywhere)
    _, over = step_cusps(sd, fr[:-1], fr[1:], everywhere, 0.001, reach=True)
    monkeypatch.setattr(cusps_module, "BLOCK", 3 * len(sd.points))
    assert np.array_equal(step_cusps(sd, fr[:-1], fr[1:], everywhere), whole)
    _, blocked = step_cusps(sd, fr[:-1], fr[1:], everywhere, 0.001, reach=True)
    assert len(over.step) > 0 and over.step.max() >= 3           # samples beyond the first block
    for a, b in zip((over.step, over.height, over.point, over.cusp),
                    (blocked.step, blocked.height, blocked.point, blocked.cusp), strict=True):
        assert np.array_equal(a, b)
    assert whole.min() > 0
    # only cusps over `least` are looked up; the rest count as none
    least = float(np.median(whole))
    above = step_cusps(sd, fr[:-1], fr[1:], everywhere, least)
    assert np.array_equal(above, np.where(whole > least, whole, 0.0))


def test_steps_say_which_samples_are_over_and_fins_reach_the_highest_that_counts():
    """step_cusps(reach=True): the samples over ``least`` in the material — each step's
    largest is its cusp — with their heights; fin_height: the next sample height up above the
    highest kept one, rounded up to 2^(1/4) steps from SPACING, inf from the tool's length."""
    from vmach.stock.cusps import SPACING, fin_height

    tool = Tool(name="cone", kind="chamfer", diameter=16.0, point_angle=150.0, cutting_length=4.0)
    sd = side(tool)
    tips, axes = turnmill(25.0, 0.0, 1.0, np.arange(0.0, 12.0, 2.0))
    fr = frames(tips, axes)
    everywhere = lambda p: np.ones(p.shape[:-1], bool)   # noqa: E731
    c, over = step_cusps(sd, fr[:-1], fr[1:], everywhere, 0.0035, reach=True)
    assert np.array_equal(c, step_cusps(sd, fr[:-1], fr[1:], everywhere, 0.0035))
    assert len(over.step) > 0 and (over.cusp > 0.0035).all()
    top = np.zeros(len(c))
    np.maximum.at(top, over.step, over.cusp)
    assert top == pytest.approx(c)
    assert set(np.round(over.height, 9)) <= set(np.round(sd.points[:, 2], 9))
    h = fin_height(over, len(c), 4.0)
    for k in range(len(c)):
        mine = over.height[over.step == k]
        want = SPACING * 2.0 ** (np.ceil(4.0 * np.log2((mine.max() + SPACING) / SPACING) - 1e-9) / 4.0)
        assert h[k] == pytest.approx(want if want < 4.0 else np.inf)
    # samples left out (cut again by another pass) do not count: none kept -> SPACING
    none = np.zeros(len(over.step), bool)
    assert fin_height(over, len(c), 4.0, none) == pytest.approx(np.full(len(c), SPACING))
    assert np.isinf(fin_height(over, len(c), 0.6)).all()
    low = over.height < 1.0                                   # only the samples below 1 mm kept
    assert fin_height(over, len(c), 4.0, low).max() <= SPACING * 2.0 ** (np.ceil(4 * np.log2(3.0)) / 4)


class _Below:
    """What another pass's sampled poses hold, as Stock.cut asks (Coverage.at_poses'
    signature): every point below ``z`` by the margin (a stand-in for a later finishing pass
    over the flank)."""

    def __init__(self, z: float):
        self.z = z

    def __call__(self, groups, omega):
        return np.zeros(len(groups), bool)

    def at_poses(self, points, margin):
        return np.asarray(points)[:, 2] + np.asarray(margin) < self.z


def test_a_cones_added_fins_reach_only_the_cusps_no_other_pass_cuts(tmp_path, monkeypatch):
    """The chamfer program's cone (its cusps over the tolerance near its tip, at the end
    face, and on its land further out): told that another pass cuts everything below
    z = -1.5 again, its added poses' fins stop at the highest sample over the tolerance
    above that (the same poses); the part differs from whole-length fins' only there, where
    it keeps more (a fin lies inside the true tool: never less)."""
    from catalog import POLYGON_TOOLS

    import vmach.stock.cusps as cusps_module
    from interpreters import sinumerik
    from vmach.machine import load_model
    from vmach.motion.table import build
    from vmach.stock.simulate import _between, sample_rows
    from vmach.tooling import load_tools

    path = tmp_path / "CHAMFER.MPF"
    path.write_text(CHAMFER)
    model = load_model("turnmill")
    table = build(sinumerik.run(str(path), model.control).commands, model.control)
    lib = load_tools(POLYGON_TOOLS)
    tool = lib.lookup("GLOD D16_15")
    axes_ = tuple(model.axes)
    rot = np.array([table.rotary[table.axes.index(a)] if a in table.axes else False for a in axes_])
    rows = np.nonzero(np.asarray(table.tool) >= 0)[0]
    q0 = table.columns(axes_, model.home, table.start)[rows]
    q1 = table.columns(axes_, model.home, table.end)[rows]
    q, _ = sample_rows(q0, q1, rot, model.fk, 2.0, 1.0)
    pose = model.fk(q)
    below = Stock.from_spec("cylinder:d=60,l=20", cusp=0.0025)
    below.cut(tool, pose.tip, pose.axis, _between(q, model.fk), _Below(-1.5))
    monkeypatch.setattr(cusps_module, "fin_height",
                        lambda over, steps, length, keep=None: np.full(steps, np.inf))
    whole = Stock.from_spec("cylinder:d=60,l=20", cusp=0.0025)
    whole.cut(tool, pose.tip, pose.axis, _between(q, model.fk), _Below(-1.5))
    assert below.stats.cusp_poses == whole.stats.cusp_poses > 10
    tall = [k[3] for k in below.maker._fins]
    assert np.isfinite(tall).any() and max(t for t in tall if np.isfinite(t)) < tool.cutting_length
    assert all(np.isinf(k[3]) for k in whole.maker._fins)
    # what the shorter fins leave lies below z = -1.5; above it both parts differ by slivers
    # no thicker than the fins' arcs (both lie within that sag of the true cone), both ways
    more = engine.subtract(below.solid, [whole.solid])
    less = engine.subtract(whole.solid, [below.solid])
    top = engine.box([-40, -40, -1.5], [40, 40, 1])
    above = engine.intersect(more, top)
    assert engine.volume(more) - engine.volume(above) > 0.002
    sag = 0.8 * 0.0025                                        # the fins' arcs (make.Maker.fin_piece)

    def thickness(piece) -> float:
        """The thickest of its sections' polygons (twice the area over the perimeter: a
        sliver's width) at heights over the chamfer."""
        widest = 0.0
        for z in np.arange(-1.45, 0.0, 0.1):
            for poly in engine.slice_polygons(piece, float(z)):
                x, y = poly[:, 0], poly[:, 1]
                area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
                perimeter = np.linalg.norm(np.diff(np.vstack([poly, poly[:1]]), axis=0), axis=1).sum()
                widest = max(widest, 2.0 * area / perimeter)
        return widest

    assert thickness(above) < sag
    assert thickness(less) < sag


def _whole_poses(monkeypatch):
    """Cut every added pose whole (no fins)."""
    import vmach.stock.make as make_module

    monkeypatch.setattr(make_module, "fin_bucket", lambda half, radius: np.full(len(half), np.inf))


@pytest.mark.parametrize("arcs", [False, True])
def test_added_poses_cut_as_fins_keep_the_side_made_floor_on_the_true_one(monkeypatch, arcs):
    """The Ø10 end mill turned 6 deg per step (the case above), its added poses cut as fins —
    the true tool (not its polygon) within a slab through its axis across its travel, as wide
    as the envelope's lenses need: the floor is never below the true floor of the continuous
    motion, within the stock's ``cusp`` plus the polygon's deviation above it (a step's end
    poses are whole polygons: between them and the fins the polygon's own bump remains).
    Against the added poses cut whole: with the plain polygon, closer to the true floor on the
    whole (the polygons' V-shaped cusps between imprints); with the polygon round about the
    lateral (``arcs``, solid.RIM_ARC), whose whole poses leave no V there, nowhere more than
    the fins' arcs' sag (0.8 × ``cusp``) above them (measured 0.0016 mm)."""
    tool, c, tips, axes, between = _turned_flat10()

    fins = Stock.from_spec("cylinder:d=30,l=20", fans=False, cusp=0.0025, arcs=arcs)
    fins.cut(tool, tips, axes, between)
    _whole_poses(monkeypatch)
    whole = Stock.from_spec("cylinder:d=30,l=20", fans=False, cusp=0.0025, arcs=arcs)
    whole.cut(tool, tips, axes, between)
    assert fins.stats.cusp_fins == fins.stats.cusp_poses == whole.stats.cusp_poses > 10
    assert whole.stats.cusp_fins == 0
    phis = np.radians(np.linspace(1.0, 59.0, 117))
    rs = np.linspace(12.2, 14.8, 14)
    truth = true_floor(phis, rs, 12.0, 5.0, c, np.full(len(c), -2.0))
    dev = tool_solid(tool, fins.chord).deviation
    left, left_whole = floor_hits(fins.solid, phis, rs) - truth, floor_hits(whole.solid, phis, rs) - truth
    assert np.isfinite(left).all()
    assert np.nanmin(left) >= -1e-6                           # never below the true floor
    assert np.nanmax(left) <= 0.0025 + dev
    if not arcs:
        assert np.mean(left) < 0.8 * np.mean(left_whole)      # measured 0.0021 against 0.0030
    else:
        assert np.nanmax(left - left_whole) <= 0.8 * 0.0025 + 1e-6
        assert np.nanmax(left - left_whole) > 0.2 * 0.0025   # (the two do differ)
        plain = floor_hits(_plain_whole(tool, tips, axes, between), phis, rs) - truth
        assert np.mean(left_whole) < 0.5 * np.mean(plain)


def _plain_whole(tool, tips, axes, between):
    """The turned Ø10 case with its added poses cut whole, plain polygons (the caller has made
    every added pose whole): the solid."""
    stock = Stock.from_spec("cylinder:d=30,l=20", fans=False, cusp=0.0025)
    stock.cut(tool, tips, axes, between)
    return stock.solid


def test_the_chamfer_cone_cut_with_fins_is_the_whole_poses_cut(tmp_path, monkeypatch):
    """The chamfer program above (the cone's cusps near its sharp tip, the envelope off the
    meridian where the tool also moves along its axis): its added poses cut as fins leave
    the part the whole poses leave, to 1e-3 of the volume they remove either way (fins are
    the true cone, the whole poses its polygon)."""
    from catalog import POLYGON_TOOLS

    from interpreters import sinumerik
    from vmach.machine import load_model
    from vmach.motion.table import build
    from vmach.stock import engine
    from vmach.stock.simulate import simulate
    from vmach.tooling import load_tools

    path = tmp_path / "CHAMFER.MPF"
    path.write_text(CHAMFER)
    model = load_model("turnmill")
    table = build(sinumerik.run(str(path), model.control).commands, model.control)
    lib = load_tools(POLYGON_TOOLS)
    fins = Stock.from_spec("cylinder:d=60,l=20", cusp=0.0025)
    simulate(table, model, lib, fins)
    _whole_poses(monkeypatch)
    whole = Stock.from_spec("cylinder:d=60,l=20", cusp=0.0025)
    simulate(table, model, lib, whole)
    assert fins.stats.cusp_fins == whole.stats.cusp_poses > 10
    removed = engine.volume(whole.initial) - whole.volume
    assert engine.volume(engine.subtract(whole.solid, [fins.solid])) < 1e-3 * removed
    assert engine.volume(engine.subtract(fins.solid, [whole.solid])) < 1e-3 * removed


def _one_turn(library, x: float, inward: bool = False, y: float = 0.0):
    """The D25 end mill turned about the work axis 1.713° per pose over 60°, its tip at
    radius ``x`` (Y offset ``y``, Z -20): radial and facing the axis (a shaft's flank, a
    convex chain of faces), or with ``inward`` facing away from it (a bore's wall, concave).
    Returns (tool, solid, frames turned as placed poses, fin half-widths over two steps)."""
    from vmach.stock.cusps import fin_normal, fin_widths
    from vmach.tooling.solid import lateral, spun

    tool = library.lookup("GLOD D25")
    ts = tool_solid(tool, 0.01, arcs=True)
    tips, axes = turnmill(x, y, -20.0, np.arange(0.0, 60.0, 1.713))
    if inward:
        axes = -axes
    fr = spun(frames(tips, axes), lateral(tips, axes), ts.segments)
    i = np.arange(1, len(fr) - 1)
    half = np.full(len(fr), np.inf)
    half[i] = fin_widths(fr[i], fr[i - 1], fr[i + 1], fin_normal(ts.segments), np.full(len(i), 2), side(tool),
                         lambda p: np.ones(p.shape[:-1], bool), face=tool.radius)
    return tool, ts, fr, half


def test_a_runs_inner_poses_may_be_fins_where_their_neighbours_hold_the_rest(library):
    """fins_cover: on a shaft's flank (the faces a convex chain) every inner pose's surface
    outside its own fin that may lie in the stock (a Ø60 blank) lies in its neighbours'
    fins — the fins hold what the whole poses remove; inside a bore (a concave chain) the
    face's far parts lie in front of the neighbours' faces, and the poses stay whole. Beyond
    the blank the tool's back is not held (its corners stand behind the neighbours' backs):
    only what may lie in the stock counts."""
    from vmach.stock.cusps import fin_normal
    from vmach.stock.strategies.fins import fins_cover

    blank = lambda p: np.hypot(p[:, 0], p[:, 1]) <= 30.0     # noqa: E731
    everywhere = lambda p: np.ones(len(p), bool)            # noqa: E731
    for x, inward, holds, want in ((26.0, False, blank, True), (26.0, False, everywhere, False),
                                   (40.0, True, lambda p: ~blank(p) | blank(p), False)):
        tool, ts, fr, half = _one_turn(library, x, inward)
        inner = np.arange(1, len(fr) - 1)
        assert np.all(half[inner] < 0.3 * tool.radius)      # slabs, far narrower than the tool
        got = fins_cover(tool, fr, half, inner, fin_normal(ts.segments), holds)
        assert got.all() if want else not got.any(), (x, inward, got)
    # nothing in the stock: nothing to hold
    got = fins_cover(tool, fr, half, inner, fin_normal(ts.segments), lambda p: np.zeros(len(p), bool))
    assert got.all()


@pytest.mark.parametrize("arcs", [False, True])
def test_a_turns_placed_poses_cut_as_fins_leave_the_whole_poses_part(library, monkeypatch, arcs):
    """The D25's last turn on a Ø60 shaft — constant Z, the tip 0.8 mm off the contact
    point as the polygon program's saw-tooth Y leaves it, no fans: its inner placed poses cut
    as fins (:mod:`vmach.stock.strategies.fins`) leave the part the whole poses leave, to a sliver: the
    volumes within 1e-5 of what they remove, the flank at z = -30 and the shoulder floor the
    same to the fins' arcs (they are the true tool, the whole poses its polygon)."""
    tool = library.lookup("GLOD D25")
    c = np.arange(0.0, 90.0, 1.713)
    tips, axes = turnmill(26.0, 0.8, -27.5, c)
    cuts = []
    for whole in (False, True):
        with monkeypatch.context() as mp:
            if whole:
                mp.setenv(WITHOUT, "fins")
            stock = Stock.from_spec("cylinder:d=60,l=60", fans=False, arcs=arcs)
            stock.cut(tool, tips, axes)
        cuts.append(stock)
    fins, whole = cuts
    assert fins.stats.inner_fins > 0.9 * (len(c) - 2) and whole.stats.inner_fins == 0
    # the fins are the true tool, the whole poses its polygon, whose vertices stand out of it
    # by up to its deviation (with arcs not about the laterals): no more than that over the
    # cut's surface apart (measured 0.89 mm³ plain, 0.039 with arcs, against 45 and 47)
    v, f = engine.to_mesh(whole.removed())
    area = 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1).sum()
    dev = tool_solid(tool, fins.chord, arcs=arcs).deviation
    assert 0 < abs(fins.volume - whole.volume) <= dev * area
    phis = np.radians(np.linspace(10.0, 80.0, 141))
    rs = np.array([26.5, 28.0, 29.5])
    floor = floor_hits(fins.solid, phis, rs) - floor_hits(whole.solid, phis, rs)
    assert np.nanmax(np.abs(floor)) <= dev
    from vmach.checks.profile import axis_contour

    for z in (-30.0, -39.9):
        a = axis_contour(fins.section(z))
        b = axis_contour(whole.section(z))
        ra, rb = np.hypot(*a.T), np.hypot(*b.T)
        assert abs(ra.min() - rb.min()) <= dev


def test_rim_feet_are_the_triangle_two_corners_leave():
    """rim_feet at the lateral sample: a flat face's rim corner moved by du along the axis
    and dv along the rim's outward normal leaves the right triangle of legs du, dv between
    the two quadrants: |du dv| / sqrt(du² + dv²) high, its right angle where the later face
    meets the earlier rim — none when du and dv differ in sign (one quadrant holds the
    other's corner) or when the edge only slides along itself."""
    from vmach.stock.feet import FOOT_SAMPLES, rim_feet
    from vmach.tooling.solid import lateral_angle

    segments, radius = 56, 12.5
    a = frames(np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]]))
    alpha = lateral_angle(segments)
    er = a[0, :, :3] @ np.array([math.cos(alpha), math.sin(alpha), 0.0])      # the lateral, world
    along = a[0, :, :3] @ np.array([-math.sin(alpha), math.cos(alpha), 0.0])
    k = FOOT_SAMPLES // 2
    for du, dv, want in ((0.01, 0.02, 0.01 * 0.02 / math.hypot(0.01, 0.02)), (-0.01, -0.005, None),
                         (0.01, -0.02, 0.0), (-0.01, 0.02, 0.0), (0.0, 0.0, 0.0)):
        b = a.copy()
        b[0, :, 3] += du * a[0, :, 2] + dv * er + 0.3 * along
        feet = rim_feet(a, b, radius, segments)
        expect = abs(du * dv) / math.hypot(du, dv) if want is None else want
        assert feet.foot[0, k] == pytest.approx(expect, abs=1e-12), (du, dv)
        if expect > 0:
            corner = radius * er
            mid = corner + 0.5 * (b[0, :, 3] - a[0, :, 3])
            right = corner + (du * a[0, :, 2] if du > 0 else dv * er) + 0.15 * along
            assert feet.apex[0, k] == pytest.approx(right, abs=1e-12)
            # the right angle lies `foot` from the edge's path (the hypotenuse), off it
            hyp = (feet.b[0, k] - feet.a[0, k]) / np.linalg.norm(feet.b[0, k] - feet.a[0, k])
            off = feet.apex[0, k] - mid
            assert np.linalg.norm(off - (off @ hyp) * hyp) == pytest.approx(expect, rel=1e-9)


def _advancing_turn(library, x0: float, x1: float, sub: int = 1):
    """The D25 turned 60° about the work axis 1.713° / ``sub`` per pose at Z -27.5 (its rim's
    foot on the floor z = -40), 0.8 mm off the contact point, its face advancing from
    X = x0 to x1 as it turns: a :class:`vmach.stock.sweeps.Motion`."""
    from tests.stock.test_fans import _turn_motion

    c = np.arange(0.0, 60.0 - 1e-9, 1.713 / sub)
    return _turn_motion(library.lookup("GLOD D25"), np.linspace(x0, x1, len(c)), 0.8, -27.5, c)


def _flank_foot(stock, z):
    from tests.stock.test_fans import inward

    phis = np.radians(np.linspace(10.0, 50.0, 81))
    return np.array([40.0 - inward(stock.solid, p, z) for p in phis])


def test_placed_steps_are_parted_against_the_feet_their_rim_leaves(library):
    """The D25's face advancing 0.3 mm over a 60° turn while it passes 0.8 mm off the
    contact point — as the polygon program's last turn does where its saw-tooth Y reverses —
    leaves between two placed poses a foot at the flank's foot, where the rim draws back from
    the material as the face advances into it (0.011 mm against a dense cut, 8 poses per
    step). Told what the true tools sweep (``others``), the stock parts those steps until the
    feet are within the side-cusp tolerance; without, it does not."""
    from vmach.stock.simulate import _between
    from vmach.stock.sweeps import Sweeps

    tool = library.lookup("GLOD D25")

    def cut(m, others):
        stock = Stock.from_spec("cylinder:d=60,l=60", fans=False, cusp=0.0035, chord=0.004, arcs=True)
        stock.cut(tool, m.tips, m.axes, _between(m.q, m.fk), others)
        return stock

    m = _advancing_turn(library, 26.3, 26.0)
    feet, plain = cut(m, Sweeps([m]).coverage(0)), cut(m, None)
    dense = cut(_advancing_turn(library, 26.3, 26.0, 8), None)
    assert feet.stats.foot_steps == len(m.tips) - 1 and plain.stats.foot_steps == 0
    assert feet.stats.cusp_poses > plain.stats.cusp_poses
    for z in (-39.995, -39.99, -39.98, -39.97):
        truth = _flank_foot(dense, z)
        assert (_flank_foot(feet, z) - truth).max() <= 0.0035 + 2e-4, z
    assert (_flank_foot(plain, -39.995) - _flank_foot(dense, -39.995)).max() > 0.008


def test_feet_another_pass_cuts_again_need_no_poses(library):
    """The same advancing turn followed by a finishing turn 0.1 mm deeper at constant X
    (from 5° before to 5° after it): its true tool passes through every foot the first one
    leaves, at its own placed poses, so the first turn is not parted for them."""
    from tests.stock.test_fans import _turn_motion
    from vmach.stock.simulate import _between
    from vmach.stock.sweeps import Sweeps

    tool = library.lookup("GLOD D25")
    first = _advancing_turn(library, 26.3, 26.0)
    finish = _turn_motion(tool, 25.9, 0.8, -27.5, np.arange(-5.0, 65.0, 1.713))
    sweeps = Sweeps([first, finish])
    stock = Stock.from_spec("cylinder:d=60,l=60", fans=False, cusp=0.0035, chord=0.004, arcs=True)
    stock.cut(tool, first.tips, first.axes, _between(first.q, first.fk), sweeps.coverage(0))
    assert stock.stats.foot_steps == 0
    alone = Stock.from_spec("cylinder:d=60,l=60", fans=False, cusp=0.0035, chord=0.004, arcs=True)
    alone.cut(tool, first.tips, first.axes, _between(first.q, first.fk), Sweeps([first]).coverage(0))
    assert alone.stats.foot_steps > 0
