"""Sinumerik arithmetic: priorities, DIV/MOD, relative comparisons, functions in degrees."""

from __future__ import annotations

import math

import pytest

from interpreters.sinumerik.expr import Env, EvalError, ExprParser, ParseError, compile_expr
from interpreters.sinumerik.lexer import tokenize
from vmach.source import SourceRef


def ev(text: str, r: dict[int, float] | None = None, variables: dict | None = None):
    env = Env()
    for k, v in (r or {}).items():
        env.r[k] = v
    env.vars = dict(variables or {})
    toks = tokenize(text, SourceRef("t", 1, 1, text))
    p = ExprParser(toks, 0, env.vars.__contains__)
    node = p.parse()
    assert toks[p.pos].kind == "end", f"unparsed rest at {p.pos}"
    return compile_expr(node, env)()


@pytest.mark.parametrize(
    "text, expected",
    [
        ("2+3*4", 14),
        ("(2+3)*4", 20),
        ("10-4-3", 3),  # left to right
        ("2*3/4", 1.5),
        ("3/4", 0.75),  # INT/INT is REAL
        ("7 DIV 2", 3),
        ("-7 DIV 2", -3),  # truncation toward zero
        ("361.2 DIV 360", 1),
        ("7 MOD 3", 1),
        ("-7 MOD 3", -1),  # sign of the dividend
        ("3.5 MOD 2", 1.5),
        ("1+2 == 3", True),  # comparisons bind loosest
        ("1 OR 0 AND 0", True),  # AND binds tighter than OR
        ("1 XOR 1 OR 1", True),  # XOR tighter than OR
        ("NOT 0 == 1", True),  # NOT binds tightest: (NOT 0) == 1
        ("6 B_AND 3", 2),
        ("6 B_OR 3", 7),
        ("6 B_XOR 3", 5),
        ("B_NOT 0", -1),
        ("1 B_OR 2 B_AND 0", 1),  # B_AND before B_OR
        ("5 > 3 AND 2", True),  # 5 > (3 AND 2): comparison after AND
        ('"A" << 1 << "B"', "A1B"),
        ("2*-3", -6),
        ("-2*-3", 6),
        ("'H1F'", 31),
        ("'B101'", 5),
        ("1.5EX2", 150.0),
        ("TRUE + TRUE", 2),
    ],
)
def test_operators_follow_the_controls_priorities(text, expected):
    got = ev(text)
    assert got == pytest.approx(expected) if isinstance(expected, float) else got == expected


def test_priority_rule_makes_unparenthesised_and_compare_the_controls_way():
    # IF R1>0 AND R2>0 is R1 > (0 AND R2) > 0 on the control: with R1=5, R2=-1 that is
    # (5 > (0 AND -1)) > 0 = (5 > 0) > 0 = 1 > 0 = TRUE, although R2 > 0 is false
    assert ev("R1>0 AND R2>0", {1: 5.0, 2: -1.0}) is True
    assert ev("(R1>0) AND (R2>0)", {1: 5.0, 2: -1.0}) is False


@pytest.mark.parametrize(
    "text, expected",
    [
        ("SIN(30)", 0.5),
        ("COS(60)", 0.5),
        ("TAN(45)", 1.0),
        ("ASIN(0.5)", 30.0),
        ("ACOS(0.5)", 60.0),
        ("ATAN2(1, 1)", 45.0),
        ("ATAN2(-1, -1)", -135.0),
        ("SQRT(16)", 4.0),
        ("ABS(-2.5)", 2.5),
        ("POT(3)", 9),
        ("TRUNC(2.9)", 2),
        ("TRUNC(-2.9)", -2),
        ("ROUND(2.5)", 3),
        ("ROUND(-2.5)", -3),
        ("ROUND(2.49)", 2),
        ("ROUNDUP(2.1)", 3),
        ("ROUNDUP(-2.1)", -3),
        ("MIN(3, -1)", -1),
        ("MAX(3, -1)", 3),
        ("LN(EXP(2))", 2.0),
        ("$PI", math.pi),
    ],
)
def test_functions_work_in_degrees(text, expected):
    assert ev(text) == pytest.approx(expected, abs=1e-12)


def test_comparisons_use_relative_equality():
    # 4000 additions of 0.01 do not give exactly 40.0 in binary, the control still calls it equal
    acc = 0.0
    for _ in range(4000):
        acc += 0.01
    assert acc != 40.0
    assert ev("R1 >= 40", {1: acc}) is True
    assert ev("R1 == 40", {1: acc}) is True
    assert ev("R1 < 40", {1: acc}) is False
    # a real difference is still a difference
    assert ev("R1 < 40", {1: 40.0 - 1e-9}) is True
    assert ev("R1 == R2", {1: 1e-20, 2: 2e-20}) is False


@pytest.mark.parametrize(
    "text, kind",
    [
        ("1/0", "division_by_zero"),
        ("1 DIV 0", "division_by_zero"),
        ("1 MOD 0", "division_by_zero"),
        ("SQRT(-1)", "domain_error"),
        ("ASIN(2)", "domain_error"),
        ("LN(0)", "domain_error"),
        ("EXP(1000)", "domain_error"),
        ("TAN(90)", "domain_error"),
        ('"A" + 1', "type_error"),
        ("R[1000]", "index_range"),
        ("R[1.5]", "index_range"),
        ("1EX300*1EX300", "domain_error"),
        ("-1EX308-1EX308", "domain_error"),
        ("TRUNC(1EX300*1EX300)", "domain_error"),
    ],
)
def test_runtime_errors_have_stable_kinds(text, kind):
    with pytest.raises(EvalError) as exc:
        ev(text.replace("R1/", "R1/"), {1: 0.0})
    assert exc.value.kind == kind


@pytest.mark.parametrize(
    "text, kind",
    [
        ("FOO + 1", "undefined_variable"),
        ("SIN(1, 2)", "syntax"),
        ("(1 + 2", "syntax"),
        ("R1000", "index_range"),
        ("NOSUCHFN(1)", "unknown_word"),
        ("$AA_NO_SUCH_VARIABLE[X]", "unsupported"),
        ("$P_GG", "syntax"),                    # $P_GG takes a group number
    ],
)
def test_parse_errors_have_stable_kinds(text, kind):
    with pytest.raises(ParseError) as exc:
        ev(text)
    assert exc.value.kind == kind


def test_variables_and_arrays():
    assert ev("A*2 + B[1]", variables={"A": 1.5, "B": [0.0, 4.0]}) == 7.0
    with pytest.raises(EvalError) as exc:
        ev("B[2]", variables={"B": [0.0, 4.0]})
    assert exc.value.kind == "index_range"


def test_expressions_at_the_limits_evaluate_and_beyond_them_are_syntax_errors():
    """Nesting and chains that would exhaust Python's recursion (found by fuzzing: a
    RecursionError traceback) stop at vmach's limits with a syntax error at the expression;
    the deepest expressions within the limits still evaluate."""
    from interpreters.sinumerik.expr import MAX_DEPTH, MAX_NESTING

    n = MAX_NESTING - 2
    assert ev("(" * n + "1" + ")" * n) == 1
    assert ev("+".join(["1"] * (MAX_DEPTH - 1))) == MAX_DEPTH - 1
    assert ev("-" * (MAX_NESTING - 2) + "1") == 1                 # an even number of signs
    for text in ("(" * 5000 + "1" + ")" * 5000, "-" * 5000 + "1", "SIN(" * 3000 + "1" + ")" * 3000,
                 "+".join(["1"] * 200_000), "+".join(["1"] * (MAX_DEPTH + 1))):
        with pytest.raises(ParseError) as exc:
            ev(text)
        assert exc.value.kind == "syntax"
        assert exc.value.col <= 4 * MAX_NESTING + 1               # where the limit is passed, not at the end


@pytest.mark.parametrize("literal", ["9" * 400, "9" * 100_000, "1.5EX400", "1EX99999999",
                                     "'H" + "F" * 17 + "'", "1" + "0" * 309 + ".5"])
def test_number_literals_beyond_a_double_are_syntax_errors(literal):
    """A literal that is no finite double (a 100,000-digit integer raised ValueError from
    Python's int conversion limit; '9'*400 silently became inf) is a syntax error."""
    from vmach.errors import ProgramError

    with pytest.raises(ProgramError) as exc:
        tokenize(f"R1={literal}", SourceRef("t", 1, 1, f"R1={literal}"))
    assert exc.value.kind == "syntax"
    assert exc.value.source.column == 4
    assert tokenize("R1=" + "9" * 300, SourceRef("t", 1, 1, ""))[2].value == int("9" * 300)


def test_strings_and_arrays_beyond_vmachs_limits_are_resource_limit_errors(tmp_path):
    """Found by fuzzing: `S=S<<S` in a loop filled the memory (MemoryError traceback) and
    `DEF REAL A[1000,1000,1000]` ran for minutes building a billion elements."""
    from interpreters import sinumerik
    from interpreters.sinumerik.expr import MAX_ARRAY_ELEMENTS, MAX_STRING
    from vmach.machine import load_model

    control = load_model("turnmill").control
    cases = {
        "DEF STRING[100] S=\"AB\"\nFOR R1=1 TO 60\nS=S<<S\nENDFOR\nM30\n": 3,
        "DEF REAL A[1000,1000,1000]\nM30\n": 1,
        f"DEF INT B[{MAX_ARRAY_ELEMENTS + 1}]\nM30\n": 1,
    }
    for i, (text, line) in enumerate(cases.items()):
        path = tmp_path / f"P{i}.MPF"
        path.write_text(text)
        errors = [f for f in sinumerik.run(str(path), control).findings if f.severity == "error"]
        assert [(f.kind, f.line) for f in errors] == [("resource_limit", line)]
    assert len(ev('S << S', variables={"S": "x" * (MAX_STRING // 2)})) == MAX_STRING
    path = tmp_path / "OK.MPF"
    path.write_text(f"DEF INT B[{MAX_ARRAY_ELEMENTS // 1000},1000]\nB[999,999]=3\nM30\n")
    assert not [f for f in sinumerik.run(str(path), control).findings if f.severity == "error"]
