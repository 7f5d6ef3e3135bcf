"""Where a program's machine, tools and stock come from.

Command-line options win; otherwise a ``vmach.toml`` beside the program says what it is for::

    machine = "turnmill"                 # a model name in models/ or a file beside this one
    tools = "tools.toml"
    stock = "cylinder:d=60,l=100"
    profile = "P3G:50"
    profile_z = "-35:-5"
    accuracy = "fine"                    # stock simulation preset (vmach.tol.ACCURACY)
    default_tool = "flat:d=10"           # stands in for tools the library lacks (vmach.defaults)
    definitions = ["GUD/MAKER.DEF"]      # GUD definition files besides _N_SGUD_DEF … (Sinumerik)

    [zero_offsets.G54]                   # settable zero offsets, mm / degrees
    Z = 0.0

    [parameters]                         # the model's set-up parameters, e.g. where the part
    rotation_centre = [0.0, 0.0, -30.0]  # sits on a table-table machine (--set wins)

    [programs.POLY100]                   # overrides for one program (by file stem)
    stock = "cylinder:d=120,l=150"

The files it names (``machine``, ``tools``) lie beside it — in its directory or below, with every
link followed — or are bundled models named by name: nothing is read from outside the program's
directory on the word of a file that came with the program. Files elsewhere are given on the
command line (``--machine``, ``--tools``), the user's own choice.
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from vmach.bundled import MODELS_DIR  # the bundled models (checkout or wheel)
from vmach.canon import DEFAULT_CONTROL, ControlSpec
from vmach.errors import InputError, ModelError
from vmach.files import contained, file_problem, leads_outside
from vmach.source import SourceRef

SETUP_NAME = "vmach.toml"


@dataclass(frozen=True)
class Setup:
    """Resolved options for one program (paths absolute or None)."""

    machine: Path | None = None
    tools: Path | None = None
    stock: str | None = None
    profile: str | None = None
    profile_z: str | None = None
    accuracy: str | None = None
    default_tool: str | None = None
    zero_offsets: dict[str, dict[str, float]] = field(default_factory=dict)
    parameters: dict[str, float | tuple[float, ...]] = field(default_factory=dict)  # the model's set-up
    definitions: tuple[str, ...] = ()  # GUD files, relative to the program's directory
    source: Path | None = None  # the vmach.toml read, if any
    #: where each text setting was read (key -> its line in the vmach.toml), for findings about it
    places: dict[str, SourceRef] = field(default_factory=dict)


#: why a file a vmach.toml names outside its directory is refused
OUTSIDE = ("leads outside the program's directory (never read): a vmach.toml names files beside "
           "it, or a bundled model by name; give others on the command line (--machine, --tools)")


def _bundled(model: Path) -> bool:
    """A model file of vmach's own (``models/``), which a vmach.toml may name from anywhere."""
    return contained(model, MODELS_DIR) and model.resolve().parent == MODELS_DIR.resolve()


def resolve_model(spec: str | Path, base: Path | None = None) -> Path:
    """A model given as a path, or as a bare name found in ``models/`` (``turnmill``)."""
    p = Path(spec)
    candidates = [p] if p.is_absolute() else ([base / p] if base else []) + [p]
    if p.suffix == "" and len(p.parts) == 1:
        candidates.append(MODELS_DIR / f"{p.name}.toml")
    elif len(p.parts) == 1:
        candidates.append(MODELS_DIR / p.name)
    for c in candidates:
        if file_problem(c) is None:                # a regular file (not a dir, device, loop)
            return c
    known = ", ".join(sorted(x.stem for x in MODELS_DIR.glob("*.toml")))
    raise InputError(f"machine model {spec!s} not found (a path, or one of: {known})", kind="unreadable")


#: the setup file's text settings (each a string when given)
TEXT_KEYS = ("machine", "tools", "stock", "profile", "profile_z", "accuracy", "default_tool")
#: every key a setup file's top level (and, but for ``programs``, a program's table) may hold
SETUP_KEYS = (*TEXT_KEYS, "definitions", "zero_offsets", "parameters", "programs")


def unknown_keys(data: dict[str, Any], places) -> list:
    """An ``unknown_key`` error (a Finding at its line) for every key of ``data`` that a setup
    file cannot hold, top level and ``[programs.NAME]`` tables, with the closest known key as
    a hint ("did you mean"), as a model file's loader does."""
    import difflib

    from vmach.findings import Finding

    out = []

    def check(table: dict, known: tuple[str, ...], key: tuple) -> None:
        for k in table:
            if k in known:
                continue
            close = difflib.get_close_matches(str(k), known, n=1, cutoff=0.6)
            hint = f"; did you mean {close[0]!r}?" if close else f" (keys: {', '.join(known)})"
            out.append(Finding("unknown_key", "error", f"{SETUP_NAME}: {'.'.join((*key, k))} is not a "
                               f"setting{hint}", places.find((*key, k))))

    check(data, SETUP_KEYS, ())
    programs = data.get("programs")
    if isinstance(programs, dict):
        for name, table in programs.items():
            if isinstance(table, dict):
                check(table, tuple(k for k in SETUP_KEYS if k != "programs"), ("programs", name))
    return out


def read_setup(program: str | Path) -> Setup:
    """The ``vmach.toml`` beside ``program``, or an empty Setup. A value of the wrong type is
    an ``error[setup]`` at its line in the file."""
    from vmach.machine.control import parse_toml, read_text
    from vmach.machine.tomlpos import KeyLines

    directory = Path(program).resolve().parent
    path = directory / SETUP_NAME
    if leads_outside(path, directory):             # never read from outside the program's directory
        raise InputError(f"{path}: a link leading outside the program's directory (never read)",
                         kind="setup", source=SourceRef(str(path), 1))
    if not path.is_file():
        return Setup()
    text = read_text(path)
    data: dict[str, Any] = parse_toml(text, str(path))
    places = KeyLines.scan(text, str(path))
    if problems := unknown_keys(data, places):
        raise ModelError(problems)

    def bad(key: tuple, what: str):
        return InputError(f"{SETUP_NAME}: {'.'.join(map(str, key))} {what}", kind="setup",
                          source=places.find(key))

    programs = data.pop("programs", {})
    if not isinstance(programs, dict) or not all(isinstance(v, dict) for v in programs.values()):
        raise bad(("programs",), "must hold tables: [programs.NAME]")
    stem = Path(program).stem.upper()
    where = {k: (k,) for k in data}               # each setting's key, for the error's line
    for name, values in programs.items():
        if name.upper() == stem:
            data.update(values)
            where.update({k: ("programs", name, k) for k in values})
    for key in TEXT_KEYS:
        if key in data and not isinstance(data[key], str):
            raise bad(where[key], "must be a string")
    offsets = data.get("zero_offsets", {})
    zero: dict[str, dict[str, float]] = {}
    if not isinstance(offsets, dict):
        raise bad(("zero_offsets",), "must hold tables: [zero_offsets.G54]")
    for k, vals in offsets.items():
        if not isinstance(vals, dict):
            raise bad(("zero_offsets", k), "must be a table of axis values")
        row = {}
        for a, v in vals.items():
            if not _finite(v):
                raise bad(("zero_offsets", k, a), "must be a finite number (mm or degrees)")
            row[a] = float(v)
        zero[k.upper()] = row
    params: dict[str, float | tuple[float, ...]] = {}
    raw_params = data.get("parameters", {})
    if not isinstance(raw_params, dict):
        raise bad(("parameters",), "must be a table: [parameters] rotation_centre = [0, 0, -30]")
    for k, v in raw_params.items():
        vals = v if isinstance(v, list) else [v]
        if not vals or not all(_finite(x) for x in vals):
            raise bad(where.get("parameters", ("parameters",)) + (k,),
                      "must be a finite number or a list of them (mm or degrees)")
        params[k] = tuple(float(x) for x in vals) if isinstance(v, list) else float(v)
    base = path.parent
    machine = data.get("machine")
    tools = data.get("tools")
    try:
        model = resolve_model(machine, base) if machine else None
    except InputError as exc:
        raise InputError(f"{SETUP_NAME}: {exc.message}", kind=exc.kind,
                         source=places.find(where["machine"])) from None
    if model is not None and not _bundled(model) and not contained(model, base):
        raise InputError(f"{SETUP_NAME}: machine = {machine!r} {OUTSIDE}", kind="file_outside",
                         source=places.find(where["machine"]))
    if tools and (problem := file_problem(base / tools)) is not None:
        raise bad(where["tools"], f"= {tools!r}: {problem}")
    if tools and not contained(base / tools, base):
        raise InputError(f"{SETUP_NAME}: tools = {tools!r} {OUTSIDE}", kind="file_outside",
                         source=places.find(where["tools"]))
    definitions = data.get("definitions", [])
    if not isinstance(definitions, list) or not all(isinstance(v, str) and v for v in definitions):
        raise bad(where.get("definitions", ("definitions",)), "must be a list of file names")
    for name in definitions:
        if (problem := file_problem(base / name)) is not None:
            raise bad(where["definitions"], f"names {name!r}: {problem}")
        if not contained(base / name, base):
            raise InputError(f"{SETUP_NAME}: definitions names {name!r}, which {OUTSIDE}",
                             kind="file_outside", source=places.find(where["definitions"]))
    return Setup(
        machine=model,
        tools=(base / tools) if tools else None,
        stock=data.get("stock"),
        profile=data.get("profile"),
        profile_z=data.get("profile_z"),
        accuracy=data.get("accuracy"),
        default_tool=data.get("default_tool"),
        zero_offsets=zero,
        parameters=params,
        definitions=tuple(definitions),
        source=path,
        places={k: places.find(where[k]) for k in TEXT_KEYS if k in data},
    )


@contextmanager
def setting(setup: Setup, key: str, given: object = None):
    """Run the reading of setting ``key``; when its value came from the setup file (not the
    command line: ``given`` is None), an InputError it raises points at the key's line in the
    file and says so."""
    try:
        yield
    except InputError as exc:
        if given is not None or key not in setup.places or exc.source is not None:
            raise
        raise InputError(f"{SETUP_NAME}: {key}: {exc.message}", kind=exc.kind,
                         source=setup.places[key]) from None


def _finite(v: Any) -> bool:
    return not isinstance(v, bool) and isinstance(v, int | float) and math.isfinite(v)


def control_for(program: str | Path, machine: str | None, *,
                machine_data: bool = True) -> tuple[ControlSpec, Path | None]:
    """The ControlSpec a program runs against: ``--machine``, else the setup file, else none.

    ``machine_data=False`` reads the model's control part alone (axes, dialect, declared names and
    its ``[machine_data]`` table, without the values derived from its kinematic chain): what the
    static checks need, without loading numpy and the kinematics (``vmach check`` starts fast)."""
    setup = read_setup(program)
    path = resolve_model(machine) if machine else setup.machine
    if not path:
        control = DEFAULT_CONTROL
    elif machine_data:
        from vmach.machine.loader import load_model_control

        control = load_model_control(path)
    else:
        from vmach.machine.control import load_control

        control = load_control(path)
    return with_offsets(control, setup), path


def with_offsets(control: ControlSpec, setup: Setup) -> ControlSpec:
    """The control with the setup file's zero offsets laid over the model's (and its GUD
    definition files after the model's)."""
    if setup.definitions:
        control = replace(control, definitions=tuple(dict.fromkeys(control.definitions + setup.definitions)))
    if not setup.zero_offsets:
        return control
    merged = {k: dict(v) for k, v in control.zero_offsets.items()}
    for k, v in setup.zero_offsets.items():
        merged.setdefault(k, {}).update(v)
    return replace(control, zero_offsets=merged)
