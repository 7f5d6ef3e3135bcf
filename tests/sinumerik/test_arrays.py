"""Arrays as the Programming Manual (Job planning, "Array definition and initialization")
describes them: SET with empty places, REP, row order (the last index fastest), fills from an
element on, and arrays passed to a PROC's array parameter by reference."""

from __future__ import annotations

import pytest
from nc import check, error_of, moves, ok, run


def xs(result) -> list[float]:
    return [m.axes["X"] for m in moves(result)]


def show(cells: str) -> str:
    """Blocks that move X to each of ``cells`` (``A[0,1]`` …) in turn."""
    return "".join(f"G0 X={c}\n" for c in cells.split())


def test_set_fills_in_row_order_and_skips_empty_places(tmp_path):
    text = "DEF REAL F[3,2]=SET(1,,3,4)\n" + show("F[0,0] F[0,1] F[1,0] F[1,1] F[2,0]") + "M30\n"
    assert xs(ok(tmp_path, text)) == [1.0, 0.0, 3.0, 4.0, 0.0]


def test_rep_fills_a_count_or_the_rest(tmp_path):
    text = ("DEF INT G[2,3,4]=REP(7,23)\nDEF REAL H[3]=REP(2.5)\n"
            + show("G[0,0,0] G[1,2,2] G[1,2,3] H[2]") + "M30\n")
    assert xs(ok(tmp_path, text)) == [7.0, 7.0, 0.0, 2.5]


def test_set_and_rep_assign_from_an_element_on(tmp_path):
    text = ("DEF REAL F[3,2]\nDEF REAL V[5]\nR1=2\nF[1,1]=SET(5,,7)\nV[R1]=REP(9,3)\nV[0]=SET(1)\n"
            + show("F[1,1] F[2,0] F[2,1] V[0] V[1] V[2] V[4]") + "M30\n")
    assert xs(ok(tmp_path, text)) == [5.0, 0.0, 7.0, 1.0, 0.0, 9.0, 9.0]


@pytest.mark.parametrize("text", [
    "DEF REAL F[2,2]=SET(1,2,3,4,5)\nM30\n",
    "DEF REAL F[2,2]\nF[1,1]=SET(1,2)\nM30\n",
])
def test_more_values_than_elements_is_index_range(tmp_path, text):
    assert [f.kind for f in check(tmp_path, text)] == ["index_range"]


def test_an_array_is_passed_by_reference(tmp_path):
    sub = "PROC FILL(VAR REAL A[3], REAL V)\nA[1]=V\nA[2]=A[0]+V\nM17\n"
    text = "DEF REAL F[3]=SET(1,2,3)\nFILL(F, 10)\n" + show("F[0] F[1] F[2]") + "M30\n"
    assert xs(ok(tmp_path, text, FILL_DOT_SPF=sub)) == [1.0, 10.0, 11.0]
    # an array where a value is expected, or the wrong size, is a type error at the call
    f = error_of(run(tmp_path, "DEF REAL F[4]\nFILL(F, 1)\nM30\n", FILL_DOT_SPF=sub))
    assert (f.kind, f.line) == ("type_error", 2)
    f = error_of(run(tmp_path, "DEF REAL F[3]\nFILL(1, F)\nM30\n", FILL_DOT_SPF=sub))
    assert (f.kind, f.line) == ("type_error", 2)


def test_rep_to_the_end_from_a_computed_element_is_unsupported(tmp_path):
    text = "DEF REAL V[5]\nR1=2\nV[R1]=REP(9)\nM30\n"
    assert [(f.kind, f.line) for f in check(tmp_path, text)] == [("unsupported", 3)]
