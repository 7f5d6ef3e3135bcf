"""The machine model object: loading, forward and inverse kinematics, hybrid drives.

:class:`Model` is thin: it holds a :class:`ModelSpec` and its compiled :class:`Chain` and
delegates to the module functions of ``chain``, ``closed_form``, ``parallel`` and ``numeric``.
Axis values are always ``q : (n, k) float`` in ``model.axes`` order (mm, degrees).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from vmach.bundled import MODELS_DIR  # the bundled models (checkout or wheel)
from vmach.errors import InputError, ModelError
from vmach.findings import error, sort_key
from vmach.machine import closed_form, numeric, parallel
from vmach.machine.chain import Chain
from vmach.machine.control import parse_toml, read_text
from vmach.machine.loader import build_spec
from vmach.machine.spec import ModelSpec, TimingSpec
from vmach.machine.tomlpos import KeyLines


@dataclass(frozen=True)
class ToolPose:
    """Tool poses in the workpiece frame: tip (n, 3) float, mm; axis (n, 3) float, unit."""

    tip: np.ndarray
    axis: np.ndarray


@dataclass(frozen=True)
class IkResult:
    """Inverse kinematics of n poses.

    q : (n, k) float, mm / degrees, model axis order. ok : (n,) bool — False = unreachable
    (no solution, or a parallel drive without a real root). singular : (n,) bool — B = 0 poses
    where the strategy chose C. drives : ``{name: (n,) float, mm}`` for hybrids (NaN where
    unreachable).
    """

    axes: tuple[str, ...]
    q: np.ndarray
    ok: np.ndarray
    singular: np.ndarray
    drives: Mapping[str, np.ndarray] = field(default_factory=dict)

    def row(self, i: int = 0) -> dict[str, float]:
        out = {a: float(self.q[i, j]) for j, a in enumerate(self.axes)}
        out.update({d: float(v[i]) for d, v in self.drives.items()})
        return out


def resolve_path(model: str | Path) -> Path:
    """A model file path, or a bare name (``s5d``) looked up in the project's ``models/``."""
    p = Path(model)
    if p.is_file():
        return p
    for folder in (Path.cwd() / "models", MODELS_DIR):
        for cand in (folder / p.name, folder / f"{p.name}.toml"):
            if cand.is_file():
                return cand
    raise InputError(f"{model}: no such model file (nor models/{p.name}.toml)", kind="unreadable")


def load_model(path: str | Path, parameters: Mapping[str, Any] | None = None) -> Model:
    """Load a machine model; raise :class:`ModelError` listing every problem with its line."""
    p = resolve_path(path)
    text = read_text(p)
    raw = parse_toml(text, str(p))
    return Model.build(raw, KeyLines.scan(text, str(p)), parameters)


class Model:
    """A loaded machine: ``control`` (ControlSpec), ``axes``, kinematics, limits."""

    def __init__(self, spec: ModelSpec, raw: Mapping[str, Any], lines: KeyLines):
        self.spec = spec
        self._raw = raw
        self._lines = lines
        self.chain = Chain(spec)
        self.control = spec.control
        self.axes = spec.axes
        self.name = spec.name
        self.rotary = np.array([a.kind == "rotary" for a in spec.control.axes], bool)
        self.home = np.array([a.home for a in spec.control.axes], float)
        self.drives = tuple(d for m in spec.parallel for d in m.drives)

    @classmethod
    def build(
        cls, raw: Mapping[str, Any], lines: KeyLines, parameters: Mapping[str, Any] | None = None
    ) -> Model:
        spec, problems = build_spec(raw, lines.path, lines, parameters)
        if spec is None:
            raise ModelError(sorted(problems, key=sort_key))
        model = cls(spec, raw, lines)
        bad = model._self_check()
        if bad:
            raise ModelError([error("closed_form_mismatch", bad, lines.find(("kinematics", "ik")))])
        return model

    def with_parameters(self, **values: Any) -> Model:
        """The same model with setup parameters changed (``rotation_centre=(x, y, z)``)."""
        new = dict(self.spec.parameters)
        for name, v in values.items():
            if name not in new:
                known = ", ".join(sorted(new)) or "none"
                raise InputError(f"{self.name} has no parameter {name!r} (parameters: {known})")
            old = new[name]
            if isinstance(old, tuple):
                v = tuple(float(x) for x in np.atleast_1d(v))
                if len(v) != len(old):
                    raise InputError(f"parameter {name} needs {len(old)} values")
            else:
                if np.size(v) != 1:
                    raise InputError(f"parameter {name} needs one value")
                v = float(np.ravel(v)[0])
            new[name] = v
        return Model.build(self._raw, self._lines, new)

    # -- limits and rates of axes and drives -------------------------------------------------
    def _joint_of(self, axis: str):
        return next((j for j in self.spec.joints if j.variable == axis), None)

    @property
    def limits(self) -> np.ndarray:
        """(k, 2) float travel limits per axis, mm / degrees; NaN where unlimited."""
        out = np.full((len(self.axes), 2), np.nan)
        for i, a in enumerate(self.axes):
            j = self._joint_of(a)
            if j is not None and j.limits is not None:
                out[i] = j.limits
        return out

    @property
    def max_rates(self) -> np.ndarray:
        """(k,) float, mm/min or degrees/min; NaN where not stated."""
        out = np.full(len(self.axes), np.nan)
        for i, a in enumerate(self.axes):
            j = self._joint_of(a)
            if j is not None and j.max_rate is not None:
                out[i] = j.max_rate
        return out

    @property
    def max_accel(self) -> np.ndarray:
        """(k,) float, mm/s² or degrees/s²; NaN where not stated."""
        out = np.full(len(self.axes), np.nan)
        for i, a in enumerate(self.axes):
            j = self._joint_of(a)
            if j is not None and j.max_accel is not None:
                out[i] = j.max_accel
        return out

    @property
    def timing(self) -> TimingSpec:
        """Tool-change, spindle and corner data for the cycle time (``[timing]``)."""
        return self.spec.timing

    @property
    def drive_limits(self) -> np.ndarray:
        """(d, 2) float limits of the parallel drives, mm; NaN where unlimited."""
        legs = [leg for m in self.spec.parallel for leg in m.legs]
        return np.array([leg.limits or (np.nan, np.nan) for leg in legs], float).reshape(-1, 2)

    @property
    def drive_rates(self) -> np.ndarray:
        legs = [leg for m in self.spec.parallel for leg in m.legs]
        return np.array([np.nan if leg.max_rate is None else leg.max_rate for leg in legs], float)

    # -- forward kinematics ------------------------------------------------------------------
    def q(self, values: Mapping[str, float] | None = None, n: int = 1) -> np.ndarray:
        """(n, k) axis array: ``values`` by name, home for the rest."""
        q = np.tile(self.home, (n, 1))
        for name, v in (values or {}).items():
            if name not in self.axes:
                raise InputError(f"{self.name} has no axis {name!r} (axes: {' '.join(self.axes)})")
            q[:, self.axes.index(name)] = v
        return q

    @property
    def tool_spindle(self) -> int | None:
        """The spindle that turns the cutter (``[control] tool_spindle``), None if not stated."""
        ctl = self._raw.get("control", {}) if isinstance(self._raw, Mapping) else {}
        ts = ctl.get("tool_spindle") if isinstance(ctl, Mapping) else None
        return int(ts) if isinstance(ts, int) and not isinstance(ts, bool) else None

    def fk(self, q: np.ndarray) -> ToolPose:
        """Tool tip and axis in the workpiece frame for q : (n, k) float (mm, degrees)."""
        tip, axis = self.chain.tool_in_work(q)
        return ToolPose(tip, axis)

    def link2base(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """Every link's pose ``{name: (n, 4, 4)}`` plus ``work``, ``tool``, ``tool_mount``."""
        return self.chain.link2base(q)

    def tool2work(self, q: np.ndarray) -> np.ndarray:
        """(n, 4, 4) tool frame (origin at the tip, z = tool axis) in the workpiece frame."""
        return self.chain.tool2work(q)

    # -- hybrids: drives ---------------------------------------------------------------------
    def drive_values(self, q: np.ndarray) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """Parallel drive values for axis values q (n, k): ``{drive: (n,) mm}``, ok (n,) bool."""
        q = np.atleast_2d(np.asarray(q, float))
        out: dict[str, np.ndarray] = {}
        ok = np.ones(q.shape[0], bool)
        for mech in self.spec.parallel:
            cols = [self.axes.index(v) for v in mech.virtual]
            p, good = parallel.inverse(mech, q[:, cols])
            ok &= good
            out.update({d: p[:, i] for i, d in enumerate(mech.drives)})
        return out, ok

    def axes_from_drives(
        self, q: np.ndarray, drives: Mapping[str, Any]
    ) -> tuple[np.ndarray, np.ndarray]:
        """Replace the virtual axes of q (n, k) by the forward solution of the given drives."""
        q = np.array(np.atleast_2d(q), float)
        ok = np.ones(q.shape[0], bool)
        for mech in self.spec.parallel:
            given = [d in drives for d in mech.drives]
            if not any(given):
                continue
            if not all(given):
                raise InputError(f"give all of {', '.join(mech.drives)} or none")
            p = np.stack(
                [np.broadcast_to(np.asarray(drives[d], float), q.shape[:1]) for d in mech.drives],
                axis=1,
            )
            v, good = parallel.forward(mech, p)
            ok &= good
            for i, name in enumerate(mech.virtual):
                q[:, self.axes.index(name)] = v[:, i]
        return q, ok

    # -- inverse kinematics ------------------------------------------------------------------
    def ik(
        self, tip, axis, *, previous: np.ndarray | None = None, strategy: str = "keep"
    ) -> IkResult:
        """Axis values that put the tool tip at ``tip`` with tool axis ``axis`` (work frame).

        tip : (n, 3) float, mm. axis : (n, 3) float (normalised here).
        previous : (k,) axis values before the first pose (start guess; C for the B = 0
        strategy); default home. strategy : ``"keep"`` or ``"shortest"`` (closed forms).
        """
        tip = np.atleast_2d(np.asarray(tip, float))
        unit, nonzero = closed_form.unit_rows(axis)
        n = tip.shape[0]
        prev = self.home if previous is None else np.asarray(previous, float)
        q = np.tile(prev, (n, 1))
        singular = np.zeros(n, bool)
        ok = nonzero.copy()
        if self.spec.ik == "table_table":
            c_prev = float(prev[self.axes.index("C")])
            vals, singular = closed_form.table_table_ik(
                tip,
                unit,
                self.spec.parameters["rotation_centre"],
                strategy=strategy,
                previous_c=c_prev,
            )
            for name, v in vals.items():
                q[:, self.axes.index(name)] = v
        elif self.spec.ik == "head_bc":
            q, singular = self._head_ik(tip, unit, prev, strategy)
        else:
            q, good = numeric.solve(
                lambda x: self.chain.tool_in_work(x), tip, unit, q, rotary=self.rotary
            )
            ok &= good
        drives, good = self.drive_values(q)
        ok &= good
        return IkResult(self.axes, q, ok, singular, drives)

    def _head_ik(self, tip, unit, prev, strategy):
        P = self._head_geometry()
        R, t = P["work2base"][:3, :3], P["work2base"][:3, 3]
        tip_b = tip @ R.T + t
        a_b = unit @ R.T
        b, c, singular = closed_form.head_bc_ik(
            a_b, strategy=strategy, previous_c=float(prev[self.axes.index("C")])
        )
        p2 = closed_form.head_platform_point(
            tip_b, b, c, float(self.spec.parameters["l1"]), float(self.spec.parameters["l2"])
        )
        lin = np.linalg.solve(P["M"], (p2 - P["home"]).T).T
        q = np.tile(prev, (tip.shape[0], 1))
        for i, name in enumerate(P["linear"]):
            q[:, self.axes.index(name)] = lin[:, i]
        q[:, self.axes.index("B")] = b
        q[:, self.axes.index("C")] = c
        return q, singular

    def _head_geometry(self) -> dict[str, Any]:
        """Constants of a B/C head chain: the linear joints before the head, their directions."""
        path = self.chain.tool_path
        lin = []
        for st in path:
            if st.kind == 2:
                break
            if st.kind == 1:
                lin.append(st)
        zero = np.zeros((1, len(self.axes)))
        poses = self.chain.link2base(zero)
        names = [self.axes[st.col] for st in lin]
        joints = {j.variable: j for j in self.spec.joints}
        M = np.stack(
            [
                poses[joints[nm].parent][0, :3, :3]
                @ joints[nm].origin.rotation
                @ np.asarray(joints[nm].axis)
                for nm in names
            ],
            axis=1,
        )
        home = poses[joints[names[-1]].child][0, :3, 3]
        return {"work2base": poses["work"][0], "M": M, "home": home, "linear": names}

    def _self_check(self) -> str:
        """Verify a declared closed form against this chain's FK; '' if it holds."""
        if self.spec.ik == "numeric":
            return ""
        need = {"X", "Y", "Z", "B", "C"}
        if not need <= set(self.axes):
            return f"ik {self.spec.ik!r} needs axes X Y Z B C"
        if self.spec.ik == "head_bc":
            work_joints = [st for st in self.chain.work_path if st.kind]
            lin = [st for st in self.chain.tool_path if st.kind == 1]
            if work_joints or len(lin) != 3:
                return "ik 'head_bc' needs three linear axes carrying the head and a fixed table"
        rng = np.random.default_rng(12345)
        q = np.tile(self.home, (32, 1))
        for i in range(len(self.axes)):
            q[:, i] = rng.uniform(-40.0, 40.0, 32) + (self.home[i] if not self.rotary[i] else 0)
        q[:, self.axes.index("B")] = rng.uniform(5.0, 80.0, 32)
        pose = self.fk(q)
        try:
            sol = self.ik(pose.tip, pose.axis)
        except np.linalg.LinAlgError:
            return f"ik {self.spec.ik!r}: the head's linear axes are not independent"
        back = self.fk(sol.q)
        err = max(np.abs(back.tip - pose.tip).max(), np.abs(back.axis - pose.axis).max())
        if not np.isfinite(err) or err > 1e-6:
            return (
                f"ik {self.spec.ik!r} does not invert this chain (round-trip error {err:.3g});"
                " check the joint axes, signs and parameters against the closed form"
            )
        return ""
