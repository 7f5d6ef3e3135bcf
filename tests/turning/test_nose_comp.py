"""Tool nose radius compensation on the lathe (#34): G42 with the CNMG 120408 (nose radius
0.8 mm, cutting edge position SL 3) along a drawn contour — chamfer, cylinder, concave R5,
shoulder — turns the part to the drawn contour itself, nose radius included: the compensated
path is written for the tool's reference point P (interpreters/sinumerik/turning/nose.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from catalog import FIXTURES, TURNMILL
from nc import write
from turning.test_shaft import TOOLS, part_radius

from interpreters import sinumerik
from vmach.canon import LinearFeed, RunOptions
from vmach.machine.control import load_control
from vmach.tooling.library import load_tools
from vmach.verify import VerifyOptions, verify

PROGRAM = FIXTURES / "turning" / "NOSE_COMP.MPF"


def drawn(z: float) -> float:
    """The drawn contour's radius at z (mm): the chamfer r = 12 − z from the face (Z1) to r15
    at Z-3, r15 to Z-15, concave R5 about (r20, Z-15) to Z-20, then r23 to Z-30."""
    if z >= -3:
        return 12.0 - z
    if z >= -15:
        return 15.0
    if z > -20:
        return 20.0 - math.sqrt(25.0 - (z + 15.0) ** 2)
    return 23.0


@pytest.fixture(scope="module")
def part():
    rep = verify(PROGRAM, VerifyOptions(machine="lathe", tools=TOOLS, stock="cylinder:d=50,l=60,z=1",
                                        images=False))
    assert [f for f in rep.findings if f.severity in ("error", "warning")] == []
    return rep.part


def slope(z: float) -> float:
    """|dr/dz| of the drawn contour at z."""
    if -3 <= z:
        return 1.0
    if -20 < z < -15:
        return abs(z + 15.0) / math.sqrt(25.0 - (z + 15.0) ** 2)
    return 0.0


def test_the_turned_part_is_the_drawn_contour_within_5_microns(part):
    """At stations every 0.1 mm (off the shoulder face Z-20, where the radius jumps): the
    part's distance from the contour along its normal (the radial difference times cos of the
    contour's slope; near the shoulder the R5 runs almost radially, where a micron along Z is
    several in radius) stays within 5 µm, and so does the radial difference itself wherever
    the contour is no steeper than 45°."""
    z = np.array([v for v in np.arange(-29.95, 0.95, 0.1) if abs(v + 20) > 0.02])
    got = part_radius(part, z)
    want = np.array([drawn(v) for v in z])
    k = np.array([slope(v) for v in z])
    assert np.abs((got - want) / np.sqrt(1 + k * k)).max() < 0.005
    assert np.abs(got - want)[k <= 1].max() < 0.005
    # without the shift to P the part would lie 0.8·(1 − 1/√2)… 0.8 mm off: nowhere near
    assert got[np.argmin(np.abs(z + 10))] == pytest.approx(15.0, abs=0.005)


def test_the_stream_carries_p_not_the_nose_centre(tmp_path):
    """N80 along Ø30 ends where the concave R5 starts: the nose centre S at (r15.8, Z-15), so
    P = S + (−0.8, −0.8) = (r15, Z-15.8). Without the library's edge position (only a radius)
    the stream keeps S, as for a milling cutter."""
    lib = load_tools(TOOLS)
    prog = write(tmp_path, PROGRAM.read_text())
    control = load_control(TURNMILL)
    with_sl = sinumerik.run(prog, control, RunOptions(tool_radius=lib.radius, tool_data=lib.data))
    radius_only = sinumerik.run(prog, control, RunOptions(tool_radius=lib.radius))
    ends = [{c.source.line: c for c in r.commands if isinstance(c, LinearFeed)}[27]
            for r in (with_sl, radius_only)]
    assert (ends[0].axes["X"], ends[0].axes["Z"]) == (pytest.approx(15.0), pytest.approx(-15.8))
    assert (ends[1].axes["X"], ends[1].axes["Z"]) == (pytest.approx(15.8), pytest.approx(-15.0))
