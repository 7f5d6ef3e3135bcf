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
