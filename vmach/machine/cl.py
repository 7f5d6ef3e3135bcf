"""APT cutter-location (CL) data: the CAM system's tool poses in the workpiece frame.

Read statements (one per line; a line ending in a single ``$`` continues on the next)::

    GOTO/x, y, z [, i, j, k]    tool tip (mm) and tool-axis vector (from tip toward spindle)
    RAPID                       the next GOTO is a rapid move
    FEDRAT/f [, MMPM | IPM]     feed for the following GOTOs
    LOADTL/n [, ...]            tool change
    MULTAX [/ON | /OFF]         GOTOs carry i, j, k (a GOTO without them keeps the last axis)
    UNITS/MM | /INCHES          inch data are converted to mm
    $$ text, PPRINT/text        comments
    PARTNO, CUTTER, SPINDL, COOLNT, FINI, END, TLAXIS, ... — accepted, nothing to check

Unknown statements and malformed numbers are findings with the line (``cl_syntax`` error,
``cl_unsupported`` warning for ``CIRCLE`` and other records that change the path).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vmach.files import decode_text, read_bytes
from vmach.findings import Finding, error, warning
from vmach.source import SourceRef
from vmach.tol import tol

IGNORED = {"PARTNO", "CUTTER", "SPINDL", "COOLNT", "FINI", "END", "TLAXIS", "CLPRNT", "INTOL",
           "OUTTOL", "MACHIN", "SELCTL", "TOLER", "NOPS", "OPSKIP", "DISPLY", "TPRINT", "INSERT",
           "PPRINT", "STOP", "OPSTOP", "ORIGIN", "MODE", "CYCLE", "DELAY", "AUTOPS", "CUTCOM"}
UNSUPPORTED = {"CIRCLE", "GODLTA", "MOVARC", "FROM", "INDIRV", "GOFWD", "GOLFT", "GORGT"}
_WORD = re.compile(r"\s*([A-Za-z][A-Za-z0-9_]*)\s*(/(.*))?$")


@dataclass(frozen=True)
class ClData:
    """The poses of a CL file.

    tip : (n, 3) float, mm, workpiece frame. axis : (n, 3) float, unit.
    rapid : (n,) bool. feed : (n,) float, mm/min (NaN before the first FEDRAT).
    tool : (n,) int (0 before the first LOADTL). sources : one SourceRef per pose.
    findings : problems met while reading.
    """

    path: str
    tip: np.ndarray
    axis: np.ndarray
    rapid: np.ndarray
    feed: np.ndarray
    tool: np.ndarray
    sources: tuple[SourceRef, ...]
    findings: tuple[Finding, ...] = ()

    def __len__(self) -> int:
        return len(self.sources)


def _statements(text: str):
    """(line number, joined statement text, first line text) with ``$`` continuations."""
    buf, start, first = "", 0, ""
    for no, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not buf:
            start, first = no, raw
        if line.startswith("$$") and not buf:
            yield start, line, first
            continue
        if line.endswith("$") and not line.endswith("$$"):
            buf += line[:-1] + " "
            continue
        stmt, buf = buf + line, ""
        if stmt.strip():
            yield start, stmt, first


def parse_cl(text: str, path: str = "<cl>") -> ClData:
    """Parse CL text; every problem becomes a finding in ``ClData.findings``."""
    tips, axes, rapids, feeds, tools, sources = [], [], [], [], [], []
    found: list[Finding] = []
    scale, axis, feed, tool = 1.0, (0.0, 0.0, 1.0), math.nan, 0
    rapid_next = False
    for no, stmt, first in _statements(text):
        src = SourceRef(path, no, 1, first)
        if stmt.startswith("$$"):
            continue
        m = _WORD.match(stmt)
        if not m:
            found.append(error("cl_syntax", f"cannot read {stmt[:40]!r}", src))
            continue
        word, args = m.group(1).upper(), (m.group(3) or "").strip()
        fields = [f.strip() for f in args.split(",")] if args else []
        if word == "GOTO":
            try:
                vals = [float(f) for f in fields]
            except ValueError:
                found.append(error("cl_syntax", f"GOTO needs numbers: {args!r}", src))
                continue
            big = tol.max_magnitude
            if len(vals) not in (3, 6) or not all(math.isfinite(v) and abs(v) <= big for v in vals):
                found.append(error("cl_syntax", f"GOTO needs x,y,z or x,y,z,i,j,k (finite, within "
                                                f"{tol.max_magnitude:g})", src))
                continue
            if len(vals) == 6:
                a = np.array(vals[3:])
                norm = float(np.linalg.norm(a))
                if norm < 1e-9:
                    found.append(error("cl_syntax", "GOTO tool axis is the zero vector", src))
                    continue
                axis = tuple(a / norm)
            tips.append([v * scale for v in vals[:3]])
            axes.append(axis)
            rapids.append(rapid_next)
            feeds.append(feed)
            tools.append(tool)
            sources.append(src)
            rapid_next = False
        elif word == "RAPID":
            rapid_next = True
        elif word == "FEDRAT":
            try:
                f = float(fields[0])
                if not (math.isfinite(f) and f > 0):
                    raise ValueError(f)
            except (ValueError, IndexError):
                found.append(error("cl_syntax", "FEDRAT needs a number > 0", src))
                continue
            unit = fields[1].upper() if len(fields) > 1 else "MMPM"
            if unit not in ("MMPM", "IPM", "MMPR", "IPR"):
                found.append(warning("cl_unsupported", f"FEDRAT unit {unit} is not checked", src))
            feed = f * (25.4 if unit in ("IPM", "IPR") else 1.0)
        elif word == "LOADTL":
            try:
                number = int(float(fields[0]))
                if not 0 <= number < 2**31:
                    raise ValueError(number)
                tool = number
            except (ValueError, IndexError, OverflowError):
                found.append(error("cl_syntax", "LOADTL needs a tool number (0 to 2147483647)", src))
        elif word == "UNITS":
            unit = args.upper()
            if unit not in ("MM", "INCHES", "INCH"):
                found.append(error("cl_syntax", f"UNITS/{args}: MM or INCHES", src))
            scale = 25.4 if unit.startswith("INCH") else 1.0
        elif word == "MULTAX":
            if args.upper() == "OFF":
                axis = (0.0, 0.0, 1.0)
        elif word in UNSUPPORTED:
            found.append(warning("cl_unsupported", f"{word} is not supported: its path is not "
                                                   "checked", src))
        elif word not in IGNORED:
            found.append(warning("cl_unsupported", f"unknown CL statement {word}", src))
    n = len(sources)
    if n == 0 and not any(f.severity == "error" for f in found):
        found.append(error("cl_syntax", "no GOTO pose in the CL data: nothing to check against",
                           SourceRef(path, 1, 1, "")))
    return ClData(path, np.array(tips, float).reshape(n, 3), np.array(axes, float).reshape(n, 3),
                  np.array(rapids, bool), np.array(feeds, float), np.array(tools, int),
                  tuple(sources), tuple(found))


def read_cl(path: str | Path) -> ClData:
    """Read a CL file (UTF-8 or Latin-1 text)."""
    return parse_cl(decode_text(read_bytes(path, limit=tol.max_program_bytes)), str(path))
