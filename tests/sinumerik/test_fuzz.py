"""Random blocks and random bytes: only our own diagnostics may come out, never a traceback."""

from __future__ import annotations

import tempfile
from pathlib import Path

from catalog import TURNMILL
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from interpreters import sinumerik
from vmach.canon import RunOptions
from vmach.errors import VmachError
from vmach.findings import Finding
from vmach.machine.control import load_control

TURN = load_control(TURNMILL)
WORDS = [
    "G0",
    "G1",
    "G2",
    "G3",
    "G4",
    "G17",
    "G18",
    "G19",
    "G90",
    "G91",
    "G53",
    "G54",
    "G500",
    "X",
    "Y",
    "Z",
    "C1",
    "I",
    "J",
    "K",
    "CR=",
    "F",
    "S",
    "S2=",
    "M2=",
    "M3",
    "M5",
    "M17",
    "M30",
    "T=",
    "D",
    "R1",
    "R85",
    "=",
    "+",
    "-",
    "*",
    "/",
    "(",
    ")",
    "[",
    "]",
    ",",
    "<",
    ">",
    "==",
    "<>",
    ">=",
    "AND",
    "OR",
    "NOT",
    "DIV",
    "MOD",
    "SIN(",
    "SQRT(",
    "ACP(",
    "ACN(",
    "DC(",
    "AC(",
    "IC(",
    "IF",
    "ELSE",
    "ENDIF",
    "WHILE",
    "ENDWHILE",
    "FOR",
    "TO",
    "ENDFOR",
    "REPEAT",
    "UNTIL",
    "LOOP",
    "ENDLOOP",
    "CASE",
    "OF",
    "DEFAULT",
    "GOTOF",
    "GOTOB",
    "GOTO",
    "GOTOC",
    "LBL",
    "LBL:",
    "N10",
    "N20",
    "DEF",
    "REAL",
    "INT",
    "A1",
    "PROC",
    "TRANS",
    "ROT",
    "RPL=",
    "AROT",
    "ATRANS",
    "DIAMON",
    "DIAMOF",
    "SETMS(2)",
    "MSG(",
    '"txt"',
    "C_AXIS_ON",
    "L12",
    "RET",
    "0",
    "1",
    "2.5",
    "-3",
    "360",
    "1EX3",
    "1EX300",
    "1EX400",
    "TRUNC(",
    "ROUND(",
    ";",
    "/",
    ":",
    "$P",
    "'H1F'",
    "\t",
    "é",
    # compensation, contour, cycles, frames, polar, circles, repetition, TRACYL
    "G40",
    "G41",
    "G42",
    "G450",
    "G451",
    "KONT",
    "RND=",
    "RNDM=",
    "CHF=",
    "CHR=",
    "FRC=",
    "CYCLE81(",
    "CYCLE83(",
    "MCALL",
    "HOLES2(",
    "SCALE",
    "MIRROR",
    "AMIRROR",
    "G111",
    "G110",
    "AP=",
    "RP=",
    "CIP",
    "CT",
    "I1=",
    "AR=",
    "REPEATB",
    "P=",
    "ENDLABEL:",
    "TRACYL(",
    "TRAFOOF",
]

block = st.lists(st.sampled_from(WORDS), max_size=8).map(" ".join)
program = st.lists(block, min_size=1, max_size=12).map("\n".join)


def _radius(tool: str, d: int) -> float | None:
    """Every D offset 2 mm but D3 (none): compensation runs as far as the program lets it."""
    return None if d == 3 else 2.0


def _exercise(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "FUZZ.MPF"
        p.write_bytes(data)
        (Path(d) / "L12.SPF").write_text("R1=R1+1\nM17\n")
        for control in (TURN, None):
            kwargs = {} if control is None else {"control": control}
            try:
                findings = sinumerik.check(p, **kwargs)
                result = sinumerik.run(p, options=RunOptions(max_blocks=2000, tool_radius=_radius), **kwargs)
            except VmachError:
                continue
            assert all(isinstance(f, Finding) and f.kind for f in findings)
            assert all(isinstance(f, Finding) for f in result.findings)
            if not result.completed:
                assert any(f.severity == "error" for f in result.findings)
            for f in findings + result.findings:
                f.render()


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(program)
def test_random_blocks_give_only_diagnostics(text):
    _exercise(text.encode("utf-8"))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.binary(max_size=400))
def test_random_bytes_give_only_diagnostics(data):
    _exercise(data)
