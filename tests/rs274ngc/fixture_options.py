"""The rs274 options of a golden program (``fixtures/rs274ngc``), as regen.py gave them."""

from __future__ import annotations

import shutil
from pathlib import Path

_OPTIONS = {"-b": "block_delete", "-n0": "continue_after_error"}


def fixture_options(program: Path, tmp: Path, update: bool = True) -> dict:
    """The rs274 options regen.py gave ``program`` as the dialect's options: the tool table,
    INI file, a copy (in ``tmp``) of the parameter file, updated in place with ``update``
    as rs274 does, and the options of ``NAME.opts``."""
    extra: dict = {}
    table = program.with_suffix(".tbl")
    if table.exists():
        extra["tool_table"] = table.name
    ini = program.with_suffix(".ini")
    if ini.exists():
        extra["ini"] = ini.name
    var = program.with_suffix(".var")
    if var.exists():
        shutil.copyfile(var, tmp / var.name)
        extra.update(var_file=str(tmp / var.name), var_file_update=update)
    opts = program.with_suffix(".opts")
    if opts.exists():
        for word in opts.read_text(encoding="utf-8").replace("-n 0", "-n0").split():
            extra[_OPTIONS[word]] = True
    return extra
