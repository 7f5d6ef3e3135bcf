"""Fuzzing every input a user hands vmach (issue #30), kept in the suite so that what was found
stays found: grammar-shaped Sinumerik and RS274/NGC blocks through the command line, byte-level
mutations of the fixture programs, and a value of every TOML type at every key of the machine
models, tool libraries and setup files.

Asserted each time: no exception but vmach's own (``VmachError``), exit codes 0, 1 or 2, a place
(file and line) for every error, and nothing written when the command fails.

The budget is about a minute in the suite. ``VMACH_FUZZ_LONG=1`` runs fifty times as many
examples (``VMACH_FUZZ_LONG=N``: N times) for a search of its own; the examples hypothesis
shrinks to are printed as usual.
"""

from __future__ import annotations

import os
import tempfile
import tomllib
from pathlib import Path

import pytest
from catalog import FIXTURES, MODELS
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from tomlgen import EVERY_TYPE, dumps, leaves, replaced

from interpreters import rs274ngc, sinumerik
from vmach.canon import RunOptions
from vmach.cli import main
from vmach.errors import VmachError
from vmach.machine import load_model
from vmach.machine.control import load_control
from vmach.setup import read_setup
from vmach.tooling.library import load_tools

_LONG = os.environ.get("VMACH_FUZZ_LONG", "")
SCALE = (50 if _LONG in ("1", "true", "yes") else int(_LONG)) if _LONG not in ("", "0") else 1
OPTIONS = RunOptions(max_blocks=5_000)


def budget(n: int):
    """Hypothesis settings for ``n`` examples in the suite (times SCALE in a long run)."""
    return settings(max_examples=n * SCALE, deadline=None, derandomize=SCALE == 1,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much,
                                           HealthCheck.data_too_large])


def _placed(findings) -> None:
    """Every error names its file and line."""
    for f in findings:
        f.render()
        if f.is_error:
            assert f.source is not None and f.source.path and f.source.line >= 1, f.render()


# -- grammar-shaped blocks through the command line ------------------------------------------------
_num = st.one_of(st.integers(-999, 999).map(str), st.sampled_from(
    ["0", "1", ".5", "-0.001", "1E3", "1EX308", "360", "1e400", "", "-", "[1/0]", "#1", "R1"]))
_SIN_WORDS = ["G0", "G1", "G2", "G3", "G17", "G18", "G41", "G40", "G90", "G91", "G54", "G500",
              "X", "Y", "Z", "C1=", "I", "J", "CR=", "F", "S", "M3", "M5", "M17", "M30", "T=\"EM10\"",
              "D1", "R1=", "R2=R1*", "IF R1>", "GOTOF END", "GOTOB L1", "L1:", "END:", "WHILE R1<",
              "ENDWHILE", "REPEAT", "UNTIL", "FOR R3=1 TO", "ENDFOR", "ENDIF", "ELSE", "L12",
              "SUB2", "CALL \"../X\"", "TRANS X", "ROT Z", "SCALE X", "MIRROR X0", "CYCLE81(10,0,2,-5)",
              "MCALL", "HOLES2(0,0,20,0,90,4)", "RND=", "CHF=", "G111 X0 Y0", "AP=", "RP=", "DEF REAL A",
              "A=", "MSG(\"x\")", "SETMS(2)", "TRACYL(30)", "TRAFOOF", ";c", "(", ")", "$AA_IW[X]"]
_NGC_WORDS = ["G0", "G1", "G2", "G3", "G17", "G18", "G19", "G20", "G21", "G28", "G41", "G40", "G43",
              "G53", "G54", "G81", "G83", "G90", "G91", "G92", "X", "Y", "Z", "I", "J", "K", "R", "F",
              "S", "T", "M3", "M6", "M2", "M30", "P", "Q", "L", "H", "D", "#1=", "#<a>=", "o100 sub",
              "o100 endsub", "o100 call", "o<lib> call", "o<../x> call", "o101 while [#1 LT 3]",
              "o101 endwhile", "o102 if [#1]", "o102 else", "o102 endif", "o103 do", "o104 repeat [2]",
              "o104 endrepeat", "(msg,x)", ";c", "[", "]", "/", "%", "N10"]


def _block(words):
    return st.lists(st.tuples(st.sampled_from(words), st.one_of(st.just(""), _num)), max_size=6).map(
        lambda ws: " ".join(w + n for w, n in ws))


def _program(words, end):
    return st.lists(_block(words), min_size=1, max_size=15).map(lambda b: "\n".join([*b, end]) + "\n")


def _cli(tmp: Path, name: str, text: str | bytes, dialect) -> None:
    """``check`` and ``run -o`` of one program: exit codes, placed errors, nothing written
    unless the run completed."""
    p = tmp / name
    p.write_bytes(text if isinstance(text, bytes) else text.encode("utf-8"))
    (tmp / "L12.SPF").write_text("R1=R1+1\nM17\n")
    (tmp / "SUB2.SPF").write_text("PROC SUB2\nG1 X1 F100\nM17\n")
    (tmp / "lib.ngc").write_text("o<lib> sub\nG0 X1\no<lib> endsub\n")
    out = tmp / "out.txt"
    if out.exists():
        out.unlink()
    assert main(["check", str(p)]) in (0, 1)
    rc = main(["run", str(p), "-o", str(out), "--max-blocks", "5000"])
    assert rc in (0, 1)
    result = dialect.run(p, options=OPTIONS)
    _placed(result.findings)
    _placed(dialect.check(p))
    assert out.exists() == result.completed
    assert rc == (1 if not result.completed or any(f.is_error for f in result.findings) else 0)


@budget(60)
@given(_program(_SIN_WORDS, "M30"))
def test_sinumerik_blocks_through_the_cli(text):
    with tempfile.TemporaryDirectory() as d:
        _cli(Path(d), "FUZZ.MPF", text, sinumerik)


@budget(60)
@given(_program(_NGC_WORDS, "M2"))
def test_rs274_blocks_through_the_cli(text):
    with tempfile.TemporaryDirectory() as d:
        _cli(Path(d), "fuzz.ngc", text, rs274ngc)


# -- byte-level mutations of the fixtures ---------------------------------------------------------
SIN_FIXTURES = sorted(FIXTURES.glob("*/*.MPF")) + sorted(FIXTURES.glob("*/*.SPF"))
NGC_FIXTURES = sorted(FIXTURES.glob("rs274ngc/*.ngc"))


@st.composite
def _mutated(draw, files: list[Path]) -> bytes:
    data = bytearray(draw(st.sampled_from(files)).read_bytes()[:4000])
    for _ in range(draw(st.integers(1, 6))):
        op = draw(st.sampled_from(["flip", "insert", "delete", "repeat", "splice"]))
        at = draw(st.integers(0, len(data)))
        if op == "flip" and data:
            i = min(at, len(data) - 1)
            data[i] ^= 1 << draw(st.integers(0, 7))
        elif op == "insert":
            data[at:at] = draw(st.one_of(st.binary(max_size=8), st.sampled_from(
                [b"\x00", b"\r", b"\n", b"(", b";", b"[", b"\"", b"\xff\xfe", b"\xc3", b"E999", b"--"])))
        elif op == "delete":
            del data[at:at + draw(st.integers(1, 40))]
        elif op == "repeat":
            data[at:at] = data[at:at + draw(st.integers(1, 80))] * draw(st.integers(1, 4))
        else:
            other = draw(st.sampled_from(files)).read_bytes()
            j = draw(st.integers(0, len(other)))
            data[at:at] = other[j:j + 60]
    return bytes(data)


def _dialect_only(dialect, p: Path, control=None) -> None:
    kwargs = {} if control is None else {"control": control}
    for f in (dialect.check, lambda q, **k: dialect.run(q, options=OPTIONS, **k).findings):
        try:
            _placed(f(p, **kwargs))
        except VmachError as exc:
            _placed([x for x in exc.findings() if exc.exit_code == 1])


@budget(80)
@given(_mutated(SIN_FIXTURES))
def test_mutated_sinumerik_fixtures(data):
    with tempfile.TemporaryDirectory() as d:
        for f in FIXTURES.glob("sinumerik/*.SPF"):
            (Path(d) / f.name).write_bytes(f.read_bytes())
        p = Path(d) / "MUT.MPF"
        p.write_bytes(data)
        _dialect_only(sinumerik, p)
        _dialect_only(sinumerik, p, TURNMILL_CONTROL)


@budget(80)
@given(_mutated(NGC_FIXTURES))
def test_mutated_rs274_fixtures(data):
    with tempfile.TemporaryDirectory() as d:
        (Path(d) / "lib_square.ngc").write_bytes((FIXTURES / "rs274ngc" / "lib_square.ngc").read_bytes())
        p = Path(d) / "mut.ngc"
        p.write_bytes(data)
        _dialect_only(rs274ngc, p)


TURNMILL_CONTROL = load_control(MODELS / "turnmill.toml")


# -- a value of every TOML type at every key ---------------------------------------------------------
def _keys(path: Path) -> list[tuple[Path, tuple]]:
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    return [(path, k) for k in leaves(data)]


MODEL_KEYS = [x for m in sorted(MODELS.glob("*.toml")) for x in _keys(m)]
TOOL_KEYS = [x for t in (FIXTURES / "polygon_shaft" / "tools.toml", FIXTURES / "milling" / "tools.toml")
             for x in _keys(t)]
SETUP_KEYS = [x for s in sorted(FIXTURES.glob("*/vmach.toml")) for x in _keys(s)]


def _shapes(kind: str, keys: list[tuple[Path, tuple]]) -> list[tuple[str, Path, tuple]]:
    """One key of each shape (``axes[3].home`` stands for every ``axes[i].home``), first found."""
    seen: dict[tuple, tuple[str, Path, tuple]] = {}
    for source, key in keys:
        seen.setdefault((kind, *(0 if isinstance(k, int) else k for k in key)), (kind, source, key))
    return list(seen.values())


SHAPES = _shapes("model", MODEL_KEYS) + _shapes("tools", TOOL_KEYS) + _shapes("setup", SETUP_KEYS)


def _mutated_toml(tmp: Path, source: Path, key: tuple, value, name: str) -> Path:
    data = tomllib.loads(source.read_text(encoding="utf-8"))
    out = tmp / name
    out.write_text(dumps(replaced(data, key, value)), encoding="utf-8")
    return out


def _load(kind: str, tmp: Path, source: Path, key: tuple, value) -> None:
    """Write the file with ``value`` at ``key`` and load it as vmach does: either it loads, or a
    VmachError (exit 2) whose every finding has a place."""
    if kind == "setup":
        (tmp / "tools.toml").write_bytes((FIXTURES / "milling" / "tools.toml").read_bytes())
        _mutated_toml(tmp, source, key, value, "vmach.toml")
        prog = tmp / "P.MPF"
        prog.write_text("G0 X1\nM30\n")
    else:
        path = _mutated_toml(tmp, source, key, value, "m.toml")
    try:
        if kind == "model":
            load_control(path)
            load_model(path)
        elif kind == "tools":
            load_tools(path)
        else:
            setup = read_setup(prog)
            if setup.tools:
                load_tools(setup.tools)
            if setup.machine:
                load_control(setup.machine)
    except VmachError as exc:
        assert exc.exit_code == 2
        _placed(exc.findings())
    if kind == "setup":
        assert main(["check", str(prog)]) in (0, 2)


@pytest.mark.parametrize("kind, source, key", SHAPES, ids=[
    f"{k}:{s.parent.name}/{s.name}:{'.'.join(map(str, key))}" for k, s, key in SHAPES])
def test_every_type_at_every_key(tmp_path, kind, source, key):
    """Exhaustive: each key shape of the models, tool libraries and setup files, with a value of
    each TOML type (tests/tomlgen.py EVERY_TYPE) — the model's ``control.dialect = {a = 1}``
    was a TypeError traceback (issue #30)."""
    for i, value in enumerate(EVERY_TYPE):
        d = tmp_path / str(i)
        d.mkdir()
        _load(kind, d, source, key, value)


_scalar = st.one_of(st.integers(-(2**63), 2**63 - 1), st.floats(), st.booleans(),
                    st.text(max_size=12), st.dates(), st.times(), st.datetimes())
_toml_value = st.recursive(_scalar, lambda inner: st.lists(inner, max_size=3)
                           | st.dictionaries(st.text(min_size=1, max_size=6), inner, max_size=3),
                           max_leaves=6)


@budget(60)
@given(st.sampled_from([("model", *k) for k in MODEL_KEYS] + [("tools", *k) for k in TOOL_KEYS]
                       + [("setup", *k) for k in SETUP_KEYS]), _toml_value)
def test_any_toml_value_at_any_key(where, value):
    kind, source, key = where
    with tempfile.TemporaryDirectory() as d:
        _load(kind, Path(d), source, key, value)


def test_the_fuzzed_files_have_keys_of_every_kind():
    assert {k for k, _, _ in SHAPES} == {"model", "tools", "setup"} and len(SHAPES) > 150
