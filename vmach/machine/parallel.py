"""Parallel mechanisms of the hybrid machines (domain §3): sliders on guideways, struts, platform.

Mechanism coordinates have m = 2 (planar, H5D) or m = 3 (spatial, hybrid5) components, mm.
Slider i sits at ``g_i + p_i·u_i``; a strut of length L_i joins it to ``P + b_i``::

    |P + b_i − (g_i + p_i·u_i)| = L_i
    p_i = u_i·d_i + root_i·√((u_i·d_i)² − |d_i|² + L_i²),   d_i = P + b_i − g_i

``root_i`` = −1 is the domain's root (slider behind the strut's platform end along u_i).
A negative discriminant means the pose is unreachable: the drive value is NaN and ``ok`` False;
nothing is clipped. The forward problem (drives → P) is closed form for m = 2 (intersection of
two circles, ``assembly`` picks the side) and Newton's method for m = 3; a forward solution is
accepted only if the inverse with the declared roots gives the drives back.
"""

from __future__ import annotations

import numpy as np

from vmach.machine.spec import Parallel

FWD_TOL = 1e-9  # mm, accepted drive mismatch of a forward solution


def _arrays(mech: Parallel):
    g = np.array([leg.guide_point for leg in mech.legs], float)  # (m, m)
    u = np.array([leg.guide_dir for leg in mech.legs], float)
    b = np.array([leg.attach for leg in mech.legs], float)
    L = np.array([leg.length for leg in mech.legs], float)
    root = np.array([leg.root for leg in mech.legs], float)
    return g, u, b, L, root


def inverse(mech: Parallel, virtual: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drive values for virtual-axis values.

    virtual : (n, m) float, mm — values of ``mech.virtual`` (P = origin + virtual).
    Returns p : (n, m) float, mm (NaN where unreachable) and ok : (n,) bool.
    """
    v = np.atleast_2d(np.asarray(virtual, float))
    g, u, b, L, root = _arrays(mech)
    P = v + np.asarray(mech.origin, float)
    d = P[:, None, :] + b[None] - g[None]  # (n, m legs, m)
    ud = np.einsum("nij,ij->ni", d, u)
    disc = ud * ud - np.einsum("nij,nij->ni", d, d) + L * L
    ok_leg = disc >= 0
    p = np.where(ok_leg, ud + root * np.sqrt(np.where(ok_leg, disc, 0.0)), np.nan)
    return p, ok_leg.all(axis=1)


def forward(
    mech: Parallel, drives: np.ndarray, max_iter: int = 50
) -> tuple[np.ndarray, np.ndarray]:
    """Virtual-axis values for drive values.

    drives : (n, m) float, mm, in the order of ``mech.legs``.
    Returns virtual : (n, m) float, mm (NaN where no assembly exists) and ok : (n,) bool.
    """
    p = np.atleast_2d(np.asarray(drives, float))
    g, u, b, L, root = _arrays(mech)
    centres = g[None] + p[:, :, None] * u[None] - b[None]  # strut centres seen from P
    origin = np.asarray(mech.origin, float)
    if len(mech.legs) == 2:
        c1, c2 = centres[:, 0], centres[:, 1]
        e = c2 - c1
        dist = np.linalg.norm(e, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            e = e / dist[:, None]
            a = (L[0] ** 2 - L[1] ** 2 + dist**2) / (2 * dist)
            h2 = L[0] ** 2 - a * a
            h = np.sqrt(np.where(h2 >= 0, h2, np.nan))
        perp = np.stack([-e[:, 1], e[:, 0]], axis=1)
        P = c1 + a[:, None] * e + (mech.assembly * h)[:, None] * perp
    else:
        P = _newton(mech, p, centres, L, origin, max_iter)
    virtual = P - origin
    back, ok = inverse(mech, np.nan_to_num(virtual, nan=0.0))
    ok &= np.isfinite(P).all(axis=1) & (np.abs(back - p) <= FWD_TOL).all(axis=1)
    virtual[~ok] = np.nan
    return virtual, ok


def _newton(mech: Parallel, p, centres, L, origin, max_iter):
    n = p.shape[0]
    home_p, _ = inverse(mech, np.zeros((1, len(mech.legs))))
    P = np.broadcast_to(origin, (n, origin.size)).copy()
    u = np.array([leg.guide_dir for leg in mech.legs], float)
    if np.allclose(u, u[0]) and np.isfinite(home_p).all():
        P += u[0] * (p - home_p).mean(axis=1, keepdims=True)  # common travel along the guides
    for _ in range(max_iter):
        r = P[:, None, :] - centres  # (n, legs, m)
        f = np.einsum("nij,nij->ni", r, r) - L * L
        if np.all(np.abs(f) < 1e-12 * L.max() ** 2):
            break
        J = 2 * r
        jt = np.swapaxes(J, 1, 2)
        lhs = jt @ J + 1e-12 * np.eye(J.shape[-1])  # never singular; exact at the solution
        step = np.linalg.solve(lhs, -(jt @ f[..., None]))[..., 0]
        P = P + step
    return P
