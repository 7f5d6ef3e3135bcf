"""Shared helpers of the machine tests: the named models, loaded once, and pose samplers."""

from __future__ import annotations

from functools import cache

import numpy as np

from vmach.machine import load_model

FIVE_AXIS = ("s5d", "h5d", "hybrid5")
ALL_MODELS = ("turnmill",) + FIVE_AXIS + ("mill3", "mill5ac", "lathe")


@cache
def model(name: str):
    return load_model(name)


def random_q(m, n: int, rng: np.random.Generator, b_range=(1.0, 89.0)) -> np.ndarray:
    """(n, k) axis values inside the travel limits (±50 where unlimited)."""
    q = np.empty((n, len(m.axes)))
    lim = m.limits
    for i, a in enumerate(m.axes):
        lo, hi = lim[i]
        if np.isnan(lo):
            lo, hi = -179.0, 179.0
        if a == "B":
            lo, hi = max(lo, b_range[0]), min(hi, b_range[1])
        q[:, i] = rng.uniform(lo, hi, n)
    return q


def tilted_axes(tilt_deg: np.ndarray, azimuth_deg: np.ndarray) -> np.ndarray:
    """(n, 3) unit vectors at ``tilt`` from +Z, turned ``azimuth`` about Z."""
    t, a = np.radians(tilt_deg), np.radians(azimuth_deg)
    return np.stack([np.sin(t) * np.cos(a), np.sin(t) * np.sin(a), np.cos(t)], axis=1)
