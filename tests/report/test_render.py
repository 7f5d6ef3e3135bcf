"""Image regression of the pictures with a fixed theme (pyvista off-screen, EGL/Mesa).

Regenerate the baselines after a deliberate change with
``VMACH_REGEN=1 python -m pytest tests/report/test_render.py`` and look at them.
Skips only when no off-screen OpenGL can be had (it fails instead under CI=true, where
``.ci/run`` installs Mesa's EGL).
"""

from __future__ import annotations

import math
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from vmach.report import render, scene
from vmach.report.pictures import box_mesh, cylinder_mesh, transformed

BASELINE = Path(__file__).with_name("baseline")
#: mean pixel error (pyvista.compare_images) tolerated between renders of the same scene
THRESHOLD = 100.0


@pytest.fixture(scope="module")
def gl(tmp_path_factory):
    probe = tmp_path_factory.mktemp("gl") / "probe.png"
    try:
        render.chart_png(probe, [(np.arange(3.0), np.arange(3.0), "x", "b")], "x", "y")
    except Exception as exc:  # no OpenGL context at all
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(f"off-screen rendering unavailable under CI: {exc}")
        pytest.skip(f"off-screen rendering unavailable: {exc}")
    return True


def check(tmp_path: Path, name: str, make) -> None:
    out = tmp_path / name
    make(out)
    assert out.stat().st_size > 1000
    base = BASELINE / name
    if os.environ.get("VMACH_REGEN") or not base.exists():
        if not os.environ.get("VMACH_REGEN"):
            pytest.fail(f"no baseline {base}; run with VMACH_REGEN=1 and review it")
        shutil.copy(out, base)
    ok, err = render.images_equal(out, base, THRESHOLD)
    assert ok, f"{name}: image error {err:.1f} > {THRESHOLD}"


def test_chart(gl, tmp_path):
    c = np.linspace(0, 360, 721)
    series = [
        (c, 25 - 1.8 * np.sin(np.radians(3 * c)), "X", "b"),
        (c, -5.4 * np.cos(np.radians(3 * c)), "Y", "r"),
    ]
    check(
        tmp_path,
        "chart.png",
        lambda p: render.chart_png(p, series, "C1 [deg]", "mm", title="X and Y over C1"),
    )


def test_toolpath(gl, tmp_path):
    t = np.linspace(0, 4 * math.pi, 400)
    pts = np.column_stack([25 * np.cos(t), 25 * np.sin(t), -t])
    seg = np.stack([pts[:-1], pts[1:]], axis=1)
    kinds = (np.arange(len(seg)) % 50 >= 5).astype(int)
    v, f = cylinder_mesh(30.0, -15.0, 0.0)
    far = np.array([[[25.0, 0, 0], [400.0, 0, 300.0]]])     # a move far outside, drawn all the same
    seg, kinds = np.concatenate([seg, far]), np.r_[kinds, 0]
    markers = [(pts[100], "L12", "#d62728"), (pts[300], "L40", "#ff7f0e")]
    box = np.array([[-30.0, -30, -15], [30, 30, 0]])
    check(tmp_path, "toolpath.png", lambda p: render.toolpath_png(p, seg, kinds, (v, f), title="helix",
                                                                  markers=markers, focus=box))


def test_part_deviation(gl, tmp_path):
    v, f = cylinder_mesh(25.0, -40.0, 0.0, segments=96)
    dev = np.where(v[:, 2] < -5, -0.0085 + 0.01 * np.sin(3 * np.arctan2(v[:, 1], v[:, 0])), np.nan)
    lo, hi = -0.0125, -0.0045          # a g6 band of a 50 mm shaft, mm
    span = scene.band_span(lo, hi, dev)
    colours, rng = scene.colour_bar(lo, hi, span)
    ticks = [t * 1000 for t in scene.round_ticks(lo, hi, rng)]
    assert -12.5 in ticks and -4.5 in ticks
    check(
        tmp_path,
        "part_deviation.png",
        lambda p: render.part_deviation_png(p, v, f, dev * 1000, (rng[0] * 1000, rng[1] * 1000),
                                            title="deviation", colours=colours, ticks=ticks, unit="µm",
                                            nan_colour=scene.NOT_MEASURED.tolist()),
    )


def test_scene(gl, tmp_path):
    bv, bf = box_mesh((40.0, 25.0, 35.0))
    m = np.eye(4)
    m[:3, 3] = (50, 0, -80)
    cv, cf = cylinder_mesh(12.5, 0.0, 40.0)
    r = np.array([[0, 0, 1, 40], [0, 1, 0, 0], [-1, 0, 0, -75], [0, 0, 0, 1]], float)
    meshes = [(transformed(bv, m), bf, "tomato", 0.8), (transformed(cv, r), cf, "gold", 1.0)]
    check(
        tmp_path,
        "scene.png",
        lambda p: render.scene_png(
            p, meshes, (np.array([45.0, 0, -77]), 40.0), title="close-up", marker=np.array([45.0, 0, -77]),
            legend=[("jaw (struck)", "tomato"), ("cutter", "gold")],
            lines=[(np.array([[[20.0, 0, -60], [40.0, 0, -75]]]), "red")],
        ),
    )


def test_a_different_picture_is_caught(gl, tmp_path):
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    c = np.linspace(0, 360, 100)
    render.chart_png(a, [(c, np.sin(np.radians(c)), "s", "b")], "x", "y")
    render.chart_png(b, [(c, np.cos(np.radians(c)), "s", "b")], "x", "y")
    assert not render.images_equal(a, b, THRESHOLD)[0]
    assert render.images_equal(a, a, THRESHOLD) == (True, 0.0)


def test_preload_imports_pyvista_in_the_background(gl, tmp_path):
    """verify starts it before the stock stage; a picture asked for while it still runs waits
    for it (pyvista loads its parts lazily: a half-done import showed a module without
    ``Plotter``). In a fresh interpreter, where nothing has imported pyvista yet."""
    import subprocess
    import sys

    out = tmp_path / "early.png"
    code = (
        "import sys\n"
        "import numpy as np\n"
        "from vmach.report import render\n"
        "thread = render.preload()\n"
        "assert thread.daemon and thread.name == 'vmach-preload-pyvista'\n"
        f"render.toolpath_png({str(out)!r}, np.array([[[0, 0, 0], [10, 5, 2.0]]]), np.array([1]))\n"
        "assert not thread.is_alive() and 'pyvista.plotting' in sys.modules\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert out.stat().st_size > 1000


def test_a_picture_that_cannot_be_written_whole_is_not_left_half_written(gl, tmp_path, monkeypatch):
    """The PNG is encoded into a temporary file and renamed into place: a write that fails half
    way (a full disk) is error[unwritable] and leaves no picture and no temporary file."""
    import errno

    from PIL import Image

    from vmach.errors import InputError

    def full_disk(self, fh, *args, **kwargs):
        fh.write(b"\x89PNG\r\n\x1a\n" + b"\0" * 100)
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", full_disk)
    with pytest.raises(InputError) as err:
        render.chart_png(tmp_path / "x.png", [(np.arange(3.0), np.arange(3.0), "x", "b")], "x", "y")
    assert err.value.kind == "unwritable"
    assert list(tmp_path.iterdir()) == []
