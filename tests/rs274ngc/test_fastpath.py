"""The fast paths against the general path: the same trace, commands, findings and blocks.

``fastpath.py`` executes flat lines (G0/G1, F and axis words) from words read for the whole
file at once, and simple lines without building a block. These tests run programs both
ways (``Interpreter.fast_paths`` switched off for the general path) and compare everything
that comes out, exactly (``repr``, so that -0.0 and 0.0 differ).
"""

from __future__ import annotations

import contextlib
import dataclasses
import random
import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rs274ngc.fixture_options import fixture_options

from interpreters.rs274ngc import FORMATS, fastpath, output, rs274_trace, run
from interpreters.rs274ngc.interp import Interpreter
from vmach.canon import AxisSpec, ControlSpec, LinearFeed, RunOptions, Traverse
from vmach.source import SourceRef

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "rs274ngc"
PROGRAMS = sorted(p for p in FIXTURES.glob("*.ngc") if not p.name.startswith("lib_"))
BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


@contextlib.contextmanager
def _fast_paths(on: bool):
    saved = Interpreter.fast_paths
    Interpreter.fast_paths = on
    try:
        yield
    finally:
        Interpreter.fast_paths = saved


def _outcome(path, control=None, options=None, extra=None) -> dict:
    lines, traced = FORMATS["rs274"](path, control, options, extra or {})
    assert traced.commands == []  # the trace format builds the trace only
    both_lines, both = rs274_trace(path, control, options, extra or {}, commands=True)
    assert both_lines == lines
    result = run(path, control, options)
    return {
        "trace": lines,
        "traced": (traced.completed, traced.blocks, repr(traced.findings)),
        "traced with commands": (both.completed, both.blocks, repr(both.findings)),
        "commands": [repr(c) for c in result.commands],
        "commands with the trace": [repr(c) for c in both.commands],
        "result": (result.completed, result.blocks, repr(result.findings)),
    }


def assert_same_both_ways(path, control=None, options=None, extra=None) -> dict:
    """Run ``path`` with and without the fast paths; everything must agree."""
    with _fast_paths(True):
        fast = _outcome(path, control, options, extra)
    with _fast_paths(False):
        general = _outcome(path, control, options, extra)
    for key in fast:
        assert fast[key] == general[key], key
    assert fast["traced"] == fast["traced with commands"]
    if not extra:  # run() knows no tool table nor block delete
        assert fast["commands"] == fast["commands with the trace"]
        assert fast["traced"][0] == fast["result"][0]
    return fast


def _write(directory: Path, text: str, name: str = "prog.ngc") -> Path:
    path = directory / name
    path.write_bytes(text.encode("utf-8"))
    return path


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_golden_programs_both_ways(program: Path, monkeypatch, tmp_path):
    monkeypatch.chdir(FIXTURES)
    extra = fixture_options(program, tmp_path, update=False)  # each run reads the same file
    out = assert_same_both_ways(program.name, options=RunOptions(dialect_options=extra),
                                extra=extra)
    expected = program.with_suffix(".expected").read_text(encoding="utf-8").splitlines()
    assert out["trace"] == expected


def test_the_benchmark_programs_both_ways(tmp_path):
    sys.path.insert(0, str(BENCHMARKS))
    try:
        import interpreter_rs274ngc as bench
    finally:
        sys.path.remove(str(BENCHMARKS))
    for text in (bench.flat_program(300), bench.loop_program(300)):
        out = assert_same_both_ways(_write(tmp_path, text))
        assert out["result"][0]
        assert sum(1 for c in out["commands"] if c.startswith("LinearFeed")) == 300


def test_an_error_inside_a_flat_run_is_reported_at_its_line_and_column(tmp_path):
    text = "G21 G90 F100\nG1 X1\nG1 X2 Y1\nN30 G1 X3 X4\nG1 X5\nM2\n"
    out = assert_same_both_ways(_write(tmp_path, text))
    assert not out["result"][0]
    assert "kind='duplicate_word'" in out["result"][2]
    assert "line=4, column=11" in out["result"][2]
    assert out["trace"][-3].endswith("STRAIGHT_FEED(2.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)")


@pytest.mark.parametrize(
    "text",
    [
        "G0 X1\nG1 X2\nM2\n",  # G1 without feed: g1_zero_feed
        "F0\nG1 X1\nM2\n",
        "G1 X1 F0\nM2\n",
        "G1 F100 X1\nX2\nG80\nX3\nM2\n",  # axis words without a motion mode
        "G1 X1 F100\nG1 X2 F-5\nM2\n",
        "G1 X1 F100\nG1 X2 F10 F20\nM2\n",
        "G1 X1 F100\nG1 F10 X2 F20\nM2\n",
        "G1 X1 F100\nG1 X2\nG1 X3\n",  # runs off the end of the file
        "G1 X1 F100\nG1 X2\nG1 X3",  # ... without a last newline
        "G1 X1 F100\r\nG1 X2\r\nG1 X3\r\nM2\r\n",
        "%\nG1 X1 F100\nG1 X2\n%\nG1 X9\n",
        "G1 X1 F100\n" + "G1 X2" + " " * 260 + "\nM2\n",  # too long for LinuxCNC's buffer
        "G1 X1 F100\n" + "G1 X2" + " " * 246 + "\nG1 X3" + " " * 247 + "\nM2\n",
        "G1 X1 F100\nG1 X1 0\nG1 X 2 Y - 3\nG1 X1.2.3\nM2\n",
        "G1 X1 F100\nN 20 G1 X2\nN0030 G1 X3\nN40.5 G1 X4\nN1234567 X5\nN50\n\n  \nM2\n",
        "G1 X1 F100\nG1 X2 (note)\nG1 X3 ; tail\n(MSG,hi)\nG1 X4 é\nM2\n",
        "G1 X1 F100\ng01x2.y-.5z+1.\nG1.0 X3\nG1.5 X4\nM2\n",
        "G1 X1 F100\nG0 A10\nG0 X2\nG0 A0\nG0 X3\nG1 B-0 C.5\nM2\n",
        "G1 X-0 Y-0 Z-0 F100\nG0 X0\nM2\n",
        "G20 G1 X1 F10\nG1 X2 Y2\nG21\nG1 X3\nM2\n",
        "G1 X1 F100\nG91\nG1 X1\nG1 X1\nG90\nG1 X1\nM2\n",
        "G1 X1 F100\nG93\nG1 X2 F10\nG94\nG1 X3 F100\nM2\n",
        "G1 X1 F100\nG95 S100 M3\nG1 X2 F0.1\nG94\nG1 X3 F100\nM5\nM2\n",
        "G10 L2 P1 X5 Y-1 Z2\nG92 X1\nG1 X1 F100\nG1 Y2\nG92.1\nG1 X3\nM2\n",
        "G10 L2 P1 R30\nG1 X1 F100\nG1 Y2\nM2\n",
        # offsets added in Output.machine's order: (0.1 + 0.2) + 0.3 is not 0.1 + (0.2 + 0.3)
        "G10 L2 P1 X0.3 Y0.3 Z0.3\nG0 X0 Y0 Z0\nG92 X-0.2 Y-0.2 Z-0.2\nG1 X0.1 Y0.1 Z0.1 F1\nM2\n",
        "G1 X1 F100\nM3 S1000\nG1 X2\nS2000\nG1 X3\nM5\nM2\n",
        "T1 M6\nG1 X1 F100\nG43 H1\nG1 X2\nG49\nG1 X3\nM2\n",
        "G1 X1 F100\nG2 X2 Y1 R1\nX3 Y0 R1\nG1 X4\nM2\n",
        "G1 X1 F100\nG81 X1 Y1 Z-1 R1\nX2\nG80\nG0 X0\nM2\n",
        "G1 X1 F100\n#1=2\nG1 X#1\nG1 X[#1+1]\nG1 X3\nM2\n",
        "G1 F100\no1 repeat [3]\nG1 X1\nG1 X2\nG0 Z1\no1 endrepeat\nM2\n",
        "o1 sub\nG1 X1\nG1 Y1\no1 endsub\nG1 F100\no1 call\no1 call\nM2\n",
        "/G1 X1 F100\nG1 X2 F100\nM2\n",
        "G1 X1 F100\nM30\n",
        "",
        "\n\n\n",
    ],
)
def test_edge_cases_both_ways(tmp_path, text):
    assert_same_both_ways(_write(tmp_path, text))


def test_block_limit_inside_a_flat_run(tmp_path):
    text = "G21 F100\n" + "G1 X1\nG1 X2\n" * 20 + "M2\n"
    for limit in (1, 2, 5, 17, 41, 42, 43):
        out = assert_same_both_ways(_write(tmp_path, text), options=RunOptions(max_blocks=limit))
        # the block over the limit is counted, then refused
        assert out["result"][:2] == (limit >= 42, min(limit + 1, 42))


@pytest.mark.parametrize("axes", ["XYZ", "XYZAC", "XZ", "XYZB"])
@pytest.mark.parametrize("strict", [True, False])
def test_machines_both_ways(tmp_path, axes, strict):
    control = ControlSpec(axes=tuple(AxisSpec(a) for a in axes), strict_axes=strict)
    for text in (
        "G1 X1 Y1 F100\nG1 X2\nG1 Z-1\nG1 A3\nG1 X3\nM2\n",
        "G1 X1 F100\nX2\nY3\nM2\n",
        "G0 X1 A5\nG0 C3\nG0 X2\nG0 B1\nG0 A0 C0\nM2\n",
        "F100\no1 repeat [2]\nG1 X1 Y[1+1]\nG1 Z[-1] C[2]\no1 endrepeat\nM2\n",
    ):
        out = assert_same_both_ways(_write(tmp_path, text), control=control)
        if strict and any(c in text for c in "ABCY" if c not in axes):
            assert "unknown_axis" in out["result"][2]


def test_block_delete_both_ways(tmp_path):
    path = _write(tmp_path, "G1 X1 F100\n/G1 X2\nG1 X3\nM2\n")
    out = assert_same_both_ways(path, extra={"block_delete": True})
    assert not any("2.0000" in line for line in out["trace"])


# -- generated flat programs ---------------------------------------------------------------

_number = st.one_of(
    st.integers(-300, 300).map(str),
    st.floats(-500, 500, allow_nan=False).map(lambda v: f"{v:.4f}"),
    st.sampled_from(["0", "-0", "+1.", ".5", "0.1", "-.25", "1.", "0.0", "007", "1.2.3", "", "-", "1e3"]),
)
_axis = st.tuples(st.sampled_from(list("XYZABCxyzabc")), st.sampled_from(["", " ", "\t"]), _number)
_flat_line = st.builds(
    lambda n, g, f, axes, f_last, upper: " ".join(
        w for w in (
            n,
            g,
            "" if f_last else f,
            *(letter + gap + value for letter, gap, value in axes),
            f if f_last else "",
        ) if w
    ) if upper else (n + g + ("" if f_last else f)
                     + "".join(letter.lower() + value for letter, _, value in axes)
                     + (f if f_last else "")),
    st.sampled_from(["", "", "N10", "N 20", "n0030", "N5.5"]),
    st.sampled_from(["", "G0", "G1", "G00", "G01", "g1", "G1.", "G 1", "G1.0", "G2", "G0.5"]),
    st.sampled_from(["", "", "F100", "F 250.5", "F0", "F-1", "F.5", "f60"]),
    st.lists(_axis, max_size=4),
    st.booleans(),
    st.booleans(),
)
_other_line = st.sampled_from([
    "", "M2", "G90", "G91", "G20", "G21", "G93", "G94", "G80", "G17", "G18", "G92 X1",
    "G92.1", "G10 L2 P1 X3 Y1", "G10 L2 P1 R15", "G10 L2 P1 X0.3 Y0.3 Z0.3",
    "G92 X-0.2 Y-0.2 Z-0.2", "G55", "G54", "M3 S500", "M5", "T1 M6",
    "G43 H1", "G49", "#1=5", "G1 X#1", "G0 X1 (c)", "G1 X1 ; c", "(MSG,m)", "G2 X1 Y1 R5",
    "X1 X2", "G1 X1 Y1 Z1 A1 B1 C1 F1", "/G1 X7", "%", "G1 X1 é", "G1 X1 Y2" + " " * 250,
])
_program = st.lists(
    st.one_of(_flat_line, _flat_line, _flat_line, _other_line), min_size=0, max_size=40,
).flatmap(lambda lines: st.tuples(
    st.just(lines), st.sampled_from(["\n", "\r\n"]), st.booleans(), st.integers(5, 60)))


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_program)
def test_generated_flat_programs_both_ways(program):
    lines, newline, ends, limit = program
    text = newline.join(lines) + (newline + "M2" + newline if ends else "")
    with tempfile.TemporaryDirectory() as d:
        assert_same_both_ways(_write(Path(d), text), options=RunOptions(max_blocks=limit))


def test_long_random_flat_programs_both_ways(tmp_path):
    """Mostly flat CAM-like programs of a few thousand lines, a few other lines between."""
    rng = random.Random(6)
    for _ in range(3):
        lines = ["G21 G90 G17", "G0 Z5", "G1 Z-1 F300"]
        for _ in range(3000):
            r = rng.random()
            if r < 0.01:
                lines.append(rng.choice(["G91", "G90", "G0 Z5", "M3 S1000", "(pass)", "G92 X1",
                                         "G92.1", "F0", "G20", "G21", "G1 X1 F0", "G2 X1 Y1 R9"]))
            else:
                words = [rng.choice(["", "G1", "G0", "G01"])]
                for axis in rng.sample("XYZ", rng.randint(1, 3)):
                    words.append(f"{axis}{rng.uniform(-100, 100):.{rng.randint(0, 4)}f}")
                if rng.random() < 0.1:
                    words.append(f"F{rng.randint(1, 2000)}")
                lines.append(" ".join(w for w in words if w))
        lines.append("M2")
        assert_same_both_ways(_write(tmp_path, "\n".join(lines) + "\n"))


# -- the objects the flat path builds ----------------------------------------------------------

def test_flat_path_builds_the_same_objects_as_the_constructors():
    src = SourceRef("a.ngc", 3, 1, "G1 X1")
    made = []
    for cls, setters, values in (
        (SourceRef, output.SOURCE_SETTERS, ("a.ngc", 3, 1, "G1 X1")),
        (LinearFeed, output.FEED_SETTERS, (src, {"X": 1.0}, 500.0)),
        (Traverse, output.TRAVERSE_SETTERS, (src, {"X": -0.0})),
    ):
        assert setters is not None, cls
        obj = object.__new__(cls)
        for setter, value in zip(setters, values, strict=True):
            setter(obj, value)
        assert obj == cls(*values) and repr(obj) == repr(cls(*values))
        made.append(obj)
    with pytest.raises(dataclasses.FrozenInstanceError):
        made[1].feed = 1.0


def test_slot_setters_refuse_classes_they_cannot_build():
    @dataclasses.dataclass(frozen=True, slots=True)
    class Checked:
        a: int

        def __post_init__(self):
            pass

    @dataclasses.dataclass(frozen=True)
    class Unslotted:
        a: int

    assert output._slot_setters(Checked, ("a",)) is None
    assert output._slot_setters(Unslotted, ("a",)) is None
    assert output._slot_setters(SourceRef, ("path", "line")) is None
    assert output._slot_setters(SourceRef, ("path", "line", "column", "text")) is not None


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.one_of(
    _flat_line,
    st.text(alphabet=st.sampled_from(list("GgXxYyZzFfNnAa01-+. \t\r\x0b\x0c(;)#[]%/é\u2028")),
            max_size=20),
), max_size=12))
def test_odd_characters_both_ways(lines):
    """Line ends and blanks of every kind, control characters, non-ASCII letters."""
    with tempfile.TemporaryDirectory() as d:
        assert_same_both_ways(_write(Path(d), "\n".join(lines) + "\nM2\n"),
                              options=RunOptions(max_blocks=200))


def test_flat_path_with_the_constructors(tmp_path, monkeypatch):
    """Should the command classes change so that the slot setters cannot build them, the flat
    path builds them with their constructors: the same output."""
    text = "G21 F100\nG1 X1 Y-0\nG0 Z5\nN10 G1 X2 A1\nG1 X3\nG1 B0 A0\nM2\n"
    path = _write(tmp_path, text)
    quick = assert_same_both_ways(path)
    monkeypatch.setattr(fastpath, "SOURCE_SETTERS", None)
    assert assert_same_both_ways(path) == quick
