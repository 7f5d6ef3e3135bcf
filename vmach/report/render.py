"""Pictures: the only module of vmach that imports pyvista/vtk.

Rendering is off-screen with a fixed theme so pictures are reproducible; every function takes
plain numpy arrays and writes a PNG.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from vmach.errors import InputError

#: fixed look of every picture (image-regression tests compare against it)
WINDOW = (800, 800)
BACKGROUND = "white"
FOREGROUND = "black"


def _plotter(size: tuple[int, int] = WINDOW):
    import pyvista as pv

    pv.OFF_SCREEN = True
    plotter = pv.Plotter(off_screen=True, window_size=list(size))
    plotter.set_background(BACKGROUND)
    return pv, plotter


def profile_png(path: str | Path, curves: Sequence[tuple[np.ndarray, str]], title: str = "",
                size: tuple[int, int] = WINDOW) -> Path:
    """Closed plane curves, seen along −Z, as a PNG.

    curves : sequence of (points (n, 2) float mm, colour name); each is drawn closed.
    """
    out = Path(path)
    if out.suffix.lower() != ".png":
        raise InputError(f"{out}: pictures are written as .png", kind="export_format")
    pv, plotter = _plotter(size)
    for pts, colour in curves:
        p = np.asarray(pts, dtype=float)
        xyz = np.column_stack([p, np.zeros(len(p))])
        xyz = np.vstack([xyz, xyz[:1]])
        plotter.add_mesh(pv.lines_from_points(xyz), color=colour, line_width=3)
    axis = np.array([[-1.0, 0, 0], [1.0, 0, 0], [0, -1.0, 0], [0, 1.0, 0]])
    plotter.add_mesh(pv.line_segments_from_points(axis), color="gray", line_width=1)
    if title:
        plotter.add_text(title, font_size=14, color=FOREGROUND, position="upper_left")
    plotter.view_xy()
    plotter.enable_parallel_projection()
    plotter.reset_camera()
    try:
        plotter.screenshot(str(out))
    except OSError as exc:
        raise InputError(f"{out}: cannot write: {exc.strerror or exc}", kind="unwritable") from None
    finally:
        plotter.close()
    return out
