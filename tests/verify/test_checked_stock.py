"""The verify checks of the stock stage (``simulate(..., checks=True)``) against the plain cut.

A D40 face mill (5.5 mm of inserts, a Ø36 shank behind them) turns a Ø30 shaft about its
axis twice: with its face at X = 12, then at X = 9. In the second turn the shank (X >= 14.5)
lies inside the blank's radius, but the first turn has cleared everything beyond X = 12 there:
the shank meets the blank and never the stock. Without the first turn, the shank meets the
shaft's rim (14.5 < r < 15) until the cutter's own edge, turning ahead of it, has cleared it.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from catalog import POLYGON_TOOLS

from interpreters import sinumerik
from vmach.checks import stock_events
from vmach.machine import load_model
from vmach.motion.table import build
from vmach.stock import Stock, engine
from vmach.stock import hull as hull_module
from vmach.stock.events import Part, cylinders_beyond, part_solids
from vmach.stock.simulate import simulate
from vmach.stock.sweep import scallop_bound
from vmach.tooling import load_tools

HEAD = """N10 G0 G53 X325 Y0 D0
N20 T="GLOD D40" D1
N30 G54 G19 G90
N40 DIAMOF
N50 SETMS(2)
N60 G94 S2=640 M2=3
N70 C_AXIS_ON
N80 C1=0
N90 G0 X40 Y0 Z25
"""
FIRST_TURN = """N100 G0 X12
N110 G1 Z-10 F400
N120 R1=0
N130 WHILE R1<360
N140 R1=R1+3
N150 G1 C1=R1
N160 ENDWHILE
N170 G1 X9
"""
PLUNGE = """N170 G0 X9
N175 G1 Z-10 F400
"""
SECOND_TURN = """N180 R1=0
N190 WHILE R1<360
N200 R1=R1+3
N210 G1 C1=R1
N220 ENDWHILE
N230 G1 X40
N240 G0 Z25
N250 M2=5
N260 C_AXIS_OFF
N270 M30
"""


def _run(tmp_path, text: str, checks: bool, monkeypatch=None, spec: str = "cylinder:d=30,l=60"):
    path = tmp_path / "TURN.MPF"
    path.write_text(text)
    model = load_model("turnmill")
    table = build(sinumerik.run(str(path), model.control).commands, model.control)
    stock = Stock.from_spec(spec)
    moved: list[int] = []
    if monkeypatch is not None:
        one = stock_events._cut_one

        def spy(stock_, local, done, tool, table_, row, *a, **k):
            moved.append(row)
            return one(stock_, local, done, tool, table_, row, *a, **k)

        monkeypatch.setattr(stock_events, "_cut_one", spy)
    sim = simulate(table, model, load_tools(POLYGON_TOOLS), stock, checks=checks)
    return sim, stock, moved, table


def _line(text: str, prefix: str) -> int:
    return next(i + 1 for i, ln in enumerate(text.splitlines()) if ln.startswith(prefix))


def test_parts_that_meet_only_cleared_material_cost_no_move_by_move_cut(tmp_path, monkeypatch):
    """Every row of the second turn has its shank inside the blank's box and the blank, so
    it is a candidate; measured once on the stock before its chunk it reaches nothing, so no
    row is cut and measured on its own, and the chunks are cut together as one path — the
    part is the plain cut's (to the slivers by which the poses at the ends of a path, cut
    whole, differ from their fins where the one path has them: :mod:`vmach.stock.strategies.fins`)."""
    text = HEAD + FIRST_TURN + SECOND_TURN
    plain, plain_stock, _, table = _run(tmp_path, text, checks=False)
    checked, stock, moved, _ = _run(tmp_path, text, checks=True, monkeypatch=monkeypatch)
    assert len(table) > 3 * stock_events.CHUNK          # several chunks
    assert checked.findings == []
    assert moved == []
    assert stock.volume == pytest.approx(plain_stock.volume, rel=2e-6)
    # held chunks are cut as one path: at most one more cut than the plain run's single path
    assert stock.stats.cutters <= plain_stock.stats.cutters + 2


def test_a_shank_in_uncut_material_is_found_until_the_cutter_clears_it(tmp_path):
    """Plunging at X = 9 puts the shank into the shaft's rim; turning, the cutter's side
    clears the rim ahead of the shank, so the overlap shrinks row by row to nothing."""
    text = HEAD + PLUNGE + SECOND_TURN
    sim, _, _, _ = _run(tmp_path, text, checks=True)
    hits = [f for f in sim.findings if f.kind == "holder_collision"]
    assert {f.data["part"] for f in hits} == {"shank"}
    assert hits[0].line == _line(text, "N175")
    turn = [f for f in hits if f.line == _line(text, "N210")]
    assert len(turn) >= 3
    vols = np.array([f.data["volume_mm3"] for f in turn])
    assert np.all(np.diff(vols) < 0)                     # the rim is cut away ahead of it
    assert len(turn) < 40                                # ... and is gone well before the turn ends



def test_a_finely_meshed_blank_gives_the_findings_of_its_exact_hull(tmp_path, monkeypatch):
    """The same shank case (a quarter turn) on a blank read from a mesh: with the blank's hull
    reduced to 64 planes, and with every probe met with the blank in cells of 200 triangles
    (vmach/stock/hull.py, ``Stock.blank_meets``), the findings are those of the exact hull and
    the whole blank."""
    mesh = trimesh.creation.cylinder(radius=15.0, height=60.0, sections=512)
    mesh.apply_translation([0.0, 0.0, -30.0])
    mesh.export(tmp_path / "shaft.stl")
    text = HEAD + PLUNGE + SECOND_TURN.replace("WHILE R1<360", "WHILE R1<90")   # a quarter turn
    spec = f"mesh:{tmp_path / 'shaft.stl'}"

    def found(sim):
        return [(f.kind, f.line, f.data.get("part"), round(f.data.get("volume_mm3", 0.0), 6))
                for f in sim.findings]

    exact, stock, _, _ = _run(tmp_path, text, checks=True, spec=spec)
    assert stock.blank.hull.exact and stock.blank.cells is None
    monkeypatch.setattr(hull_module, "MAX_PLANES", 64)
    monkeypatch.setattr(Stock, "BLANK_CELL", 200)
    reduced, stock, _, _ = _run(tmp_path, text, checks=True, spec=spec)
    assert not stock.blank.hull.exact
    assert any(f.kind == "holder_collision" for f in reduced.findings)
    assert found(reduced) == found(exact)
    # every probe through the cells (no vertex taken for inside at once)
    monkeypatch.setattr(Stock, "blank_holds", lambda self, p: np.zeros(len(np.reshape(p, (-1, 3))), bool))
    celled, stock, _, _ = _run(tmp_path, text, checks=True, spec=spec)
    assert len(stock.blank.cells) > 1
    assert found(celled) == found(exact)


def test_a_shank_sweeping_through_the_shaft_between_two_far_poses_is_found(tmp_path):
    """One straight G1 across the shaft, Y -60 → +60 with the face at X = 8: the cutter takes
    X 8…13.5 and the Ø36 shank behind it sweeps through the rim (13.5 < r < 15), while at both
    ends of the move the shank's box lies clear of the blank's. The row is judged by the box
    around its whole sweep (a collision used to go unseen unless a pose lay near the shaft)."""
    text = HEAD.replace("N90 G0 X40 Y0 Z25", "N90 G0 X40 Y-60 Z25") + """N100 G0 Z-30
N110 G1 X8 F400
N120 G1 Y60
N130 G0 X40
N140 G0 Z25
N150 M30
"""
    sim, _, _, _ = _run(tmp_path, text, checks=True)
    hits = [f for f in sim.findings if f.kind == "holder_collision"]
    assert [(f.line, f.data["part"]) for f in hits] == [(_line(text, "N120"), "shank")]
    # the rim's segment beyond X = 13.5 (|y| < 6.54), over the 36 mm the shank spans along Z
    y = np.linspace(-np.sqrt(15**2 - 13.5**2), np.sqrt(15**2 - 13.5**2), 20001)
    area = np.trapezoid(np.sqrt(15**2 - y**2) - 13.5, y)
    assert hits[0].data["volume_mm3"] == pytest.approx(area * 36.0, rel=0.02)

def test_the_scallop_bound_counts_only_rotary_steps_whose_cutter_may_reach_the_blank(tmp_path):
    """A 3° turn at X = 12, Z = -10 is sampled in 1.5° steps; then the tool rises to Z = 25
    (the Ø40 cutter's lowest point 5 mm above the end face) and C turns 100° there, in 2°
    steps — with the tip still inside the blank's radius, but its cutter nowhere near the
    blank: those steps make no surface, and the bound is the turn's."""
    text = HEAD + "N100 G0 X12\nN110 G1 Z-10 F400\nN120 G1 C1=3\nN130 G0 Z25\nN140 G0 C1=103\n" \
        "N150 G0 X40\nN160 M30\n"
    for checks in (False, True):
        sim, _, _, _ = _run(tmp_path, text, checks=checks)
        assert sim.max_step_deg == pytest.approx(1.5)
        assert sim.bound_mm == pytest.approx(scallop_bound(np.array([12.0]), np.array([1.5]))[0], rel=1e-6)


def test_cylinders_beyond_is_the_least_distance_of_the_cylinder_beyond_a_plane():
    rng = np.random.default_rng(3)
    planes = rng.normal(size=(7, 4))
    planes[:, :3] /= np.linalg.norm(planes[:, :3], axis=1, keepdims=True)
    tips = rng.normal(scale=20.0, size=(5, 3))
    axes = rng.normal(size=(5, 3))
    got = cylinders_beyond(planes, tips, axes, 2.0, 30.0, 9.0)
    # the cylinder's two rims, densely: the least distance lies on one of them
    a = axes / np.linalg.norm(axes, axis=1, keepdims=True)
    u = np.cross(a, [0.3, 0.5, 0.8])
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    w = np.cross(a, u)
    t = np.linspace(0.0, 2 * np.pi, 20000, endpoint=False)
    for k in range(len(tips)):
        ring = 9.0 * (np.cos(t)[:, None] * u[k] + np.sin(t)[:, None] * w[k])
        pts = np.concatenate([tips[k] + 2.0 * a[k] + ring, tips[k] + 30.0 * a[k] + ring])
        least = (pts @ planes[:, :3].T - planes[:, 3]).min(axis=0)
        assert got[k] == pytest.approx(least, abs=1e-5)
        assert np.all(got[k] <= least + 1e-12)


def test_parts_beyond_a_face_of_the_blank_get_no_solids(tmp_path, monkeypatch):
    """The first turn alone, face at X = 12: the shank (X >= 17.5) lies inside the blank's
    box in most poses, but beyond the Ø30 blank's face plane at its angle in all of them — no
    part solid is made or met, and the findings are the plain screening's (none). (The turn's
    last block goes from C357 back to C0, round the shaft: its row is looked at, pose by pose.)"""
    made: list[int] = []

    def counted(part, tips, axes, *a, **k):
        out = part_solids(part, tips, axes, *a, **k)
        made.append(len(out))
        return out

    monkeypatch.setattr(stock_events, "part_solids", counted)
    text = HEAD + FIRST_TURN.replace("N170 G1 X9\n", "") + SECOND_TURN[SECOND_TURN.index("N230"):]
    sim, _, _, _ = _run(tmp_path, text, checks=True)
    assert sim.findings == [] and sum(made) == 0
    # the plunge at X = 9 puts the shank into the rim: its rows get solids, and are found
    sim, _, _, _ = _run(tmp_path, HEAD + PLUNGE + SECOND_TURN, checks=True)
    assert sum(made) > 0 and any(f.kind == "holder_collision" for f in sim.findings)
    # a rapid: apart only beyond the clearance (the Ø40 cutter's rim 1.5 mm off the blank)
    tool = load_tools(POLYGON_TOOLS).lookup("GLOD D40")
    stock = Stock.from_spec("cylinder:d=30,l=60")
    cutter = [Part("cutter", 0.0, tool.cutting_length, tool.radius)]
    tips, axes = np.array([[16.5, 0.0, -10.0]]), np.array([[1.0, 0.0, 0.0]])
    for gap, apart in ((1.0, True), (2.0, False)):
        got = stock_events._apart(stock.blank_planes(), cutter, tips, axes, [(0, 1)], np.ones(1, bool),
                                     gap)
        assert got[0, 0] == apart


def test_part_solids_of_a_turning_path_are_the_placed_prisms():
    """A turning step places the part at its poses (each once); a straight step is the hull
    of its two ends — the same solids as hulls of the placed points."""
    part = Part("shank", 5.5, 40.0, 18.0)
    c = np.radians([0.0, 2.0, 4.0, 4.0])
    axes = np.column_stack([np.cos(c), np.sin(c), np.zeros(4)])
    tips = 9.0 * axes + np.array([[0, 0, -10.0], [0, 0, -10.0], [0, 0, -10.0], [0, 0, -12.0]])
    solids = part_solids(part, tips, axes)
    assert len(solids) == 1 + 3                          # the straight step, then three poses
    straight, *placed = solids
    ring = part_solids(part, tips[:1], axes[:1])[0]
    for k, s in enumerate(placed):
        one = part_solids(part, tips[k : k + 1], axes[k : k + 1])[0]
        assert engine.volume(s) == pytest.approx(engine.volume(ring), rel=1e-9)
        assert engine.volume(engine.subtract(s, [one])) < 1e-6
        assert engine.volume(engine.subtract(one, [s])) < 1e-6
    # the straight step sweeps the prism 2 mm along Z: its volume grows by 2 mm times the
    # prism's shadow on the XY plane, a rectangle (length z1 - z0, the polygon's width across)
    u = np.array([-np.sin(c[3]), np.cos(c[3]), 0.0])
    v, _ = engine.to_mesh(placed[-1], double=True)
    shadow = (part.z1 - part.z0) * np.ptp(v @ u)
    assert engine.volume(straight) == pytest.approx(engine.volume(ring) + 2.0 * shadow, rel=1e-9)


def test_a_rapid_through_cleared_material_costs_no_move_by_move_cut(tmp_path, monkeypatch):
    """After the first turn, the tool backs off 1.5 mm (X13.5), rises 2 mm off the floor it
    cut, and moves up with G0: its cutter passes through the blank's radius where the turn
    has cleared everything, at least 1.5 mm from the stock (the clearance is 1 mm). Judged
    on the stock before its chunk, the rapid can neither remove material nor pass close to
    it, so no row is cut on its own — and there is no finding."""
    text = HEAD + FIRST_TURN.replace("N170 G1 X9\n", "") + "N300 G1 X13.5\nN305 G1 Z-8\nN310 G0 Z-5\n" \
        + SECOND_TURN[SECOND_TURN.index("N230"):]
    sim, _, moved, _ = _run(tmp_path, text, checks=True, monkeypatch=monkeypatch)
    assert sim.findings == []
    assert moved == []
    # the same rapid 1.5 mm lower, its cutter's edge in the floor: found, cut row by row
    low = text.replace("N305 G1 Z-8\nN310 G0 Z-5", "N305 G1 Z-8\nN310 G0 Z-11.5")
    sim, _, moved, _ = _run(tmp_path, low, checks=True, monkeypatch=monkeypatch)
    errors = [(f.kind, f.line) for f in sim.findings if f.severity == "error"]
    assert errors == [("rapid_into_stock", _line(low, "N310"))]
    assert moved


def test_a_turn_of_a_million_degrees_is_a_resource_limit_not_a_memory_blow_up(tmp_path):
    """Found by fuzzing: `G1 C1=IC(1EX6)` sampled 500,000 stock poses (7.7 GB) and, without a
    stock, 2.8 million collision samples (7.6 GB); `C1=IC(1EX10)` asked numpy for 37 GiB."""
    from vmach.errors import ProgramError
    from vmach.verify import VerifyOptions, verify

    cut = dict(tools=str(POLYGON_TOOLS), stock="cylinder:d=60,l=100")
    for turn, opts in (("1EX6", cut), ("1EX10", cut), ("1EX6", {})):
        path = tmp_path / "C.MPF"
        head = 'T="GLOD D40" D1\nSETMS(2)\nG94 S2=640 M2=3\nG0 X40 Y0 Z5\n'
        path.write_text(f"{head}G1 C1=IC({turn}) F100\nM30\n")
        with pytest.raises(ProgramError) as exc:
            verify(path, VerifyOptions(machine="turnmill", images=False, quiet=True, **opts))
        assert (exc.value.kind, exc.value.source.line) == ("resource_limit", 5)
