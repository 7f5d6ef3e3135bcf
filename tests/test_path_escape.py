"""Nothing is read from outside the program's directory (issue #30): every way a name could lead
out of it — ``..``, an absolute name, a link to a file or a directory outside, a chain of links,
a dangling link, a link loop — is refused in ``check`` and in ``run``, in both dialects, and the
file outside is never read (its moves never appear). Names in a setup file are the user's
configuration (README, "Limits"): they may name a shared library anywhere, but only a regular
file is read, and anything else is an error at its key."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from interpreters import rs274ngc, sinumerik
from vmach.canon import RunOptions
from vmach.cli import main
from vmach.files import contained, leads_outside

OPTIONS = RunOptions(max_blocks=10_000)
#: X of the only move the file outside makes: found in a trace only if that file was run
OUTSIDE_X = 987.0


def _outside(tmp_path: Path) -> Path:
    """A directory beside the job's with the subprogram of both dialects in it."""
    out = tmp_path / "elsewhere"
    out.mkdir()
    (out / "EVIL.SPF").write_text(f"G0 X{OUTSIDE_X:g}\nM17\n")
    (out / "evil.ngc").write_text(f"o<evil> sub\nG0 X{OUTSIDE_X:g}\no<evil> endsub\n")
    return out


def _layouts(tmp_path: Path, sub: str):
    """(name, job directory) pairs: each job's ``sub`` (EVIL.SPF or evil.ngc) leads outside."""
    out = _outside(tmp_path)
    jobs = {}

    def job(name: str) -> Path:
        d = tmp_path / name
        d.mkdir()
        jobs[name] = d
        return d

    os.symlink(out / sub, job("link_to_file") / sub)                     # absolute target
    os.symlink(Path("..") / "elsewhere" / sub, job("relative_link") / sub)  # ../elsewhere/...
    d = job("chain")                                                      # two hops, then out
    os.symlink(Path("..") / "elsewhere" / sub, d / "hop2")
    os.symlink("hop2", d / "hop1")
    os.symlink("hop1", d / sub)
    d = job("through_dir_link")                                           # a dir link inside
    os.symlink(out, d / "lib")
    os.symlink(Path("lib") / sub, d / sub)
    os.symlink(out, job("link_to_dir") / sub)                             # the name is a dir
    os.symlink(tmp_path / "nowhere" / sub, job("dangling") / sub)
    d = job("loop")
    os.symlink("b", d / sub)
    os.symlink(sub, d / "b")
    return jobs


def _xs(result) -> list[float]:
    return [c.axes.get("X") for c in result.commands if hasattr(c, "axes")]


@pytest.mark.parametrize("layout", ["link_to_file", "relative_link", "chain", "through_dir_link",
                                    "link_to_dir", "dangling", "loop"])
def test_rs274_subroutine_file_leading_outside_is_refused(tmp_path, layout):
    job = _layouts(tmp_path, "evil.ngc")[layout]
    prog = job / "main.ngc"
    prog.write_text("G0 X1\no<evil> call\nM2\n")
    result = rs274ngc.run(prog, options=OPTIONS)
    assert OUTSIDE_X not in _xs(result)
    assert not result.completed
    assert [(f.kind, f.line) for f in result.findings if f.is_error] == [("subprogram_outside", 2)]
    assert [(f.kind, f.line) for f in rs274ngc.check(prog)] == [("subprogram_outside", 2)]


@pytest.mark.parametrize("layout", ["link_to_file", "relative_link", "chain", "through_dir_link",
                                    "dangling", "loop"])
def test_sinumerik_subprogram_leading_outside_is_refused(tmp_path, layout):
    job = _layouts(tmp_path, "EVIL.SPF")[layout]
    prog = job / "MAIN.MPF"
    prog.write_text("G0 X1\nEVIL\nM30\n")
    result = sinumerik.run(prog, options=OPTIONS)
    assert OUTSIDE_X not in _xs(result)
    assert [(f.kind, f.line) for f in result.findings if f.is_error] == [("subprogram_outside", 2)]
    assert [(f.kind, f.line) for f in sinumerik.check(prog)] == [("subprogram_outside", 2)]


def test_sinumerik_subprogram_name_that_is_a_directory_outside_is_not_read(tmp_path):
    job = _layouts(tmp_path, "EVIL.SPF")["link_to_dir"]
    prog = job / "MAIN.MPF"
    prog.write_text("G0 X1\nEVIL\nM30\n")
    result = sinumerik.run(prog, options=OPTIONS)
    assert OUTSIDE_X not in _xs(result)
    assert [(f.kind, f.line) for f in result.findings if f.is_error] == [("subprogram_outside", 2)]


@pytest.mark.parametrize("name", ["../elsewhere/evil", "/etc/passwd", "..", "a/../../evil"])
def test_rs274_names_that_are_paths_are_refused(tmp_path, name):
    _outside(tmp_path)
    job = tmp_path / "job"
    job.mkdir()
    prog = job / "main.ngc"
    prog.write_text(f"G0 X1\no<{name}> call\nM2\n")
    result = rs274ngc.run(prog, options=OPTIONS)
    assert OUTSIDE_X not in _xs(result)
    assert [(f.kind, f.line) for f in result.findings if f.is_error] == [("subprogram_outside", 2)]
    assert [(f.kind, f.line) for f in rs274ngc.check(prog)] == [("subprogram_outside", 2)]


@pytest.mark.parametrize("name", ['"../elsewhere/EVIL"', '"/etc/passwd"', '"../EVIL"'])
def test_sinumerik_names_that_are_paths_are_never_read(tmp_path, name):
    out = _outside(tmp_path)
    (tmp_path / "EVIL.SPF").write_text((out / "EVIL.SPF").read_text())
    job = tmp_path / "job"
    job.mkdir()
    prog = job / "MAIN.MPF"
    prog.write_text(f"G0 X1\nCALL {name}\nM30\n")
    result = sinumerik.run(prog, options=OPTIONS)
    assert OUTSIDE_X not in _xs(result)
    assert not result.completed
    assert [f.line for f in result.findings if f.is_error] == [2]
    assert [f.line for f in sinumerik.check(prog) if f.is_error] == [2]


def test_links_that_stay_inside_are_followed(tmp_path):
    """The same machinery lets a link within the directory work (a renamed subprogram)."""
    job = tmp_path / "job"
    (job / "lib").mkdir(parents=True)
    (job / "lib" / "real.ngc").write_text("o<part> sub\nG0 X5\no<part> endsub\n")
    os.symlink(Path("lib") / "real.ngc", job / "part.ngc")
    prog = job / "main.ngc"
    prog.write_text("o<part> call\nM2\n")
    result = rs274ngc.run(prog, options=OPTIONS)
    assert result.completed and 5.0 in _xs(result)
    assert rs274ngc.check(prog) == []


@pytest.mark.parametrize("command", ["check", "run"])
def test_cli_refuses_with_exit_1_and_the_place(tmp_path, command, capsys):
    job = _layouts(tmp_path, "evil.ngc")["chain"]
    prog = job / "main.ngc"
    prog.write_text("G0 X1\no<evil> call\nM2\n")
    assert main([command, str(prog)]) == 1
    captured = capsys.readouterr()
    assert f"{prog}:2:1: error[subprogram_outside]" in captured.out + captured.err
    assert f"{OUTSIDE_X:g}" not in captured.out


def test_contained_and_leads_outside(tmp_path):
    jobs = _layouts(tmp_path, "evil.ngc")
    for name in ("link_to_file", "chain", "through_dir_link", "dangling", "loop"):
        assert leads_outside(jobs[name] / "evil.ngc", jobs[name]), name
    inside = jobs["chain"] / "plain.ngc"
    inside.write_text("M2\n")
    assert contained(inside, jobs["chain"]) and not leads_outside(inside, jobs["chain"])
    assert not leads_outside(jobs["chain"] / "missing.ngc", jobs["chain"])
