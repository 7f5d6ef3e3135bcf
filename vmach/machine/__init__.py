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

from vmach.machine.control import control_spec, load_control
from vmach.machine.limits import (
    axis_limit_findings,
    limit_mask,
    rate_findings,
    unreachable_findings,
)
from vmach.machine.model import IkResult, Model, ToolPose, load_model, resolve_path

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
