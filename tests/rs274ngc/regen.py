"""Regenerate the golden traces of ``fixtures/rs274ngc`` with LinuxCNC's ``rs274``.

Usage (from the repository root, with Debian's ``linuxcnc-uspace`` installed)::

    python tests/rs274ngc/regen.py            # every program
    python tests/rs274ngc/regen.py arcs_r_form tools_table

For each program ``NAME.ngc`` (files named ``lib_*.ngc`` are subroutine files, not programs)
this runs, in the fixture directory and with a fresh empty ``HOME``::

    rs274 -g [-t NAME.tbl] NAME.ngc > NAME.expected 2> NAME.stderr

``NAME.tbl`` is passed when it exists. ``NAME.stderr`` is kept only when rs274 exits with an
error; it then holds rs274's message and the offending line. The golden tests compare vmach
against these files and do not need rs274.
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
        cmd.append(program.name)
        proc = subprocess.run(cmd, cwd=FIXTURES, env={**os.environ, "HOME": home},
                              capture_output=True, text=True, check=False)
    finally:
        shutil.rmtree(home, ignore_errors=True)
    program.with_suffix(".expected").write_text(proc.stdout, encoding="utf-8")
    stderr = program.with_suffix(".stderr")
    if proc.returncode != 0:
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
