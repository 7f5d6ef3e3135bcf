"""Where a program's machine, tools and stock come from.

Command-line options win; otherwise a ``vmach.toml`` beside the program says what it is for::

    machine = "turnmill"                 # a model name in models/ or a path (relative to this file)
    tools = "../tools/polygon_shaft.toml"
    stock = "cylinder:d=60,l=100"
    profile = "P3G:50"
    profile_z = "-35:-5"
    accuracy = "fine"                    # stock simulation preset (vmach.tol.ACCURACY)

    [zero_offsets.G54]                   # settable zero offsets, mm / degrees
    Z = 0.0

    [programs.POLY100]                   # overrides for one program (by file stem)
    stock = "cylinder:d=120,l=150"
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from vmach.canon import DEFAULT_CONTROL, ControlSpec
from vmach.errors import InputError

SETUP_NAME = "vmach.toml"
MODELS_DIR = Path(__file__).resolve().parents[1] / "models"


@dataclass(frozen=True)
class Setup:
    """Resolved options for one program (paths absolute or None)."""

    machine: Path | None = None
    tools: Path | None = None
    stock: str | None = None
    profile: str | None = None
    profile_z: str | None = None
    accuracy: str | None = None
    zero_offsets: dict[str, dict[str, float]] = field(default_factory=dict)
    source: Path | None = None  # the vmach.toml read, if any


def resolve_model(spec: str | Path, base: Path | None = None) -> Path:
    """A model given as a path, or as a bare name found in ``models/`` (``turnmill``)."""
    p = Path(spec)
    candidates = [p] if p.is_absolute() else ([base / p] if base else []) + [p]
    if p.suffix == "" and len(p.parts) == 1:
        candidates.append(MODELS_DIR / f"{p.name}.toml")
    elif len(p.parts) == 1:
        candidates.append(MODELS_DIR / p.name)
    for c in candidates:
        if c.is_file():
            return c
    known = ", ".join(sorted(x.stem for x in MODELS_DIR.glob("*.toml")))
    raise InputError(f"machine model {spec!s} not found (a path, or one of: {known})", kind="unreadable")


def read_setup(program: str | Path) -> Setup:
    """The ``vmach.toml`` beside ``program``, or an empty Setup."""
    from vmach.machine.control import read_toml

    path = Path(program).resolve().parent / SETUP_NAME
    if not path.is_file():
        return Setup()
    data: dict[str, Any] = read_toml(path)
    overrides = {k.upper(): v for k, v in data.pop("programs", {}).items()}
    data.update(overrides.get(Path(program).stem.upper(), {}))
    base = path.parent
    machine = data.get("machine")
    tools = data.get("tools")
    return Setup(
        machine=resolve_model(machine, base) if machine else None,
        tools=(base / tools) if tools else None,
        stock=data.get("stock"),
        profile=data.get("profile"),
        profile_z=data.get("profile_z"),
        accuracy=data.get("accuracy"),
        zero_offsets={
            k.upper(): {a: float(v) for a, v in vals.items()}
            for k, vals in data.get("zero_offsets", {}).items()
        },
        source=path,
    )


def control_for(program: str | Path, machine: str | None) -> tuple[ControlSpec, Path | None]:
    """The ControlSpec a program runs against: ``--machine``, else the setup file, else none."""
    from vmach.machine.control import load_control

    setup = read_setup(program)
    path = resolve_model(machine) if machine else setup.machine
    control = load_control(path) if path else DEFAULT_CONTROL
    return with_offsets(control, setup), path


def with_offsets(control: ControlSpec, setup: Setup) -> ControlSpec:
    """The control with the setup file's zero offsets laid over the model's."""
    if not setup.zero_offsets:
        return control
    merged = {k: dict(v) for k, v in control.zero_offsets.items()}
    for k, v in setup.zero_offsets.items():
        merged.setdefault(k, {}).update(v)
    return replace(control, zero_offsets=merged)
