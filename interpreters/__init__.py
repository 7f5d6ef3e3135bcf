"""NC dialects. Each dialect depends only on ``vmach.canon``, ``vmach.source``, ``vmach.errors``
and ``vmach.findings``; everything downstream sees only canonical commands.

A dialect module exposes::

    EXTENSIONS : tuple of str          lower-case file extensions it reads
    check(path, control) -> list[Finding]
    run(path, control, options) -> RunResult

The registry below is a plain dict from extension to module name (imported on first use).
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path
from types import ModuleType

from vmach.errors import InputError

DIALECTS: dict[str, str] = {
    ".mpf": "interpreters.sinumerik",
    ".spf": "interpreters.sinumerik",
    ".arc": "interpreters.sinumerik",
    ".ngc": "interpreters.rs274ngc",
    ".nc": "interpreters.rs274ngc",
    ".tap": "interpreters.rs274ngc",
}

NAMES: dict[str, str] = {
    "sinumerik": "interpreters.sinumerik",
    "rs274ngc": "interpreters.rs274ngc",
}


#: a program named as a Sinumerik control's file system names it (``_N_PART_MPF``, ``_N_L100_SPF``),
#: as copied from the control without an extension
CONTROL_FILE = re.compile(r"^_N_\w+_(?:MPF|SPF)$", re.IGNORECASE)

#: extensions several controls use: the machine's dialect decides when it declares one
GENERIC = frozenset({".nc", ".tap"})


def dialect_for(path: str | Path, name: str | None = None, machine: str | None = None) -> ModuleType:
    """The dialect module for ``path``: the explicit ``name`` (``--dialect``); else the
    extension when only one dialect uses it (``.mpf``, ``.ngc``); else the ``machine``'s
    declared dialect (``control.dialect`` of its model); else the extension's usual one."""
    if name is not None:
        if name not in NAMES:
            raise InputError(f"unknown dialect {name!r}; known: {', '.join(sorted(NAMES))}")
        return importlib.import_module(NAMES[name])
    ext = Path(path).suffix.lower()
    if ext not in DIALECTS and CONTROL_FILE.match(Path(path).name):
        return importlib.import_module(NAMES["sinumerik"])   # _N_NAME_MPF: a Sinumerik control's file
    if machine in NAMES and (ext in GENERIC or ext not in DIALECTS):
        return importlib.import_module(NAMES[machine])
    if ext not in DIALECTS:
        raise InputError(
            f"{path}: cannot tell the dialect from the extension {ext!r}; "
            f"use --dialect ({', '.join(sorted(NAMES))})"
        )
    return importlib.import_module(DIALECTS[ext])
