"""Siemens milling, boring and tapping cycles (interpreters/sinumerik/cycles/): the moves each
call makes, worked out from the cycles manual's description of the cycle, the phases the moves
carry, MCALL with the boring cycles, and the errors of bad parameters."""

from __future__ import annotations

import math

import pytest
from nc import error_of, moves, ok, run

from interpreters.sinumerik.cycles import MODAL, NAMES
from interpreters.sinumerik.cycles.parameters import SPECS
from interpreters.sinumerik.language import COMMANDS
from vmach.canon import ArcFeed, Dwell, LinearFeed, Pause, RunOptions, Spindle, Traverse

R5 = RunOptions(tool_radius=lambda tool, d: 5.0 if d == 1 else 3.0)
TINY = "0.000000000001"  # MID, MIDA, _DAM that would make a trillion levels
HEAD = "T1 D1\nG17 G90 G0 X0 Y0 Z50\nS1000 M3 F300\n"


def go(tmp_path, call: str):
    r = run(tmp_path, HEAD + call + "\nM30\n", options=R5)
    assert r.completed, [f.render() for f in r.findings]
    return [m for m in moves(r) if m.source.line == 4]


def test_every_cycle_has_its_parameter_list_as_data():
    assert NAMES == set(SPECS) and MODAL <= NAMES
    for spec in SPECS.values():
        names = [p.name for p in spec.parameters]
        assert len(names) == len(set(names))
        heights = names[1:4] if spec.parameters[0].type == "string" else names[:3]  # after a text
        assert heights in (["RTP", "RFP", "SDIS"], ["_RTP", "_RFP", "_SDIS"]) \
            or spec.family in ("positions", "measuring")
        assert all(p.type in ("real", "int", "string") and p.meaning for p in spec.parameters)
    # the simulated cycles are no longer in the table of cycles that stop a run
    assert not any(COMMANDS.get(n) is not None and COMMANDS[n].kind == "cycle" for n in NAMES)


def test_pocket3_rings_stay_inside_the_outline_and_reach_the_walls(tmp_path):
    """40 × 24 R6 at (30, 20), 6 deep in 2 levels of 3, a Ø10 tool, roughing with vertical
    insertion: the tool centre keeps 5 mm (+ FAL 0.5) inside the walls and reaches them."""
    ms = go(tmp_path, "POCKET3(10, 0, 2, -6, 40, 24, 6, 30, 20, 0, 3, 0.5, 0.2, 600, 200, 0, 1, 8)")
    cut = [m for m in ms if not isinstance(m, Traverse)]
    xs = [m.axes["X"] for m in cut]
    ys = [m.axes["Y"] for m in cut]
    assert min(xs) == pytest.approx(10 + 5.5) and max(xs) == pytest.approx(50 - 5.5)
    assert min(ys) == pytest.approx(8 + 5.5) and max(ys) == pytest.approx(32 - 5.5)
    assert sorted({round(m.axes["Z"], 9) for m in cut}) == [-5.8, -2.9]      # DP + FALD in 2 levels
    arcs = [m for m in cut if isinstance(m, ArcFeed)]
    # the outer ring's corners: radius CRAD − r − FAL = 0.5 about (16, 14) …
    assert any(math.dist(m.center, (16, 14)) < 1e-9 for m in arcs)
    # over the start at the height it had (above RTP), out to RTP
    assert ms[0].axes["Z"] == 50 and ms[-1].axes["Z"] == 10
    assert {m.feed for m in cut if m.axes["Z"] < 0 and m.axes["X"] == ms[2].axes["X"]} >= {200}
    phases = {m.source.phase for m in ms}
    assert {"approach", "roughing depth 1/2 insertion", "roughing depth 2/2 ring 2/2", "retraction"} <= phases


def test_pocket3_finishing_goes_to_the_outline_at_the_depth(tmp_path):
    ms = go(tmp_path, "POCKET3(10, 0, 2, -6, 40, 24, 6, 30, 20, 0, 3, 0.5, 0.2, 600, 200, 0, 2, 8)")
    cut = [m for m in ms if not isinstance(m, Traverse)]
    assert min(m.axes["X"] for m in cut) == pytest.approx(15)
    assert max(m.axes["Y"] for m in cut) == pytest.approx(27)
    assert {round(m.axes["Z"], 9) for m in cut} == {-6}
    assert all(m.source.phase.startswith("finishing") for m in cut)


def test_pocket3_helical_insertion_turns_at_dp1_per_turn(tmp_path):
    ms = go(tmp_path, "POCKET3(10, 0, 2, -6, 40, 24, 6, 30, 20, 0, 6, 0, 0, 600, 200, 3, 11, 8, , , , 4, 2)")
    helix = [m for m in ms if isinstance(m, ArcFeed) and "insertion" in m.source.phase]
    # from RFP + SDIS = 2 down to −6: 8 mm at 2 per turn, 8 half turns, then a circle at −6
    assert len(helix) == 8 + 2
    assert [round(m.axes["Z"], 9) for m in helix[:8]] == [2 - k for k in range(1, 9)]
    assert all(m.center == (30, 20) and not m.clockwise for m in helix)       # CDIR 3: G3


def test_pocket3_oscillating_insertion_sinks_at_most_the_angle(tmp_path):
    ms = go(tmp_path, "POCKET3(10, 0, 2, -2, 40, 24, 6, 30, 20, 0, 2, 0, 0, 600, 200, 0, 21, 8, , , , 5, 0)")
    ins = [m for m in ms if "insertion" in m.source.phase]
    slope = math.tan(math.radians(5))
    for a, b in zip(ins, ins[1:], strict=False):
        run_xy = math.dist((a.axes["X"], a.axes["Y"]), (b.axes["X"], b.axes["Y"]))
        assert a.axes["Z"] - b.axes["Z"] <= run_xy * slope + 1e-9
    assert min(m.axes["Z"] for m in ins) == pytest.approx(-2)


def test_pocket4_rings_reach_the_radius(tmp_path):
    ms = go(tmp_path, "POCKET4(10, 0, 2, -5, 20, 50, 40, 5, 0, 0, 600, 200, 0, 1, 6)")
    arcs = [m for m in ms if isinstance(m, ArcFeed)]
    radii = {round(math.dist((m.axes["X"], m.axes["Y"]), m.center), 9) for m in arcs}
    assert max(radii) == 15 and all(m.center == (50, 40) for m in arcs)    # PRAD − r
    assert len(radii) == math.ceil(15 / 6)
    assert all(m.clockwise is False for m in arcs)                          # climb inside: G3


def test_cycle76_and_77_rings_come_in_from_the_blank(tmp_path):
    ms = go(tmp_path, "CYCLE76(10, 0, 2, -4, , 20, 14, 3, 30, 60, 0, 0, 0, 0, 600, 200, 0, 1, 40, 30)")
    rings = {}
    for m in ms:
        if isinstance(m, (LinearFeed, ArcFeed)) and "ring" in m.source.phase:
            rings.setdefault(m.source.phase, []).append(m.axes["X"])
    # blank 40 × 30 about the 20 × 14 spigot: the outer ring a radius outside the blank's
    # 40, the inner one a radius outside the spigot's 20, 10 mm between them in 2 steps (≤ 8)
    assert sorted(round(min(xs), 9) for xs in rings.values()) == [30 - 20 - 5, 30 - 15 - 5, 30 - 10 - 5]
    ms = go(tmp_path, "CYCLE77(10, 0, 2, -4, , 20, 90, 60, 0, 0.5, 0, 600, 200, 0, 1, 30)")
    arcs = [m for m in ms if isinstance(m, ArcFeed)]
    radii = sorted({round(math.dist((m.axes["X"], m.axes["Y"]), m.center), 9) for m in arcs})
    assert radii[0] == 10 + 5 + 0.5 and radii[-1] == 15 + 5
    assert all(m.clockwise for m in arcs)                                   # climb outside: G2


def test_cycle77_dpr_wins_over_dp(tmp_path):
    ms = go(tmp_path, "CYCLE77(10, -1, 2, -40, 3, 20, 90, 60, 0, 0, 0, 600, 200, 0, 1, 30)")
    assert min(m.axes["Z"] for m in ms) == pytest.approx(-4)


def test_longhole_strokes_alternate_ends(tmp_path):
    """Two holes 20 long on a circle of radius 20 about (50, 40), at 0° and 180°; Ø10 tool:
    the centre line runs from radius 15 to 25; 3 deep in strokes of 1.5."""
    ms = go(tmp_path, "LONGHOLE(10, 0, 2, , 3, 2, 20, 50, 40, 20, 0, 180, 100, 400, 1.5)")
    cut = [m for m in ms if isinstance(m, LinearFeed)]
    first = [(m.axes["X"], m.axes["Y"], m.axes["Z"]) for m in cut[:4]]
    assert first == [(65, 40, -1.5), (75, 40, -1.5), (75, 40, -3), (65, 40, -3)]
    assert [m.feed for m in cut[:4]] == [100, 400, 100, 400]
    assert min(m.axes["X"] for m in cut) == pytest.approx(25)
    assert {m.source.phase for m in cut} >= {"hole 2/2 stroke 2/2"}


def test_slot1_and_slot2_outline_at_the_walls(tmp_path):
    ms = go(tmp_path, "SLOT1(10, 0, 2, -3, , 1, 30, 16, 50, 40, 20, 90, 0, 100, 400, 3, 2, 0.5, 0, 0, 300)")
    fin = [m for m in ms if "finishing" in m.source.phase and not isinstance(m, Traverse)]
    # slot 30 × 16 centred at (50, 60), radial (along Y): finishing at x = 50 ± (8 − 5)
    assert min(m.axes["X"] for m in fin) == pytest.approx(47)
    ends = [m.center[1] + math.dist(m.center, (m.axes["X"], m.axes["Y"]))
            for m in fin if isinstance(m, ArcFeed)]
    assert max(ends) == pytest.approx(75 - 5)
    rough = [m for m in ms if "roughing" in m.source.phase and not isinstance(m, Traverse)]
    assert min(m.axes["X"] for m in rough) == pytest.approx(47.5)             # FAL 0.5 left
    ms = go(tmp_path, "SLOT2(10, 0, 2, -3, , 2, 60, 14, 50, 40, 25, 0, 180, 100, 400, 3, 2, 0.3, 2, 0, 300)")
    arcs = [m for m in ms if isinstance(m, ArcFeed) and m.center == (50, 40)]
    radii = {round(math.dist((m.axes["X"], m.axes["Y"]), m.center), 9) for m in arcs}
    assert radii == {25 - 2, 25 + 2}                                        # finishing only: WID/2 − r
    assert all(m.feed == 300 for m in arcs)


def test_cycle71_face_passes_to_and_fro(tmp_path):
    """Area 100 × 40 from (0, 0), passes along X to and fro, MIDA 8, Ø10: passes at y = 5 …
    35 (the tool's edge on the area's sides), 5 passes; each overruns r + FDP 2 at either end;
    1 mm off in one level (RFP 1, DP 0)."""
    ms = go(tmp_path, "CYCLE71(10, 1, 2, 0, 0, 0, 100, 40, 0, 2, 8, 2, 0, 800, 31, 0)")
    cut = [m for m in ms if isinstance(m, LinearFeed) and m.axes["Z"] == 0]
    ys = sorted({round(m.axes["Y"], 9) for m in cut})
    assert ys == [5, 12.5, 20, 27.5, 35]
    assert {round(m.axes["X"], 9) for m in cut} == {-7, 107}
    assert {m.source.phase for m in cut} == {f"roughing pass {k}/5" for k in range(1, 6)}
    one_way = go(tmp_path, "CYCLE71(10, 1, 2, 0, 0, 0, 100, 40, 0, 2, 8, 2, 0, 800, 11, 0)")
    assert sum(isinstance(m, Traverse) and m.axes["Z"] == 3 for m in one_way) >= 4  # back over the top


def test_mcall_cycle85_bores_at_each_position(tmp_path):
    text = "MCALL CYCLE85(10, 0, 2, -8, , 0.5, 100, 300)\nX20\nX30\nMCALL\nX40\nM30\n"
    r = run(tmp_path, HEAD + text, options=R5)
    assert r.completed
    feeds = [(m.axes["X"], m.axes["Z"], m.feed) for m in moves(r) if isinstance(m, LinearFeed)]
    assert feeds == [(20, -8, 100), (20, 2, 300), (30, -8, 100), (30, 2, 300)]
    assert [c.seconds for c in r.commands if isinstance(c, Dwell)] == [0.5, 0.5]


def test_cycle84_taps_at_pitch_times_speed_and_reverses(tmp_path):
    ms_r = run(tmp_path, HEAD + "CYCLE84(10, 0, 2, -8, , 0, 3, 8, , 0, 200, 400)\nM30\n", options=R5)
    feeds = [(m.axes["Z"], m.feed) for m in moves(ms_r) if isinstance(m, LinearFeed)]
    assert feeds == [(-8, 1.25 * 200), (2, 1.25 * 400)]                      # M8: 1.25 mm pitch
    dirs = [c.direction for c in ms_r.commands if isinstance(c, Spindle) and c.source.line == 4]
    assert dirs == ["ccw", "cw"]


def test_cycle87_and_88_stop_the_spindle_and_the_program(tmp_path):
    r = run(tmp_path, HEAD + "CYCLE88(10, 0, 2, -8, , 1, 4)\nM30\n", options=R5)
    assert any(isinstance(c, Pause) and c.source.line == 4 for c in r.commands)
    spindle = [c.direction for c in r.commands if isinstance(c, Spindle) and c.source.line == 4]
    assert spindle == ["stop", "ccw"]


@pytest.mark.parametrize("call, kind", [
    ("POCKET3(10, 0, 2, -6, 40, 24, 3, 30, 20, 0, 3)", "cycle_parameter"),       # CRAD 3 < r 5
    ("POCKET3(10, 0, 2, 6, 40, 24, 6, 30, 20, 0, 3)", "cycle_parameter"),        # depth above RFP
    ("POCKET4(10, 0, 2, -5, 4, 50, 40)", "cycle_parameter"),                     # tool too large
    ("POCKET3(10, 0, 2, -6, 40, 24, 6, 30, 20, 0, 3, 0, 0, 600, 200, 0, 11)", "cycle_parameter"),  # no RAD1
    ("POCKET3(10, 0, 2, -6, 40, 24, 6, 30, 20, 0, 3, 0, 0, 600, 200, 0, 7)", "cycle_parameter"),   # VARI
    (f"POCKET3(10, 0, 2, -6, 40, 24, 6, 30, 20, 0, {TINY})", "cycle_parameter"),
    (f"POCKET4(10, 0, 2, -5, 20, 50, 40, 5, 0, 0, 600, 200, 0, 1, {TINY})", "cycle_parameter"),
    (f"CYCLE71(10, 1, 2, 0, 0, 0, 100, 40, 0, 2, {TINY})", "cycle_parameter"),
    (f"CYCLE84(10, 0, 2, -8, , 0, 3, 8, , 0, 200, 400, 0, 0, 0, 1, {TINY})", "cycle_parameter"),
    ("SLOT1(10, 0, 2, -3, , 100000, 30, 16, 50, 40, 20)", "cycle_parameter"),                  # NUM
    ("CYCLE71(10, 1, 2, 0, 0, 0, 100, 40, 0, 2, 12)", "cycle_parameter"),          # MIDA > diameter
    ("SLOT1(10, 0, 2, -3, , 1, 30, 8)", "cycle_parameter"),                        # narrower than the tool
    ("CYCLE84(10, 0, 2, -8, , 0, 3, 7)", "cycle_parameter"),                       # M7 is no coarse thread
    ("CYCLE85(10, 0, 2, -8, , 0, 100, 300, 0, 0, 0, 0, 1)", "call_arguments"),  # Operate has 12
    ("POCKET4(10, 0, 2, -5, \"A\", 50, 40)", "type_error"),
    ("POCKET4(10, 0, 2, -5, 20, 50, 40, 5, 0, 0, 600, 200, 0.5)", "cycle_parameter"),  # CDIR not whole
])
def test_bad_parameters_are_errors_at_the_call(tmp_path, call, kind):
    e = error_of(run(tmp_path, HEAD + call + "\nM30\n", options=R5))
    assert (e.kind, e.line) == (kind, 4)


def test_a_milling_cycle_without_a_tool_radius_or_with_g41_is_an_error(tmp_path):
    e = error_of(run(tmp_path, "G17 G90 G0 Z50\nF100\nPOCKET4(10, 0, 2, -5, 20, 50, 40)\nM30\n"))
    assert (e.kind, e.line) == ("cycle_parameter", 3)                        # D0: no radius
    e = error_of(run(tmp_path, HEAD + "POCKET4(10, 0, 2, -5, 20, 50, 40)\nM30\n"))
    assert (e.kind, e.line) == ("no_tool_radius", 4)                         # no tool library
    e = error_of(run(tmp_path, HEAD + "G41 G1 X10\nPOCKET4(10, 0, 2, -5, 20, 50, 40)\nM30\n", options=R5))
    assert (e.kind, e.line) == ("cutcom", 5)


def test_a_pocket_program_beside_the_main_one_is_called_instead(tmp_path):
    sub = "PROC POCKET4(REAL A, REAL B)\nG0 X=A+B\nM17\n"
    r = ok(tmp_path, "POCKET4(1, 2)\nM30\n", POCKET4_DOT_SPF=sub)
    assert moves(r)[-1].axes["X"] == 3.0


def test_inch_programs_are_converted(tmp_path):
    ms = go(tmp_path, "G70 POCKET4(1, 0, 0.1, -0.2, 1, 2, 2, 0.1, 0, 0, 20, 10, 0, 1, 0.3)")
    arcs = [m for m in ms if isinstance(m, ArcFeed)]
    assert max(math.dist((m.axes["X"], m.axes["Y"]), m.center) for m in arcs) == pytest.approx(25.4 - 5)
    assert min(m.axes["Z"] for m in ms) == pytest.approx(-0.2 * 25.4)


def test_what_is_not_simulated_is_said_once_at_the_first_call(tmp_path):
    call = "CYCLE86(10, 0, 2, -8, , 0, 3, 0.5)"
    text = HEAD + f"{call}\nX20\n{call}\nM30\n"
    r = run(tmp_path, text, options=R5)
    assert r.completed
    notes = [(f.kind, f.severity, f.line) for f in r.findings if f.kind == "cycle_simplified"]
    assert notes == [("cycle_simplified", "info", 4)]
    # the bar retracts on its axis: every move of the cycle at X0 Y0
    assert all((m.axes["X"], m.axes["Y"]) == (0, 0) for m in moves(r) if m.source.line == 4)


def test_cycles_work_in_the_plane_selected_and_under_a_rotation(tmp_path):
    """G19: the pocket lies in Y/Z and goes down along X; ROT RPL=90 turns the pocket's
    length from X to Y (program coordinates through the frame)."""
    r = run(tmp_path, "T1 D1\nG19 G90 G0 X50 Y0 Z0\nF300\nPOCKET4(10, 0, 2, -5, 20, 30, 40, 5)\nM30\n",
            options=R5)
    ms = [m for m in moves(r) if m.source.line == 4]
    arcs = [m for m in ms if isinstance(m, ArcFeed)]
    assert arcs and all(m.plane == ("Y", "Z", "X") and m.center == (30, 40) for m in arcs)
    assert min(m.axes["X"] for m in ms) == pytest.approx(-5)
    call = "POCKET3(10, 0, 2, -3, 40, 20, 5, 0, 0, 0, 3, 0, 0, 600, 200, 0, 1, 8)"
    r = run(tmp_path, HEAD + f"ROT RPL=90\n{call}\nM30\n", options=R5)
    cut = [m for m in moves(r) if m.source.line == 5 and not isinstance(m, Traverse)]
    assert max(m.axes["Y"] for m in cut) == pytest.approx(15)
    assert max(m.axes["X"] for m in cut) == pytest.approx(5)


def test_a_hole_pattern_runs_the_modal_boring_cycle_at_each_hole(tmp_path):
    text = "MCALL CYCLE89(10, 0, 2, -6, , 0.2)\nHOLES2(50, 40, 20, 0, 90, 4)\nMCALL\nM30\n"
    r = run(tmp_path, HEAD + text, options=R5)
    assert r.completed
    bottoms = [(round(m.axes["X"], 9), round(m.axes["Y"], 9)) for m in moves(r)
               if isinstance(m, LinearFeed) and m.axes["Z"] == -6]
    assert bottoms == [(70, 40), (50, 60), (30, 40), (50, 20)]
    assert all(m.source.line == 5 for m in moves(r) if isinstance(m, LinearFeed))
