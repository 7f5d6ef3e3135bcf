"""Cutter radius compensation beyond the golden traces: static checks, canonical commands.

The traces themselves are compared with rs274 by ``test_golden.py`` (``comp_*.ngc``).
"""

from __future__ import annotations

import math
import tempfile
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from interpreters.rs274ngc import FORMATS, check, run
from interpreters.rs274ngc.comp import LdConstant
from interpreters.rs274ngc.diag import MESSAGES
from interpreters.rs274ngc.longdouble import PI_2L, PI_L, plus_pi_halves, round_ld
from vmach.canon import Comment, LinearFeed

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "rs274ngc"


def test_check_accepts_every_compensation_code(tmp_path):
    path = tmp_path / "comp.ngc"
    path.write_text("G20 T1 M6\nG41 G1 X1 F10\nG40\nG42 G1 X2\nG40\nG41.1 D0.1 G1 X3\nG40\n"
                    "G42.1 D0.1 G1 X4\nG40\nM2\n", encoding="utf-8")
    assert check(path) == []
    result = run(path)
    assert result.completed, [f.render() for f in result.findings]


def test_held_back_move_keeps_its_line_and_comes_after_later_comments():
    """N70's move waits for N90 to decide its end; the comment of N80 is issued meanwhile
    and waits behind it, as in rs274's trace."""
    result = run(FIXTURES / "comp_lines.ngc")
    assert result.completed
    commands = result.commands
    feed = next(i for i, c in enumerate(commands)
                if isinstance(c, LinearFeed) and c.source.line == 8)
    after = commands[feed + 1]
    assert isinstance(after, Comment) and after.source.line == 9
    # 0.125 in tool on the left of X0 -> X2 at Y0: the tool centre runs 1/16 in above
    assert abs(commands[feed].axes["Y"] - 0.0625 * 25.4) < 1e-9


def test_error_stops_with_the_queue_unprinted(tmp_path):
    path = tmp_path / "gouge.ngc"
    path.write_text("G20 T3 M6\nG0 X0 Y0\nG41 G1 X1 F10\nY1\nX0.9\nY0\nM2\n", encoding="utf-8")
    result = run(path)
    assert not result.completed
    finding = result.findings[-1]
    assert finding.kind == "comp_feed_concave"
    assert finding.source.line == 6
    # each concave corner released the move before it; the move to X0.9 was still held
    # back when the corner after it failed: it is never emitted
    assert [c.source.line for c in result.commands if isinstance(c, LinearFeed)] == [3, 4]


_values = st.sampled_from(["0", "1", "-1", "0.0001", "0.5", "2", "0.0625", "0.06250001",
                           "[1/3]", "[10**300]", "[-10**300]", "[10**-300]", "1000000"])
_moves = st.one_of(
    st.sampled_from(["G41", "G42", "G40", "G41 D2", "G42 D0", "M0", "G20", "G21", "(c)",
                     "G91", "G90", "M3 S100", "G4 P1"]),
    st.tuples(st.sampled_from(["G41.1", "G42.1"]), _values).map(lambda t: f"{t[0]} D{t[1]}"),
    st.tuples(st.sampled_from(["G0", "G1"]), _values, _values, _values).map(
        lambda t: "{} X{} Y{} Z{}".format(*t)),
    st.tuples(st.sampled_from(["G2", "G3"]), _values, _values, _values).map(
        lambda t: "{} X{} Y{} R{}".format(*t)),
    st.tuples(st.sampled_from(["G2", "G3"]), _values, _values, _values, _values).map(
        lambda t: "{} X{} Y{} I{} J{}".format(*t)),
)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(["G17", "G18"]), st.lists(_moves, max_size=14))
def test_compensated_moves_give_only_own_diagnostics(plane, moves):
    """Whatever the moves (huge, tiny, degenerate), compensation ends in a trace or one of
    the dialect's own errors, never a Python exception."""
    text = "\n".join(["G20 " + plane, "T1 M6", "F10", *moves, "M2"]) + "\n"
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "comp.ngc"
        path.write_text(text, encoding="utf-8")
        result = run(path)
        lines, traced = FORMATS["rs274"](path, None, None, {})
    assert traced.completed == result.completed
    for f in result.findings:
        assert f.kind in MESSAGES, f.render()


def test_zero_radius_r_arc_within_tolerance_has_a_nan_centre(tmp_path):
    """``G2 ... R0`` to a point closer than the radius tolerance: LinuxCNC divides 0 by 0
    and prints a NaN centre (it was a ZeroDivisionError here)."""
    path = tmp_path / "r0.ngc"
    path.write_text("G20\nF10\nG0 X0 Y0\nG2 X0.00001 Y0 R0\nG1 X1\nM2\n", encoding="utf-8")
    lines, result = FORMATS["rs274"](path, None, None, {})
    assert result.completed
    assert "ARC_FEED(0.0000, 0.0000, nan, nan, -1," in lines[9]


@settings(max_examples=2000, deadline=None)
@given(st.one_of(st.floats(-10, 10, allow_nan=False),
                 st.sampled_from([0.0, -0.0, math.pi, -math.pi, math.pi / 2, 5e-324, -1e-300])),
       st.sampled_from([-4, -2, -1, 1, 2, 4]))
def test_plus_pi_halves_is_the_long_double_sum(x, k):
    """The integer shortcut gives what rationals give for ``x + k * M_PI_2l``."""
    assert plus_pi_halves(x, k) == float(round_ld(Fraction(x) + k * PI_2L))


@settings(max_examples=2000, deadline=None)
@given(st.one_of(st.floats(-7, 7, allow_nan=False),
                 st.sampled_from([math.pi + 0.05, math.pi - 0.05, 1.5 * math.pi, -math.pi / 2]),
                 st.sampled_from([math.nan, math.inf, -math.inf])))
def test_long_double_constants_compare_exactly(x):
    for value in (round_ld(PI_L + Fraction(0.05)), round_ld(PI_L * 3 / 2), -PI_2L):
        c = LdConstant(value)
        if math.isnan(x):
            assert not c.less_than(x) and not c.greater_than(x)
        elif math.isinf(x):
            assert c.less_than(x) == (x > 0) and c.greater_than(x) == (x < 0)
        else:
            assert c.less_than(x) == (value < Fraction(x))
            assert c.greater_than(x) == (value > Fraction(x))


def test_verify_takes_the_radius_from_vmachs_tool_library(tmp_path):
    """With RunOptions.tool_radius (what verify and `run --tools` pass) G41 uses the library's
    radius of the tool (here 5 mm) instead of the rs274 built-in table's (T1: 0.125 in
    diameter); a tool the library lacks is an error at the G41 block; a LinuxCNC tool table
    given explicitly wins."""
    import math

    from interpreters import rs274ngc
    from vmach.canon import MOTIONS, RunOptions

    prog = tmp_path / "c.ngc"
    prog.write_text("G21 G17 T1 M6\nG0 X0 Y-20 Z1\nG41 G1 X0 Y0 F100\nX20\nG40 X30 Y-20\nM2\n")
    lib = RunOptions(tool_radius=lambda tool, d: {"1": 5.0}.get(tool))

    def entry_radius(result):
        moves = [c for c in result.commands if isinstance(c, MOTIONS)]
        end = moves[1].axes
        return math.hypot(end["X"], end["Y"])

    assert entry_radius(rs274ngc.run(prog, options=lib)) == pytest.approx(5.0)
    assert entry_radius(rs274ngc.run(prog)) == pytest.approx(0.125 * 25.4 / 2)
    missing = rs274ngc.run(prog, options=RunOptions(tool_radius=lambda tool, d: None))
    assert not missing.completed and missing.findings[-1].kind == "comp_no_library_radius"
    assert missing.findings[-1].line == 3
