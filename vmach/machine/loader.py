"""Machine model files (TOML) → :class:`vmach.machine.spec.ModelSpec`, every problem collected.

Schema (all lengths mm, angles degrees, rates per minute; see ``docs/kinematics.md``)::

    name = "s5d"
    [parameters]                 # setup values; ``--set NAME=VALUE`` overrides them
    rotation_centre = [0.0, 0.0, 0.0]
    [kinematics]
    ik = "table_table"           # or "head_bc", "numeric" (default)
    [[joints]]                   # hand-written chain ...
    name = "B"                   # drives machine axis B (``variable`` overrides)
    type = "revolute"            # prismatic | revolute | fixed
    parent = "base"
    child = "b"
    axis = [0, 1, 0]             # unit vector
    origin = [0, 0, 0]           # or "-rotation_centre"; each component may be "name"/"-name"
    rpy = [0, 0, 0]
    limits = [-10, 120]
    max_rate = 3600
    max_accel = 5000             # mm/s² or °/s² (per second squared)
    formula = "WCBVXYZT"         # ... or a structure formula with [dimensions.<axis|W|T>]
    [work]   link, origin, rpy
    [tool]   link, origin, direction, length
    [[geometry]]  name, link, shape = box|cylinder|mesh, size | radius+length | path, origin, rpy
    [[parallel]]  name, virtual, origin, assembly, [[parallel.legs]] drive, guide_point,
                  guide_dir, length, attach, root, limits, max_rate
    [positions.tool_change]  X = 325.0, Y = 0.0    # named machine positions (G53 values)
    [timing]  tool_change_s, spindle_start_s, ..., [timing.cycles] C_AXIS_ON = 2.0  (seconds;
              see vmach.machine.spec.TimingSpec)
    [machine_data]  MC_TRAFO_TYPE_1 = 24, MA_POS_LIMIT_PLUS = { X = 500.0 } ... (the control's
              machine, setting, swivel and PLC data; see vmach.machine.machdata)

A value that refers to a parameter is a string: ``"name"`` or ``"-name"``; nothing is evaluated.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

from vmach.canon import ControlSpec
from vmach.findings import Finding, error
from vmach.machine.control import collect_control, control_spec, parse_toml, read_text
from vmach.machine.dynamics import read_timing
from vmach.machine.formula import FormulaError, parse_formula
from vmach.machine.machdata import derive, read_table
from vmach.machine.spec import (
    Geometry,
    Joint,
    Leg,
    ModelSpec,
    Origin,
    Parallel,
    ToolMount,
    WorkMount,
)
from vmach.machine.tomlpos import KeyLines
from vmach.source import SourceRef
from vmach.tol import tol

IK_METHODS = ("numeric", "table_table", "head_bc")
UNIT_TOL = 1e-9

_MOUNT = frozenset({"origin", "rpy"})
_DRIVE = frozenset({"limits", "max_rate", "max_accel"})
_JOINT = frozenset({"name", "variable", "type", "parent", "child", "axis"}) | _MOUNT | _DRIVE
#: The keys each table of a model may hold (tables whose keys are names — parameters,
#: positions, zero_offsets, timing.cycles — are not listed; timing checks its own). A key
#: outside them is an ``unknown_key`` error: a misspelt ``max_rat`` must not silently drop a
#: rate limit.
KEYS: dict[str, frozenset[str]] = {
    "": frozenset({"name", "description", "formula", "control", "axes", "parameters", "kinematics",
                   "joints", "dimensions", "work", "tool", "geometry", "parallel", "positions",
                   "timing", "zero_offsets", "machine_data"}),
    "control": frozenset({"dialect", "geometry", "transverse", "spindles", "master_spindle",
                          "tool_spindle", "cycles", "gcodes"}),
    "axes": frozenset({"name", "type", "modulo", "g90_mode", "home"}),
    "kinematics": frozenset({"ik"}),
    "joints": _JOINT,
    "dimensions": frozenset({"axis", "variable"}) | _MOUNT | _DRIVE,
    "dimensions.W": _MOUNT,
    "dimensions.T": _MOUNT | {"direction", "length"},
    "work": frozenset({"link"}) | _MOUNT,
    "tool": frozenset({"link", "direction", "length"}) | _MOUNT,
    "geometry": frozenset({"name", "link", "shape", "size", "radius", "length", "path"}) | _MOUNT,
    "parallel": frozenset({"name", "virtual", "origin", "assembly", "legs"}),
    "parallel.legs": frozenset({"drive", "guide_point", "guide_dir", "length", "attach", "root"}) | _DRIVE,
}


def _unknown_keys(r: Reader) -> None:
    """An ``unknown_key`` error for every key no table of the schema (:data:`KEYS`) knows,
    with the closest known key as a hint."""

    def check(table: Any, schema: str, key: tuple) -> None:
        if not isinstance(table, Mapping):
            return                  # the table's own reader reports the wrong type
        known = KEYS[schema]
        for k in table:
            if k not in known:
                close = difflib.get_close_matches(str(k), sorted(known), n=1, cutoff=0.6)
                hint = f"; did you mean {close[0]!r}?" if close else ""
                where = f"{schema}." if schema else ""
                r.err("unknown_key", f"{where}{k} is not a key of the model{hint}", key + (k,))

    def each(value: Any, schema: str, key: tuple) -> None:
        for i, t in enumerate(value if isinstance(value, list) else []):
            check(t, schema, key + (i,))

    raw = r.raw
    check(raw, "", ())
    for name in ("control", "kinematics", "work", "tool"):
        check(raw.get(name, {}), name, (name,))
    for name in ("axes", "joints", "geometry", "parallel"):
        each(raw.get(name, []), name, (name,))
    for i, par in enumerate(raw.get("parallel", []) if isinstance(raw.get("parallel"), list) else []):
        if isinstance(par, Mapping):
            each(par.get("legs", []), "parallel.legs", ("parallel", i, "legs"))
    dims = raw.get("dimensions", {})
    for k, t in (dims.items() if isinstance(dims, Mapping) else ()):
        check(t, f"dimensions.{k}" if k in ("W", "T") else "dimensions", ("dimensions", k))
#: smallest max_rate (mm/min or degrees/min): a denormal rate made times infinite
MIN_RATE = 1e-6


class Reader:
    """Typed access to the parsed TOML that records a finding (with line) for every problem."""

    def __init__(
        self,
        path: str,
        lines: KeyLines,
        raw: Mapping[str, Any],
        overrides: Mapping[str, Any] | None = None,
    ):
        self.path = path
        self.lines = lines
        self.raw = raw
        self.problems: list[Finding] = []
        self.params: dict[str, float | tuple[float, ...]] = {}
        self._read_parameters(overrides or {})

    # -- reporting ---------------------------------------------------------------------------
    def where(self, key: tuple, fallback: tuple = ()) -> SourceRef:
        k = tuple(key)
        while k and k not in self.lines.places:
            k = k[:-1]
        if not k and fallback:
            return self.lines.find(fallback)
        return self.lines.find(k)

    def err(self, kind: str, msg: str, key: tuple, fallback: tuple = ("formula",)) -> None:
        self.problems.append(error(kind, msg, self.where(key, fallback)))

    # -- parameters --------------------------------------------------------------------------
    def _read_parameters(self, overrides: Mapping[str, Any]) -> None:
        table = self.raw.get("parameters", {})
        if not isinstance(table, Mapping):
            self.err("bad_value", "parameters must be a table", ("parameters",))
            return
        for name, value in table.items():
            if _is_num(value):
                self.params[name] = float(value)
            elif isinstance(value, list) and value and all(_is_num(v) for v in value):
                self.params[name] = tuple(float(v) for v in value)
            else:
                self.err(
                    "bad_value",
                    f"parameter {name} must be a number or a list of numbers",
                    ("parameters", name),
                )
        for name, value in overrides.items():
            self.params[name] = value

    def _ref(self, text: str, key: tuple) -> float | tuple[float, ...] | None:
        sign = -1.0 if text.startswith("-") else 1.0
        name = text.lstrip("+-").strip()
        if name not in self.params:
            self.err(
                "unknown_parameter",
                f"{text!r} is not a number and {name!r} is not a parameter",
                key,
            )
            return None
        v = self.params[name]
        return sign * v if isinstance(v, float) else tuple(sign * x for x in v)

    # -- typed getters -------------------------------------------------------------------------
    def scalar(self, value: Any, key: tuple, what: str) -> float | None:
        """A number or a scalar parameter reference: finite, and within ``tol.max_magnitude``."""
        v: Any = None
        if _is_num(value):
            try:
                v = float(value)
            except OverflowError:
                v = math.inf
        elif isinstance(value, str):
            v = self._ref(value, key)
            if v is None:
                return None
        if isinstance(v, float):
            if math.isfinite(v) and abs(v) <= tol.max_magnitude:
                return v
            self.err("bad_value", f"{what} must be a finite number within ±{tol.max_magnitude:g}", key)
            return None
        self.err("bad_value", f"{what} must be a number", key)
        return None

    def vector(self, value: Any, key: tuple, what: str, n: int = 3) -> tuple[float, ...] | None:
        """A list of ``n`` numbers (components may be scalar refs) or a vector reference."""
        if isinstance(value, str):
            v = self._ref(value, key)
            if v is None:
                return None
            if isinstance(v, tuple) and len(v) == n:
                return v
        elif isinstance(value, list) and len(value) == n:
            out = [self.scalar(x, key, what) for x in value]
            return None if any(x is None for x in out) else tuple(out)  # type: ignore[arg-type]
        self.err("bad_value", f"{what} must be a list of {n} numbers", key)
        return None

    def unit(self, value: Any, key: tuple, what: str, n: int = 3) -> tuple[float, ...] | None:
        v = self.vector(value, key, what, n)
        if v is None:
            return None
        norm = math.sqrt(sum(x * x for x in v))
        if abs(norm - 1.0) > UNIT_TOL:
            self.err(
                "non_unit_axis", f"{what} {list(v)} is not a unit vector (length {norm:.6g})", key
            )
            return None
        return v

    def limits(self, value: Any, key: tuple, what: str) -> tuple[float, float] | None:
        if value is None:
            return None
        v = self.vector(value, key, what, 2)
        if v is None:
            return None
        if v[0] > v[1]:
            self.err("inverted_limits", f"{what} [{v[0]:g}, {v[1]:g}]: minimum above maximum", key)
            return None
        return (v[0], v[1])

    def rate(self, value: Any, key: tuple, what: str) -> float | None:
        if value is None:
            return None
        v = self.scalar(value, key, what)
        if v is not None and v < MIN_RATE:
            self.err("bad_value", f"{what} must be at least {MIN_RATE:g}", key)
            return None
        return v

    def origin(self, table: Mapping[str, Any], key: tuple) -> Origin:
        xyz = self.vector(table.get("origin", [0, 0, 0]), key + ("origin",), "origin")
        rpy = self.vector(table.get("rpy", [0, 0, 0]), key + ("rpy",), "rpy")
        return Origin(xyz or (0.0, 0.0, 0.0), rpy or (0.0, 0.0, 0.0))

    def table(self, value: Any, key: tuple, what: str) -> Mapping[str, Any]:
        if isinstance(value, Mapping):
            return value
        self.err("bad_value", f"{what} must be a table", key)
        return {}

    def tables(self, key: str) -> list[tuple[int, Mapping[str, Any]]]:
        value = self.raw.get(key, [])
        if not isinstance(value, list):
            self.err("bad_value", f"{key} must be an array of tables ([[{key}]])", (key,))
            return []
        out = []
        for i, t in enumerate(value):
            if isinstance(t, Mapping):
                out.append((i, t))
            else:
                self.err("bad_value", f"{key}[{i}] must be a table", (key, i))
        return out


def _is_num(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


# ------------------------------------------------------------------------------------------------


def build_spec(
    raw: Mapping[str, Any], path: str, lines: KeyLines, overrides: Mapping[str, Any] | None = None
) -> tuple[ModelSpec | None, list[Finding]]:
    """Read a parsed model; return the spec (None if unusable) and every problem found."""
    r = Reader(path, lines, raw, overrides)
    control, cproblems = collect_control(raw, path, lines.find)
    r.problems.extend(cproblems)
    _unknown_keys(r)
    axes = tuple(a.name for a in control.axes)
    formula = raw.get("formula")
    if formula is not None:
        joints, work, tool = _formula_chain(r, formula)
        if "joints" in raw:
            r.err("bad_value", "a model has either a formula or [[joints]], not both", ("joints",))
    else:
        joints = tuple(_joint(r, i, t) for i, t in r.tables("joints"))
        joints = tuple(j for j in joints if j is not None)
        work = _work(r, raw.get("work"), ("work",))
        tool = _tool(r, raw.get("tool"), ("tool",))
    links = _check_chain(r, joints, axes)
    for what, mount in (("work", work), ("tool", tool)):
        if mount is not None and mount.link not in links:
            r.err(
                "unknown_link",
                f"{what}.link {mount.link!r} is not a link of the chain",
                (what, "link"),
            )
    frames = links + ["work", "tool", "tool_mount"]
    geometry = tuple(g for i, t in r.tables("geometry") if (g := _geometry(r, i, t, frames)))
    parallel = tuple(p for i, t in r.tables("parallel") if (p := _parallel(r, i, t, axes)))
    kin = r.table(raw.get("kinematics", {}), ("kinematics",), "kinematics")
    ik = kin.get("ik", "numeric")
    if ik not in IK_METHODS:
        r.err(
            "bad_value",
            f"kinematics.ik must be one of {', '.join(IK_METHODS)}",
            ("kinematics", "ik"),
        )
        ik = "numeric"
    needs = {"table_table": ("rotation_centre",), "head_bc": ("l1", "l2")}.get(ik, ())
    for p in needs:
        if p not in r.params:
            r.err("unknown_parameter", f"ik {ik!r} needs parameter {p!r}", ("kinematics", "ik"))
    positions = _positions(r, axes)
    timing = read_timing(r)
    name = raw.get("name", Path(path).stem)
    given, md_problems = read_table(raw.get("machine_data"))
    for key, msg in md_problems:
        r.err("bad_value", msg, key)
    if r.problems or work is None or tool is None:
        return None, r.problems
    spec = ModelSpec(
        name=str(name),
        path=path,
        control=control,
        axes=axes,
        links=tuple(links),
        joints=joints,
        work=work,
        tool=tool,
        geometry=geometry,
        parallel=parallel,
        parameters=dict(r.params),
        ik=ik,
        positions=positions,
        formula=formula,
        description=str(raw.get("description", "")),
        timing=timing,
    )
    spec = replace(spec, control=replace(control, machine_data=derive(spec, given)))
    return spec, r.problems


def load_model_control(path: str | Path) -> ControlSpec:
    """The ControlSpec of the model file at ``path`` with its machine data (limits, rates, swivel
    data need the kinematic part); a model whose kinematic part does not load gives the
    control part alone, as :func:`vmach.machine.control.load_control` reads it."""
    text = read_text(path)
    data = parse_toml(text, str(path))
    lines = KeyLines.scan(text, str(path))
    spec, _problems = build_spec(data, str(path), lines)
    if spec is not None:
        return spec.control
    return control_spec(data, str(path), lines.find)


def _joint(r: Reader, i: int, t: Mapping[str, Any], key: tuple | None = None) -> Joint | None:
    key = key or ("joints", i)
    name = t.get("name")
    ok = True
    if not isinstance(name, str) or not name:
        r.err("missing_key", f"joints[{i}] needs a name", key)
        return None
    jtype = t.get("type")
    if jtype not in ("prismatic", "revolute", "fixed"):
        r.err(
            "bad_value", f"joint {name}: type must be prismatic, revolute or fixed", key + ("type",)
        )
        jtype = "fixed"  # placeholder so the chain checks still run; the spec is refused anyway
    for k in ("parent", "child"):
        if not isinstance(t.get(k), str) or not t.get(k):
            r.err("missing_key", f"joint {name}: {k} link is missing", key + (k,))
            ok = False
    axis = r.unit(t.get("axis", [0, 0, 1]), key + ("axis",), f"joint {name}: axis")
    origin = r.origin(t, key)
    variable = None if jtype == "fixed" else t.get("variable", name)
    if variable is not None and not isinstance(variable, str):
        r.err("bad_value", f"joint {name}: variable must be an axis name", key + ("variable",))
        variable = None
    unit = "°" if jtype == "revolute" else "mm"
    limits = r.limits(t.get("limits"), key + ("limits",), f"joint {name}: limits ({unit})")
    rate = r.rate(t.get("max_rate"), key + ("max_rate",), f"joint {name}: max_rate")
    accel = r.rate(t.get("max_accel"), key + ("max_accel",), f"joint {name}: max_accel")
    if not ok:
        return None
    return Joint(
        name,
        jtype,
        t["parent"],
        t["child"],
        axis or (0.0, 0.0, 1.0),
        origin,
        variable,
        limits,
        rate,
        accel,
    )


def _work(r: Reader, t: Any, key: tuple) -> WorkMount | None:
    if t is None:
        r.err("missing_key", "the model needs a [work] table (the workpiece frame)", key)
        return None
    t = r.table(t, key, "work")
    if not isinstance(t.get("link"), str):
        r.err("missing_key", "work.link is missing", key + ("link",))
        return None
    return WorkMount(t["link"], r.origin(t, key))


def _tool(r: Reader, t: Any, key: tuple) -> ToolMount | None:
    if t is None:
        r.err("missing_key", "the model needs a [tool] table (the tool mount)", key)
        return None
    t = r.table(t, key, "tool")
    if not isinstance(t.get("link"), str):
        r.err("missing_key", "tool.link is missing", key + ("link",))
        return None
    direction = r.unit(t.get("direction", [0, 0, 1]), key + ("direction",), "tool.direction")
    length = r.scalar(t.get("length", 0.0), key + ("length",), "tool.length")
    return ToolMount(t["link"], r.origin(t, key), direction or (0.0, 0.0, 1.0), length or 0.0)


def _formula_chain(r: Reader, formula: Any):
    if not isinstance(formula, str):
        r.err("bad_formula", 'formula must be a string such as "WCBVXYZT"', ("formula",))
        return (), None, None
    try:
        chain = parse_formula(formula)
    except FormulaError as exc:
        r.err("bad_formula", f"structure formula {formula!r}: {exc}", ("formula",))
        return (), None, None
    dims = r.table(r.raw.get("dimensions", {}), ("dimensions",), "dimensions")
    known = {j.token for j in chain.joints} | {"W", "T"}
    for k in dims:
        if k not in known:
            r.err(
                "bad_value",
                f"dimensions.{k}: {k} is not in the formula {formula}",
                ("dimensions", k),
            )
    joints = []
    for fj in chain.joints:
        d = r.table(dims.get(fj.token, {}), ("dimensions", fj.token), f"dimensions.{fj.token}")
        entry = {
            "name": fj.token,
            "type": fj.kind,
            "parent": fj.parent,
            "child": fj.child,
            "axis": list(fj.axis),
            **d,
        }
        j = _joint(r, 0, entry, ("dimensions", fj.token))
        if j is not None:
            joints.append(j)
    w = dict(r.table(dims.get("W", {}), ("dimensions", "W"), "dimensions.W"))
    t = dict(r.table(dims.get("T", {}), ("dimensions", "T"), "dimensions.T"))
    w["link"], t["link"] = chain.work_link, chain.tool_link
    return (tuple(joints), _work(r, w, ("dimensions", "W")), _tool(r, t, ("dimensions", "T")))


def _check_chain(r: Reader, joints: tuple[Joint, ...], axes: tuple[str, ...]) -> list[str]:
    """Links of the chain (base first); reports unknown parents, loops, unknown axes."""
    links = ["base"]
    key_of = {}
    for i, j in enumerate(joints):
        key = ("joints", i) if r.raw.get("formula") is None else ("dimensions", j.name)
        key_of[j.name] = key
        if j.child in links:
            r.err(
                "duplicate_name",
                f"joint {j.name}: link {j.child!r} already has a parent",
                key + ("child",),
            )
        else:
            links.append(j.child)
    names = [j.name for j in joints]
    for n in sorted({n for n in names if names.count(n) > 1}):
        r.err("duplicate_name", f"joint name {n!r} is used twice", key_of[n] + ("name",))
    parent_of = {j.child: j.parent for j in joints}
    for j in joints:
        if j.parent not in links:
            r.err(
                "unknown_link",
                f"joint {j.name}: unknown parent link {j.parent!r}",
                key_of[j.name] + ("parent",),
            )
            continue
        seen, cur = {j.child}, j.parent
        while cur != "base" and cur in parent_of:
            if cur in seen:
                r.err(
                    "disconnected_link",
                    f"joint {j.name}: the chain loops and never reaches base",
                    key_of[j.name] + ("parent",),
                )
                break
            seen.add(cur)
            cur = parent_of[cur]
        if j.variable is not None and axes and j.variable not in axes:
            r.err(
                "unknown_axis",
                f"joint {j.name}: axis {j.variable!r} is not in [[axes]]",
                key_of[j.name] + ("variable",),
            )
    return links


def _geometry(r: Reader, i: int, t: Mapping[str, Any], links: list[str]) -> Geometry | None:
    key = ("geometry", i)
    name = str(t.get("name", f"geometry{i}"))
    link = t.get("link")
    ok = True
    if link not in links:
        r.err("unknown_link", f"geometry {name}: unknown link {link!r}", key + ("link",))
        ok = False
    shape = t.get("shape")
    origin = r.origin(t, key)
    size = radius = length = mpath = None
    if shape == "box":
        size = r.vector(t.get("size"), key + ("size",), f"geometry {name}: size")
        if size is not None and not (min(size) > 0 and max(size) <= tol.max_size):
            r.err("bad_value", f"geometry {name}: box sizes must be > 0 and at most {tol.max_size:g} mm",
                  key + ("size",))
            size = None
        ok = ok and size is not None
    elif shape == "cylinder":
        radius = r.scalar(t.get("radius"), key + ("radius",), f"geometry {name}: radius")
        length = r.scalar(t.get("length"), key + ("length",), f"geometry {name}: length")
        for v, k in ((radius, "radius"), (length, "length")):
            if v is not None and not 0 < v <= tol.max_size:
                r.err("bad_value", f"geometry {name}: {k} must be > 0 and at most {tol.max_size:g} mm",
                      key + (k,))
                ok = False
        ok = ok and radius is not None and length is not None
    elif shape == "mesh":
        mpath = t.get("path")
        full = Path(r.path).parent / str(mpath)
        if not isinstance(mpath, str) or not full.is_file():
            r.err(
                "missing_mesh", f"geometry {name}: mesh file {mpath!r} not found", key + ("path",)
            )
            ok = False
        else:
            mpath = str(full)
    else:
        r.err(
            "bad_value", f"geometry {name}: shape must be box, cylinder or mesh", key + ("shape",)
        )
        ok = False
    if not ok:
        return None
    return Geometry(name, link, shape, origin, size, radius, length, mpath)


def _parallel(r: Reader, i: int, t: Mapping[str, Any], axes: tuple[str, ...]) -> Parallel | None:
    key = ("parallel", i)
    name = str(t.get("name", f"parallel{i}"))
    virtual = t.get("virtual")
    if (
        not isinstance(virtual, list)
        or len(virtual) not in (2, 3)
        or not all(isinstance(v, str) for v in virtual)
        or len(set(virtual)) != len(virtual)
    ):
        r.err("bad_value", f"parallel {name}: virtual must name 2 or 3 different axes", key + ("virtual",))
        return None
    for v in virtual:
        if v not in axes:
            r.err("unknown_axis", f"parallel {name}: {v!r} is not in [[axes]]", key + ("virtual",))
    m = len(virtual)
    origin = r.vector(t.get("origin", [0.0] * m), key + ("origin",), f"parallel {name}: origin", m)
    assembly = t.get("assembly", -1)
    if assembly not in (1, -1):
        r.err("bad_value", f"parallel {name}: assembly must be 1 or -1", key + ("assembly",))
    legs_raw = t.get("legs", [])
    if not isinstance(legs_raw, list) or len(legs_raw) != m:
        r.err("bad_value", f"parallel {name}: needs {m} [[parallel.legs]]", key)
        return None
    legs = []
    for j, lt in enumerate(legs_raw):
        lk = key + ("legs", j)
        lt = r.table(lt, lk, "leg")
        drive = lt.get("drive")
        if not isinstance(drive, str) or not drive or drive in axes:
            r.err(
                "bad_value",
                f"parallel {name}: leg {j + 1} needs a drive name that is not an axis",
                lk + ("drive",),
            )
            continue
        g = r.vector(lt.get("guide_point"), lk + ("guide_point",), f"{drive}: guide_point", m)
        u = r.unit(lt.get("guide_dir"), lk + ("guide_dir",), f"{drive}: guide_dir", m)
        b = r.vector(lt.get("attach", [0.0] * m), lk + ("attach",), f"{drive}: attach", m)
        length = r.scalar(lt.get("length"), lk + ("length",), f"{drive}: length")
        if length is not None and length <= 0:
            r.err("bad_value", f"{drive}: strut length must be > 0", lk + ("length",))
            length = None
        root = lt.get("root", -1)
        if isinstance(root, bool) or root not in (1, -1):
            r.err("bad_value", f"{drive}: root must be 1 or -1", lk + ("root",))
            continue
        lim = r.limits(lt.get("limits"), lk + ("limits",), f"{drive}: limits (mm)")
        rate = r.rate(lt.get("max_rate"), lk + ("max_rate",), f"{drive}: max_rate")
        if None in (g, u, b, length):
            continue
        legs.append(Leg(drive, g, u, length, b, int(root), lim, rate))
    if len(legs) != m or origin is None or assembly not in (1, -1):
        return None
    return Parallel(name, tuple(virtual), origin, tuple(legs), int(assembly))


def _positions(r: Reader, axes: tuple[str, ...]) -> dict[str, dict[str, float]]:
    table = r.table(r.raw.get("positions", {}), ("positions",), "positions")
    out: dict[str, dict[str, float]] = {}
    for pname, vals in table.items():
        vals = r.table(vals, ("positions", pname), f"positions.{pname}")
        row = {}
        for a, v in vals.items():
            if a not in axes:
                r.err(
                    "unknown_axis",
                    f"positions.{pname}: {a!r} is not an axis",
                    ("positions", pname, a),
                )
                continue
            fv = r.scalar(v, ("positions", pname, a), f"positions.{pname}.{a}")
            if fv is not None:
                row[a] = fv
        out[pname] = row
    return out
