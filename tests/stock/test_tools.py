"""Tool library loading, lookup, profiles and solids."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vmach.errors import ModelError
from vmach.tooling import Tool, load_tools, tool_solid
from vmach.tooling.solid import convex_runs, polygon_deviation, segments_for, straddle_radius


def test_fixture_library_has_the_three_cutters_by_name_and_number(library):
    # the three cutters of domain §4, the larger finishing cutter of the biggest sizes, and the
    # turning insert TURNED50 turns the bar with first (#34)
    assert [t.name for t in library.tools] == ["GLOD D40", "GLOD D16_15", "GLOD D25", "GLOD D32",
                                               "CNMG120408"]
    d40 = library.lookup("GLOD D40")
    assert (d40.kind, d40.diameter, d40.cutting_length, d40.teeth) == ("face", 40.0, 5.5, 4)
    assert library.lookup("glod d16_15").kind == "chamfer"
    d25 = library.lookup(3)
    assert (d25.name, d25.diameter, d25.teeth) == ("GLOD D25", 25.0, 3)
    assert library.lookup("2").name == "GLOD D16_15"
    assert library.lookup("GLOD D99") is None and "GLOD D40" in library
    assert d40.offsets[1].radius == 20.0 and d40.length(1) == 0.0 and d40.length(7) == 0.0


def test_chamfer_mill_puts_radius_4_at_4_tan_15_behind_the_tip(library):
    """domain §4: the tool sits 4·tan 15° inside the profile to cut a 15° x 3 mm chamfer."""
    prof = library.lookup("GLOD D16_15").profile()
    z4 = np.interp(4.0, prof[:2, 1], prof[:2, 0])
    assert z4 == pytest.approx(4 * math.tan(math.radians(15)), abs=1e-12)


def library_problems(tmp_path, text: str) -> list[tuple[str, int]]:
    """Sorted (kind, line) of the problems a library text raises (it must raise)."""
    path = tmp_path / "lib.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ModelError) as exc:
        load_tools(path)
    return sorted((f.kind, f.line) for f in exc.value.findings())


def test_bad_library_reports_every_problem_at_its_line(tmp_path):
    got = library_problems(
        tmp_path,
        "[[tool]]\n"                      # 1
        'name = "A"\n'                    # 2
        'type = "flat"\n'                 # 3
        "diameter = -3\n"                 # 4
        "cutting_length = 10\n"           # 5
        "[[tool]]\n"                      # 6
        'name = "B"\n'                    # 7
        'type = "cone"\n'                 # 8
        "diameter = 8\n"                  # 9
        "cutting_length = 5\n"            # 10
        "colour = 3\n"                    # 11
        "[[tool]]\n"                      # 12
        'name = "C"\n'                    # 13
        'type = "bull"\n'                 # 14
        "diameter = 8\n"                  # 15
        "cutting_length = 5\n"            # 16
        "corner_radius = 6\n",            # 17
    )
    assert got == [("tool_library", 4), ("tool_library", 8), ("tool_library", 11), ("tool_library", 17)]


def test_duplicate_names_and_numbers_are_errors(tmp_path):
    path = tmp_path / "dup.toml"
    one = '[[tool]]\nname = "{}"\nnumber = {}\ntype = "flat"\ndiameter = 6\ncutting_length = 10\n'
    path.write_text(one.format("A", 1) + one.format("a", 2) + one.format("B", 1), encoding="utf-8")
    with pytest.raises(ModelError) as exc:
        load_tools(path)
    assert [f.line for f in exc.value.findings()] == [8, 15]  # the name, then the number


@pytest.mark.parametrize(
    "tool",
    [
        Tool("flat", "flat", 10.0, 20.0),
        Tool("ball", "ball", 10.0, 20.0),
        Tool("bull", "bull", 10.0, 20.0, corner_radius=2.0),
        Tool("chamfer", "chamfer", 16.0, 6.0, point_angle=90.0, tip_diameter=2.0),
        Tool("drill", "drill", 8.0, 30.0, point_angle=118.0),
    ],
)
def test_profiles_are_convex_single_pieces_with_the_right_radius(tool):
    prof = tool.profile(chord=0.001)
    assert prof[0].tolist() == [0.0, 0.0] and prof[-1, 1] == 0.0
    assert prof[:, 1].max() == pytest.approx(tool.radius)
    assert len(convex_runs(prof)) == 1
    solid = tool_solid(tool, 0.002)
    assert len(solid.pieces) == 1 and solid.deviation <= 0.002
    r = np.hypot(solid.points[:, 0], solid.points[:, 1])
    assert r.max() == pytest.approx(straddle_radius(tool.radius, solid.segments))
    if tool.kind == "ball":  # every profile point on the sphere of radius R about (0,0,R)
        assert np.allclose(np.hypot(prof[:-1, 1], prof[:-1, 0] - tool.radius)[1:-1], tool.radius)


def test_a_necked_profile_splits_into_convex_pieces():
    prof = np.array([[0, 0], [0, 5], [10, 5], [10, 3], [30, 3], [30, 0]], float)
    runs = convex_runs(prof)
    assert len(runs) == 2
    assert runs[0][:, 0].max() == 10 and runs[1][:, 0].min() == 10


def test_straddling_polygon_deviation_is_within_the_chord():
    for r in (2.0, 8.0, 12.5, 20.0, 30.0):
        n = segments_for(r, 0.002)
        assert polygon_deviation(r, n) <= 0.002
        assert n % 4 == 0                  # four directions exact when turned (solid.spun)
        assert polygon_deviation(r, n - 4) > 0.002 or n == 12
        rv = straddle_radius(r, n)
        assert rv - r == pytest.approx(r - rv * math.cos(math.pi / n))


def test_tool_sizes_beyond_any_machine_are_library_errors(tmp_path):
    """Found by fuzzing: a mistyped size must be a finding at its line, not an attempt to
    polygonise a kilometre-wide cutter."""
    got = library_problems(
        tmp_path,
        "[[tool]]\n"                                         # 1
        'name = "A"\n'                                       # 2
        'type = "flat"\n'                                    # 3
        "diameter = 1e9\n"                                   # 4
        "cutting_length = 10\n"                              # 5
        "[[tool]]\n"                                         # 6
        'name = "B"\n'                                       # 7
        'type = "flat"\n'                                    # 8
        "diameter = 10\n"                                    # 9
        "cutting_length = 10\n"                              # 10
        "holder = { diameter = 63.0, length = 1e12 }\n",     # 11
    )
    assert got == [("tool_library", 4), ("tool_library", 11)]


@pytest.mark.parametrize("half", [0.3, 1.1, 40.0])
def test_a_fin_is_the_true_tool_within_a_slab_through_its_lateral(library, half):
    """fin_points: the true tool (not its polygon) within |x·m| <= half about the plane of
    the axis and the lateral direction poses are turned for — points on the true circles,
    inside the slab, reaching the true radius toward ±lateral, and the volume of the true
    cylinder's slab (the circular segment's area times the length) to the inscribed
    polygon's sagitta."""
    import math

    from vmach.stock import engine
    from vmach.stock.cusps import fin_normal
    from vmach.tooling.solid import exact_phase, fin_points

    for name in ("GLOD D25", "GLOD D16_15"):
        tool = library.lookup(name)
        ts = tool_solid(tool, 0.01)
        pts = fin_points(ts.pieces[0], ts.segments, half)
        m = fin_normal(ts.segments)
        alpha = math.pi / ts.segments - exact_phase(ts.segments)
        lat = np.array([math.cos(alpha), math.sin(alpha), 0.0])
        assert np.abs(pts @ m).max() <= half + 1e-9
        assert np.abs(lat @ m) < 1e-12
        prof = tool.profile(0.01)
        r = np.hypot(pts[:, 0], pts[:, 1])
        # the profile's radius at each point's height (the largest where it steps there)
        want = [max([rr for zz, rr in prof if abs(zz - z) < 1e-12],
                    default=np.interp(z, prof[:, 0], prof[:, 1])) for z in pts[:, 2]]
        assert r == pytest.approx(np.array(want), abs=1e-9)
        assert (pts @ lat).max() == pytest.approx(tool.radius, abs=1e-12)
        assert (pts @ -lat).max() == pytest.approx(tool.radius, abs=1e-12)
    # the Ø25 end mill is a cylinder: the slab's cross-section is known
    ts = tool_solid(library.lookup("GLOD D25"), 0.01)
    big = 12.5
    h = min(half, big)
    area = 2.0 * (h * math.sqrt(big * big - h * h) + big * big * math.asin(h / big))
    got = engine.volume(engine.hull(fin_points(ts.pieces[0], ts.segments, half))) / ts.length
    assert got <= area
    assert got == pytest.approx(area, rel=5e-4)               # the inscribed arcs: within 0.002 mm


@pytest.mark.parametrize("height", [0.6, 1.0, 2.5, 3.9])
def test_a_fin_cut_to_a_height_is_the_fin_below_it(library, height):
    """fin_points(height=h): the fin (true tool within the slab) up to h mm from the tip — no
    point above h, every point on the true surface or the ring at h, reaching the true
    radius toward ±lateral at h, and its hull the whole fin's below h: as big as the whole
    fin's points below h with its ring at h, and inside the whole fin but for the arcs' sag
    (the ring's arc points lie on the true cone at other angles than the whole fin's)."""
    import math

    from vmach.stock import engine
    from vmach.stock.cusps import fin_normal
    from vmach.tooling.solid import exact_phase, fin_points

    tool = library.lookup("GLOD D16_15")          # cone to 2.14 mm, then a cylindrical land to 4
    ts = tool_solid(tool, 0.004, arcs=True)
    half = 0.7
    whole = fin_points(ts.pieces[0], ts.segments, half)
    cut = fin_points(ts.pieces[0], ts.segments, half, height=height)
    assert cut[:, 2].max() == pytest.approx(height, abs=1e-12)
    prof = tool.profile(0.004)
    want = np.interp(cut[:, 2], prof[:-1, 0], prof[:-1, 1])
    assert np.hypot(cut[:, 0], cut[:, 1]) == pytest.approx(want, abs=1e-9)
    assert np.abs(cut @ fin_normal(ts.segments)).max() <= half + 1e-9
    alpha = math.pi / ts.segments - exact_phase(ts.segments)
    lat = np.array([math.cos(alpha), math.sin(alpha), 0.0])
    top = cut[np.abs(cut[:, 2] - height) < 1e-12]
    assert (top @ lat).max() == pytest.approx(float(np.interp(height, prof[:-1, 0], prof[:-1, 1])), abs=1e-12)
    a, b = engine.hull(whole), engine.hull(cut)
    sag = 0.002                                      # fin_points' default
    assert engine.volume(engine.subtract(b, [a])) < sag * 2.0 * half * 2.0 * tool.radius
    below = engine.volume(engine.hull(np.vstack([whole[whole[:, 2] <= height], top])))
    assert engine.volume(b) == pytest.approx(below, rel=1e-9)
    assert engine.volume(b) < engine.volume(a)
    assert len(fin_points(ts.pieces[0], ts.segments, half, height=-1.0)) == 0


@pytest.mark.parametrize("chord", [0.01, 0.004])
def test_a_prism_tools_rings_are_round_about_the_laterals(library, chord):
    """A flat or face mill's rings (the face's rim, and the side with it) are arcs of the
    true circle over ±RIM_ARC about the two lateral directions poses are turned for: within
    RIM_SAG inside the circle there and never outside it, exactly the true radius at the
    laterals — elsewhere the straddling polygon (within its deviation either way). The piece
    stays a right prism (fans take it), and a chamfer mill keeps its plain polygon."""
    from vmach.stock.fan import prism
    from vmach.tooling.solid import RIM_ARC, RIM_SAG, lateral_angle

    for name in ("GLOD D25", "GLOD D40"):
        tool = library.lookup(name)
        ts = tool_solid(tool, chord, arcs=True)
        pr = prism(ts.pieces[0])
        assert pr is not None and pr.inner >= tool.radius - ts.deviation - 1e-9
        assert len(prism(tool_solid(tool, chord).pieces[0]).ring) == ts.segments     # (opt-in)
        ring = pr.ring[:, :2]
        alpha = lateral_angle(ts.segments)
        # the ring's radial reach along rays (its boundary: the hull's support along a ray
        # is not the reach, so the polygon edges' crossings are taken)
        order = np.argsort(np.arctan2(ring[:, 1], ring[:, 0]))
        a, b = ring[order], np.roll(ring[order], -1, axis=0)
        rays = alpha + np.radians(np.linspace(-RIM_ARC, RIM_ARC, 201))
        rays = np.concatenate([rays, rays + np.pi])
        reach = []
        for t in rays:
            u = np.array([math.cos(t), math.sin(t)])
            cross_a, cross_b = a[:, 0] * u[1] - a[:, 1] * u[0], b[:, 0] * u[1] - b[:, 1] * u[0]
            k = np.nonzero((cross_a >= 0) & (cross_b < 0) & (a @ u > 0))[0][0]
            d = b[k] - a[k]
            s = cross_a[k] / (cross_a[k] - cross_b[k])
            reach.append(np.linalg.norm(a[k] + s * d))
        reach = np.array(reach)
        assert reach.max() <= tool.radius + 1e-9                       # never outside
        assert reach.min() >= tool.radius - RIM_SAG - 1e-9             # within RIM_SAG inside
        for t in (alpha, alpha + math.pi):                              # exact at the laterals
            assert (ring @ [math.cos(t), math.sin(t)]).max() == pytest.approx(tool.radius, abs=1e-12)
        # elsewhere the straddling polygon: every point on the circle or one of its vertices,
        # those beyond RIM_ARC from both laterals
        far = np.abs(np.mod(np.arctan2(ring[:, 1], ring[:, 0]) - alpha + np.pi / 2, np.pi) - np.pi / 2)
        rho = np.hypot(*ring.T)
        vertex = np.abs(rho - straddle_radius(tool.radius, ts.segments)) < 1e-9
        assert np.all(vertex | (np.abs(rho - tool.radius) < 1e-9))
        assert np.all(far[vertex] > math.radians(RIM_ARC)) and vertex.sum() >= ts.segments - 8
    cone = tool_solid(library.lookup("GLOD D16_15"), chord, arcs=True)
    assert prism(cone.pieces[0]) is None
    r = np.hypot(cone.pieces[0][:, 0], cone.pieces[0][:, 1])
    assert np.isin(np.round(r[r > 0], 9), np.round([straddle_radius(rr, cone.segments)
                                                    for rr in (8.0,)], 9)).all()
