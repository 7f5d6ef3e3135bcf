"""The control-facing part of a machine model: :class:`vmach.canon.ControlSpec` from TOML.

Reads ``[control]`` and ``[[axes]]`` of a model file (see ``models/turnmill.toml``)::

    [control]
    geometry = ["X", "Y", "Z"]     # optional, default X Y Z
    transverse = "X"               # optional, DIAMON axis
    cycles = ["C_AXIS_ON"]         # maker's cycles callable by name
    gcodes = ["G971"]              # machine-specific G codes
    spindles = [1, 2]
    master_spindle = 1
    definitions = ["MAKER_GUD.DEF"]  # GUD files besides _N_SGUD_DEF …, read beside the program

    [[axes]]
    name = "C1"
    type = "rotary"                # or "linear"
    modulo = 360.0                 # modulo rotary axis (optional)
    home = 0.0                     # position at program start
    g90_mode = "ac"                # or "dc" (modulo axis positioning under G90)

A model written as a structure formula (``formula = "WCBVXYZT"``) without ``[[axes]]`` gets its
axes from the formula (X Y Z A B C order; rotary letters are rotary axes without modulo); a
hand-written chain without ``[[axes]]`` gets the variables of its joints in file order.
Travel limits and rates belong to the kinematic part (joints), not to this section.
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import interpreters
from vmach.canon import AxisSpec, ControlSpec
from vmach.errors import ModelError
from vmach.files import input_file, read_bytes
from vmach.findings import Finding, error
from vmach.machine.formula import FormulaError, formula_axes
from vmach.machine.tomlpos import KeyLines
from vmach.source import SourceRef
from vmach.tol import tol

Locate = Callable[[tuple], SourceRef]


def read_text(path: str | Path) -> str:
    """The model file's text; unreadable or non-UTF-8 files become errors (exit 2), as does a
    name that is not a regular file (a device, a pipe: ``--tools /dev/null``)."""
    data = read_bytes(input_file(path))
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise ModelError([error("model", "not UTF-8 text", SourceRef(str(path), 1))]) from None


def parse_toml(text: str, path: str) -> dict[str, Any]:
    """Parse TOML text; a syntax error becomes :class:`ModelError` with line and column."""
    try:
        return tomllib.loads(text)
    except RecursionError:
        raise ModelError([error("model_syntax", "values nested too deeply", SourceRef(path, 1))]) from None
    except tomllib.TOMLDecodeError as exc:
        line = getattr(exc, "lineno", None)
        col = getattr(exc, "colno", None)
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        if line is None and m:  # Python < 3.14 only puts the place in the message
            line, col = int(m.group(1)), int(m.group(2))
        line, col = line or 1, col or 1
        lines = text.splitlines()
        src = SourceRef(path, line, col, lines[line - 1] if 0 < line <= len(lines) else "")
        raise ModelError([error("model_syntax", str(exc).split(" (at")[0], src)]) from None


def read_toml(path: str | Path) -> dict[str, Any]:
    """Parse a TOML file; unreadable or malformed files become :class:`ModelError`."""
    return parse_toml(read_text(path), str(path))


def _float(value: Any) -> float | None:
    """A finite number within ``tol.max_size`` (mm or degrees), else None."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    try:
        v = float(value)
    except OverflowError:
        return None
    return v if math.isfinite(v) and abs(v) <= tol.max_size else None


def default_axes(model: Mapping[str, Any]) -> list[dict[str, Any]]:
    """``[[axes]]`` entries implied by a formula when the file has none (else ``[]``)."""
    formula = model.get("formula")
    if "axes" in model:
        return []
    if isinstance(formula, str):
        try:
            names = formula_axes(formula)
        except FormulaError:
            return []  # the kinematic loader reports the formula itself
        return [{"name": n, "type": "rotary" if n[0] in "ABC" else "linear"} for n in names]
    joints = model.get("joints")
    if not isinstance(joints, list):
        return []
    kinds: dict[str, str] = {}
    for j in joints:
        if isinstance(j, Mapping) and j.get("type") in ("prismatic", "revolute"):
            var = j.get("variable", j.get("name"))
            if isinstance(var, str) and var:
                kinds.setdefault(var, "rotary" if j["type"] == "revolute" else "linear")
    return [{"name": n, "type": k} for n, k in kinds.items()]


def collect_control(
    model: Mapping[str, Any], path: str = "<model>", locate: Locate | None = None
) -> tuple[ControlSpec, list[Finding]]:
    """ControlSpec of a parsed model and every problem found (the spec is partial if any)."""
    where: Locate = locate or (lambda key: SourceRef(path, 1))
    problems: list[Finding] = []

    def bad(key: tuple, msg: str, kind: str = "model") -> None:
        problems.append(error(kind, msg, where(key)))

    ctl = model.get("control", {})
    if not isinstance(ctl, Mapping):
        bad(("control",), "control must be a table")
        ctl = {}
    axes: list[AxisSpec] = []
    seen: set[str] = set()
    entries = model.get("axes", None)
    if entries is None:
        entries = default_axes(model)
    if not isinstance(entries, list):
        bad(("axes",), "axes must be an array of tables ([[axes]])")
        entries = []
    for i, ax in enumerate(entries):
        if not isinstance(ax, Mapping):
            bad(("axes", i), f"axes[{i}] must be a table")
            continue
        name = ax.get("name")
        if not isinstance(name, str) or not name:
            bad(("axes", i), f"axes[{i}] has no name", "missing_key")
            continue
        if name in seen:
            bad(("axes", i, "name"), f"axis {name!r} is defined twice", "duplicate_name")
        seen.add(name)
        kind = ax.get("type", "linear")
        if kind not in ("linear", "rotary"):
            bad(("axes", i, "type"), f"axis {name}: type must be linear or rotary", "bad_value")
            kind = "linear"
        modulo = ax.get("modulo")
        if modulo is not None:
            modulo = _float(modulo)
            if modulo is None or kind != "rotary" or modulo <= 0:
                bad(
                    ("axes", i, "modulo"),
                    f"axis {name}: modulo needs a rotary axis and a finite value > 0",
                    "bad_value",
                )
                modulo = None
        g90 = ax.get("g90_mode", "ac")
        if g90 not in ("ac", "dc"):
            bad(("axes", i, "g90_mode"), f"axis {name}: g90_mode must be 'ac' or 'dc'", "bad_value")
            g90 = "ac"
        home = _float(ax.get("home", 0.0))
        if home is None:
            bad(("axes", i, "home"), f"axis {name}: home must be a finite number", "bad_value")
            home = 0.0
        axes.append(AxisSpec(name=name, kind=kind, modulo=modulo, home=home, g90_mode=g90))
    geometry = ctl.get("geometry", ("X", "Y", "Z"))
    if (not isinstance(geometry, list | tuple) or len(geometry) != 3
            or not all(isinstance(g, str) for g in geometry) or len(set(geometry)) != 3
            or ("geometry" in ctl and seen and not set(geometry) <= seen)):
        bad(("control", "geometry"), "control.geometry must name three different axes of the model",
            "bad_value")
        geometry = ("X", "Y", "Z")
    transverse = ctl.get("transverse")
    if transverse is not None and not isinstance(transverse, str):
        bad(("control", "transverse"), "control.transverse must name an axis", "bad_value")
        transverse = None
    if transverse is not None and transverse not in seen:
        bad(
            ("control", "transverse"),
            f"control.transverse {transverse!r} is not an axis",
            "unknown_axis",
        )
    spindles_raw = ctl.get("spindles", [1])
    if not isinstance(spindles_raw, list) or not all(
        isinstance(s, int) and not isinstance(s, bool) and 0 <= s <= 99 for s in spindles_raw
    ):
        bad(("control", "spindles"), "control.spindles must be a list of integers 0..99", "bad_value")
        spindles_raw = [1]
    spindles = tuple(spindles_raw)
    master = ctl.get("master_spindle", spindles[0] if spindles else 1)
    if not isinstance(master, int) or (spindles and master not in spindles):
        bad(
            ("control", "master_spindle"),
            f"control.master_spindle {master} is not in spindles",
            "bad_value",
        )
        master = spindles[0] if spindles else 1
    offsets: dict[str, dict[str, float]] = {}
    raw_offsets = model.get("zero_offsets", {})
    if isinstance(raw_offsets, Mapping):
        for k, vals in raw_offsets.items():
            if not isinstance(vals, Mapping):
                bad(("zero_offsets", k), f"zero_offsets.{k} must be a table", "bad_value")
                continue
            row = {}
            for a, v in vals.items():
                fv = _float(v)
                if fv is None:
                    bad(
                        ("zero_offsets", k, a),
                        f"zero_offsets.{k}.{a} must be a number",
                        "bad_value",
                    )
                else:
                    row[str(a)] = fv
            offsets[str(k).upper()] = row
    dialect = ctl.get("dialect")
    if dialect is not None and (not isinstance(dialect, str) or dialect not in interpreters.NAMES):
        bad(("control", "dialect"), f"control.dialect must be one of {', '.join(sorted(interpreters.NAMES))}",
            "bad_value")
        dialect = None
    names = {}
    for key in ("cycles", "gcodes"):
        raw = ctl.get(key, ())
        if not isinstance(raw, list | tuple) or not all(isinstance(v, str) for v in raw):
            bad(("control", key), f"control.{key} must be a list of names", "bad_value")
            raw = ()
        names[key] = frozenset(v.upper() for v in raw)
    definitions = ctl.get("definitions", ())
    if not isinstance(definitions, list | tuple) or not all(isinstance(v, str) and v for v in definitions):
        bad(("control", "definitions"), "control.definitions must be a list of file names", "bad_value")
        definitions = ()
    spec = ControlSpec(
        axes=tuple(axes),
        geometry=tuple(str(g) for g in geometry),  # type: ignore[arg-type]
        transverse=transverse,
        cycles=names["cycles"],
        gcodes=names["gcodes"],
        strict_axes=bool(axes),
        zero_offsets=offsets,
        spindles=spindles,
        master_spindle=master,
        dialect=dialect,
        definitions=tuple(definitions),
    )
    return spec, problems


def control_spec(
    model: Mapping[str, Any], path: str = "<model>", locate: Locate | None = None
) -> ControlSpec:
    """Build the ControlSpec of a parsed model; collects every problem before failing."""
    spec, problems = collect_control(model, path, locate)
    if problems:
        raise ModelError(problems)
    return spec


def load_control(path: str | Path) -> ControlSpec:
    """ControlSpec of the model file at ``path`` (only ``[control]``/``[[axes]]`` are read)."""
    text = read_text(path)
    data = parse_toml(text, str(path))
    spec = control_spec(data, str(path), KeyLines.scan(text, str(path)).find)
    if not spec.axes:                              # an empty file (or /dev/null) is no machine
        raise ModelError([error("missing_key", "the model has no axes ([[axes]], a formula or "
                                "joints)", SourceRef(str(path), 1))])
    return spec
