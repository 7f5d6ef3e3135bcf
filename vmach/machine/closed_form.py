"""Closed-form inverse kinematics: table-table ``WCBVXYZT`` (domain §2), B/C head (domain §3).

All functions are vectorised over n poses. Inputs in the workpiece frame O_W: ``tip`` (n, 3) mm,
``axis`` (n, 3) tool-axis vector (normalised here; from the tip toward the spindle). Angles out
in degrees.

Singularity at B = 0 (tool axis along the rotary axis C): C is free. ``strategy`` chooses it:

- ``"keep"`` — C keeps the previous pose's value (forward-filled over consecutive singular
  poses; ``previous_c`` before the first pose). Regular poses get the principal value of the
  formula, C ∈ [−180°, 180°].
- ``"shortest"`` — as ``keep`` at the singularity, and every C is then unwrapped (±360°) to the
  turn nearest the previous pose's C: the shortest rotary move for a modulo C axis.

Numerically, ``B = atan2(√(a_x² + a_y²), a_z)``, which equals domain §2's ``arccos(a_z)`` for a unit
vector but keeps full precision near B = 0, and ``C = atan2(a_y, −a_x)``, which equals
``atan2(a_y / sB, −a_x / sB)`` because sB > 0 does not change an atan2.
"""

from __future__ import annotations

import numpy as np

STRATEGIES = ("keep", "shortest")
#: sin B below which a pose is treated as the B = 0 singularity.
SINGULAR = 1e-12


def unit_rows(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Normalise (n, 3) rows; returns (unit rows, ok mask) — zero rows are not ok (left zero)."""
    v = np.atleast_2d(np.asarray(v, float))
    norm = np.linalg.norm(v, axis=1)
    ok = norm > 1e-12
    out = np.zeros_like(v)
    out[ok] = v[ok] / norm[ok, None]
    return out, ok


def choose_c(
    c_deg: np.ndarray, singular: np.ndarray, strategy: str, previous_c: float
) -> np.ndarray:
    """Apply a B = 0 strategy to principal C values (n,) degrees; see the module docstring."""
    if strategy not in STRATEGIES:
        raise ValueError(f"strategy must be one of {STRATEGIES}")
    c = np.asarray(c_deg, float).copy()
    if singular.any():
        idx = np.where(~singular, np.arange(c.size), -1)
        np.maximum.accumulate(idx, out=idx)
        filled = np.where(idx >= 0, c[np.maximum(idx, 0)], previous_c)
        c = np.where(singular, filled, c)
    if strategy == "shortest":
        c = np.unwrap(np.concatenate([[previous_c], c]), period=360.0)[1:]
    return c


def table_table_ik(tip, axis, r_R, *, strategy: str = "keep", previous_c: float = 0.0):
    """Domain §2 inverse of ``WCBVXYZT``.

    tip : (n, 3) float, mm — r_T in O_W.
    axis : (n, 3) float — tool axis a in O_W.
    r_R : (3,) float, mm — rotation centre in O_W.
    Returns ``{"X","Y","Z","B","C": (n,) float}`` (mm, degrees) and ``singular`` (n,) bool.
    """
    a, _ = unit_rows(axis)
    t = np.atleast_2d(np.asarray(tip, float))
    ax, ay, az = a[:, 0], a[:, 1], a[:, 2]
    sb_raw = np.hypot(ax, ay)
    b = np.arctan2(sb_raw, az)
    singular = sb_raw <= SINGULAR
    c_deg = choose_c(np.degrees(np.arctan2(ay, -ax)), singular, strategy, previous_c)
    c = np.radians(c_deg)
    sB, cB, sC, cC = np.sin(b), np.cos(b), np.sin(c), np.cos(c)
    xR, yR, zR = (float(v) for v in r_R)
    dx, dy, dz = t[:, 0] - xR, t[:, 1] - yR, t[:, 2] - zR
    px = dx * cB * cC - dy * cB * sC + dz * sB
    py = dx * sC + dy * cC
    pz = -dx * sB * cC + dy * sB * sC + dz * cB
    axes = {"X": xR + px, "Y": yR + py, "Z": zR + pz, "B": np.degrees(b), "C": c_deg}
    return axes, singular


def head_axis(b_deg, c_deg) -> np.ndarray:
    """Tool axis of the §3 head, ``k = (cC·sB, sC·sB, cB)``: (n, 3) from (n,) degrees."""
    b, c = np.radians(b_deg), np.radians(c_deg)
    return np.stack([np.cos(c) * np.sin(b), np.sin(c) * np.sin(b), np.cos(b)], axis=-1)


def head_bc_ik(axis, *, strategy: str = "keep", previous_c: float = 0.0, b_sign: int = 1):
    """Domain §3: ``B = atan2(±√(1 − k_z²), k_z)``, ``C = atan2(k_y, k_x)``.

    axis : (n, 3) float — tool axis k (in the head's base frame).
    b_sign : +1 or −1, the ± of the formula (−1 gives the mirrored solution −B, C + 180°).
    Returns B, C (n,) degrees and ``singular`` (n,) bool.
    """
    k, _ = unit_rows(axis)
    s = np.hypot(k[:, 0], k[:, 1])
    singular = s <= SINGULAR
    b = np.degrees(np.arctan2(b_sign * s, k[:, 2]))
    c = np.degrees(np.arctan2(b_sign * k[:, 1], b_sign * k[:, 0]))
    return b, choose_c(c, singular, strategy, previous_c), singular


def head_platform_point(tip, b_deg, c_deg, l1: float, l2: float) -> np.ndarray:
    """Domain §3: the platform point P2 for tool tip T and head angles B, C.

    ``P2 = T + l2·(cC·sB, sC·sB, cB) + (0, 0, l1)``; tip (n, 3) mm → (n, 3) mm.
    l2 : tool tip to the tilt axis (tool length included), mm; l1 : tilt axis to P2, mm.
    """
    t = np.atleast_2d(np.asarray(tip, float))
    p = t + l2 * head_axis(b_deg, c_deg)
    p[:, 2] += l1
    return p
