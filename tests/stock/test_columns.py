"""Column cutters (vmach/stock/column.py): one solid for the same sector of several turns of a
helix, instead of one fan per turn.

What they must do, tested against cuts made without them and against answers known on their
own: every fan step is cut by exactly one column cell or one fan run; the part is the part the
turns' fans make — the same flank (to the bound the columns report), floors no deeper than
the true tool's by more than that bound, no material the fans remove left behind — and where
the turns do not follow one profile (a second pass deeper) there are no columns at all.
"""

from __future__ import annotations

import numpy as np
import pytest

from tests.stock.conftest import turnmill
from tests.stock.test_fans import floor_hits, inward, true_floor
from vmach.stock import Stock, engine
from vmach.stock.column import plan_columns
from vmach.stock.fan import back_clear, plan_fans, prism
from vmach.stock.halfplanes import clip_box, polygon
from vmach.stock.make_fans import FanMaker
from vmach.tol import tol
from vmach.tooling import tool_solid

CHORD = 0.002
PITCH = 0.01          # mm along Z per pose, as the polygon program's finishing (2.1 mm a turn)
STEP = 1.713          # degrees of C1 per pose


def helix(turns: float, x=26.0, z0=-5.0, sense=1.0):
    """The D25's finishing helix on a round of radius ``x`` (or X as a function of C1): tips
    and radial axes, C1 in degrees (increasing, or decreasing with ``sense`` -1)."""
    c = sense * np.arange(0.0, 360.0 * turns, STEP)
    z = z0 - PITCH * np.arange(len(c))
    x = x(np.abs(c)) if callable(x) else np.full(c.shape, float(x))
    tips, axes = turnmill(x, 0.0, z, c)
    return tips, axes, c, z


def _fan_plan(tool, tips, axes, blank="cylinder:d=60,l=60"):
    stock = Stock.from_spec(blank, chord=CHORD)
    ts = tool_solid(tool, CHORD)
    pr = prism(ts.pieces[0])
    fans = plan_fans(tips, axes, np.ones(len(tips) - 1, bool), pr,
                     clear=back_clear(tips, axes, pr, stock.blank.hull.corners), stock_box=stock.bounds)
    return ts, fans


@pytest.mark.parametrize("seed", range(8))
def test_the_dual_polygon_is_the_box_clipped_by_every_half_plane(seed):
    """polygon() (the lines' dual hull) against clipping the box by each half-plane in turn,
    on random sets of face lines — a sector of outward normals, as a column's — with and
    without lines that make it empty."""
    rng = np.random.default_rng(seed)
    m = int(rng.integers(1, 150))
    ang = rng.uniform(-0.5, 0.5, m) + rng.uniform(-np.pi, np.pi)
    lines = np.column_stack([np.cos(ang), np.sin(ang), rng.uniform(20.0, 27.0, m)])
    if seed % 4 == 3:               # a line facing the other way, beyond the others: empty
        lines = np.vstack([lines, [-np.cos(ang[0]), -np.sin(ang[0]), -40.0]])
    lo, hi = np.array([-70.0, -60.0]), np.array([65.0, 80.0])
    a, b = polygon(lines, lo, hi), clip_box(lines, lo, hi)
    assert len(a) == 0 if len(b) == 0 else len(a) >= 3
    if len(b):
        near = lambda p, q: np.linalg.norm(p[:, None] - q[None], axis=2).min(axis=1).max()  # noqa: E731
        assert max(near(a, b), near(b, a)) < 1e-7
        # and every corner is on the region's boundary: inside all, on at least one line
        s = a @ lines[:, :2].T - lines[:, 2]
        assert s.max() < 1e-7


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_columns_take_every_fan_step_once(library, sense):
    """On 4.5 turns of the helix: columns hold two or more cells of consecutive turns in the
    same sector, each cell beginning before its wedge and ending after it; the fan runs left
    and the cells together hold every fan step exactly once (a one-step leftover grows into a
    neighbouring cell, which is allowed: both are right on their own)."""
    tool = library.lookup("GLOD D25")
    tips, axes, c, _ = helix(4.5, sense=sense)
    ts, fans = _fan_plan(tool, tips, axes)
    plan = plan_columns(tips, axes, fans, radius=ts.radius, inner=ts.radius * np.cos(np.pi / ts.segments))
    # one column per sector (of 4.5 turns: the first and last half turns lack the neighbours
    # that sweep a cell's spill, and the last turn in a sector has no turn below to cut its
    # floor anyway)
    assert len(plan.columns) == round(360.0 / tol.column_sector)
    assert all(len(col.cells) >= 2 for col in plan.columns)
    fan_steps = np.zeros(len(tips) - 1, int)
    for a, b in fans.runs:
        fan_steps[a:b] += 1
    cell_steps = np.zeros_like(fan_steps)
    for col in plan.columns:
        assert len(col.cells) >= 2
        sector = np.floor(np.abs(c[col.cells[:, 0]]) / tol.column_sector)
        assert np.all(np.diff(sector) == 360.0 / tol.column_sector)          # consecutive turns
        for a, b in col.cells:
            cell_steps[a:b] += 1
            for plane, pose in zip(col.wedge, (a, b), strict=True):
                assert tips[pose] @ plane[:3] > plane[3]     # the cell's end poses lie outside
        assert 0.0 <= col.depth <= tol.fan_overcut
    left = np.zeros_like(fan_steps)
    for a, b in plan.fans.runs:
        assert b - a >= 2
        left[a:b] += 1
    both = cell_steps + left
    assert np.all(both[fan_steps > 0] >= 1)            # every fan step is cut ...
    assert np.all(both[fan_steps == 0] == 0)           # ... and nothing else
    # twice only where neighbouring sectors' cells meet (each begins before its wedge and the
    # last ends after it) or a one-step leftover grew into a cell
    assert cell_steps.max() <= 2 and left.max() == 1 and both.max() <= 2


@pytest.fixture(scope="module")
def helix_parts(library):
    """4.5 turns of the helix cut with columns and with fans only; the true floor its side
    cuts in the last turn."""
    tool = library.lookup("GLOD D25")
    tips, axes, c, z = helix(4.5)
    out = {"tool": tool}
    for name, kw in (("columns", {}), ("fans", {"columns": False})):
        stock = Stock.from_spec("cylinder:d=60,l=60", chord=CHORD, **kw)
        stock.cut(tool, tips, axes)
        out[name] = stock
    phis = np.radians(np.linspace(5, 355, 200))
    rs = np.linspace(26.5, 29.5, 4)
    last = c >= c[-1] - 400.0
    out["floor"] = (phis, rs, true_floor(phis, rs, 26.0, tool.radius, c[last], z[last]))
    return out


def test_columns_are_made_and_leave_nothing_the_fans_remove(helix_parts):
    cols, fans = helix_parts["columns"], helix_parts["fans"]
    # every sector's column is made
    assert cols.stats.columns == round(360.0 / tol.column_sector)
    assert cols.stats.column_cells >= 2 * cols.stats.columns
    assert fans.stats.columns == 0
    assert cols.stats.cutters < 0.9 * fans.stats.cutters
    assert 0.0 <= cols.stats.column_overcut_mm <= tol.fan_overcut
    # the two cuts differ by films: on the floor the last turn's side sweeps (each within
    # its bound of the true floor, fans cut to other lengths), and on the flank (a column's
    # face chain is the finer tangent polygon of all its turns' faces)
    left = engine.volume(engine.subtract(cols.solid, [fans.solid]))
    extra = engine.volume(engine.subtract(fans.solid, [cols.solid]))
    floor = np.pi * (30.0**2 - 26.0**2)
    flank = 2 * np.pi * 26.0 * 40.0
    assert left < floor * tol.fan_overcut
    assert extra < floor * tol.fan_overcut + flank * cols.stats.column_overcut_mm


def test_the_flank_is_within_the_columns_bound_of_the_fans(helix_parts):
    """Radial rays at the flank: the columns cut it at most their reported bound deeper than
    the fans (the face chain of all a column's turns, a finer tangent polygon), never
    shallower (beyond the eps by which M is moved out)."""
    cols, fans = helix_parts["columns"], helix_parts["fans"]
    bound = cols.stats.column_overcut_mm
    for z in (-6.0, -12.0, -20.0, -30.0):
        for phi in np.radians(np.linspace(3, 357, 120)):
            deeper = inward(cols.solid, phi, z) - inward(fans.solid, phi, z)
            assert -1e-5 <= deeper <= bound + 1e-5


def test_the_floor_the_side_cuts_is_within_the_reported_bound(helix_parts):
    """The floor the last turn's side leaves (rays from above, beyond the flank): no deeper
    than the true tool's continuous motion by more than the reported bound plus the
    polygon's deviation."""
    cols = helix_parts["columns"]
    phis, rs, true = helix_parts["floor"]
    dev = tool_solid(helix_parts["tool"], CHORD).deviation
    hits = floor_hits(cols.solid, phis, rs, top=-20.0)
    assert np.nanmax(true - hits) <= cols.stats.fan_overcut_mm + dev + 1e-6


def test_turns_on_different_profiles_make_no_columns(library):
    """Every other turn 0.05 mm deeper: at a height only a shallower turn reaches, a column
    would cut the deeper turn's chain — so the planner makes none, and the cut is the fans'."""
    tool = library.lookup("GLOD D25")

    def x(c):
        return 26.0 - 0.05 * (np.floor(c / 360.0) % 2)

    tips, axes, _, _ = helix(3.5, x=x)
    ts, fans = _fan_plan(tool, tips, axes)
    assert len(fans.runs) > 10
    plan = plan_columns(tips, axes, fans, radius=ts.radius, inner=ts.radius * np.cos(np.pi / ts.segments))
    assert plan.columns == []
    # 0.001 mm apart, within the bound: columns, and their depth says so
    tips2, axes2, _, _ = helix(3.5, x=lambda c: 26.0 - 0.001 * (np.floor(c / 360.0) % 2))
    ts, fans2 = _fan_plan(tool, tips2, axes2)
    plan2 = plan_columns(tips2, axes2, fans2, radius=ts.radius, inner=ts.radius * np.cos(np.pi / ts.segments))
    assert plan2.columns and max(col.depth for col in plan2.columns) >= 0.001 - 1e-6


def test_the_last_turns_floor_is_kept_within_the_bound_by_two_guards(library, helix_parts, monkeypatch):
    """The last turn in a sector has no turn below to cut the floor its side sweeps anyway, and
    a cell spans more than a fan: in a column its hull would bridge that floor by more than
    the bound. The planner leaves such turns out (no turn beyond them); let in anyway, the
    made column's measurement sends their cells back to fans, and the floor stays within the
    bound; with neither guard the column hulls cut it deeper than the bound and the polygon
    allow."""
    import vmach.stock.column as column_module

    tool = helix_parts["tool"]
    tips, axes, _, _ = helix(4.5)
    ts, fans = _fan_plan(tool, tips, axes)
    inner = ts.radius * np.cos(np.pi / ts.segments)

    def cells():
        plan = plan_columns(tips, axes, fans, radius=ts.radius, inner=inner)
        return sum(len(col.cells) for col in plan.columns)

    kept = cells()
    assert helix_parts["columns"].stats.column_cells == kept          # as planned, all made
    monkeypatch.setattr(column_module, "_turn_beyond", lambda *a: True)
    planned = cells()
    assert planned > kept
    phis, rs, true = helix_parts["floor"]
    dev = tool_solid(tool, CHORD).deviation
    measured = Stock.from_spec("cylinder:d=60,l=60", chord=CHORD)
    measured.cut(tool, tips, axes)
    assert measured.stats.column_cells < planned
    over = true - floor_hits(measured.solid, phis, rs, top=-20.0)
    assert np.nanmax(over) <= measured.stats.fan_overcut_mm + dev + 1e-6
    monkeypatch.setattr(FanMaker, "column_bridges",
                        lambda self, job, *a: (np.zeros(len(job.column.cells)), 0.0))
    forced = Stock.from_spec("cylinder:d=60,l=60", chord=CHORD)
    forced.cut(tool, tips, axes)
    assert forced.stats.column_cells == planned
    over = true - floor_hits(forced.solid, phis, rs, top=-20.0)
    assert np.nanmax(over) > tol.fan_overcut + dev + 1e-3
