"""Programs as CAM post-processors write them for an 840D (#32): the constructs of Siemens NX,
hyperMILL, Mastercam, PowerMill, Fusion 360, ESPRIT, Edgecam, SolidCAM and CATIA posts, in
programs written for these tests after the Programming Manual's descriptions. Each must
check without an error and run to its end; what vmach does not simulate stops the run with
``unsupported`` naming the one feature."""

from __future__ import annotations

from catalog import MODELS
from nc import check, error_of, moves, ok, run

from vmach.canon import Dwell
from vmach.machine.control import load_control

MILL3 = load_control(MODELS / "mill3.toml")
MILL5AC = load_control(MODELS / "mill5ac.toml")
HEAD = "G17 G90 G94 G710\nT1 D1\nS1000 M3 F300\nG0 X0 Y0 Z50\n"


def errors(findings) -> list[tuple[str, int]]:
    return [(f.kind, f.line) for f in findings if f.severity == "error"]


def test_boring_and_tapping_cycles_take_operates_longer_lists(tmp_path):
    # SINUMERIK Operate appends _AXN, _GMODE, _DMODE, _AMODE (CYCLE84 also _PITA, _TECHNO_X,
    # _PTABA) to the classic lists; posts for Operate controls write the whole list
    calls = [
        "CYCLE85(50,0,2,-15,,0.5,100,200,0,0,0,0)",
        "CYCLE86(50,0,2,-15,,0,3,0,0,0,0,0,0,0,0)",
        "CYCLE84(50,0,2,-15,,0,3,,1.25,0,500,500,0,0,0,0,0,0,0,0,0,0,0,0)",
        "CYCLE840(50,0,2,-15,,0,0,3,0,,1.25,0,0,0,0,0,0)",
    ]
    for call in calls:
        text = HEAD + call + "\nM30\n"
        assert errors(check(tmp_path, text, MILL3)) == [], call
        r = ok(tmp_path, text, MILL3)
        deepest = min(m.axes["Z"] for m in moves(r) if m.source.line == 5)
        assert abs(deepest + 15) < 1e-9, call
    dwell = [c for c in ok(tmp_path, HEAD + calls[0] + "\nM30\n", MILL3).commands if isinstance(c, Dwell)]
    assert [d.seconds for d in dwell] == [0.5]


def test_one_parameter_more_than_operate_knows_is_an_error(tmp_path):
    e = error_of(run(tmp_path, HEAD + "CYCLE85(50,0,2,-15,,0,100,200,0,0,0,0,7)\nM30\n", MILL3))
    assert (e.kind, e.line) == ("call_arguments", 5)


def test_a_boring_axis_other_than_the_planes_normal_is_unsupported(tmp_path):
    e = error_of(run(tmp_path, HEAD + "CYCLE86(50,0,2,-15,,0,3,0,0,0,0,1,0,0,0)\nM30\n", MILL3))
    assert (e.kind, e.line) == ("unsupported", 5)
    # 3 under G17 is Z, the plane's normal: it runs
    ok(tmp_path, HEAD + "CYCLE86(50,0,2,-15,,0,3,0,0,0,0,3,0,0,0)\nM30\n", MILL3)


def test_g_groups_posts_write_in_their_headers(tmp_path):
    # the Programming Manual's table of G groups: spline begin/end (19, 20), collision
    # monitoring (23), REPOS mode (26), corners with orientation (27), thread interruption
    # (41), tool carrier (42), SAR (43, 44), cutcom approach (48), G0 interpolation (55),
    # tool wear (56), working area limits (60): valid, no effect on the geometry vmach simulates
    header = ("N10 G40 G17 G710 G94 G90 G60 G601 FNORM BNAT ENAT CDOF RMB ORID LFOF TCOABS\n"
              "N20 G140 G340 G460 RTLION TOWSTD WALCS0\n")
    text = header + "N30 T1 D1\nN40 G0 X10 Y5 Z20\nN50 M30\n"
    assert errors(check(tmp_path, text, MILL5AC)) == []
    r = ok(tmp_path, text, MILL5AC)
    noted = {f.data.get("code") or f.message.split(":")[0] for f in r.findings if f.kind == "no_effect"}
    assert {"TCOABS", "G460", "RTLION", "CDOF", "WALCS0"} <= noted
    assert [m.axes["X"] for m in moves(r)] == [10.0]


def test_g_codes_that_change_the_path_are_unsupported_by_name(tmp_path):
    # RTLIOF: G0 axis by axis (no straight line); TCOFR: the tool along the frame; G461/G462:
    # an arc or extension at cutcom approach; CDON: bottleneck detection skips blocks
    for code in ("RTLIOF", "TCOFR", "G461", "CDON"):
        text = f"T1 D1\nG0 X0 Y0 Z20\n{code}\nG0 X10\nM30\n"
        e = error_of(run(tmp_path, text, MILL3))
        assert (e.kind, e.line) == ("unsupported", 3), code
        assert code in e.message


def test_cycle832_modes_as_the_posts_write_them(tmp_path):
    # the tolerance first, then the mode: a number (1003, 112001), a mode constant of the
    # cycle's definitions (_ROUGH, _ORI_FINISH) or a sum of them; CYCLE832() switches off
    from vmach.canon import PathTolerance

    calls = ["CYCLE832(0.1,1003)", "CYCLE832(0.1,112001)", "CYCLE832(_camtol,_SEMIFIN,1)",
             "CYCLE832(0.01,_ORI_FINISH,1,0.5,1)", "CYCLE832(0.01,_FINISH+_TOP_SURFACE_SMOOTH_ON,1)",
             "CYCLE832(0.02,_OFF,1)", "CYCLE832()"]
    text = "DEF REAL _camtol=0.05\n" + HEAD + "\n".join(calls) + "\nG1 X5\nM30\n"
    assert errors(check(tmp_path, text, MILL3)) == []
    r = ok(tmp_path, text, MILL3)
    tol = [c for c in r.commands if isinstance(c, PathTolerance)]
    assert [t.tolerance for t in tol] == [0.1, 0.1, 0.05, 0.01, 0.01, 0.02, 0.0]
    assert tol[4].setting[0] == "_FINISH+_TOP_SURFACE_SMOOTH_ON"
    # a sum with a name the program defines is an expression, evaluated as such
    e = error_of(run(tmp_path, HEAD + "CYCLE832(0.01,_FINISH+UNDEFINED_NAME,1)\nM30\n", MILL3))
    assert (e.kind, e.line) == ("undefined_variable", 5)


def test_a_parenthesised_comment_is_a_syntax_error_that_says_why(tmp_path):
    # an 840D in Siemens mode reads ';' comments only; '( … )' is an ISO-dialect comment
    f = check(tmp_path, "G0 X0\n(OPERATION 1 ROUGH)\nM30\n", MILL3)
    assert errors(f) == [("syntax", 2)]
    assert "G291" in f[0].message
