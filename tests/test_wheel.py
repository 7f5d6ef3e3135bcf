"""Packaging (issue 31): a wheel built with ``pip wheel .`` and installed in a fresh venv runs
every README command that names real files — from a folder that holds only a copy of
``fixtures/``, so that the bundled models come from the wheel and nothing from the checkout.

The fresh venv gets the wheel alone (``--no-deps``); its dependencies are the test
interpreter's own (a ``.pth`` line adds that site-packages, whose editable ``vmach`` hook is not
run from there) and ``pip check`` holds them to what the wheel declares.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import site
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest
from catalog import ROOT

pytestmark = pytest.mark.slow

#: words that stand for something the reader supplies
PLACEHOLDER = re.compile(r"PROG|FILE|MODEL|DIR\b|…|\.\.\.|\[|\||<|=x|=…")


#: commands whose first argument is a program file
PROGRAM_COMMANDS = ("check", "run", "verify", "postcheck")


def readme_commands() -> list[list[str]]:
    """Every ``vmach ...`` command README shows (code spans and indented lines) whose words
    are real: no placeholder, and a program it names exists in the checkout."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    found = re.findall(r"`(vmach [^`]+)`", text)
    found += [m.split("&&")[-1].strip() for m in re.findall(r"^    (.*vmach [^\n]+)$", text, re.M)]
    out: list[list[str]] = []
    for cmd in found:
        if PLACEHOLDER.search(cmd):
            continue
        argv = shlex.split(cmd)
        if argv[1] in PROGRAM_COMMANDS and not (len(argv) > 2 and (ROOT / argv[2]).is_file()):
            continue            # an example of the form (`vmach verify prog.mpf`), not a file here
        if argv not in out:
            out.append(argv)
    return out


def test_readme_names_runnable_commands():
    cmds = readme_commands()
    assert ["vmach", "verify", "fixtures/polygon_shaft/POLY50.MPF", "--out", "out/poly50"] in cmds
    assert ["vmach", "machines"] in cmds


def test_the_wheel_installed_in_a_fresh_venv_runs_every_readme_command(tmp_path):
    wheels = tmp_path / "wheels"
    src = tmp_path / "src"        # built from a copy: setuptools leaves build/ in the tree it builds
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(
        ".git", ".venv*", "build", "dist", "out", "*.egg-info", "__pycache__", ".*_cache", ".hypothesis"))
    build = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(wheels),
                            str(src)], capture_output=True, text=True, timeout=600)
    assert build.returncode == 0, build.stderr[-3000:]
    (wheel,) = wheels.glob("vmach-*.whl")
    # every data file of the packages is in it (the P3G size table, the dialects' language
    # files, report.html's scripts), and the models under vmach/models
    inside = set(zipfile.ZipFile(wheel).namelist())
    files = [p for top in ("vmach", "interpreters") for p in (ROOT / top).rglob("*") if p.is_file()]
    data = {p.relative_to(ROOT).as_posix() for p in files
            if p.suffix not in (".py", ".pyc") and "__pycache__" not in p.parts}
    assert data and data <= inside, sorted(data - inside)
    assert {f"vmach/models/{p.name}" for p in (ROOT / "models").glob("*.toml")} <= inside
    # the demo's program, its subprogram, tools and settings (vmach demo without a checkout)
    assert {f"vmach/examples/polygon_shaft/{n}" for n in ("POLY.MPF", "P3G_SHAFT.SPF", "tools.toml",
                                                          "vmach.toml")} <= inside
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    py = env_dir / "bin" / "python"
    purelib = subprocess.run([py, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                             capture_output=True, text=True, check=True).stdout.strip()
    ours = [p for p in site.getsitepackages() if Path(p, "numpy").is_dir()]
    Path(purelib, "vmach_test_deps.pth").write_text("\n".join(ours) + "\n")
    inst = subprocess.run([py, "-m", "pip", "install", "-q", "--no-deps", str(wheel)],
                          capture_output=True, text=True, timeout=600)
    assert inst.returncode == 0, inst.stderr[-3000:]
    check = subprocess.run([py, "-m", "pip", "check"], capture_output=True, text=True)
    assert "vmach" not in check.stdout, check.stdout       # its declared dependencies are there

    work = tmp_path / "work"                 # a copy of the fixtures, and nothing of the checkout
    shutil.copytree(ROOT / "fixtures", work / "fixtures")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    probe = "import vmach, vmach.bundled as b; print(vmach.__file__, b.MODELS_DIR)"
    where = subprocess.run([py, "-c", probe], cwd=work, capture_output=True, text=True, env=env,
                           check=True).stdout.split()
    assert all(Path(w).is_relative_to(env_dir) for w in where), where
    exe = env_dir / "bin" / "vmach"
    cmds = readme_commands()
    assert len(cmds) >= 4
    done: set[str] = set()
    for argv in cmds:
        if argv[1] == "verify" and argv[2] in done:
            continue                  # the same program again with other options: once is enough
        done.add(argv[2] if len(argv) > 2 else "")
        res = subprocess.run([str(exe), *argv[1:]], cwd=work, capture_output=True, text=True, env=env,
                             timeout=900)
        assert res.returncode in (0, 1), (argv, res.returncode, res.stderr[-2000:])
        assert "Traceback" not in res.stderr, (argv, res.stderr[-2000:])
        if argv[1] == "verify":
            out = [argv[i + 1] for i, a in enumerate(argv) if a == "--out"]
            folder = work / (out[0] if out else Path("out") / Path(argv[2]).stem)
            assert (folder / "report.json").is_file(), argv
        if argv[1] == "machines":
            assert "turnmill" in res.stdout and str(env_dir) in res.stdout

    # the instructor's demo from the wheel alone, in a folder without any fixture
    bare = tmp_path / "bare"
    bare.mkdir()
    res = subprocess.run([str(exe), "demo", "polygon-shaft", "--size", "14", "--frames", "2", "--out", "d"],
                         cwd=bare, capture_output=True, text=True, env=env, timeout=900)
    assert res.returncode == 0, res.stderr[-2000:]
    assert "Traceback" not in res.stderr
    assert (bare / "d" / "demo.html").is_file() and (bare / "d" / "cut_P3G_014.gif").stat().st_size > 0
