"""The control's data of a machine model: ``[machine_data]`` plus what the model already says.

A model may give any machine, setting, swivel or PLC datum a program reads, by its name with or
without ``$`` (TOML keys with ``$`` need quotes)::

    [machine_data]
    MN_SCALING_SYSTEM_IS_METRIC = 1
    MC_TRAFO_TYPE_1 = 24                       # a scalar
    MC_AXCONF_GEOAX_NAME_TAB = ["X", "Y", "Z"]   # an array, index 0, 1, 2 ...
    MA_POS_LIMIT_PLUS = { X = 500.0, Y = 450.0 } # an axis datum
    MA_DRIVE_AX_RATIO_DENOM = { S1 = [1, 1, 4] } # [n, axis]: a list per axis
    TC_CARR1 = { 1 = 0.0 }                     # swivel data record 1
    A_IN = { 1 = 1 }                           # PLC / I/O start values

What the model knows is filled in unless ``[machine_data]`` says otherwise: axis names
(``$MN_AXCONF_MACHAX_NAME_TAB``, ``$MC_AXCONF_CHANAX_NAME_TAB``, ``$MC_AXCONF_GEOAX_NAME_TAB``),
rotary and modulo axes (``$MA_IS_ROT_AX``, ``$MA_ROT_IS_MODULO``, ``$MA_MODULO_RANGE``), travel
limits (``$MA_POS_LIMIT_PLUS/MINUS``), rates (``$MA_MAX_AX_VELO``, mm/min or deg/min),
accelerations (``$MA_MAX_AX_ACCEL``: m/s² for linear axes, rev/s² for rotary ones), the metric
basic system (models are in mm), the transverse axis (``$MC_DIAMETER_AX_DEF``), the master
spindle, and swivel data record 1 (``$TC_CARR``) of a machine with two rotary axes: the rotary
axes' directions (7..9, 10..12), the kinematic type (23: T head, P table, M mixed), their
travel (30..33) and names (35, 36). The offset vectors (1..6, 15..20) are not derived: a model
gives them in ``[machine_data]`` when a program needs them.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from vmach.canon import ControlSpec
from vmach.machine.spec import Joint, ModelSpec

#: name prefixes a ``[machine_data]`` key may have
PREFIXES = ("MN_", "MC_", "MA_", "SN_", "SC_", "SA_", "TC_CARR", "A_", "AN_")

Value = int | float | str


def _scalar(v: Any) -> bool:
    return isinstance(v, int | float | str) and not (isinstance(v, float) and v != v)


def read_table(raw: Any) -> tuple[dict[str, Any], list[tuple[tuple, str]]]:
    """``[machine_data]`` as ``{"$NAME": value or {index: value}}`` and the problems found,
    each ``(key path, message)``."""
    out: dict[str, Any] = {}
    problems: list[tuple[tuple, str]] = []
    if raw is None:
        return out, problems
    if not isinstance(raw, Mapping):
        return out, [(("machine_data",), "machine_data must be a table")]
    for key, value in raw.items():
        name = str(key).upper().lstrip("$")
        where = ("machine_data", key)
        if not name.startswith(PREFIXES):
            problems.append((where, f"machine_data.{key}: not a machine, setting, swivel or PLC datum "
                             f"(names start with {', '.join(PREFIXES)})"))
            continue
        if isinstance(value, bool):
            value = int(value)
        if _scalar(value):
            out["$" + name] = value
        elif isinstance(value, list) and all(_scalar(v) for v in value):
            out["$" + name] = {i: v for i, v in enumerate(value)}
        elif isinstance(value, Mapping):
            table: dict[Any, Any] = {}
            for k, v in value.items():
                index: Any = int(k) if str(k).isdigit() else str(k).upper()
                if isinstance(v, bool):
                    v = int(v)
                if _scalar(v):
                    table[index] = v
                elif isinstance(v, list) and all(_scalar(x) for x in v):
                    table.update({(i, index): x for i, x in enumerate(v)})
                else:
                    problems.append((where + (k,), f"machine_data.{key}.{k}: a number, string or list"))
            out["$" + name] = table
        else:
            problems.append((where, f"machine_data.{key}: a number, string, list or table"))
    return out, problems


def derive(spec: ModelSpec, given: Mapping[str, Any]) -> dict[str, Any]:
    """The machine data of a loaded model: what the model knows, overlaid by ``given``."""
    control: ControlSpec = spec.control
    names = [a.name for a in control.axes]
    md: dict[str, Any] = {
        "$MN_SCALING_SYSTEM_IS_METRIC": 1,
        "$MN_AXCONF_MACHAX_NAME_TAB": dict(enumerate(names)),
        "$MC_AXCONF_CHANAX_NAME_TAB": dict(enumerate(names)),
        "$MC_AXCONF_GEOAX_NAME_TAB": dict(enumerate(control.geometry)),
        "$MC_SPIND_DEF_MASTER_SPIND": control.master_spindle,
        "$MC_DIAMETER_AX_DEF": control.transverse or "",
        "$MA_IS_ROT_AX": {a.name: int(a.kind == "rotary") for a in control.axes},
        "$MA_ROT_IS_MODULO": {a.name: int(a.modulo is not None) for a in control.axes},
        "$MA_MODULO_RANGE": {a.name: a.modulo for a in control.axes if a.modulo is not None},
    }
    plus, minus, velo, accel = {}, {}, {}, {}
    for j in spec.joints:
        v = j.variable
        if v is None or v not in names:
            continue
        if j.limits is not None:
            minus[v], plus[v] = float(j.limits[0]), float(j.limits[1])
        if j.max_rate is not None:
            velo[v] = float(j.max_rate)
        if j.max_accel is not None:
            accel[v] = float(j.max_accel) / (360.0 if j.type == "revolute" else 1000.0)
    md.update({"$MA_POS_LIMIT_PLUS": plus, "$MA_POS_LIMIT_MINUS": minus, "$MA_MAX_AX_VELO": velo,
               "$MA_MAX_AX_ACCEL": accel})
    md.update(swivel(spec))
    for name, value in given.items():
        if isinstance(value, Mapping) and isinstance(md.get(name), Mapping):
            md[name] = {**md[name], **value}
        else:
            md[name] = value
    return {k: v for k, v in md.items() if v != {}}


def _side(spec: ModelSpec, link: str) -> list[Joint]:
    """Revolute joints between the base and ``link``, from the base outward."""
    by_child = {j.child: j for j in spec.joints}
    out: list[Joint] = []
    seen = set()
    while link in by_child and link not in seen:
        seen.add(link)
        j = by_child[link]
        if j.type == "revolute":
            out.append(j)
        link = j.parent
    return out[::-1]


def swivel(spec: ModelSpec) -> dict[str, Any]:
    """Swivel data record 1 of a machine with two rotary axes (see the module docstring)."""
    table = _side(spec, spec.work.link)
    head = _side(spec, spec.tool.link)
    rotary = head + table
    if len(rotary) != 2:
        return {}
    kind = "P" if not head else "T" if not table else "M"
    md: dict[str, Any] = {"$TC_CARR23": {1: kind}}
    for k, j in enumerate(rotary):
        for i, c in enumerate(j.axis):
            md[f"$TC_CARR{7 + 3 * k + i}"] = {1: float(c)}
        if j.limits is not None:
            md[f"$TC_CARR{30 + k}"] = {1: float(j.limits[0])}
            md[f"$TC_CARR{32 + k}"] = {1: float(j.limits[1])}
        md[f"$TC_CARR{35 + k}"] = {1: j.variable or j.name}
    md["$TC_CARR34"] = {1: spec.name}
    return md
