"""Numeric inverse kinematics for chains without a closed form (batched Levenberg–Marquardt).

Solves ``FK(q) = (tip, axis)`` for n poses at once. The residual is
``[tip(q) − tip, W·(axis(q) − axis)]`` (mm; W = ``AXIS_WEIGHT`` mm per unit of axis error), the
Jacobian is taken by central differences of the batched forward kinematics, and each pose keeps
its own damping. Poses that do not converge from the start guess are retried from a few seeds
with the rotary axes turned by ±90° and 180°. A pose whose residual stays above the tolerance is
reported not ``ok`` (unreachable); its ``q`` is the best least-squares guess, never clipped.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

FK = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
AXIS_WEIGHT = 100.0
POS_TOL = 1e-10  # mm
AXIS_TOL = 1e-12  # unit-vector components (≈ rad)


def _residual(fk: FK, q, tip, axis):
    t, a = fk(q)
    return np.concatenate([t - tip, AXIS_WEIGHT * (a - axis)], axis=1)


def _jacobian(fk: FK, q, steps):
    n, k = q.shape
    qq = np.repeat(q[None], 2 * k, axis=0)  # (2k, n, k)
    for j in range(k):
        qq[2 * j, :, j] += steps[j]
        qq[2 * j + 1, :, j] -= steps[j]
    t, a = fk(qq.reshape(-1, k))
    r = np.concatenate([t, AXIS_WEIGHT * a], axis=1).reshape(2 * k, n, 6)
    return np.stack([(r[2 * j] - r[2 * j + 1]) / (2 * steps[j]) for j in range(k)], axis=2)


def _converged(r):
    return (np.abs(r[:, :3]).max(axis=1) <= POS_TOL) & (
        np.abs(r[:, 3:]).max(axis=1) <= AXIS_TOL * AXIS_WEIGHT
    )


def solve_lm(
    fk: FK, tip, axis, q0, *, rotary=None, max_iter: int = 100
) -> tuple[np.ndarray, np.ndarray]:
    """Batched LM from one start guess.

    tip, axis : (n, 3) float (mm; unit vector). q0 : (n, k) float, mm / degrees.
    rotary : (k,) bool, which axes are angles (for the difference step).
    Returns q : (n, k) float and ok : (n,) bool.
    """
    q = np.array(q0, float)
    n, k = q.shape
    rotary = np.zeros(k, bool) if rotary is None else np.asarray(rotary, bool)
    steps = np.where(rotary, 1e-5, 1e-6)
    lam = np.full(n, 1e-3)
    r = _residual(fk, q, tip, axis)
    cost = np.einsum("ni,ni->n", r, r)
    active = ~_converged(r)
    for _ in range(max_iter):
        if not active.any():
            break
        idx = np.flatnonzero(active)
        J = _jacobian(fk, q[idx], steps)
        jt = np.swapaxes(J, 1, 2)
        A = jt @ J
        g = (jt @ r[idx, :, None])[..., 0]
        diag = np.einsum("nii->ni", A)
        A = A + (lam[idx, None] * (diag + 1e-9))[:, :, None] * np.eye(k)
        dq = -np.linalg.solve(A, g[..., None])[..., 0]
        q_new = q[idx] + dq
        r_new = _residual(fk, q_new, tip[idx], axis[idx])
        c_new = np.einsum("ni,ni->n", r_new, r_new)
        better = c_new < cost[idx]
        acc = idx[better]
        q[acc], r[acc], cost[acc] = q_new[better], r_new[better], c_new[better]
        lam[acc] = np.maximum(lam[acc] / 3.0, 1e-12)
        lam[idx[~better]] *= 4.0
        stalled = idx[~better & (lam[idx] > 1e12)]
        active[stalled] = False
        active[acc] = ~_converged(r[acc])
    return q, _converged(r)


def solve(
    fk: FK, tip, axis, q0, *, rotary=None, max_iter: int = 100
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`solve_lm` with restarts from rotated seeds for the poses that failed."""
    tip = np.atleast_2d(np.asarray(tip, float))
    axis = np.atleast_2d(np.asarray(axis, float))
    q0 = np.array(np.broadcast_to(q0, (tip.shape[0], np.shape(q0)[-1])), float)
    rotary = np.zeros(q0.shape[1], bool) if rotary is None else np.asarray(rotary, bool)
    q, ok = solve_lm(fk, tip, axis, q0, rotary=rotary, max_iter=max_iter)
    for turn in (90.0, -90.0, 180.0):
        if ok.all() or not rotary.any():
            break
        bad = np.flatnonzero(~ok)
        seed = q0[bad] + np.where(rotary, turn, 0.0)
        q2, ok2 = solve_lm(fk, tip[bad], axis[bad], seed, rotary=rotary, max_iter=max_iter)
        q[bad[ok2]] = q2[ok2]
        ok[bad[ok2]] = True
    return q, ok
