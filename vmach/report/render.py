"""Pictures: the only module of vmach that imports pyvista/vtk.

Rendering is off-screen with a fixed theme so pictures are reproducible; every function takes
plain numpy arrays and writes a PNG.
"""

from __future__ import annotations

import threading
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from vmach.errors import InputError
from vmach.output import atomic_writer

#: fixed look of every picture (image-regression tests compare against it)
WINDOW = (800, 800)
BACKGROUND = "white"
FOREGROUND = "black"


_preloading: threading.Thread | None = None   # the background import, while it may run


def _import():
    """pyvista, imported the way every picture needs it (1–3 s the first time: VTK) — after
    the background import of :func:`preload` has finished (pyvista loads its parts lazily:
    a half-done import in another thread would show a module without them)."""
    import os

    pending = _preloading
    if pending is not None and pending is not threading.current_thread():
        pending.join()

    if not os.environ.get("DISPLAY"):
        # no X server: go straight to EGL (Mesa) instead of trying X first and warning
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    return pv


def preload() -> threading.Thread:
    """Import pyvista in a background thread, so that the import overlaps other work (the
    stock's booleans release the GIL) instead of adding to the pictures' time. An import
    error is left for the pictures to raise."""

    def run() -> None:
        try:
            _import()
            import pyvista.plotting  # noqa: F401 - pyvista loads it (and matplotlib) lazily
        except Exception:  # noqa: BLE001 - reported when the pictures import it again
            pass

    global _preloading
    thread = threading.Thread(target=run, name="vmach-preload-pyvista", daemon=True)
    _preloading = thread
    thread.start()
    return thread


def _plotter(size: tuple[int, int] = WINDOW):
    pv = _import()

    pv.OFF_SCREEN = True
    plotter = pv.Plotter(off_screen=True, window_size=list(size))
    plotter.set_background(BACKGROUND)
    return pv, plotter


def profile_png(
    path: str | Path,
    curves: Sequence[tuple[np.ndarray, str]],
    title: str = "",
    size: tuple[int, int] = WINDOW,
) -> Path:
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
    return _save(plotter, out)


def _save(plotter, out: Path) -> Path:
    if out.suffix.lower() != ".png":
        plotter.close()
        raise InputError(f"{out}: pictures are written as .png", kind="export_format")
    try:
        image = plotter.screenshot(None, return_img=True)   # (h, w, 3) uint8
    finally:
        plotter.close()
    from PIL import Image

    with atomic_writer(out, "wb") as fh:           # whole or not at all, as every file vmach writes
        Image.fromarray(np.asarray(image, dtype=np.uint8)).save(fh, format="PNG")
    return out


def _faces(faces: np.ndarray) -> np.ndarray:
    f = np.asarray(faces, dtype=np.int64)
    return np.column_stack([np.full(len(f), 3), f]).ravel()


def _camera(plotter, view: str) -> None:
    if view == "iso":
        plotter.view_isometric()
    elif view == "xy":
        plotter.view_xy()
    elif view == "xz":
        plotter.view_xz()
    plotter.reset_camera()


def _finish_part(plotter, path: Path, title: str) -> Path:
    """Title, the part seen from above and aside, and the PNG written."""
    if title:
        plotter.add_text(title, font_size=12, color=FOREGROUND, position="upper_left")
    plotter.camera_position = "xy"
    plotter.camera.elevation = 35
    plotter.camera.azimuth = 20
    plotter.reset_camera()
    return _save(plotter, path)


def part_deviation_png(
    path: str | Path,
    vertices: np.ndarray,
    faces: np.ndarray,
    deviation: np.ndarray,
    clim: tuple[float, float],
    title: str = "",
    size: tuple[int, int] = WINDOW,
) -> Path:
    """A part coloured by deviation.

    vertices (n, 3) mm, faces (m, 3); deviation (n,) mm per vertex, NaN where not measured
    (drawn grey); clim (lo, hi) mm of the colour bar.
    """
    pv, plotter = _plotter(size)
    mesh = pv.PolyData(np.asarray(vertices, float), _faces(faces))
    mesh.point_data["deviation [mm]"] = np.asarray(deviation, float)
    plotter.add_mesh(
        mesh,
        scalars="deviation [mm]",
        cmap="coolwarm",
        clim=list(clim),
        nan_color="lightgray",
        smooth_shading=False,
        scalar_bar_args={
            "title": "deviation [mm]",
            "color": FOREGROUND,
            "fmt": "%.4f",
            "n_labels": 5,
            "vertical": True,
            "position_x": 0.8,
            "position_y": 0.1,
            "width": 0.08,
            "height": 0.6,
        },
    )
    return _finish_part(plotter, Path(path), title)


#: colours of a part against its design: gouge, within the band, excess (RGB 0..255)
GOUGE_RGB, BAND_RGB, EXCESS_RGB = (40, 80, 220), (190, 190, 190), (220, 40, 40)


def design_colours(deviation: np.ndarray, band: tuple[float, float]) -> np.ndarray:
    """RGB (n, 3) uint8 per vertex: grey within the band ``(lo, hi)`` mm, blue below it (a
    gouge) and red above it (excess), paling to the band's grey at its edge and full at
    three times the band's width beyond it."""
    d = np.asarray(deviation, dtype=float)
    lo, hi = band
    width = max(hi - lo, 1e-6)
    out = np.tile(np.array(BAND_RGB, dtype=float), (len(d), 1))
    for mask, past, rgb in ((d < lo, lo - d, GOUGE_RGB), (d > hi, d - hi, EXCESS_RGB)):
        t = np.clip(0.35 + 0.65 * past[mask] / (3 * width), 0.0, 1.0)[:, None]
        out[mask] = (1 - t) * np.array(BAND_RGB) + t * np.array(rgb)
    return np.clip(np.round(out), 0, 255).astype(np.uint8)


def design_deviation_png(
    path: str | Path,
    vertices: np.ndarray,
    faces: np.ndarray,
    deviation: np.ndarray,
    band: tuple[float, float],
    labels: Sequence[tuple[np.ndarray, str]] = (),
    title: str = "",
    size: tuple[int, int] = WINDOW,
) -> Path:
    """A part coloured by its signed distance to the design (:func:`design_colours`: gouge
    blue, excess red, within the band grey), with labels at points.

    vertices (n, 3) mm, faces (m, 3); deviation (n,) mm per vertex; band (lo, hi) mm;
    labels: (point (3,) mm, text) each.
    """
    pv, plotter = _plotter(size)
    mesh = pv.PolyData(np.asarray(vertices, float), _faces(faces))
    mesh.point_data["colour"] = design_colours(deviation, band)
    plotter.add_mesh(mesh, scalars="colour", rgb=True, smooth_shading=False, ambient=0.45, diffuse=0.6)
    if labels:
        plotter.add_point_labels(np.array([p for p, _ in labels], dtype=float), [t for _, t in labels],
                                 font_size=14, text_color=FOREGROUND, point_color="black",
                                 point_size=8, shape_opacity=0.6, always_visible=True)
    lo, hi = band
    legend = (f"blue: gouge (below {lo:+.3f} mm)   red: excess (above {hi:+.3f} mm)   "
              "grey: within the band")
    plotter.add_text(legend, font_size=9, color=FOREGROUND, position="lower_left")
    return _finish_part(plotter, Path(path), title)


def toolpath_png(
    path: str | Path,
    points: np.ndarray,
    kinds: np.ndarray,
    outline: tuple | None = None,
    title: str = "",
    size: tuple[int, int] = WINDOW,
) -> Path:
    """A tool path in 3-D: rapids red, feeds green (as the control's simulation draws them).

    points (n, 2, 3) mm — segment end points; kinds (n,) — 0 rapid, 1 feed.
    outline : optional (vertices, faces) of the stock drawn as a translucent body.
    """
    pv, plotter = _plotter(size)
    pts = np.asarray(points, float).reshape(-1, 3)
    kinds = np.asarray(kinds)
    for k, colour, width in ((1, "green", 1.5), (0, "red", 1.0)):
        sel = np.flatnonzero(kinds == k)
        if len(sel):
            seg = np.asarray(points, float)[sel].reshape(-1, 3)
            plotter.add_mesh(pv.line_segments_from_points(seg), color=colour, line_width=width)
    if outline is not None:
        v, f = outline
        plotter.add_mesh(pv.PolyData(np.asarray(v, float), _faces(f)), color="lightsteelblue", opacity=0.25)
    if title:
        plotter.add_text(title, font_size=12, color=FOREGROUND, position="upper_left")
    if len(pts):
        plotter.view_isometric()
        plotter.reset_camera()
    return _save(plotter, Path(path))


def chart_png(
    path: str | Path,
    series: Sequence[tuple[np.ndarray, np.ndarray, str, str]],
    x_label: str,
    y_label: str,
    title: str = "",
    size: tuple[int, int] = (900, 500),
) -> Path:
    """Line chart; series: (x (n,), y (n,), label, colour)."""
    pv, plotter = _plotter(size)
    chart = pv.Chart2D(x_label=x_label, y_label=y_label)
    for x, y, label, colour in series:
        chart.line(np.asarray(x, float), np.asarray(y, float), color=colour, width=2, label=label)
    chart.title = title
    plotter.add_chart(chart)
    return _save(plotter, Path(path))


def scene_png(
    path: str | Path,
    meshes: Sequence[tuple[np.ndarray, np.ndarray, str, float]],
    focus: tuple[np.ndarray, float],
    title: str = "",
    marker: np.ndarray | None = None,
    size: tuple[int, int] = WINDOW,
) -> Path:
    """A close-up of solids: meshes (vertices, faces, colour, opacity); the camera looks at
    ``focus`` = (centre (3,), radius mm); ``marker`` (3,) draws a small sphere at a point."""
    pv, plotter = _plotter(size)
    for v, f, colour, opacity in meshes:
        if len(f):
            plotter.add_mesh(
                pv.PolyData(np.asarray(v, float), _faces(f)),
                color=colour,
                opacity=opacity,
                smooth_shading=False,
            )
    centre, radius = focus
    if marker is not None:
        plotter.add_mesh(
            pv.Sphere(radius=max(radius / 40, 0.2), center=np.asarray(marker, float)), color="red"
        )
    if title:
        plotter.add_text(title, font_size=12, color=FOREGROUND, position="upper_left")
    plotter.view_isometric()
    plotter.reset_camera(
        bounds=[
            centre[0] - radius,
            centre[0] + radius,
            centre[1] - radius,
            centre[1] + radius,
            centre[2] - radius,
            centre[2] + radius,
        ]
    )
    return _save(plotter, Path(path))


def images_equal(a: str | Path, b: str | Path, threshold: float) -> tuple[bool, float]:
    """Image regression: pyvista's mean pixel error between two PNGs, and whether it is within
    ``threshold``."""
    err = float(_import().compare_images(str(a), str(b)))
    return err <= threshold, err
