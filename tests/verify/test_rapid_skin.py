"""A rapid that leaves a feed along the tool axis meets the feed's last tool polygon with its own
polygon, turned otherwise: the crescent between them (thinner than the tool polygons' stated
bound) is not material the rapid hits. A rapid into material is still ``rapid_into_stock``
(found by h35 and h36: ``G2`` then ``G0 Z10`` was an error of 0.022 mm³ on mill3)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vmach.cli import main

ROOT = Path(__file__).resolve().parents[2]

PROGRAM = """G17 G90 G54 G71
T1 D1 M6
S5000 M3
G0 X10 Y0 Z5
G1 Z-1 F300
G2 X-10 Y0 I-10 J0
G0 Z10
{extra}M30
"""


def _verify(tmp_path: Path, extra: str = "") -> list[dict]:
    (tmp_path / "T.MPF").write_text(PROGRAM.format(extra=extra))
    (tmp_path / "tools.toml").write_bytes((ROOT / "fixtures" / "milling" / "tools.toml").read_bytes())
    out = tmp_path / "out"
    main(["verify", str(tmp_path / "T.MPF"), "--machine", "mill3", "--tools", str(tmp_path / "tools.toml"),
          "--stock", "box:xmin=-20,xmax=20,ymin=-20,ymax=20,zmin=-10,zmax=0", "--out", str(out),
          "--no-images", "--quiet"])
    return json.loads((out / "report.json").read_text())["findings"]


@pytest.mark.slow
def test_a_retract_after_an_arc_removes_nothing(tmp_path):
    assert [f for f in _verify(tmp_path) if f["kind"] == "rapid_into_stock"] == []


@pytest.mark.slow
def test_a_rapid_into_material_is_still_found(tmp_path):
    # 0.5 mm deep beside the groove, and along the groove's wall 0.3 mm into it
    found = [f for f in _verify(tmp_path, "G0 X0 Y15 Z-0.5\nG0 Z10\nG0 X-10 Y-4.7\nG0 Z-0.8\nG0 Z10\n")
             if f["kind"] == "rapid_into_stock"]
    assert [f["line"] for f in found] == [8, 11]
    assert found[0]["volume_mm3"] > 30 and found[1]["volume_mm3"] > 0.1
