"""Regenerate the golden traces of ``fixtures/rs274ngc`` with LinuxCNC's ``rs274``.

Usage (from the repository root, with Debian's ``linuxcnc-uspace`` installed)::

    python tests/rs274ngc/regen.py            # every program
    python tests/rs274ngc/regen.py arcs_r_form tools_table

For each program ``NAME.ngc`` (files named ``lib_*.ngc`` are subroutine files, not programs)
this runs, in the fixture directory and with a fresh empty ``HOME``::

    rs274 -g [-t NAME.tbl] [-i NAME.ini] [-v COPY] [OPTIONS] NAME.ngc > NAME.expected 2> NAME.stderr

``NAME.tbl`` (a tool table) and ``NAME.ini`` (an INI file) are passed when they exist;
``NAME.var`` (a parameter file) is copied to a temporary directory and the copy passed, and
the file rs274 leaves there is kept as ``NAME.var.out``; ``NAME.opts`` holds further rs274
options (``-n 0``, ``-b``). ``NAME.stderr`` is kept when rs274 exits with an error or
printed errors (``-n 0``); it then holds rs274's messages, each followed by the offending
line. The golden tests compare vmach against these files and do not need rs274.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "rs274ngc"


def programs() -> list[Path]:
    return sorted(p for p in FIXTURES.glob("*.ngc") if not p.name.startswith("lib_"))


def regenerate(program: Path) -> int:
    home = tempfile.mkdtemp(prefix="rs274-home-")
    try:
        cmd = ["rs274", "-g"]
        table = program.with_suffix(".tbl")
        if table.exists():
            cmd += ["-t", table.name]
        ini = program.with_suffix(".ini")
        if ini.exists():
            cmd += ["-i", ini.name]
        var = program.with_suffix(".var")
        copy = Path(home) / var.name
        if var.exists():
            shutil.copyfile(var, copy)
            cmd += ["-v", str(copy)]
        opts = program.with_suffix(".opts")
        if opts.exists():
            cmd += opts.read_text(encoding="utf-8").split()
        cmd.append(program.name)
        proc = subprocess.run(cmd, cwd=FIXTURES, env={**os.environ, "HOME": home},
                              capture_output=True, text=True, check=False)
        if var.exists():
            shutil.copyfile(copy, program.with_suffix(".var.out"))
    finally:
        shutil.rmtree(home, ignore_errors=True)
    program.with_suffix(".expected").write_text(proc.stdout, encoding="utf-8")
    stderr = program.with_suffix(".stderr")
    if proc.returncode != 0 or proc.stderr.strip() != "executing":
        stderr.write_text(proc.stderr, encoding="utf-8")
    elif stderr.exists():
        stderr.unlink()
    return proc.returncode


def main(argv: list[str]) -> int:
    if shutil.which("rs274") is None:
        sys.stderr.write("regen.py: rs274 not found (Debian package linuxcnc-uspace)\n")
        return 2
    wanted = set(argv)
    for program in programs():
        if wanted and program.stem not in wanted:
            continue
        rc = regenerate(program)
        print(f"{program.name}: exit {rc}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
