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
spindle, and swivel data record 1 (``$TC_CARR``) of a machine with two rotary axes: offset
vectors l1..l4 (1..6, 15..20), the rotary axes' vectors (7..9, 10..12), the kinematic type (23:
T head, P table, M mixed), their travel (30..33) and names (35, 36); see :func:`swivel`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

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
        "$MC_AXCONF_MACHAX_USED": {k: k + 1 for k in range(len(names))},
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


def _path(spec: ModelSpec, link: str) -> list[Joint]:
    """The joints from the base out to ``link``."""
    by_child = {j.child: j for j in spec.joints}
    out: list[Joint] = []
    while link in by_child and by_child[link] not in out:
        out.append(by_child[link])
        link = by_child[link].parent
    return out[::-1]


def _zero_pose(joints: list[Joint]) -> list[np.ndarray]:
    """(4, 4) pose in the base of each joint's frame (after its origin), all axes at 0."""
    pose, out = np.eye(4), []
    for j in joints:
        pose = pose @ j.origin.matrix
        out.append(pose)
    return out


def swivel(spec: ModelSpec) -> dict[str, Any]:
    """Swivel data record 1 of a machine with two rotary axes, as CYCLE800 reads it (SINUMERIK
    Operate commissioning, "Swiveling"): rotary axis 1 is the one axis 2 is built on (with mixed
    kinematics the head's); axis vectors describe the tool's turn relative to the part, so an
    axis that turns the workpiece has its vector reversed; offset vectors at all axes zero:
    table (P) l2 machine reference → pivot 1, l3 pivot 1 → pivot 2, l4 = −(l2 + l3); head (T)
    l3 tool reference → pivot 2, l2 pivot 2 → pivot 1, l1 = −(l2 + l3); mixed (M) l2 tool
    reference → pivot 1 (head), l1 = −l2, l3 machine reference → pivot 2 (table), l4 = −l3. The
    machine and tool reference are the tool tip with all axes at zero (vmach's X Y Z carry the
    tip, the tool length being compensated)."""
    tool_path = _path(spec, spec.tool.link)
    work_path = _path(spec, spec.work.link)
    tip = (_zero_pose(tool_path)[-1] if tool_path else np.eye(4)) @ spec.tool.origin.matrix
    ref = tip[:3, 3]
    found = []                                   # (joint, pivot, direction, on the work side)
    for path, work in ((tool_path, False), (work_path, True)):
        for j, pose in zip(path, _zero_pose(path), strict=True):
            if j.type == "revolute":
                found.append((j, pose[:3, 3], pose[:3, :3] @ np.asarray(j.axis, float), work))
    if len(found) != 2:
        return {}
    head = [f for f in found if not f[3]]
    table = [f for f in found if f[3]]
    kind = "P" if not head else "T" if not table else "M"
    first, second = (head + table) if kind == "M" else found if kind == "T" else table
    p1, p2 = first[1], second[1]
    zero = np.zeros(3)
    if kind == "P":
        l1, l2, l3 = zero, p1 - ref, p2 - p1
        l4 = -(l2 + l3)
    elif kind == "T":
        l3, l2, l4 = p2 - ref, p1 - p2, zero
        l1 = -(l2 + l3)
    else:
        l2, l3 = p1 - ref, p2 - ref
        l1, l4 = -l2, -l3
    md: dict[str, Any] = {"$TC_CARR23": {1: kind}, "$TC_CARR34": {1: spec.name}}
    for base, vec in ((1, l1), (4, l2), (15, l3), (18, l4)):
        for i in range(3):
            md[f"$TC_CARR{base + i}"] = {1: _clean(vec[i])}
    for k, (j, _pivot, direction, work) in enumerate((first, second)):
        v = -direction if work else direction
        for i in range(3):
            md[f"$TC_CARR{7 + 3 * k + i}"] = {1: _clean(v[i])}
        if j.limits is not None:
            md[f"$TC_CARR{30 + k}"] = {1: float(j.limits[0])}
            md[f"$TC_CARR{32 + k}"] = {1: float(j.limits[1])}
        md[f"$TC_CARR{35 + k}"] = {1: j.variable or j.name}
    return md


def _clean(x: float) -> float:
    """A component without rounding noise (and without −0)."""
    v = round(float(x), 9)
    return v + 0.0
