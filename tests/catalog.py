"""One catalogue of named machines, tools, stocks and programs shared by all tests."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"
FIXTURES = ROOT / "fixtures"

TURNMILL = MODELS / "turnmill.toml"
S5D = MODELS / "s5d.toml"
H5D = MODELS / "h5d.toml"
HYBRID5 = MODELS / "hybrid5.toml"

POLYGON_DIR = FIXTURES / "polygon_shaft"
POLY50 = POLYGON_DIR / "POLY50.MPF"
POLYGON_TOOLS = FIXTURES / "polygon_shaft" / "tools.toml"

REFERENCE = ROOT.parent / "shared" / "reference" / "polygon_shaft_thesis.mpf"


def reference_or_skip() -> Path:
    """The published reference listing; skip when absent, but fail under CI=true."""
    return shared_or_skip(REFERENCE, "reference program")


def shared_or_skip(path: Path, what: str) -> Path:
    """A file of ``../shared``; skip when absent, but fail under CI=true."""
    if path.is_file():
        return path
    msg = f"{what} not found at {path}"
    if os.environ.get("CI", "").lower() == "true":
        pytest.fail(msg + " (CI=true: reference tests must run)")
    pytest.skip(msg)


def split_reference(directory: Path, reference: Path | None = None) -> Path:
    """Write the reference listing split as it was meant to be: the operator's parameter program
    calling ``L_POLY``, and ``L_POLY.SPF`` with the misspelt cycle name corrected. Built at run
    time from the published text (which the project never copies). Returns the main program.
    """
    reference = reference or reference_or_skip()
    lines = reference.read_text(encoding="utf-8").splitlines()
    proc = next(i for i, line in enumerate(lines) if line.lstrip().upper().startswith("PROC "))
    params = [ln for ln in lines[:proc] if ln.strip()[:1] in ("N", ";")]
    main = directory / "POLY.MPF"
    main.write_text("\n".join([*params, "L_POLY", "M30"]) + "\n", encoding="utf-8")
    sub = [
        ln.replace("C_AXIS_OF", "C_AXIS_OFF") if ln.rstrip().endswith("C_AXIS_OF") else ln
        for ln in lines[proc:]
    ]
    (directory / "L_POLY.SPF").write_text("\n".join(sub) + "\n", encoding="utf-8")
    return main
