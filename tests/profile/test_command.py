"""``vmach profile``."""

from __future__ import annotations

import json

import pytest

from vmach.cli import main


def test_profile_prints_the_sizes(capsys):
    assert main(["profile", "P3G", "50"]) == 0
    out = capsys.readouterr().out
    for text in ("P3G 50", "50.0000", "1.8000", "53.6000", "46.4000", "1922.7804"):
        assert text in out


def test_profile_json_and_p4c(capsys):
    assert main(["profile", "P4C:35x30/5", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["d1"], data["d2"], data["e1"], data["d_m"]) == (35.0, 30.0, 5.0, 40.0)


def test_profile_list(capsys):
    assert main(["profile", "P3G", "--list"]) == 0
    assert len(capsys.readouterr().out.splitlines()) == 23


@pytest.mark.parametrize("argv", [["P3G", "51"], ["P9", "50"], ["P3G", "50", "--png", "x.jpg"],
                                  ["P3G", "50", "--png", ""]])
def test_bad_input_is_a_diagnostic_and_exit_2(capsys, argv):
    assert main(["profile", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("vmach: error[") and "Traceback" not in err


def test_profile_png(tmp_path, capsys):
    png = tmp_path / "p3g.png"
    assert main(["profile", "P3G", "50", "--png", str(png)]) == 0
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 2000
