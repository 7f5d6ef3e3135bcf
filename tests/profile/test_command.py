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


def test_profile_png_draws_the_d2_and_d3_circles(tmp_path, capsys):
    """issue 31: the picture shows the circumscribed (d2) and inscribed (d3) circles in their
    colours about the black profile, a scale bar and the designation."""
    import numpy as np
    from PIL import Image

    png = tmp_path / "p3g.png"
    assert main(["profile", "P3G", "50", "--png", str(png)]) == 0
    img = np.asarray(Image.open(png).convert("RGB")).astype(int)
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    steelblue = (abs(r - 70) < 25) & (abs(g - 130) < 25) & (abs(b - 180) < 25)
    orange = (r > 220) & (abs(g - 140) < 25) & (b < 40)
    black = (r < 40) & (g < 40) & (b < 40)
    assert steelblue.sum() > 500 and orange.sum() > 500 and black.sum() > 500
    # the d2 circle lies outside the d3 circle: its pixels are farther from the centre
    h, w = steelblue.shape
    yy, xx = np.mgrid[:h, :w]
    cy, cx = np.median(yy[steelblue]), np.median(xx[steelblue])
    rad = np.hypot(yy - cy, xx - cx)
    assert np.median(rad[steelblue]) > np.median(rad[orange]) * 1.05
