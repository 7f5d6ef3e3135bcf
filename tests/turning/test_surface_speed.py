"""G96 constant cutting speed with LIMS (#34): the Sinumerik trace, and the cycle time that
follows X along every move (SINUMERIK programming manual, constant cutting rate G96/G97/LIMS)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from nc import ok  # noqa: E402

from vmach.canon import Spindle, SurfaceSpeed  # noqa: E402
from vmach.machine import load_model  # noqa: E402
from vmach.motion.table import build  # noqa: E402
from vmach.motion.timing import programmed_seconds  # noqa: E402

LATHE = load_model("lathe")


def commands(tmp_path, text):
    return ok(tmp_path, text, LATHE.control).commands


def test_g96_s_is_a_cutting_speed_and_the_spindle_turns_at_1000v_over_pi_d(tmp_path):
    cmds = commands(tmp_path, "G18 DIAMON G0 X50 Z5\nG96 S200 LIMS=2500 M3\nG1 X30 F0.2\nG97\nM30\n")
    srf = [c for c in cmds if isinstance(c, SurfaceSpeed)]
    assert (srf[0].speed, srf[0].limit, srf[0].axis) == (200.0, 2500.0, "X")
    spin = [c for c in cmds if isinstance(c, Spindle)]
    assert spin[0].speed == pytest.approx(1000 * 200 / (math.pi * 50))      # at Ø50
    # G97 keeps the speed the spindle has where it is (Ø30) and ends constant cutting speed
    assert spin[-1].speed == pytest.approx(1000 * 200 / (math.pi * 30))
    assert srf[-1].speed == 0.0


def test_lims_bounds_the_speed_and_g95_ends_g96(tmp_path):
    cmds = commands(tmp_path, "G18 DIAMON G0 X10 Z5\nG96 S200 LIMS=3000 M3\nG95 F0.2\nM30\n")
    spin = [c for c in cmds if isinstance(c, Spindle)]
    assert spin[0].speed == 3000.0                      # 6366 rev/min at Ø10, bounded by LIMS
    assert [c.speed for c in cmds if isinstance(c, SurfaceSpeed)][-1] == 0.0


def test_a_facing_cut_under_g96_is_timed_with_the_speed_following_x(tmp_path):
    cmds = commands(tmp_path, "G18 DIAMON G0 X64 Z0\nG96 S200 LIMS=3000 M3\nG1 X-1.6 F0.2\nM30\n")
    table = build(cmds, LATHE.control)
    row = int(np.flatnonzero(table.kind != 0)[0])
    got = programmed_seconds(table)[row]
    # ∫ ds / (f·n(r)) in closed form: 2π r / (1000 v) above r_lim = 1000 v / (2π LIMS), 1/LIMS below
    v, f, lim = 200.0, 0.2, 3000.0
    r_lim = 1000 * v / (2 * math.pi * lim)
    minutes = (2 * math.pi / (1000 * v) * (32.0 ** 2 - r_lim ** 2) / 2 + (r_lim + 0.8) / lim) / f
    assert got == pytest.approx(60 * minutes, rel=1e-9)
    assert got == pytest.approx(5.43, abs=0.01)
