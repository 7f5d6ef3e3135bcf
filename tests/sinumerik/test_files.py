"""The control's file commands (Job planning, "Writing, reading and deleting a file") act on an
in-memory sandbox that starts empty: never on the disk, reported as info."""

from __future__ import annotations

from nc import error_of, moves, ok, run

from vmach.canon import Message


def test_write_read_delete_isfile_filedate_on_the_sandbox(tmp_path):
    (tmp_path / "LOG").write_text("ON DISK\n")          # the disk is never read
    text = """DEF INT ERR, E2, E3
DEF STRING[40] LINES[3], DATE
DEF BOOL BEFORE, AFTER
BEFORE=ISFILE("LOG")
WRITE(ERR, "LOG", "FIRST")
WRITE(ERR, "log", "SECOND")
READ(ERR, "LOG", 1, 2, LINES)
FILEDATE(ERR, "LOG", DATE)
MSG(LINES[0] << "," << LINES[1] << "," << DATE)
READ(E2, "LOG", 2, 5, LINES)
DELETE(ERR, "LOG")
DELETE(E3, "LOG")
AFTER=ISFILE("LOG")
G0 X=ERR Y=E2 Z=E3
IF BEFORE OR AFTER
G0 X99
ENDIF
M30
"""
    r = ok(tmp_path, text)
    assert [c.text for c in r.commands if isinstance(c, Message)] == ["FIRST,SECOND,01.01.00"]
    # codes: 0 done, 4 lines outside the file, 3 no such file
    assert [(m.axes["X"], m.axes["Y"], m.axes["Z"]) for m in moves(r)] == [(0.0, 4.0, 3.0)]
    notes = {f.data["command"]: (f.line, f.data["count"]) for f in r.findings if f.kind == "file_sandbox"}
    assert notes == {'WRITE "LOG"': (5, 2), 'READ "LOG"': (7, 2), 'FILEDATE "LOG"': (8, 1),
                     'DELETE "LOG"': (11, 2)}
    assert (tmp_path / "LOG").read_text() == "ON DISK\n"


def test_a_file_command_needs_a_variable_for_its_result(tmp_path):
    f = error_of(run(tmp_path, 'WRITE(1, "LOG", "X")\nM30\n'))
    assert (f.kind, f.line) == ("syntax", 1)
