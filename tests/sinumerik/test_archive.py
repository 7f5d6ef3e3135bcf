"""Programs in punched-tape format (Operating Manual, "Formats for saving and importing data":
``%_N_NAME_MPF`` first, ``;$PATH=…``), and archives holding several files."""

from __future__ import annotations

from nc import check, moves, ok

from interpreters.sinumerik.archive import header, sections

ARCHIVE = """%_N_PART_MPF
;$PATH=/_N_WKS_DIR/_N_PART_WPD
G0 X1
SUB1(5)
M30
%_N_SUB1_SPF
;$PATH=/_N_WKS_DIR/_N_PART_WPD
PROC SUB1(REAL A)
G0 X=A
M17
%_N_UGUD_DEF
DEF NCK REAL GX
"""


def test_headers():
    assert header("%_N_PART_MPF") == ("PART", "MPF")
    assert header("%_N_MY_PART_2_SPF") == ("MY_PART_2", "SPF")
    assert header("%Flange3_MPF") == ("FLANGE3", "MPF")
    assert header("%") == ("", "") and header("G0 X1") is None
    secs = sections(ARCHIVE)
    assert [(s.name, s.kind, s.line) for s in secs] == [
        ("PART", "MPF", 1), ("SUB1", "SPF", 6), ("UGUD", "DEF", 11)]
    assert secs[1].text.splitlines()[8] == "G0 X=A" and secs[1].text.splitlines()[2] == ""


def test_an_archive_runs_its_first_program_and_calls_the_others(tmp_path):
    r = ok(tmp_path, ARCHIVE, name="PART.ARC")
    assert [(m.axes["X"], m.source.line) for m in moves(r)] == [(1.0, 3), (5.0, 9)]
    assert check(tmp_path, ARCHIVE, name="PART.ARC") == []     # its GUD section is read (definitions.py)
    other = ARCHIVE + "%_N_PART_JOB\n;a job list\n"
    notes = [(f.kind, f.line, f.severity) for f in check(tmp_path, other, name="PART.ARC")]
    assert notes == [("archive_section", 13, "info")]


def test_a_program_saved_with_its_header_reads_as_without(tmp_path):
    r = ok(tmp_path, "%_N_PART_MPF\n;$PATH=/_N_MPF_DIR\nG0 X1\nM30\n")
    assert [(m.axes["X"], m.source.line) for m in moves(r)] == [(1.0, 3)]
    assert check(tmp_path, "%\nG0 X1\nM30\n") == []


def test_check_reads_every_program_of_an_archive(tmp_path):
    text = ARCHIVE.replace("G0 X=A\n", "G0 X=A Q5\nNOPE\n")
    found = [(f.kind, f.line) for f in check(tmp_path, text, name="PART.ARC") if f.severity == "error"]
    assert found == [("unknown_word", 9), ("unknown_cycle", 10)]
