"""The limits of issue #30 defect 6 stop a runaway program (how fast: benchmarks/limits.py,
not timed here): a loop without motion at ``--max-blocks`` (3,000,000 by default, well above the
busiest real program's 1.2 million), a loop that moves at ``tol.max_commands`` canonical
commands, and ``--max-blocks`` itself is held below a ceiling (a huge value turned it off)."""

from __future__ import annotations

from dataclasses import replace

import pytest

from interpreters import rs274ngc, sinumerik
from vmach import canon
from vmach.canon import CommandList, RunOptions
from vmach.cli import main
from vmach.tol import tol

LOOPS = [
    ("loop.ngc", rs274ngc, "#1=0\no100 while [1]\n#1=[#1+1]\no100 endwhile\nM2\n", 3),
    ("GOTO.MPF", sinumerik, "N10 R1=R1+1\nN20 GOTOB N10\nM30\n", None),
    ("WHILE.MPF", sinumerik, "WHILE 1\nR1=R1+1\nENDWHILE\nM30\n", None),
]


def test_the_default_block_limit_stays_above_real_programs_and_below_the_ceiling():
    assert 1_200_000 < tol.max_blocks <= tol.max_blocks_ceiling
    assert RunOptions().max_blocks == tol.max_blocks


@pytest.mark.parametrize("name, dialect, text, line", LOOPS)
def test_an_endless_loop_stops_at_the_block_limit_with_its_place(tmp_path, name, dialect, text, line):
    p = tmp_path / name
    p.write_text(text)
    result = dialect.run(p, options=RunOptions(max_blocks=20_000))
    assert not result.completed
    errors = [f for f in result.findings if f.is_error]
    assert [f.kind for f in errors] == ["block_limit"] and errors[0].line in (1, 2, 3)
    assert "--max-blocks" in errors[0].message     # says how to raise it


@pytest.mark.parametrize("name, dialect, text", [
    ("g81.ngc", rs274ngc, "G90 G0 X0 Y0 Z10\nG91 G81 X1 Z-1 R1 F100 L1000000000\nM2\n"),
    ("move.ngc", rs274ngc, "o100 while [1]\nG0 X1\nG0 X0\no100 endwhile\nM2\n"),
    ("MOVE.MPF", sinumerik, "LBL: G0 X1\nG0 X0\nR1=R1+1\nGOTOB LBL\nM30\n"),
])
def test_a_loop_that_moves_stops_at_the_command_limit_with_its_place(tmp_path, monkeypatch, name,
                                                                       dialect, text):
    monkeypatch.setattr(canon, "tol", replace(tol, max_commands=5_000))
    p = tmp_path / name
    p.write_text(text)
    result = dialect.run(p, options=RunOptions(max_blocks=tol.max_blocks_ceiling))
    assert not result.completed
    errors = [f for f in result.findings if f.is_error]
    assert [f.kind for f in errors] == ["resource_limit"] and errors[0].line in (1, 2, 3)
    assert len(result.commands) == 5_000


def test_the_command_list_refuses_one_more_at_that_commands_place():
    cmds = CommandList(2)
    src = canon.SourceRef("P.MPF", 7)
    cmds.append(canon.ProgramEnd(src, code="M30"))
    cmds.extend([canon.ProgramEnd(src, code="M30")])
    with pytest.raises(canon.ProgramError) as err:
        cmds.append(canon.ProgramEnd(src, code="M30"))
    assert (err.value.kind, err.value.source.line, len(cmds)) == ("resource_limit", 7, 2)


@pytest.mark.parametrize("value", [str(tol.max_blocks_ceiling + 1), str(10**30), "0", "-5"])
@pytest.mark.parametrize("command", ["run", "verify"])
def test_max_blocks_beyond_the_ceiling_is_a_usage_error(tmp_path, capsys, command, value):
    p = tmp_path / "P.MPF"
    p.write_text("G0 X1\nM30\n")
    extra = (["--machine", "turnmill", "--no-images", "--out", str(tmp_path / "o")]
             if command == "verify" else [])
    assert main([command, str(p), f"--max-blocks={value}", *extra]) == 2
    assert "error[usage]" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()
