"""Fuzzing: whatever the input, only vmach's own diagnostics come out (no Python exception)."""

from __future__ import annotations

import tempfile
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from interpreters.rs274ngc import FORMATS, check, run
from interpreters.rs274ngc.diag import MESSAGES
from vmach.canon import RunOptions

OPTIONS = RunOptions(max_blocks=2000, max_call_depth=8)
KINDS = set(MESSAGES)

_letters = st.sampled_from(list("GXYZIJKRFSTMPQLHABCDEN#O"))
_numbers = st.one_of(
    st.integers(-200, 200).map(str),
    st.floats(-1000, 1000, allow_nan=False).map(lambda v: f"{v:.3f}"),
    st.sampled_from(["0", "1", "2", "3", "4", "17", "18", "19", "20", "21", "28", "30", "43",
                     "49", "53", "54", "59.3", "80", "81", "82", "83", "90", "91", "92",
                     "92.1", "93", "94", "95", "98", "99", "[1+2]", "[#1*2]", "#<a>", "-[3]",
                     "[SIN[30]]", "[1/0]", "ATAN[1]/[1]", ".5", "1.2.3", "", "[", "]"]),
)
_word = st.tuples(_letters, _numbers).map(lambda t: t[0] + t[1])
_extras = st.sampled_from([
    "(comment)", "(MSG,hi)", "(DEBUG,#1 #<a>)", "; tail", "#1=2", "#<a>=3", "#<_g>=[#1+1]",
    "o1 sub", "o1 endsub", "o1 call [2]", "o2 if [#1 GT 1]", "o2 else", "o2 endif",
    "o3 while [#1 LT 3]", "#1=[#1+1]", "o3 endwhile", "o4 repeat [2]", "o4 endrepeat",
    "o5 do", "o5 while [0]", "o6 break", "o<x> call", "%", "/G0 X1", "M2", "M30", "T1 M6",
    "o2 elseif [#1]", "o3 break", "o3 continue", "o5 continue", "o4 break", "o1 return [1/0]",
    "o3 endwhile junk", "o2 if [1 +]", "o7 foo", "o1 endsub [#<nope>]", "#<q>=[#<q>+1]",
    "G43 H1", "G10 L2 P1 X1", "G10 L20 P2 Y1", "G2 X1 Y1 R1", "G3 I1 J0", "(", ")", "&",
])
_line = st.one_of(st.lists(_word, min_size=0, max_size=6).map(" ".join), _extras)
_program = st.lists(_line, min_size=0, max_size=25).map("\n".join)


def _write(tmp: Path, text: str | bytes) -> Path:
    path = tmp / "fuzz.ngc"
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    return path


def _assert_own_diagnostics(path: Path) -> None:
    result = run(path, None, OPTIONS)
    for f in result.findings:
        assert f.kind in KINDS, f.render()
        f.render()
    lines, traced = FORMATS["rs274"](path, None, OPTIONS, {})
    assert all(isinstance(x, str) for x in lines)
    assert traced.completed == result.completed
    for f in check(path):
        assert f.kind in KINDS | {"unclosed_o_block", "unmatched_o_word", "undefined_sub"}, f
        f.render()


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_program)
def test_random_blocks_give_only_own_diagnostics(text):
    with tempfile.TemporaryDirectory() as d:
        _assert_own_diagnostics(_write(Path(d), text))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.binary(max_size=300))
def test_random_bytes_give_only_own_diagnostics(data):
    with tempfile.TemporaryDirectory() as d:
        _assert_own_diagnostics(_write(Path(d), data))


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet=st.characters(min_codepoint=1, max_codepoint=0x2FF), max_size=120))
def test_random_text_lines(text):
    with tempfile.TemporaryDirectory() as d:
        _assert_own_diagnostics(_write(Path(d), text + "\nM2\n"))
