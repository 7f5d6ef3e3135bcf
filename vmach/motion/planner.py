"""Path-speed planning for the cycle time: trapezoidal profiles, junction speeds, look-ahead.

Each segment is travelled along a path parameter ``s`` (mm for segments that move a linear
axis, degrees for segments that move rotary axes only). ``u = dq/ds`` gives every axis' share,
so an axis moves at ``v · u_i`` and accelerates at ``a · u_i``. The path speed is capped so that
no axis exceeds its rate and the path acceleration so that no axis exceeds its ``max_accel``:
the per-axis trapezoidal limits seen along the path, as a path interpolator applies them.

Junctions: with exact stop the speed is zero; in continuous-path mode (G64) each axis' velocity
may jump by ``J_i = max_accel_i · (overload − 1) · t_ipo`` at the transition (Sinumerik,
function manual B1 "Continuous-path mode", MD32310 MAX_ACCEL_OVL_FACTOR), so the speed at the
junction is ``min_i J_i / |u_i(next) − u_i(prev)|``: full speed where the path runs straight on,
less the sharper the corner. A backward then a forward pass (as motion planners do) lower the
junction speeds until every segment can reach its exit speed from its entry speed.
"""

from __future__ import annotations

import math

import numpy as np

#: |u_i| below which an axis counts as not moving in a segment (axis units per path unit).
SHARE_EPS = 1e-12


def axis_limited(u: np.ndarray, limit: np.ndarray) -> np.ndarray:
    """Largest path value such that no axis exceeds its limit: ``min_i limit_i / |u_i|``.

    u : (m, k) float, axis units per path unit. limit : (k,) float, per-axis limit (rate or
    acceleration; NaN or inf = unlimited). Returns (m,) float, inf where nothing limits.
    """
    lim = np.where(np.isfinite(limit), limit, np.inf)
    au = np.abs(u)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(au > SHARE_EPS, lim[None, :] / au, np.inf)
    return ratio.min(axis=1) if ratio.shape[1] else np.full(len(u), np.inf)


def junction_limits(u: np.ndarray, jump: np.ndarray, stop: np.ndarray) -> np.ndarray:
    """Speed allowed at each junction between consecutive segments.

    u : (m, k) float, axis shares of the m segments. jump : (k,) float, allowed velocity jump of
    each axis (axis units/s; inf = any). stop : (m - 1,) bool, junctions that must stop.
    Returns (m + 1,) float, path units/s: index j is the junction before segment j (0 and m are
    the start and end of the chain, always 0).
    """
    m = len(u)
    out = np.zeros(m + 1)
    if m < 2:
        return out
    du = np.abs(u[1:] - u[:-1])
    jmp = np.where(np.isfinite(jump), jump, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(du > SHARE_EPS, jmp[None, :] / du, np.inf)
    v = ratio.min(axis=1) if ratio.shape[1] else np.full(m - 1, np.inf)
    out[1:-1] = np.where(stop, 0.0, v)
    return out


def plan(length: np.ndarray, vcap: np.ndarray, accel: np.ndarray, vj: np.ndarray) -> np.ndarray:
    """Backward and forward passes: junction speeds every segment can meet.

    length, vcap, accel : (m,) float — path length, speed cap (>0), path acceleration (may be
    inf). vj : (m + 1,) float — junction limits (``junction_limits``). Returns (m + 1,) float.
    """
    m = len(length)
    v = np.minimum(vj, np.inf)
    v[1:-1] = np.minimum(v[1:-1], np.minimum(vcap[:-1], vcap[1:]))
    reach = (2.0 * accel * length).tolist()  # v_exit² ≤ v_entry² + 2 a s
    w = v.tolist()
    for i in range(m - 1, -1, -1):
        lim = math.sqrt(w[i + 1] * w[i + 1] + reach[i])
        if w[i] > lim:
            w[i] = lim
    for i in range(m):
        lim = math.sqrt(w[i] * w[i] + reach[i])
        if w[i + 1] > lim:
            w[i + 1] = lim
    return np.array(w)


def segment_times(length: np.ndarray, vcap: np.ndarray, accel: np.ndarray,
                  v0: np.ndarray, v1: np.ndarray) -> np.ndarray:
    """Time of a trapezoidal (or triangular) speed profile per segment.

    length : (m,) path units; vcap : (m,) path units/s (> 0, may be inf); accel : (m,) path
    units/s² (> 0, may be inf = no acceleration limit); v0, v1 : (m,) entry and exit speeds,
    reachable from each other within the length. Returns (m,) float, seconds.
    """
    s, vc, a = length, vcap, accel
    finite_a = np.isfinite(a)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        # no acceleration limit: cruise at the cap
        cruise_only = np.where(np.isfinite(vc), s / vc, 0.0)
        d_acc = (vc * vc - v0 * v0) / (2 * a)
        d_dec = (vc * vc - v1 * v1) / (2 * a)
        trapezoid = np.isfinite(vc) & (d_acc + d_dec <= s)
        t_trap = (vc - v0) / a + (vc - v1) / a + (s - d_acc - d_dec) / vc
        vp = np.sqrt(np.maximum((2 * a * s + v0 * v0 + v1 * v1) / 2, 0.0))
        t_tri = (vp - v0) / a + (vp - v1) / a
        t = np.where(trapezoid, t_trap, t_tri)
    out = np.where(finite_a, t, cruise_only)
    return np.where(s > 0, np.maximum(out, 0.0), 0.0)
