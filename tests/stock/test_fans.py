"""Fan cutters (vmach/stock/fan.py): one solid for a run of rotary steps of a flat-faced tool.

What they must do, tested against answers known independently of them: the surface the flat
face makes is the tangent polygon of the sampled faces (as with placed poses); they remove at
least what placed poses remove; where the run also moves along its rotation axis they remove
more than the true sweep by no more than the bound they report, and that bound is what a long
run would exceed; and they are not used where the hull could bridge material no pose reaches.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.stock.conftest import turnmill
from vmach.stock import Stock, engine
from vmach.stock import make_fans as make_fans_module
from vmach.stock.fan import Prism, back_clear, plan_fans, prism
from vmach.stock.fan_measure import EPS, covered
from vmach.stock.plan import WITHOUT
from vmach.stock.strategies import fans as fans_strategy
from vmach.stock.sweep import scallop_bound
from vmach.stock.view import View
from vmach.tol import tol
from vmach.tooling import Tool, tool_solid

FINE = 0.0005   # tool polygon fine enough that the twist, not the polygon, dominates


class _EverySwept:
    """A coverage index (:class:`vmach.stock.sweeps.Coverage`) for which every rim band is swept."""

    def swept(self, groups, omega):
        return np.ones(len(groups), bool)


def test_flat_faced_prisms_are_recognised(library):
    for name in ("GLOD D25", "GLOD D40", "GLOD D32"):
        ts = tool_solid(library.lookup(name), 0.01)
        p = prism(ts.pieces[0])
        assert p is not None and p.radius == pytest.approx(ts.pieces[0][:, :2].max(), abs=0.02)
        assert p.length == pytest.approx(ts.length)
    for tool in (library.lookup("GLOD D16_15"),
                 Tool(name="ball", kind="ball", diameter=10.0, cutting_length=20.0),
                 Tool(name="bull", kind="bull", diameter=10.0, corner_radius=2.0, cutting_length=20.0)):
        assert prism(tool_solid(tool, 0.01).pieces[0]) is None, tool.name


def floor_hits(solid, phis, rs, top=10.0):
    """Z of the first surface below (r, phi) seen from above, (len(phis), len(rs))."""
    out = np.full((len(phis), len(rs)), np.nan)
    for i, phi in enumerate(phis):
        for j, r in enumerate(rs):
            x, y = r * np.cos(phi), r * np.sin(phi)
            hit = solid.ray_cast((x, y, top), (x, y, -60.0))
            if hit:
                out[i, j] = hit[0].position[2]
    return out


def inward(solid, phi, z, start=40.0):
    """How far (mm) a ray from radius ``start`` at polar angle phi and height z travels toward
    the axis before it meets the solid (manifold3d reports the fraction of the segment)."""
    o, e = (start * np.cos(phi), start * np.sin(phi), z), (0.0, 0.0, z)
    return start * solid.ray_cast(o, e)[0].distance


def true_floor(phis, rs, h, radius, c_deg, z_tip):
    """The floor a round end mill's side cuts when its axis sweeps continuously through the
    poses (C1 in degrees, tip Z), radial at X = h: the lowest point of the tool over
    (r, phi), found over 0.01 deg steps of the interpolated motion."""
    cd = np.arange(c_deg[0], c_deg[-1], 0.01)
    zd = np.interp(cd, c_deg, z_tip)
    p = np.stack([np.outer(np.cos(phis), rs), np.outer(np.sin(phis), rs)], -1)
    best = np.full(p.shape[:2], np.inf)
    for c, z in zip(np.radians(cd), zd, strict=True):
        d = np.abs(-p[..., 0] * np.sin(c) + p[..., 1] * np.cos(c))
        along = p[..., 0] * np.cos(c) + p[..., 1] * np.sin(c)
        zb = np.where((d < radius) & (along >= h), z - np.sqrt(np.maximum(radius**2 - d**2, 0)), np.inf)
        best = np.minimum(best, zb)
    return best


HELIX_X = 26.0   # the finishing helix's tip radius, mm


def finishing_helix(library, degrees: float, phis, rs):
    """The D25 end mill on the finishing helix of the polygon program on a round (C +1.713 deg
    and Z -0.01 mm per pose from z = -5, X = HELIX_X) over ``degrees``: (tool, tips, axes, the
    true floor its side cuts at the polar angles ``phis`` and radii ``rs``)."""
    tool = library.lookup("GLOD D25")
    c = np.arange(0.0, degrees, 1.713)
    z = -5.0 - 0.01 * np.arange(len(c))
    tips, axes = turnmill(HELIX_X, 0.0, z, c)
    return tool, tips, axes, true_floor(phis, rs, HELIX_X, tool.radius, c, z)


@pytest.fixture(scope="module")
def helix_cut(library):
    """The finishing helix over 300 deg: fans (with the default bound and with none), placed
    poses, and the true floor its side cuts."""
    phis = np.radians(np.linspace(5, 295, 400))
    rs = np.linspace(HELIX_X + 0.5, 29.5, 7)
    tool, tips, axes, true = finishing_helix(library, 300.0, phis, rs)
    out = {"tool": tool, "true": true}
    for name, kw in (("fans", {}), ("unbounded", {"fan_overcut": 1.0}), ("placed", {"fans": False})):
        stock = Stock.from_spec("cylinder:d=60,l=60", chord=FINE, **kw)
        stock.cut(tool, tips, axes)
        out[name] = (stock, floor_hits(stock.solid, phis, rs))
    return out


def test_fans_overcut_the_side_made_floor_by_no_more_than_their_bound(helix_cut):
    dev = tool_solid(helix_cut["tool"], FINE).deviation
    stock, hits = helix_cut["fans"]
    assert stock.stats.fans > 10
    bound = stock.stats.fan_overcut_mm
    assert 0 < bound <= tol.fan_overcut
    over = helix_cut["true"] - hits          # > 0: the floor is cut deeper than the tool went
    assert np.nanmax(over) <= bound + dev + 1e-6
    # ... and the bound is not idle: the twist is really bridged (the polygon adds nothing
    # here: it reaches exactly the true radius across the travel, tooling.solid.spun)
    assert np.nanmax(over) >= 0.4 * bound


def test_an_unbounded_fan_overcuts_more_and_says_so(helix_cut):
    """Without the twist check the runs grow to tol.fan_angle and the hull bridges the floor by
    twice the default bound: the check is what keeps the error within it."""
    dev = tool_solid(helix_cut["tool"], FINE).deviation
    stock, hits = helix_cut["unbounded"]
    over = np.nanmax(helix_cut["true"] - hits)
    assert over > 2 * tol.fan_overcut
    assert over <= stock.stats.fan_overcut_mm + dev + 1e-6     # the measured bound still holds


def test_placed_poses_never_cut_below_the_true_floor(helix_cut):
    dev = tool_solid(helix_cut["tool"], FINE).deviation
    _, hits = helix_cut["placed"]
    assert np.nanmax(helix_cut["true"] - hits) <= dev + 1e-6


def test_fans_remove_at_least_what_placed_poses_remove(helix_cut):
    """A fan is the hull of the very poses placed poses would place (the same frames, turned
    alike about the tool axis) minus M, which lies eps below the face planes: its floor is
    never higher than theirs."""
    fans, fan_hits = helix_cut["fans"]
    placed, placed_hits = helix_cut["placed"]
    assert np.nanmax(fan_hits - placed_hits) <= 1e-5                # the fans' floor is not higher
    assert np.nanmean(placed_hits - fan_hits) > 0.001               # it is lower: cusps filled
    assert engine.volume(placed.solid) - engine.volume(fans.solid) > 1.0


def test_the_flank_is_the_tangent_polygon_of_the_sampled_faces(helix_cut):
    """Radial rays at the flank (the face made it): the fan cut and the placed cut agree to
    the eps by which M is moved out."""
    fans, _ = helix_cut["fans"]
    placed, _ = helix_cut["placed"]
    for z in (-3.0, -1.0):
        for phi in np.radians(np.linspace(10, 290, 50)):
            assert inward(fans.solid, phi, z) == pytest.approx(inward(placed.solid, phi, z), abs=1e-5)


def _plan(tips, axes, tool, **kw):
    pr = prism(tool_solid(tool, 0.01).pieces[0])
    return plan_fans(tips, axes, np.ones(len(tips) - 1, bool), pr, **kw)


def test_a_concave_chain_is_not_fanned(face40):
    """Inside a bore the face looks outward: the tangent chain is concave, the hull would
    bridge material that no pose reaches."""
    c = np.arange(0.0, 40.0, 2.0)
    tips, axes = turnmill(20.0, 0.0, -20.0, c)
    assert len(_plan(tips, axes, face40).runs) > 0          # outside: fanned
    assert len(_plan(tips, -axes, face40).runs) == 0        # inside a bore, face outward


def test_runs_stop_where_the_rotation_reverses_or_the_axis_tilts(face40):
    c = np.r_[np.arange(0.0, 20.0, 2.0), np.arange(20.0, 0.0, -2.0)]
    tips, axes = turnmill(26.0, 0.0, -20.0, c)
    runs = _plan(tips, axes, face40).runs
    k = int(np.argmax(c))
    assert len(runs) and all(b <= k or a >= k for a, b in runs)
    tilted = axes + np.array([0.0, 0.0, 0.3])
    tilted /= np.linalg.norm(tilted, axis=1, keepdims=True)
    assert len(_plan(tips, tilted, face40).runs) == 0


def test_runs_keep_within_the_angle_limit(face40):
    c = np.arange(0.0, 120.0, 1.0)
    tips, axes = turnmill(26.0, 0.0, -20.0, c)
    runs = _plan(tips, axes, face40, max_angle=10.0).runs
    assert len(runs) >= 12 and np.all(np.diff(runs, axis=1) <= 10)
    assert runs[0, 0] == 0 and runs[-1, 1] == len(c) - 1 and np.all(runs[1:, 0] == runs[:-1, 1])


def test_a_run_that_cannot_fit_falls_back_to_placed_poses(helix_cut, monkeypatch):
    """With a bound no fan can keep, every run is shortened to two steps and then placed:
    the cut equals the placed-pose cut with every pose whole (a path of placed poses cuts
    those between two rotary steps as fins, :mod:`vmach.stock.strategies.fins`: within the polygon's
    deviation of the whole poses)."""
    tool = helix_cut["tool"]
    c = np.arange(0.0, 60.0, 1.713)
    tips, axes = turnmill(26.0, 0.0, -5.0 - 0.01 * np.arange(len(c)), c)
    vols = []
    for kw in ({"fan_overcut": 1e-9}, {"fans": False}, {"fans": False, "whole": True}):
        with monkeypatch.context() as mp:
            if kw.pop("whole", False):
                mp.setenv(WITHOUT, "fins")
            stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01, **kw)
            stock.cut(tool, tips, axes)
        vols.append(stock.volume)
        assert stock.stats.fans == 0
    assert vols[0] == pytest.approx(vols[2], rel=1e-12)
    area = 2 * 12.5 * 60.0 * math.radians(60.0) * 26.0 / 12.5      # (a bound on the swept surface)
    assert vols[1] != vols[2] and abs(vols[1] - vols[2]) <= tool_solid(tool, 0.01).deviation * area


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_rotary_runs_stay_within_the_bound_against_dense_placed_poses(library, seed):
    """Random turn-mill runs — a convex support-function profile X(C), the tool centred on
    the contact point (Y = X'(C)) give or take a lateral offset,
    a pitch along Z, either sense of rotation — cut by fans and by placed poses 8× denser
    (which approach the true sweep from inside): the fans' floor is nowhere deeper than the
    dense cut's by more than their reported bound plus twice the polygon's deviation (the
    two use different polygon phases), and the flank nowhere deeper at all (beyond eps)."""
    rng = np.random.default_rng(seed)
    tool = library.lookup("GLOD D25")
    k = int(rng.integers(2, 5))
    amp = rng.uniform(0.0, 0.6) * 24.0 / (k * k - 1)    # h + h" >= 0.4 h (P3G-50: 0.42)
    pitch, y0, sense = rng.uniform(-0.02, 0.02), rng.uniform(-0.1, 0.1), rng.choice([-1.0, 1.0])
    n, step = 36, 1.713

    def path(sub):
        c = sense * np.arange(n * sub + 1) * step / sub
        x = 24.0 + amp * np.sin(np.radians(k * c))
        y = amp * k * np.cos(np.radians(k * c)) + y0      # the contact point h'(C), give or take
        return turnmill(x, y, -6.0 + pitch * np.arange(n * sub + 1) / sub, c)

    cuts = {}
    for name, sub, kw in (("fans", 1, {}), ("dense", 8, {"fans": False})):
        stock = Stock.from_spec("cylinder:d=60,l=60", chord=FINE, **kw)
        stock.cut(tool, *path(sub))
        cuts[name] = stock
    fans = cuts["fans"]
    assert fans.stats.fans > 0
    dev = tool_solid(tool, FINE).deviation
    phis = np.radians(sense * np.linspace(3, n * step - 3, 150))
    lo_f = floor_hits(fans.solid, phis, np.array([26.5, 28.0, 29.5]))
    lo_d = floor_hits(cuts["dense"].solid, phis, np.array([26.5, 28.0, 29.5]))
    assert np.nanmax(lo_d - lo_f) <= fans.stats.fan_overcut_mm + 2 * dev + 1e-6
    for z in (-3.0, -1.0):
        for phi in phis[::5]:
            # the fans' flank is not deeper than the dense cut's
            assert inward(fans.solid, phi, z) <= inward(cuts["dense"].solid, phi, z) + 1e-5


def _zigzag(x, y, z, c, sub):
    """Facing-style poses: at each index the workpiece turns (C to the next value, the tool's
    X/Y kept; ``sub`` samples per turn), then the tool slides to the next X/Y at that C."""
    xs, ys, zs, cs = [x[0]], [y[0]], [z[0]], [c[0]]
    for k in range(1, len(c)):
        for t in np.arange(1, sub + 1) / sub:
            xs.append(x[k - 1]), ys.append(y[k - 1]), zs.append(z[k - 1] + (z[k] - z[k - 1]) * t)
            cs.append(c[k - 1] + (c[k] - c[k - 1]) * t)
        xs.append(x[k]), ys.append(y[k]), zs.append(z[k]), cs.append(c[k])
    return turnmill(np.array(xs), np.array(ys), np.array(zs), np.array(cs))


def _zigzag_case(seed):
    """A random facing pass of the D40 face mill near X = 24 (see _zigzag): a convex
    profile or, for odd seeds, one with random notches that make the chain concave; Y near
    the contact point, jittered (back and forth along the travel), and a random pitch on the
    turns."""
    rng = np.random.default_rng(seed)
    k = int(rng.integers(2, 5))
    amp = rng.uniform(0.0, 0.8) * 24.0 / (k * k - 1)
    sense, n, step = rng.choice([-1.0, 1.0]), 30, 1.713
    c = sense * np.arange(n + 1) * step
    x = 24.0 + amp * np.sin(np.radians(k * c))
    if seed % 2:
        x = x - rng.choice([0.0, 0.0, 0.0, 0.3], size=n + 1) * rng.uniform(0.2, 1.0)
    y = amp * k * np.cos(np.radians(k * c)) + rng.uniform(-0.05, 0.05, size=n + 1)  # ~ the contact
    z = -20.0 + rng.uniform(-0.01, 0.01) * np.arange(n + 1)
    return (x, y, z, c), np.radians(sense * np.linspace(3, n * step - 3, 120))


def _fan_and_dense(tool, xyzc, blank, plain=False):
    """The pass cut with fans, and without them 8× denser (and, with ``plain``, at the same
    samples)."""
    cuts = []
    for sub, kw in ((1, {}), (8, {"fans": False})) + (((1, {"fans": False}),) if plain else ()):
        # the side's floor is exact for any polygon (turned to the travel): a coarser one will do
        stock = Stock.from_spec(blank, chord=0.002, **kw)
        stock.cut(tool, *_zigzag(*xyzc, sub))
        cuts.append(stock)
    return cuts


@pytest.mark.parametrize("seed", [1, 2, 3, 4, 5, 6])
def test_random_zigzag_runs_stay_within_the_bound_against_a_dense_cut(library, seed):
    """Fans over turns with straight slides between them (a facing pass: index C, move X/Y,
    index again), cut by fans and, without fans, with every turn sampled 8× denser and every
    slide a translation hull (exact). On a Ø56 blank the face mill's back face (X + 5.5) is
    beyond the stock, so fans may be used: their floor is nowhere deeper than the dense cut's
    by more than their bound, their flank nowhere deeper at all (beyond eps), and they remove
    all that the same samples remove without fans."""
    tool = library.lookup("GLOD D40")
    xyzc, phis = _zigzag_case(seed)
    fans, dense, plain = _fan_and_dense(tool, xyzc, "cylinder:d=56,l=60", plain=True)
    assert fans.stats.fans > 0
    rs = np.array([26.6, 27.1, 27.7])        # beyond the flank (X <= 26.3), inside the blank
    lo_f = floor_hits(fans.solid, phis, rs, top=-10.0)
    lo_d = floor_hits(dense.solid, phis, rs, top=-10.0)
    # (the two cuts turn their polygons to slightly different travel directions where the
    # turns also climb: up to twice the polygon's deviation between them)
    dev = tool_solid(tool, 0.002).deviation
    assert np.nanmax(lo_d - lo_f) <= fans.stats.fan_overcut_mm + 2 * dev + 1e-6
    for zz in (-25.0, -20.0, -15.0):
        for phi in phis[::4]:
            # the fans' flank is not deeper than the dense cut's
            assert inward(fans.solid, phi, zz) <= inward(dense.solid, phi, zz) + 1e-5
    # the fans hold the poses the plain cut places and the slides' hulls: they remove at
    # least as much (up to the eps by which M is moved out, over at most every pose's face)
    left = engine.volume(engine.subtract(fans.solid, [plain.solid]))
    assert left < EPS * (2 * tool.radius) ** 2 * fans.stats.poses


def test_fans_are_not_used_where_the_tools_back_lies_in_the_stock(library, monkeypatch):
    """The same facing pass on a Ø60 blank: the face mill's back face (X + 5.5 < 30) lies in
    the material, where the hull would fill the notches between neighbouring back faces —
    so no fans. Forced anyway, the fans cut the floor behind the tool deeper than the dense
    cut by several times their bound: the condition is what keeps them right."""

    tool = library.lookup("GLOD D40")
    xyzc, phis = _zigzag_case(2)
    fans, dense = _fan_and_dense(tool, xyzc, "cylinder:d=60,l=60")
    assert fans.stats.fans == 0
    assert engine.volume(fans.solid) >= engine.volume(dense.solid) - 1e-9
    monkeypatch.setattr(View, "back_clear", lambda self, tips, *a: np.ones(len(tips), bool))
    forced, _ = _fan_and_dense(tool, xyzc, "cylinder:d=60,l=60")
    assert forced.stats.fans > 0
    rs = np.array([27.0, 28.5, 29.5])
    over = floor_hits(dense.solid, phis, rs, top=-10.0) - floor_hits(forced.solid, phis, rs, top=-10.0)
    assert np.nanmax(over) > 3 * forced.stats.fan_overcut_mm


def test_the_tools_back_is_judged_by_the_stock_within_its_reach(library, monkeypatch):
    """The same facing pass on a stepped blank: Ø56 where the tool works (z -45..0), Ø60
    below, beyond its reach. The face mill's back face lies beyond the stock everywhere the
    tool reaches, though not beyond the whole blank: judged by the stock within the Z range of
    each pose's tool and its neighbours' (the trim slabs), the pass is fanned, within the bound
    of the dense cut; judged by the whole blank, it is not."""
    tool = library.lookup("GLOD D40")
    xyzc, phis = _zigzag_case(2)
    stepped = engine.union([engine.cylinder(28.0, -45.0, 0.0, 720), engine.cylinder(30.0, -60.0, -45.0, 720)])

    def cut(sub, **kw):
        stock = Stock(stepped, chord=0.002, **kw)
        stock.cut(tool, *_zigzag(*xyzc, sub))
        return stock

    fans, dense = cut(1), cut(8, fans=False)
    assert fans.stats.fans > 0
    rs = np.array([26.6, 27.1, 27.7])
    lo_f = floor_hits(fans.solid, phis, rs, top=-10.0)
    lo_d = floor_hits(dense.solid, phis, rs, top=-10.0)
    dev = tool_solid(tool, 0.002).deviation
    assert np.nanmax(lo_d - lo_f) <= fans.stats.fan_overcut_mm + 2 * dev + 1e-6
    monkeypatch.setattr(View, "back_clear", lambda self, tips, axes, pr: back_clear(
        tips, axes, pr, engine.to_mesh(stepped)[0]))
    assert cut(1).stats.fans == 0


@pytest.mark.parametrize("y0", [0.0, 3.0])
def test_fans_keep_the_foot_a_face_rim_leaves(library, monkeypatch, y0):
    """The D25 turned about the work axis at X = 26 with its centre Y = y0 off the contact
    point. Toward the rim of its face (the disc narrows to its bottom point) the tool reaches
    the flank only where its centre runs along it: with y0 = 3 mm the true tool leaves a foot
    of material at the flank's foot, about (3 - b)²/(2·26) proud at a height where the face is
    2b wide. Placed poses (8× denser) keep it; fans would cut it to the tangent polygon, so
    the planner does not fan such steps (fan.rim_standoff); forced, they gouge the foot.
    Centred (y0 = 0), fans are used and agree with the dense cut there."""
    import vmach.stock.fan_rims as fan_rims

    tool = library.lookup("GLOD D25")
    z_tip = -20.0
    z = z_tip - tool.radius + 0.05                     # 0.05 mm above the floor: b = 1.118
    half = math.sqrt(tool.radius ** 2 - (tool.radius - 0.05) ** 2)
    foot = 26.0 + max(y0 - half, 0.0) ** 2 / (2 * 26.0)

    def cut(sub, **kw):
        c = np.arange(0.0, 60.0 * sub + 1e-9, 1.0) * 1.713 / sub
        stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.002, **kw)
        stock.cut(tool, *turnmill(26.0, y0, z_tip, c))
        return stock

    def flank(stock):
        phis = np.radians(np.linspace(20.0, 80.0, 25))
        hits = [stock.solid.ray_cast((40 * np.cos(q), 40 * np.sin(q), z), (0.0, 0.0, z))[0].position
                for q in phis]
        return np.array([math.hypot(h[0], h[1]) for h in hits])

    fans, dense = cut(1), cut(8, fans=False)
    r_dense = flank(dense)
    assert r_dense.min() >= foot - 1e-3                     # the dense cut keeps the foot
    if y0 == 0.0:
        assert fans.stats.fans > 0
        assert np.abs(flank(fans) - r_dense).max() <= float(scallop_bound(26.0, 1.713)) + 1e-4
        return
    assert foot - 26.0 > 0.03
    assert fans.stats.fans == 0
    monkeypatch.setattr(fan_rims, "rim_standoff", lambda tips, *a, **k: np.zeros(len(tips) - 1))
    forced = cut(1)
    assert forced.stats.fans > 0
    assert (r_dense - flank(forced)).max() > 0.5 * (foot - 26.0)   # forced fans gouge the foot


def test_a_rim_whose_foot_would_lie_beyond_the_stock_is_fanned(library, monkeypatch):
    """The same D25 3 mm off the contact point, on a shaft 20 mm long with the tool centre
    at z = -10: both rims (z = +2.5 and -22.5) lie beyond the stock, so the feet they leave
    are in the air and the steps are fanned (without the stock's bounds they are not). The
    flank is the dense cut's tangent polygon at every height."""
    tool = library.lookup("GLOD D25")

    def cut(sub, **kw):
        c = np.arange(0.0, 60.0 * sub + 1e-9, 1.0) * 1.713 / sub
        stock = Stock.from_spec("cylinder:d=60,l=20", chord=0.002, **kw)
        stock.cut(tool, *turnmill(26.0, 3.0, -10.0, c))
        return stock

    fans, dense = cut(1), cut(8, fans=False)
    assert fans.stats.fans > 0
    bound = float(scallop_bound(26.0, 1.713))
    for z in (-0.5, -10.0, -19.5):
        for q in np.radians(np.linspace(20.0, 80.0, 13)):
            gap = inward(dense.solid, q, z) - inward(fans.solid, q, z)   # material the fans leave
            assert -1e-4 <= gap <= bound + 1e-4          # never deeper, within the scallops
    plan = fans_strategy.plan_fans
    monkeypatch.setattr(fans_strategy, "plan_fans", lambda *a, **k: plan(*a, **{**k, "stock_box": None}))
    assert cut(1).stats.fans == 0


@pytest.fixture(scope="module")
def helix_turns(library):
    """3.2 turns of the finishing helix: fans as made (bridges that the path's other turns cut
    anyway do not count against the bound), and with every bridge counted; and the true floor
    the side cuts over the whole motion (the last turn's)."""
    phis = np.radians(np.linspace(5, 355, 300))
    rs = np.linspace(HELIX_X + 0.5, 29.5, 5)
    tool, tips, axes, true = finishing_helix(library, 1150.0, phis, rs)
    out = {"tool": tool, "true": true}
    for name in ("fans", "alone"):
        with pytest.MonkeyPatch.context() as mp:
            if name == "alone":
                mp.setattr(make_fans_module, "covered",
                           lambda grid, need, *a, **k: np.zeros(need.shape, bool))
            # (fans alone: columns would take the same sector of consecutive turns at once)
            stock = Stock.from_spec("cylinder:d=60,l=60", chord=FINE, columns=False)
            stock.cut(tool, tips, axes)
            out[name] = (stock, floor_hits(stock.solid, phis, rs))
    return out


def test_bridges_the_other_turns_cut_anyway_let_fans_grow(helix_turns):
    """A helix's fans bridge the floor their side sweeps where the next turn, 2.1 mm lower,
    cuts it anyway: there the bridge does not count, the fans grow longer, and the part's floor
    — the last turn's, whose bridges count — stays within the bound of the true floor."""
    dev = tool_solid(helix_turns["tool"], FINE).deviation
    fans, hits = helix_turns["fans"]
    alone, alone_hits = helix_turns["alone"]
    assert fans.stats.fan_covered_mm > 2 * tol.fan_overcut          # bridged more, where covered
    assert 0 < fans.stats.fan_overcut_mm <= tol.fan_overcut
    assert alone.stats.fan_covered_mm == 0.0
    assert fans.stats.fans < 0.8 * alone.stats.fans                  # longer fans
    over = helix_turns["true"] - hits                                # > 0: floor cut too deep
    assert np.nanmax(over) <= fans.stats.fan_overcut_mm + dev + 1e-6
    assert np.nanmax(np.abs(hits - alone_hits)) <= tol.fan_overcut + 2 * dev


def test_a_sample_is_covered_only_when_every_patch_around_it_lies_in_one_pose():
    """covered(): a 3 × 2 × 4 grid of samples on the plane z = 0, a tool (radius 5, length 10)
    standing on it along +x: the samples within its cylinder — with what lies 0.1 mm above
    them — are covered; a sample whose patches reach out of the cylinder is not; with
    ``behind`` the cylinder reaches that far behind the face as well."""
    tool = Prism(radius=5.0, length=10.0, ring=np.column_stack([
        5 * np.cos(np.linspace(0, 2 * np.pi, 64, endpoint=False)),
        5 * np.sin(np.linspace(0, 2 * np.pi, 64, endpoint=False)), np.zeros(64)]),
        inner=5.0 * np.cos(np.pi / 64))
    x = np.array([1.0, 3.0, 5.0, 7.0])                         # along the lines
    y = np.array([[0.0, 1.0, 2.0], [2.0, 3.0, 4.0]]).T         # across (3, 2): two steps
    grid = np.stack(np.broadcast_arrays(x[None, None, :], y[:, :, None], 0.0), axis=-1)  # (3, 2, 4, 3)
    need = np.ones(grid.shape[:3], bool)
    up = np.array([0.0, 0.0, 1.0])
    tips, axes = np.array([[0.0, 1.5, 0.0]]), np.array([[1.0, 0.0, 0.0]])
    inner = 5.0 * np.cos(np.pi / 64)
    got = covered(grid, need, 0.1, up, tips, axes, tool)
    assert got.all()                                            # all within 2.5 + 0.1 of the axis
    # the tool moved so that the second step's far samples (y = 4) lie outside
    tips2 = np.array([[0.0, 4.0 - inner - 0.05, 0.0]])
    got = covered(grid, need, 0.1, up, tips2, axes, tool)
    assert not got[1:, 1].any()                                 # y = 3, 4: a patch reaches y = 4
    assert got[0, 1].all() and got[:, 0].all()                  # y = 2 and step 1 lie within
    # the tool ends before the last samples (x = 7): those and their neighbours are out
    got = covered(grid, need, 0.1, up, np.array([[-4.0, 1.5, 0.0]]), axes, tool)
    assert not got[..., 2:].any() and got[..., :2].all()
    # only what is asked for is answered
    assert not covered(grid, np.zeros_like(need), 0.1, up, tips, axes, tool).any()
    # the face 0.05 mm past the first samples (x = 1): they lie behind it, and their
    # neighbours' patches reach them — covered only by cylinders taken at least that far behind
    ahead = np.array([[1.05, 1.5, 0.0]])
    assert not covered(grid, need, 0.1, up, ahead, axes, tool)[..., :2].any()
    assert covered(grid, need, 0.1, up, ahead, axes, tool, behind=0.06)[..., :2].all()
    assert not covered(grid, need, 0.1, up, ahead, axes, tool, behind=0.04)[..., :2].any()


@pytest.mark.parametrize("seed", [1, 2])
def test_random_helices_over_two_turns_stay_within_the_bound(library, seed):
    """Random convex profiles turned 2.3 times with a pitch (the tool on the contact point,
    give or take): the fans' bridges that the next turn cuts anyway are not counted, and the
    part still lies within the reported bound (plus both polygons' deviation) of a cut by
    placed poses 4× denser — the floor nowhere deeper by more, the flank nowhere deeper."""
    rng = np.random.default_rng(seed)
    tool = library.lookup("GLOD D25")
    k = int(rng.integers(2, 5))
    amp = rng.uniform(0.0, 0.6) * 24.0 / (k * k - 1)
    pitch, y0, sense = rng.uniform(0.005, 0.02), rng.uniform(-0.1, 0.1), rng.choice([-1.0, 1.0])
    n, step = 483, 1.713

    def path(sub):
        c = sense * np.arange(n * sub + 1) * step / sub
        x = 24.0 + amp * np.sin(np.radians(k * c))
        y = amp * k * np.cos(np.radians(k * c)) + y0
        return turnmill(x, y, -6.0 - pitch * np.arange(n * sub + 1) / sub, c)

    cuts = {}
    for name, sub, kw in (("fans", 1, {}), ("dense", 4, {"fans": False})):
        stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.002, **kw)
        stock.cut(tool, *path(sub))
        cuts[name] = stock
    fans = cuts["fans"]
    assert fans.stats.fans > 0 and fans.stats.fan_covered_mm > tol.fan_overcut
    dev = tool_solid(tool, 0.002).deviation
    phis = np.radians(np.linspace(3, 357, 300))
    rs = np.array([26.5, 28.0, 29.5])
    deeper = floor_hits(cuts["dense"].solid, phis, rs) - floor_hits(fans.solid, phis, rs)
    assert np.nanmax(deeper) <= fans.stats.fan_overcut_mm + 2 * dev + 1e-6
    for z in (-3.0, -10.0):
        for phi in phis[::5]:
            assert inward(fans.solid, phi, z) <= inward(cuts["dense"].solid, phi, z) + 1e-5


class _Pose:
    def __init__(self, tip, axis):
        self.tip, self.axis = tip, axis


def _turn_motion(tool, x: float, y: float, z: float, c: np.ndarray):
    """A turn of ``tool`` about the work axis (turn-mill poses at X, Y, Z, C1 degrees c) as a
    :class:`vmach.stock.sweeps.Motion`: its machine axes and their kinematics."""
    from vmach.stock.cusps import outline
    from vmach.stock.sweeps import Motion

    q = np.column_stack(np.broadcast_arrays(x, y, z, c)).astype(float)
    tips, axes = turnmill(q[:, 0], q[:, 1], q[:, 2], q[:, 3])
    return Motion(q, lambda qq: _Pose(*turnmill(qq[:, 0], qq[:, 1], qq[:, 2], qq[:, 3])), tips, axes,
                  *outline(tool))


def test_what_another_paths_true_tool_sweeps(library):
    """Sweeps.holds: a point is held where another path's true tool passes through it — the
    D25 turned 60° about the work axis at X = 25, its floor at z = -40: just above the floor
    (0.01 mm) between two of its sampled poses, yes; just below it, in front of its face, or
    where it never turns to, no; its own path skipped, nothing."""
    from vmach.stock.sweeps import Sweeps

    tool = library.lookup("GLOD D25")
    sweeps = Sweeps([_turn_motion(tool, 25.0, 0.0, -27.5, np.arange(0.0, 61.0, 1.713))])
    z = np.array([0.0, 0.0, 1.0])

    def at(r, deg, height):
        a = np.radians(deg)
        return [r * np.cos(a), r * np.sin(a), height]

    pts = np.array([at(26.0, 30.85, -39.99), at(29.5, 10.3, -39.99), at(26.0, 30.85, -40.01),
                    at(24.9, 30.85, -35.0), at(26.0, 90.0, -35.0)])
    assert sweeps.holds(pts, z).tolist() == [True, True, False, False, False]
    assert not sweeps.holds(pts, z, skip=0).any()


def test_recut_asks_for_a_margin_and_keeps_a_paths_own_pass_apart(library):
    """Coverage.recut: a point 0.01 mm above the D25's floor (z = -40) is held by another
    path's sampled poses with no margin, not with 0.02 mm; the same turn given as the path's
    own is no recut within ``gap`` of the point's step (its own pass) — ``near`` asks that
    pass alone — and is one beyond it (a second pass, one full turn later)."""
    from vmach.stock.sweeps import Sweeps

    tool = library.lookup("GLOD D25")
    c = np.arange(0.0, 61.0, 1.713)
    turn = _turn_motion(tool, 25.0, 0.0, -27.5, c)
    z = np.array([0.0, 0.0, 1.0])
    a = np.radians(c[10])                                   # under a sampled pose's axis
    point = np.array([[26.0 * np.cos(a), 26.0 * np.sin(a), -39.99]])
    other = Sweeps([_turn_motion(tool, 30.0, 0.0, -60.0, c), turn]).coverage(0)
    assert other.recut(point, [10], z, np.array([0.0]), 50.0).tolist() == [True]
    assert other.recut(point, [10], z, np.array([0.02]), 50.0).tolist() == [False]
    own = Sweeps([turn]).coverage(0)
    assert own.recut(point, [10], z, np.array([0.0]), 50.0).tolist() == [False]
    assert own.recut(point, [10], z, np.array([0.0]), 50.0, near=True).tolist() == [True]
    twice = np.r_[c, c + 360.0]
    again = Sweeps([_turn_motion(tool, 25.0, 0.0, -27.5, twice)]).coverage(0)
    assert again.recut(point, [10], z, np.array([0.0]), 50.0).tolist() == [True]


def test_at_poses_holds_what_another_paths_sampled_poses_hold(library):
    """Sweeps.at_poses: a point 0.01 mm above the D25's floor under one of its sampled poses'
    axes is held by another path's poses with no margin, not with 0.02 mm, not below the
    floor, not where the turn never reaches; never by the path itself (skip); and on random
    points around the turn, only ever where one of the other path's sampled poses holds the
    point (all of them asked), and most of those."""
    from vmach.stock.sweeps import Sweeps, in_tool

    tool = library.lookup("GLOD D25")
    c = np.arange(0.0, 61.0, 1.713)
    turn = _turn_motion(tool, 25.0, 0.0, -27.5, c)
    sweeps = Sweeps([_turn_motion(tool, 30.0, 0.0, -60.0, c), turn])
    a = np.radians(c[10])
    pts = np.array([[26.0 * np.cos(a), 26.0 * np.sin(a), -39.99],
                    [26.0 * np.cos(a), 26.0 * np.sin(a), -40.01],
                    [26.0 * np.cos(np.radians(90.0)), 26.0 * np.sin(np.radians(90.0)), -35.0]])
    assert sweeps.at_poses(pts, 0, np.zeros(3)).tolist() == [True, False, False]
    assert sweeps.at_poses(pts, 0, np.full(3, 0.02)).tolist() == [False, False, False]
    assert not sweeps.at_poses(pts, 1, np.zeros(3)).any()
    assert sweeps.coverage(0).at_poses(pts, np.zeros(3)).tolist() == [True, False, False]
    rng = np.random.default_rng(3)
    phi = np.radians(rng.uniform(-5.0, 65.0, 400))
    r = rng.uniform(24.0, 40.0, 400)
    grid = np.column_stack([r * np.cos(phi), r * np.sin(phi), rng.uniform(-41.0, -14.0, 400)])
    near = sweeps.at_poses(grid, 0, np.full(400, 0.01))
    m = sweeps.motions[1]
    every = in_tool(grid[:, None, :] - m.tips[None], m.axes[None], m.zs, m.rs, 0.01, 0.01).any(axis=1)
    assert near.sum() > 100
    assert not (near & ~every).any()
    assert near.sum() >= 0.9 * every.sum()


def test_a_crossing_off_the_tips_azimuth_is_found_in_the_wide_window(library):
    """The D25 8 mm off centre (Y = 8): its plane through the axis and the work Z passes a
    point on its axis at r = 30 when the tip's azimuth is 2.2° past the point's — beyond the
    narrow window that is searched first (WINDOWS[0]), so only the wide one holds it."""
    from vmach.stock.sweeps import WINDOWS, Sweeps, _crossings

    tool = library.lookup("GLOD D25")
    motion = _turn_motion(tool, 25.0, 8.0, -27.5, np.arange(0.0, 61.0, 1.713))
    z = np.array([0.0, 0.0, 1.0])
    a = np.radians(30.0 - np.degrees(np.arctan2(8.0, 25.0)) + np.degrees(np.arcsin(8.0 / 30.0)))
    point = np.array([[30.0 * np.cos(a), 30.0 * np.sin(a), -27.5]])
    assert WINDOWS[0] < np.radians(2.0) < WINDOWS[-1]
    assert len(_crossings(motion, point, z, WINDOWS[0])[0]) == 0
    assert len(_crossings(motion, point, z, WINDOWS[-1])[0]) > 0
    assert Sweeps([motion]).holds(point, z).tolist() == [True]


def test_a_paths_one_long_move_is_indexed_apart_and_no_crossing_is_lost(library):
    """A turn of the D25 (1.713° steps at X = 25, Y = 0.5 off centre) that ends in one long
    move — the axis turned 9° more while the tool rises 60 mm — is indexed in two parts: the
    turn's steps searched with their own window and heights, the long move alone with its
    own. No crossing where a point lies inside the tool is lost: on random points about the
    turn, :func:`_crossings` finds every (point, step) pair that a search of every step
    finds (the tool's plane crossing the point, the point inside the true tool there)."""
    from vmach.stock.sweeps import WINDOWS, _crossings, _index, _inside

    tool = library.lookup("GLOD D25")
    c = np.r_[np.arange(0.0, 61.0, 1.713), 70.0]
    z = np.r_[np.full(len(c) - 1, -27.5), 32.5]
    motion = _turn_motion(tool, 25.0, 0.5, z, c)
    om = np.array([0.0, 0.0, 1.0])
    parts = _index(motion, om)
    assert len(parts) == 2
    assert [len(p.order) for p in parts] == [len(c) - 2, 1]
    assert parts[0].span < parts[1].span and parts[0].turn < parts[1].turn
    rng = np.random.default_rng(7)
    phi = np.radians(rng.uniform(-5.0, 75.0, 600))
    r = rng.uniform(22.0, 40.0, 600)
    pts = np.column_stack([r * np.cos(phi), r * np.sin(phi), rng.uniform(-45.0, 40.0, 600)])
    pi, i = _crossings(motion, pts, om, WINDOWS[-1], parts)
    held = _inside(motion, pts, om, pi, i)
    found = set(zip(pi[held].tolist(), i[held].tolist(), strict=True))
    # every pair, searched without windows or bins
    ap, ai = np.meshgrid(np.arange(len(pts)), np.arange(len(c) - 1), indexing="ij")
    ap, ai = ap.ravel(), ai.ravel()
    t = np.cross(om, motion.axes)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    f0 = np.einsum("ij,ij->i", pts[ap] - motion.tips[ai], t[ai])
    f1 = np.einsum("ij,ij->i", pts[ap] - motion.tips[ai + 1], t[ai + 1])
    cross = f0 * f1 <= 0.0
    ap, ai = ap[cross], ai[cross]
    held = _inside(motion, pts, om, ap, ai)
    every = set(zip(ap[held].tolist(), ai[held].tolist(), strict=True))
    assert len(every) > 100
    assert every == found


def test_a_rim_band_another_paths_tool_sweeps_is_fanned(library):
    """The D25 3 mm off the contact point at X = 26 leaves a foot at its face's rim, so its
    steps are not fanned (test_fans_keep_the_foot_a_face_rim_leaves) — unless another path's
    true tool sweeps that band: a finishing turn 1 mm deeper, centred, at the same floor, cuts
    through the feet (its body, from its face at X = 25 outward, passes them just above the
    floor). Told so (``others``), the first turn is fanned; the two cut together leave the
    part of the two cut densely without fans, within the scallop of the sampled faces."""
    from vmach.stock.sweeps import Sweeps

    tool = library.lookup("GLOD D25")
    first = (26.0, 3.0, -27.5)
    finish = (25.0, 0.0, -27.5)

    def cut(sub, cover=None, **kw):
        c = np.arange(0.0, 60.0 * sub + 1e-9, 1.0) * 1.713 / sub
        stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.002, **kw)
        n = stock.cut(tool, *turnmill(*first, c), cover=cover)
        fans = stock.stats.fans
        stock.cut(tool, *turnmill(*finish, np.arange(-10.0, 120.0, 1.713 / sub)))
        return stock, n, fans

    c = np.arange(0.0, 60.0 + 1e-9, 1.0) * 1.713
    sweeps = Sweeps([_turn_motion(tool, *first, c),
                     _turn_motion(tool, *finish, np.arange(-10.0, 120.0, 1.713))])
    plain, _, plain_fans = cut(1)
    told, n_told, told_fans = cut(1, sweeps.coverage(0))
    dense, _, _ = cut(8, fans=False)
    assert plain_fans == 0 and told_fans > 0
    assert n_told < plain.stats.cutters - 10
    bound = float(scallop_bound(25.0, 1.713))
    for zz in (-39.98, -35.0, -25.0):
        for q in np.radians(np.linspace(5.0, 95.0, 19)):
            gap = inward(dense.solid, q, zz) - inward(told.solid, q, zz)
            assert -1e-4 <= gap <= bound + 1e-4
    phis = np.radians(np.linspace(5.0, 95.0, 31))
    rs = np.array([25.5, 27.0, 29.5])
    assert np.nanmax(np.abs(floor_hits(told.solid, phis, rs) - floor_hits(dense.solid, phis, rs))) <= 1e-3


@pytest.mark.parametrize("sense, phase", [(1.0, 90.0), (1.0, 180.0), (-1.0, 270.0)])
def test_a_fans_end_poses_are_turned_for_its_own_steps(library, sense, phase):
    """A facing pass of the D40 face mill (turn C, slide X/Y, ...), fanned, then a retract
    along the rotation axis, as the polygon program does between its passes. The fan's last
    pose turned for the move from the slide before it to the retract after it would have its
    polygon exact toward a direction 88° off the floor's: a vertex 2° off the floor then dips
    below it, and the fan's hull spreads the dip (measured 0.0035–0.0059 mm below the floor
    for these phases). Turned for its own step, the floor is nowhere below the true one."""
    tool = library.lookup("GLOD D40")
    c = sense * np.arange(31) * 1.713
    x = 25.0 + 0.5 * np.sin(np.radians(3 * c + phase))
    y = 1.5 * np.cos(np.radians(3 * c + phase))
    tips, axes = _zigzag(x, y, np.full(len(c), -20.0), c, 1)
    tips = np.vstack([tips, tips[-1] + [0.0, 0.0, 10.0]])          # then up along Z
    axes = np.vstack([axes, axes[-1]])
    stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01)
    stock.cut(tool, tips, axes, cover=_EverySwept())   # every rim swept
    assert stock.stats.fans > 0
    lo, hi = sorted([c[0], c[-1]])
    phis = np.radians(np.linspace(lo - 15.0, hi + 15.0, 300))
    floor = floor_hits(stock.solid, phis, np.array([26.5, 27.5, 28.5, 29.5]), top=-30.0)
    assert np.nanmin(floor) >= -40.0 - 1e-6


def test_rotation_axes_are_grouped_by_line_whatever_their_sign_or_length():
    """sweeps.by_axis: the fans' rim bands and the feet ask the other paths about one axis per
    line — ω and −ω (a C axis turning either way), of any length, to 1e-9 — and leave out the
    rows without one."""
    from vmach.stock.sweeps import by_axis

    om = np.array([[0.0, 0.0, 2.0], [0.0, 0.0, -1.0], [0.0, 1e-12, 1.0], [1.0, 0.0, 0.0],
                   [0.0, 0.6, 0.8], [0.0, 0.0, 0.0], [-3.0, 0.0, 0.0]])
    ok = np.linalg.norm(om, axis=1) > 1e-9
    groups = {tuple(np.round(u, 12)): sorted(g.tolist()) for u, g in by_axis(om, ok)}
    assert groups == {(0.0, 0.0, 1.0): [0, 1, 2], (1.0, 0.0, 0.0): [3, 6], (0.0, 0.6, 0.8): [4]}
    for u, _ in by_axis(om, ok):
        assert np.linalg.norm(u) == pytest.approx(1.0, abs=1e-15)
    assert by_axis(om, np.zeros(len(om), bool)) == []
