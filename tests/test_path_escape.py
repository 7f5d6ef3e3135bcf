"""Nothing is read from outside the program's directory (issue #30): every way a name could lead
out of it — ``..``, an absolute name, a link to a file or a directory outside, a chain of links,
a dangling link, a link loop — is refused in ``check`` and in ``run``, in both dialects, and the
file outside is never read (its moves never appear). What a setup file names must lie beside
it too (or be a bundled model by name): a vmach.toml comes with the program; files elsewhere are
the user's to give on the command line. Only a regular file is read, and anything else is an
error at its key."""

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


#: per dialect: (the subprogram file, the main program, its text calling that subprogram)
DIALECTS = {
    "rs274ngc": (rs274ngc, "evil.ngc", "main.ngc", "G0 X1\no<evil> call\nM2\n"),
    "sinumerik": (sinumerik, "EVIL.SPF", "MAIN.MPF", "G0 X1\nEVIL\nM30\n"),
}


@pytest.mark.parametrize("layout", ["link_to_file", "relative_link", "chain", "through_dir_link",
                                    "link_to_dir", "dangling", "loop"])
@pytest.mark.parametrize("dialect", sorted(DIALECTS))
def test_a_subprogram_file_leading_outside_is_refused(tmp_path, dialect, layout):
    module, sub, main_name, text = DIALECTS[dialect]
    prog = _layouts(tmp_path, sub)[layout] / main_name
    prog.write_text(text)
    result = module.run(prog, options=OPTIONS)
    assert OUTSIDE_X not in _xs(result)
    assert not result.completed
    assert [(f.kind, f.line) for f in result.findings if f.is_error] == [("subprogram_outside", 2)]
    if layout != "link_to_dir":                    # (Sinumerik's check lists only files)
        assert [(f.kind, f.line) for f in module.check(prog)] == [("subprogram_outside", 2)]


@pytest.mark.parametrize("dialect, call", [
    ("rs274ngc", "o<../elsewhere/evil> call"), ("rs274ngc", "o</etc/passwd> call"),
    ("rs274ngc", "o<..> call"), ("rs274ngc", "o<a/../../evil> call"),
    ("sinumerik", 'CALL "../elsewhere/EVIL"'), ("sinumerik", 'CALL "/etc/passwd"'),
    ("sinumerik", 'CALL "../EVIL"')])
def test_names_that_are_paths_are_refused(tmp_path, dialect, call):
    out = _outside(tmp_path)
    for f in out.iterdir():                        # ../EVIL.SPF and ../evil.ngc exist as well
        (tmp_path / f.name).write_bytes(f.read_bytes())
    module, _, main_name, text = DIALECTS[dialect]
    job = tmp_path / "job"
    job.mkdir()
    prog = job / main_name
    prog.write_text(text.replace("o<evil> call", call).replace("EVIL", call))
    result = module.run(prog, options=OPTIONS)
    assert OUTSIDE_X not in _xs(result)
    assert not result.completed
    assert [(f.kind, f.line) for f in result.findings if f.is_error] == [("subprogram_outside", 2)]
    assert [(f.kind, f.line) for f in module.check(prog) if f.is_error] == [("subprogram_outside", 2)]


def test_a_setup_file_that_is_a_link_leading_outside_is_refused(tmp_path, capsys):
    out = _outside(tmp_path)
    (out / "vmach.toml").write_text('machine = "turnmill"\n')
    job = tmp_path / "job"
    job.mkdir()
    os.symlink(Path("..") / "elsewhere" / "vmach.toml", job / "vmach.toml")
    prog = job / "P.MPF"
    prog.write_text("G0 X1\nM30\n")
    for command in ("check", "run"):
        assert main([command, str(prog)]) == 2
        assert f"{job / 'vmach.toml'}:1:1: error[setup]" in capsys.readouterr().err


def _setup_naming(tmp_path: Path, key: str, target) -> tuple[Path, Path]:
    """A job whose vmach.toml names ``target`` at ``key`` (line 2); (program, setup file)."""
    job = tmp_path / "job"
    job.mkdir(exist_ok=True)
    setup = job / "vmach.toml"
    setup.write_text(f'stock = "cylinder:d=30,l=60"\n{key} = "{target}"\n')
    prog = job / "P.MPF"
    prog.write_text("G0 X1\nM30\n")
    return prog, setup


@pytest.mark.parametrize("key", ["tools", "machine"])
@pytest.mark.parametrize("target", ["dir", "fifo", "loop", "dangling", "devnull"])
def test_setup_file_references_read_only_regular_files(tmp_path, capsys, key, target):
    """Whatever a setup file names — by ``..``, an absolute name or a link — is read only when
    it is a regular file: a directory, a pipe (which would block), a device, a link loop or a
    dangling link is an error at the key's line, exit 2, and nothing is opened."""
    out = _outside(tmp_path)
    job = tmp_path / "job"
    job.mkdir()
    names = {"dir": "../elsewhere", "devnull": "/dev/null", "fifo": "../elsewhere/pipe.toml",
             "loop": "loop.toml", "dangling": "gone.toml"}
    os.mkfifo(out / "pipe.toml")
    os.symlink("loop2.toml", job / "loop.toml")
    os.symlink("loop.toml", job / "loop2.toml")
    os.symlink(tmp_path / "nowhere.toml", job / "gone.toml")
    prog, setup = _setup_naming(tmp_path, key, names[target])
    assert main(["check", str(prog)]) == 2
    err = capsys.readouterr().err
    assert f"{setup}:2:1: error[" in err and "Traceback" not in err


@pytest.mark.parametrize("key", ["tools", "machine"])
@pytest.mark.parametrize("how", ["up", "absolute", "link", "link_to_dir"])
def test_setup_file_references_outside_are_refused_and_never_read(tmp_path, capsys, key, how):
    """A vmach.toml comes with the program, so what it names must lie beside it: a tool library
    or model reached by ``..``, an absolute name, a link to a file or through a linked
    directory is ``file_outside`` at its key, exit 2, in check, run and verify — and never read
    (the file outside is not TOML: reading it would be another error)."""
    out = _outside(tmp_path)
    (out / "lib.toml").write_text("this is [ not toml\n")
    job = tmp_path / "job"
    job.mkdir()
    os.symlink(out / "lib.toml", job / "lib.toml")
    os.symlink(out, job / "linked")
    names = {"up": "../elsewhere/lib.toml", "absolute": str(out / "lib.toml"), "link": "lib.toml",
             "link_to_dir": "linked/lib.toml"}
    prog, setup = _setup_naming(tmp_path, key, names[how])
    for command in ("check", "run", "verify"):
        assert main([command, str(prog)]) == 2
        err = capsys.readouterr().err
        assert f"{setup}:2:1: error[file_outside]" in err and "Traceback" not in err


def test_setup_file_references_beside_it_and_bundled_models_are_read(tmp_path, capsys):
    """A library in the program's directory (or below it) and a bundled model by name are read."""
    tools = Path(__file__).resolve().parents[1] / "fixtures" / "milling" / "tools.toml"
    job = tmp_path / "job"
    (job / "lib").mkdir(parents=True)
    (job / "lib" / "tools.toml").write_bytes(tools.read_bytes())
    prog, setup = _setup_naming(tmp_path, "tools", "lib/tools.toml")
    setup.write_text(setup.read_text() + 'machine = "s5d"\n')
    prog.write_text('T="EM10"\nD1\nG0 X1\nM30\n')
    assert main(["run", str(prog)]) == 0
    capsys.readouterr()


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
