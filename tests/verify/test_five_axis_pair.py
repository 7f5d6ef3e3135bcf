"""The five-axis fixture pair (#35): one chamfer toolpath written once as a TRAORI program and
once post-processed into X Y Z B C (fixtures/five_axis) cuts the same stock — exported parts
of equal volume within the simulation's stated bound — on the table-table s5d and the hybrid
h5d; the TRAORI program's own axis values come from vmach's transformation, the axis program's
from domain §2's post, so the two meet only if both are right."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from vmach.cli import main

FIX = Path(__file__).resolve().parents[2] / "fixtures" / "five_axis"


def test_the_pair_is_what_the_generator_writes(tmp_path):
    subprocess.run([sys.executable, str(FIX / "make_pair.py"), str(tmp_path)], check=True)
    for name in ("chamfer_traori.mpf", "chamfer_axes.mpf"):
        assert (tmp_path / name).read_text() == (FIX / name).read_text(), name


def cut(tmp_path, program: str, machine: str):
    part = tmp_path / f"{program}_{machine}.stl"
    out = tmp_path / f"o_{program}_{machine}"
    assert main(["verify", str(FIX / f"chamfer_{program}.mpf"), "--machine", machine, "--export", str(part),
                 "--out", str(out), "--no-images", "--quiet"]) == 0
    report = json.loads((out / "report.json").read_text())
    return trimesh.load(part), report


@pytest.mark.parametrize("machine", ["s5d", "h5d"])
def test_traori_and_post_output_cut_the_same_chamfer(tmp_path, machine):
    a, ra = cut(tmp_path, "traori", machine)
    b, rb = cut(tmp_path, "axes", machine)
    assert [f["kind"] for f in ra["findings"] if f["severity"] != "info"] == []
    assert [f["kind"] for f in rb["findings"] if f["severity"] != "info"] == []
    removed = 30 * 30 * 20 - a.volume
    assert 200 < removed < 300                  # a chamfer of 2 mm legs around the block
    # the stated bound: each part's surface may lie this far from the exact one
    bound = max(max(r["simulation"]["error_bounds_mm"].values()) for r in (ra, rb))
    assert abs(a.volume - b.volume) < bound * a.area
    assert abs(a.volume - b.volume) < 0.01 * removed            # measured: 0.15 mm³ of 240
    assert np.abs(a.bounds - b.bounds).max() < 0.01
