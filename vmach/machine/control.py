"""The control-facing part of a machine model: :class:`vmach.canon.ControlSpec` from TOML.

Reads ``[control]`` and ``[[axes]]`` of a model file (see ``models/turnmill.toml``)::

    [control]
    geometry = ["X", "Y", "Z"]     # optional, default X Y Z
    transverse = "X"               # optional, DIAMON axis
    cycles = ["C_AXIS_ON"]         # maker's cycles callable by name
    gcodes = ["G971"]              # machine-specific G codes
    spindles = [1, 2]
    master_spindle = 1

    [[axes]]
    name = "C1"
    type = "rotary"                # or "linear"
    modulo = 360.0                 # modulo rotary axis (optional)
    home = 0.0                     # position at program start
    g90_mode = "ac"                # or "dc" (modulo axis positioning under G90)
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from vmach.canon import AxisSpec, ControlSpec
from vmach.errors import InputError, ModelError
from vmach.findings import error
from vmach.source import SourceRef


def read_toml(path: str | Path) -> dict[str, Any]:
    """Parse a TOML file; unreadable or malformed files become :class:`ModelError`."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror or exc}", kind="unreadable") from None
    try:
        return tomllib.loads(data.decode("utf-8"))
    except UnicodeDecodeError:
        raise ModelError([error("model", "not UTF-8 text", SourceRef(str(path), 1))]) from None
    except tomllib.TOMLDecodeError as exc:
        line = getattr(exc, "lineno", None) or 1
        col = getattr(exc, "colno", None) or 1
        text = data.decode("utf-8", "replace").splitlines()
        src = SourceRef(str(path), line, col, text[line - 1] if 0 < line <= len(text) else "")
        raise ModelError([error("model_syntax", str(exc).split(" (at")[0], src)]) from None


def control_spec(model: Mapping[str, Any], path: str = "<model>") -> ControlSpec:
    """Build the ControlSpec of a parsed model; collects every problem before failing."""
    problems = []
    where = SourceRef(path, 1)
    ctl = model.get("control", {})
    axes: list[AxisSpec] = []
    seen: set[str] = set()
    for i, ax in enumerate(model.get("axes", [])):
        name = ax.get("name")
        if not isinstance(name, str) or not name:
            problems.append(error("model", f"axes[{i}] has no name", where))
            continue
        if name in seen:
            problems.append(error("model", f"axis {name!r} is defined twice", where))
        seen.add(name)
        kind = ax.get("type", "linear")
        if kind not in ("linear", "rotary"):
            problems.append(error("model", f"axis {name}: type must be linear or rotary", where))
        modulo = ax.get("modulo")
        if modulo is not None and (kind != "rotary" or float(modulo) <= 0):
            problems.append(error("model", f"axis {name}: modulo needs a rotary axis and a value > 0", where))
        g90 = ax.get("g90_mode", "ac")
        if g90 not in ("ac", "dc"):
            problems.append(error("model", f"axis {name}: g90_mode must be 'ac' or 'dc'", where))
        axes.append(
            AxisSpec(
                name=name,
                kind=kind,
                modulo=None if modulo is None else float(modulo),
                home=float(ax.get("home", 0.0)),
                g90_mode=g90,
            )
        )
    geometry = tuple(ctl.get("geometry", ("X", "Y", "Z")))
    if len(geometry) != 3:
        problems.append(error("model", "control.geometry must name three axes", where))
    transverse = ctl.get("transverse")
    if transverse is not None and transverse not in seen:
        problems.append(error("model", f"control.transverse {transverse!r} is not an axis", where))
    spindles = tuple(int(s) for s in ctl.get("spindles", (1,)))
    master = int(ctl.get("master_spindle", spindles[0] if spindles else 1))
    if spindles and master not in spindles:
        problems.append(error("model", f"control.master_spindle {master} is not in spindles", where))
    offsets = {
        str(k).upper(): {str(a): float(v) for a, v in dict(vals).items()}
        for k, vals in dict(model.get("zero_offsets", {})).items()
    }
    if problems:
        raise ModelError(problems)
    return ControlSpec(
        axes=tuple(axes),
        geometry=geometry,  # type: ignore[arg-type]
        transverse=transverse,
        cycles=frozenset(str(c).upper() for c in ctl.get("cycles", ())),
        gcodes=frozenset(str(g).upper() for g in ctl.get("gcodes", ())),
        strict_axes=bool(axes),
        zero_offsets=offsets,
        spindles=spindles,
        master_spindle=master,
    )


def load_control(path: str | Path) -> ControlSpec:
    """ControlSpec of the model file at ``path``."""
    return control_spec(read_toml(path), str(path))
