"""Shared catalogue for the stock tests: tools and turn-mill poses made by hand (no kinematics).

Turn-mill convention (models/turnmill.toml): work Z on the spindle axis, end face at Z = 0,
material toward -Z; the milling tool's axis is radial and, seen from the workpiece, the tool
sits at the polar angle +C1; X is the tip's radius, Y its offset along the tangent.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vmach.tooling import Tool, load_tools

ROOT = Path(__file__).resolve().parents[2]


def turnmill(x, y, z, c_deg):
    """Tips (n, 3) and radial axes (n, 3) for axis values (X radius, Y, Z, C1 degrees)."""
    x, y, z, c = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, float)) for v in (x, y, z, c_deg)))
    a = np.radians(c)
    ca, sa = np.cos(a), np.sin(a)
    tips = np.stack([x * ca - y * sa, x * sa + y * ca, z], axis=1)
    axes = np.stack([ca, sa, np.zeros_like(a)], axis=1)
    return tips, axes


@pytest.fixture(scope="session")
def library():
    return load_tools(ROOT / "fixtures/polygon_shaft/tools.toml")


@pytest.fixture(scope="session")
def face40(library) -> Tool:
    return library.lookup("GLOD D40")


@pytest.fixture(scope="session")
def flat10() -> Tool:
    return Tool(name="flat 10", kind="flat", diameter=10.0, cutting_length=20.0)
