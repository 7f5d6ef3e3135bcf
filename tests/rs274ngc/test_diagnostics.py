"""Diagnostics: stable kinds, the line and column they point at, static ``check``."""

from __future__ import annotations

import pytest

from interpreters.rs274ngc import check, run


def _error(tmp_path, text: str):
    path = tmp_path / "prog.ngc"
    path.write_text(text, encoding="utf-8")
    result = run(path)
    assert not result.completed
    f = result.findings[-1]
    return f.kind, f.line, f.source.column


RUNTIME = [
    ("G0 X1\nG0 G1 X2\nM2\n", ("modal_group_conflict", 2, 4)),
    ("G0 X1\nG1 X2\nM2\n", ("g1_zero_feed", 2, 1)),
    ("G21 F10\nG0 X0\nG2 X10 I4\nM2\n", ("arc_radius_mismatch", 3, 1)),
    ("G0 X1 X2\nM2\n", ("duplicate_word", 1, 7)),
    ("G0 X[1/0]\nM2\n", ("divide_by_zero", 1, 5)),
    ("#1 = 2\nG0 X[#1 + SQRT[-#1]]\nM2\n", ("sqrt_range", 2, 11)),
    ("G0 X#<nope>\nM2\n", ("undefined_parameter", 1, 5)),
    ("G0 X1\nG0 Y2 &\nM2\n", ("bad_character", 2, 7)),
    ("G0 X1\n(nested (comment))\nM2\n", ("nested_comment", 2, 9)),
    ("G0 X1\nG0 X1.2.3\nM2\n", ("bad_number_trailing", 2, 5)),
    ("G7.7 X1\nM2\n", ("unknown_g_code", 1, 1)),
    ("M123\nM2\n", ("unknown_m_code", 1, 1)),
    ("G0 X1\n", ("file_ended", 1, 1)),
    ("%\nG0 X1\n", ("file_ended_percent", 2, 1)),
    ("X1\nM2\n", ("axis_words_unused", 1, 1)),
    ("G96 S100\nM2\n", ("unsupported", 1, 1)),
    ("G20 T1 M6\nG41\nG1 X0.01 F1\nM2\n", ("comp_entry_short", 3, 1)),
    ("G20 T1 M6\nG41 G1 X1 F1\nG55\nM2\n", ("comp_coord_system", 3, 1)),
    ("T42 M6\nM2\n", ("tool_not_found", 1, 1)),
    ("o<missing> call\nM2\n", ("seeking_o_word", 2, 1)),
    ("o1 endsub\nM2\n", ("not_in_sub", 1, 1)),
    ("o1 if [1]\no1 endwhile\nM2\n", ("no_matching_label", 2, 1)),
    ("G81 X1 Y1 Z-1 R2 F10\nG81 X2 R-2\nM2\n", ("cycle_r_below_bottom", 2, 1)),
    ("#5401 = 1\nM2\n", ("parameter_readonly", 1, 1)),
    ("G0 X1\nG10 L2 P10 X1\nM2\n", ("g10_p_range", 2, 1)),
    # the elseif of a false if is read (its condition evaluated) while skipping to it
    ("o1 if [0]\no1 elseif [SQRT[-3]]\no1 endif\nM2\n", ("sqrt_range", 2, 12)),
    ("o1 if [1]\no1 elseif [1/0]\no1 endif\nM2\n", ("divide_by_zero", 2, 11)),
    ("o1 sub\no1 endsub [1/0]\nM2\n", ("divide_by_zero", 2, 11)),
    # constants fold in reading order: the non-constant ACOS fails first
    ("#1 = 4\n#2 = [1 LT ACOS[#1] XOR LN[0]]\nM2\n", ("acos_range", 2, 12)),
    ("#1 = [1/0 + SQRT[-1]]\nM2\n", ("divide_by_zero", 1, 6)),
    ("o1 if [1]\no1 endif junk\nM2\n", ("text_after_o_word", 2, 10)),
]


@pytest.mark.parametrize("text,expected", RUNTIME, ids=[e[0] for _, e in RUNTIME])
def test_runtime_error_kind_line_column(tmp_path, text, expected):
    assert _error(tmp_path, text) == expected


def test_error_renders_with_caret(tmp_path):
    path = tmp_path / "prog.ngc"
    path.write_text("G0 X1\nG0 Y2 &\nM2\n", encoding="utf-8")
    text = run(path).findings[-1].render()
    assert text.splitlines() == [
        f"{path}:2:7: error[bad_character]: Bad character '&' used",
        "    G0 Y2 &",
        "          ^",
    ]


def test_unreadable_file_is_a_finding(tmp_path):
    result = run(tmp_path / "absent.ngc")
    assert not result.completed
    assert result.findings[-1].kind == "unreadable"


# -- static check ---------------------------------------------------------------------------


def _check(tmp_path, text: str, name: str = "prog.ngc"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return [(f.kind, f.line, f.source.column if f.source else None) for f in check(path)]


def test_check_clean_program(tmp_path):
    text = "o<s> sub\nG0 X#1\no<s> endsub\no1 if [1]\no<s> call [2]\no1 endif\nM2\n"
    assert _check(tmp_path, text) == []


def test_check_reports_every_syntax_error(tmp_path):
    text = "G0 X1 &\n(open comment\nG0 X[1 + ]\nG1 X1 X2\nG7.7\nM2\n"
    assert _check(tmp_path, text) == [
        ("bad_character", 1, 7),
        ("unclosed_comment", 2, 1),
        ("bad_number", 3, 10),
        ("duplicate_word", 4, 7),
        ("unknown_g_code", 5, 1),
    ]


def test_check_structure(tmp_path):
    text = "o1 if [1]\no2 while [1]\no1 endif\no3 endwhile\no<nowhere> call\nM2\n"
    kinds = _check(tmp_path, text)
    assert ("unmatched_o_word", 3, 1) in kinds
    assert ("unclosed_o_block", 1, 1) in kinds
    assert ("undefined_sub", 5, 1) in kinds


def test_check_finds_subroutine_file_beside_program(tmp_path):
    (tmp_path / "lib_x.ngc").write_text("o<lib_x> sub\no<lib_x> endsub\n")
    assert _check(tmp_path, "o<lib_x> call\nM2\n") == []


def test_check_missing_end_and_unsupported(tmp_path):
    assert _check(tmp_path, "G0 X1\nG17.1\n") == [
        ("unsupported", 2, 1),
    ]
    assert _check(tmp_path, "G0 X1\n", "b.ngc") == [("file_ended", 1, 1)]
    assert _check(tmp_path, "%\nG0 X1\n%\n", "c.ngc") == []


def test_check_break_and_else_need_the_right_structure(tmp_path):
    text = ("o1 repeat [2]\n  o1 break\no1 endrepeat\n"
            "o2 while [0]\n  o2 else\no2 endwhile\n"
            "o3 do\n  o3 continue\no3 while [0]\nM2\n")
    assert _check(tmp_path, text) == [
        ("no_matching_loop_label", 2, 3),
        ("unmatched_o_word", 5, 3),
    ]
