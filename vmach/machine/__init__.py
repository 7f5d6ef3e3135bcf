"""Machine models (TOML), structure formulas, batched forward/inverse kinematics, limits.

Entry points::

    model = load_model("s5d")                  # path or bare name in models/
    model.control                              # vmach.canon.ControlSpec for interpreters
    pose = model.fk(q)                         # q (n, k) → pose.tip, pose.axis (n, 3), work frame
    frames = model.link2base(q)                # {link: (n, 4, 4)}, + "work", "tool", "tool_mount"
    sol = model.ik(tip, axis)                  # sol.q (n, k), sol.ok (n,), sol.drives
    axis_limit_findings(model, q)              # axis_limit / unreachable findings
    rate_findings(model, start, end, seconds)  # rate_limit findings
"""

import importlib
from typing import TYPE_CHECKING

#: name -> the submodule that holds it: loaded on first use, so that reading a model's
#: ``[control]`` (``vmach check``) does not import numpy and the kinematics
_WHERE = {
    "control_spec": "control", "load_control": "control",
    "axis_limit_findings": "limits", "limit_mask": "limits", "rate_findings": "limits",
    "unreachable_findings": "limits",
    "IkResult": "model", "Model": "model", "ToolPose": "model", "load_model": "model",
    "resolve_path": "model",
}

if TYPE_CHECKING:  # pragma: no cover - for readers and type checkers
    from vmach.machine.control import control_spec, load_control
    from vmach.machine.limits import axis_limit_findings, limit_mask, rate_findings, unreachable_findings
    from vmach.machine.model import IkResult, Model, ToolPose, load_model, resolve_path


def __getattr__(name: str):
    if name not in _WHERE:
        raise AttributeError(f"module 'vmach.machine' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"vmach.machine.{_WHERE[name]}"), name)
    globals()[name] = value
    return value


__all__ = [
    "IkResult",
    "Model",
    "ToolPose",
    "axis_limit_findings",
    "control_spec",
    "limit_mask",
    "load_control",
    "load_model",
    "rate_findings",
    "resolve_path",
    "unreachable_findings",
]
