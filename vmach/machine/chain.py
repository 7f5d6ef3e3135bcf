"""Batched forward kinematics of a serial chain (numpy; n poses at once).

Two paths, one meaning:

- :meth:`Chain.tool_in_work` — the fast path: tool tip and tool axis in the workpiece frame for
  n poses, by moving only a point and a direction through the joints (component arrays, no
  4×4 products). This is what limits, post-checks and stock sweeps call millions of times.
- :meth:`Chain.link2base` — every link's pose ``(n, 4, 4)`` for collision checks, plus the
  frames ``work``, ``tool`` (origin at the tip, z along the tool axis) and ``tool_mount``.

Both compute ``tool2work = inv(work2base) @ tool2base``; the tests hold them equal.
Axis values ``q`` are ``(n, k)`` float in the model's axis order, mm and degrees.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vmach.machine.spec import Joint, ModelSpec

_FIXED, _PRISMATIC, _REVOLUTE = 0, 1, 2
_DEG = np.pi / 180.0


def align_z(direction) -> np.ndarray:
    """(3, 3) rotation taking (0, 0, 1) to the unit vector ``direction`` (shortest turn)."""
    d = np.asarray(direction, float)
    z = np.array([0.0, 0.0, 1.0])
    c = float(d @ z)
    if c > 1 - 1e-15:
        return np.eye(3)
    if c < -1 + 1e-15:
        return np.diag([1.0, -1.0, -1.0])  # half turn about x
    v = np.cross(z, d)
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + vx + vx @ vx / (1 + c)


def rotation_matrices(axis, angle_rad: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotations about the unit ``axis`` (3,) by ``angle_rad`` (n,) radians."""
    a = np.asarray(axis, float)
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    out = np.empty(angle_rad.shape + (3, 3))
    out[:] = np.eye(3)
    out += s[:, None, None] * k
    out += (1 - c)[:, None, None] * (k @ k)
    return out


@dataclass(frozen=True)
class _Step:
    kind: int
    col: int  # column of q, -1 for fixed
    axis: np.ndarray  # (3,)
    rot: np.ndarray | None  # (3, 3) origin rotation, None if identity
    trans: np.ndarray | None  # (3,) origin translation, None if zero
    principal: int  # 0/1/2 if axis is ±e_k, else -1
    sign: float

    @classmethod
    def of(cls, joint: Joint, col: int) -> _Step:
        kind = {"fixed": _FIXED, "prismatic": _PRISMATIC, "revolute": _REVOLUTE}[joint.type]
        axis = np.asarray(joint.axis, float)
        rot = joint.origin.rotation
        trans = np.asarray(joint.origin.xyz, float)
        principal, sign = -1, 1.0
        for i in range(3):
            if abs(abs(axis[i]) - 1.0) < 1e-15:
                principal, sign = i, float(np.sign(axis[i]))
        return cls(
            kind,
            col,
            axis,
            None if np.allclose(rot, np.eye(3), 0, 0) else rot,
            None if not trans.any() else trans,
            principal,
            sign,
        )


def _rotate(v, step: _Step, c, s):
    """Rotate component triple ``v`` about ``step.axis`` with cos ``c``/sin ``s`` arrays."""
    x, y, z = v
    if step.principal >= 0:
        s = s * step.sign if step.sign < 0 else s
        if step.principal == 0:
            return (x, c * y - s * z, s * y + c * z)
        if step.principal == 1:
            return (c * x + s * z, y, -s * x + c * z)
        return (c * x - s * y, s * x + c * y, z)
    a0, a1, a2 = step.axis
    dot = (a0 * x + a1 * y + a2 * z) * (1 - c)
    return (
        x * c + (a1 * z - a2 * y) * s + a0 * dot,
        y * c + (a2 * x - a0 * z) * s + a1 * dot,
        z * c + (a0 * y - a1 * x) * s + a2 * dot,
    )


def _affine(v, rot, trans, inverse=False):
    x, y, z = v
    if inverse:
        if trans is not None:
            x, y, z = x - trans[0], y - trans[1], z - trans[2]
        if rot is not None:
            r = rot
            x, y, z = (
                r[0, 0] * x + r[1, 0] * y + r[2, 0] * z,
                r[0, 1] * x + r[1, 1] * y + r[2, 1] * z,
                r[0, 2] * x + r[1, 2] * y + r[2, 2] * z,
            )
        return (x, y, z)
    if rot is not None:
        r = rot
        x, y, z = (
            r[0, 0] * x + r[0, 1] * y + r[0, 2] * z,
            r[1, 0] * x + r[1, 1] * y + r[1, 2] * z,
            r[2, 0] * x + r[2, 1] * y + r[2, 2] * z,
        )
    if trans is not None:
        x, y, z = x + trans[0], y + trans[1], z + trans[2]
    return (x, y, z)


class Chain:
    """Compiled chain of a :class:`ModelSpec` (immutable after construction)."""

    def __init__(self, spec: ModelSpec):
        self.spec = spec
        self.axes = spec.axes
        col = {a: i for i, a in enumerate(spec.axes)}
        self.joints = spec.joints
        self._by_child = {j.child: j for j in spec.joints}
        self._steps = {
            j.name: _Step.of(j, col.get(j.variable, -1) if j.variable else -1) for j in spec.joints
        }
        self.tool_path = self._path(spec.tool.link)
        self.work_path = self._path(spec.work.link)
        t = spec.tool
        self.tool_frame = t.origin.matrix
        self.tool_frame[:3, :3] = t.origin.rotation @ align_z(t.direction)
        self.mount_frame = self.tool_frame.copy()
        self.mount_frame[:3, 3] += self.tool_frame[:3, 2] * t.length
        self.work_frame = spec.work.origin.matrix

    def _path(self, link: str) -> tuple[_Step, ...]:
        """Steps from base out to ``link``."""
        out = []
        while link != "base":
            j = self._by_child[link]
            out.append(self._steps[j.name])
            link = j.parent
        return tuple(out[::-1])

    # ---------------------------------------------------------------------------------------
    def tool_in_work(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Tool tip and tool axis in the workpiece frame.

        q : (n, k) float, mm / degrees, model axis order.
        Returns tip : (n, 3) float, mm; axis : (n, 3) float, unit, from tip toward spindle.
        """
        q = np.atleast_2d(np.asarray(q, float))
        n = q.shape[0]
        cols = np.ascontiguousarray(q.T)
        trig: dict[int, tuple[np.ndarray, np.ndarray]] = {}

        def cs(col):
            if col not in trig:
                ang = cols[col] * _DEG
                trig[col] = (np.cos(ang), np.sin(ang))
            return trig[col]

        p = tuple(float(v) for v in self.tool_frame[:3, 3])
        d = tuple(float(v) for v in self.tool_frame[:3, 2])
        for st in reversed(self.tool_path):
            if st.kind == _PRISMATIC:
                qv = cols[st.col]
                p = (p[0] + st.axis[0] * qv, p[1] + st.axis[1] * qv, p[2] + st.axis[2] * qv)
            elif st.kind == _REVOLUTE:
                c, s = cs(st.col)
                p, d = _rotate(p, st, c, s), _rotate(d, st, c, s)
            p, d = _affine(p, st.rot, st.trans), _affine(d, st.rot, None)
        for st in self.work_path:
            p, d = _affine(p, st.rot, st.trans, True), _affine(d, st.rot, None, True)
            if st.kind == _PRISMATIC:
                qv = cols[st.col]
                p = (p[0] - st.axis[0] * qv, p[1] - st.axis[1] * qv, p[2] - st.axis[2] * qv)
            elif st.kind == _REVOLUTE:
                c, s = cs(st.col)
                p, d = _rotate(p, st, c, -s), _rotate(d, st, c, -s)
        w = self.work_frame
        p = _affine(p, w[:3, :3], w[:3, 3], True)
        d = _affine(d, w[:3, :3], None, True)
        tip = np.empty((n, 3))
        axis = np.empty((n, 3))
        for i in range(3):
            tip[:, i] = p[i]
            axis[:, i] = d[i]
        return tip, axis

    # ---------------------------------------------------------------------------------------
    def link2base(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """Pose of every link, ``{name: (n, 4, 4)}``, plus ``work``, ``tool``, ``tool_mount``.

        q : (n, k) float, mm / degrees. ``base`` is the identity.
        """
        q = np.atleast_2d(np.asarray(q, float))
        n = q.shape[0]
        eye = np.broadcast_to(np.eye(4), (n, 4, 4))
        poses: dict[str, np.ndarray] = {"base": eye}
        pending = list(self.joints)
        while pending:
            rest = []
            for j in pending:
                if j.parent not in poses:
                    rest.append(j)
                    continue
                st = self._steps[j.name]
                local = np.empty((n, 4, 4))
                local[:] = j.origin.matrix
                if st.kind == _PRISMATIC:
                    local[:, :3, 3] += q[:, st.col, None] * (j.origin.rotation @ st.axis)
                elif st.kind == _REVOLUTE:
                    local[:, :3, :3] = j.origin.rotation @ rotation_matrices(
                        st.axis, q[:, st.col] * _DEG
                    )
                poses[j.child] = poses[j.parent] @ local
            if len(rest) == len(pending):  # unreachable for a validated spec
                raise ValueError("chain does not reach base")
            pending = rest
        poses["work"] = poses[self.spec.work.link] @ self.work_frame
        tool_link = poses[self.spec.tool.link]
        poses["tool"] = tool_link @ self.tool_frame
        poses["tool_mount"] = tool_link @ self.mount_frame
        return poses

    def tool2work(self, q: np.ndarray) -> np.ndarray:
        """(n, 4, 4) pose of the tool frame (origin at the tip, z = tool axis) in the work frame."""
        poses = self.link2base(q)
        return invert(poses["work"]) @ poses["tool"]


def invert(m: np.ndarray) -> np.ndarray:
    """Inverse of rigid transforms ``(..., 4, 4)``."""
    out = np.zeros_like(m)
    rt = np.swapaxes(m[..., :3, :3], -1, -2)
    out[..., :3, :3] = rt
    out[..., :3, 3] = -(rt @ m[..., :3, 3, None])[..., 0]
    out[..., 3, 3] = 1.0
    return out
