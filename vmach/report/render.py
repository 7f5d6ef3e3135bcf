"""Pictures: the only module of vmach that imports pyvista/vtk.

Rendering is off-screen with a fixed theme so pictures are reproducible; every function takes
plain numpy arrays and writes a PNG.
"""

from __future__ import annotations

import math
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


def _triad(plotter) -> None:
    """The axis triad (X red, Y green, Z blue) in the lower left corner."""
    plotter.add_axes(line_width=3, color=FOREGROUND, viewport=(0.0, 0.0, 0.16, 0.16))


def _scale_bar(plotter, bounds: np.ndarray, along: int = 0) -> None:
    """A ruler of a round length (1, 2 or 5 × 10^k mm) along axis ``along`` at the lower
    corner of ``bounds`` (2, 3) mm, labelled with its length."""
    from vmach.report.scene import scale_length

    lo, hi = np.asarray(bounds, float)
    length = scale_length(float(np.max(hi - lo)))
    b = lo.copy()
    b[along] += length
    plotter.add_ruler(lo, b, title=f"{length:g} mm", number_labels=2, label_format="%g",
                      font_size_factor=0.5, show_labels=False)


def _frame(plotter, bounds: np.ndarray, direction=(1.0, 1.0, 1.0)) -> None:
    """Point the camera at the box ``bounds`` (2, 3) mm from ``direction`` (isometric by
    default, Z up) so that the box fills the picture; whatever lies beyond is cut off
    (VTK's ResetCamera(bounds) frames every actor instead)."""
    lo, hi = np.asarray(bounds, float)
    centre = (lo + hi) / 2
    radius = max(float(np.linalg.norm(hi - lo)) / 2, 1e-3)
    d = np.asarray(direction, float)
    cam = plotter.camera
    cam.focal_point = centre.tolist()
    distance = radius / math.sin(math.radians(cam.view_angle / 2))
    cam.position = (centre + d / np.linalg.norm(d) * distance).tolist()
    cam.up = (0.0, 0.0, 1.0)
    plotter.renderer.ResetCameraClippingRange()


def _bounds(*arrays: np.ndarray) -> np.ndarray | None:
    """(2, 3) bounds of point arrays (..., 3), or None when there is none."""
    pts = [np.asarray(a, float).reshape(-1, 3) for a in arrays if a is not None and np.size(a)]
    if not pts:
        return None
    p = np.vstack(pts)
    p = p[np.all(np.isfinite(p), axis=1)]
    return np.stack([p.min(axis=0), p.max(axis=0)]) if len(p) else None


def _markers(plotter, markers: Sequence[tuple[np.ndarray, str, str]], size: float) -> None:
    """Findings' places: (at (3,) mm, label, colour) — a dot and the label beside it."""
    pv = _import()
    for colour in dict.fromkeys(c for _, _, c in markers):
        sel = [(np.asarray(a, float), t) for a, t, c in markers if c == colour]
        pts = np.array([a for a, _ in sel])
        plotter.add_mesh(pv.PolyData(pts), color=colour, point_size=size, render_points_as_spheres=True)
        plotter.add_point_labels(pts, [t for _, t in sel], font_size=12, text_color=colour,
                                 shape_color="white", shape_opacity=0.7, show_points=False,
                                 always_visible=True)


def profile_png(
    path: str | Path,
    curves: Sequence[tuple[np.ndarray, str]],
    title: str = "",
    size: tuple[int, int] = WINDOW,
    labels: Sequence[tuple[np.ndarray, str, str]] = (),
    scale: bool = False,
) -> Path:
    """Closed plane curves, seen along −Z, as a PNG.

    curves : sequence of (points (n, 2) float mm, colour name); each is drawn closed.
    labels : (at (2,) mm, text, colour) written at points; scale: a scale bar under the curves.
    """
    out = Path(path)
    if out.suffix.lower() != ".png":
        raise InputError(f"{out}: pictures are written as .png", kind="export_format")
    pv, plotter = _plotter(size)
    allp = []
    for pts, colour in curves:
        p = np.asarray(pts, dtype=float)
        xyz = np.column_stack([p, np.zeros(len(p))])
        xyz = np.vstack([xyz, xyz[:1]])
        allp.append(xyz)
        plotter.add_mesh(pv.lines_from_points(xyz), color=colour, line_width=3)
    axis = np.array([[-1.0, 0, 0], [1.0, 0, 0], [0, -1.0, 0], [0, 1.0, 0]])
    plotter.add_mesh(pv.line_segments_from_points(axis), color="gray", line_width=1)
    for at, text, colour in labels:
        plotter.add_point_labels(np.array([[at[0], at[1], 0.0]]), [text], font_size=14, text_color=colour,
                                 shape_opacity=0.0, show_points=False, always_visible=True)
    if scale and allp:
        lo, hi = _bounds(*allp)
        pad = 0.08 * float(np.max(hi - lo))
        _scale_bar(plotter, np.stack([lo - [0, pad, 0], hi]))
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


def _finish_part(plotter, path: Path, title: str, vertices: np.ndarray, faces: np.ndarray) -> Path:
    """Title, axis triad, scale bar over the drawn faces' vertices (n, 3) mm, the part seen
    from above and aside, and the PNG written."""
    if title:
        plotter.add_text(title, font_size=12, color=FOREGROUND, position="upper_left")
    _triad(plotter)
    box = _bounds(np.asarray(vertices, float)[np.unique(np.asarray(faces).ravel())]) if len(faces) else None
    if box is not None:
        _scale_bar(plotter, box)
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
    colours: np.ndarray | None = None,
    ticks: Sequence[float] | None = None,
    unit: str = "mm",
    nan_colour: Sequence[float] | str = "lightgray",
) -> Path:
    """A part coloured by deviation, with an axis triad and a scale bar.

    vertices (n, 3) mm, faces (m, 3); deviation (n,) per vertex in ``unit``, NaN where not
    measured (drawn ``nan_colour``); clim (lo, hi) of the colour bar in ``unit``; colours
    (k, 3) float 0..1: the colour map over clim (default coolwarm); ticks: the colour bar's
    labels (values in ``unit``; default five evenly spaced).
    """
    pv, plotter = _plotter(size)
    name = f"radial deviation [{unit}]"
    mesh = pv.PolyData(np.asarray(vertices, float), _faces(faces))
    mesh.point_data[name] = np.asarray(deviation, float)
    cmap = "coolwarm"
    if colours is not None:
        from matplotlib.colors import ListedColormap

        cmap = ListedColormap(np.asarray(colours, float))
    plotter.add_mesh(
        mesh,
        scalars=name,
        cmap=cmap,
        clim=list(clim),
        nan_color=nan_colour,
        smooth_shading=False,
        scalar_bar_args={
            "title": name,
            "color": FOREGROUND,
            "fmt": "%+g" if unit == "µm" else "%.4f",
            "n_labels": 5,
            "vertical": True,
            "position_x": 0.8,
            "position_y": 0.1,
            "width": 0.08,
            "height": 0.6,
        },
    )
    if ticks is not None:
        from vtkmodules.vtkCommonCore import vtkDoubleArray

        bar = plotter.scalar_bars[name]
        values = vtkDoubleArray()
        for t in ticks:
            values.InsertNextValue(float(t))
        bar.SetCustomLabels(values)
        bar.SetUseCustomLabels(True)
    return _finish_part(plotter, Path(path), title, vertices, faces)


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
    return _finish_part(plotter, Path(path), title, vertices, faces)


def toolpath_png(
    path: str | Path,
    points: np.ndarray,
    kinds: np.ndarray,
    outline: tuple | None = None,
    title: str = "",
    size: tuple[int, int] = WINDOW,
    markers: Sequence[tuple[np.ndarray, str, str]] = (),
    focus: np.ndarray | None = None,
) -> Path:
    """A tool path in 3-D: rapids red, feeds green (as the control's simulation draws them),
    with an axis triad and a scale bar.

    points (n, 2, 3) mm — segment end points; kinds (n,) — 0 rapid, 1 feed.
    outline : optional (vertices, faces) of the stock drawn as a translucent body.
    markers : findings' places, (at (3,) mm, label, colour): a dot and the label.
    focus : (2, 3) mm, the box the camera frames (default: everything); segments beyond it are
    drawn all the same and run out of the picture.
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
    box = focus if focus is not None else _bounds(pts, None if outline is None else outline[0],
                                                   *(np.asarray(a, float) for a, _, _ in markers))
    if markers:
        _markers(plotter, markers, 14.0)
    if title:
        plotter.add_text(title, font_size=12, color=FOREGROUND, position="upper_left")
    _triad(plotter)
    if box is not None:
        _scale_bar(plotter, box)
        plotter.view_isometric()
        _frame(plotter, box)
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


def _bodies(pv, plotter, meshes, lines, line_width: int) -> None:
    """Add line segments (``lines``: (segments (n, 2, 3) mm, colour)) and solids (``meshes``:
    (vertices, faces, colour, opacity)), flat shaded; empty ones are left out."""
    for seg, colour in lines:
        if len(seg):
            plotter.add_mesh(pv.line_segments_from_points(np.asarray(seg, float).reshape(-1, 3)),
                             color=colour, line_width=line_width)
    for v, f, colour, opacity in meshes:
        if len(f):
            plotter.add_mesh(pv.PolyData(np.asarray(v, float), _faces(f)), color=colour, opacity=opacity,
                             smooth_shading=False)


def scene_png(
    path: str | Path,
    meshes: Sequence[tuple[np.ndarray, np.ndarray, str, float]],
    focus: tuple[np.ndarray, float],
    title: str = "",
    marker: np.ndarray | None = None,
    size: tuple[int, int] = WINDOW,
    legend: Sequence[tuple[str, str]] = (),
    lines: Sequence[tuple[np.ndarray, str]] = (),
) -> Path:
    """A close-up of solids: meshes (vertices, faces, colour, opacity); the camera looks at
    ``focus`` = (centre (3,), radius mm); ``marker`` (3,) draws a small sphere at a point;
    ``lines``: (segments (n, 2, 3) mm, colour) drawn thick; ``legend``: (label, colour) of
    what is which body. An axis triad and a scale bar."""
    pv, plotter = _plotter(size)
    _bodies(pv, plotter, meshes, lines, 4)
    centre, radius = focus
    if marker is not None:
        plotter.add_mesh(
            pv.Sphere(radius=max(radius / 40, 0.2), center=np.asarray(marker, float)), color="red"
        )
    if title:
        plotter.add_text(title, font_size=12, color=FOREGROUND, position="upper_left")
    if legend:
        # VTK writes each entry in its own colour: a dark box keeps light ones (silver) readable
        w, h = 0.34, 0.035 * len(legend) + 0.02
        box = plotter.add_legend([[label, colour] for label, colour in legend], bcolor=(0.22, 0.22, 0.22),
                                 border=True, size=(w, h), loc="upper right", face="rectangle")
        box.SetPosition(1.0 - w - 0.01, 1.0 - h - 0.05)      # pyvista's "upper right" runs off the edge
        box.SetPosition2(w, h)
    _triad(plotter)
    c = np.asarray(centre, float)
    _scale_bar(plotter, np.stack([c - 0.9 * radius, c + 0.9 * radius]))
    plotter.view_isometric()
    _frame(plotter, np.stack([np.asarray(centre, float) - radius, np.asarray(centre, float) + radius]))
    return _save(plotter, Path(path))


def images_equal(a: str | Path, b: str | Path, threshold: float) -> tuple[bool, float]:
    """Image regression: pyvista's mean pixel error between two PNGs, and whether it is within
    ``threshold``."""
    err = float(_import().compare_images(str(a), str(b)))
    return err <= threshold, err


def frame_rgb(
    meshes: Sequence[tuple[np.ndarray, np.ndarray, str, float]],
    bounds: np.ndarray,
    text: str = "",
    caption: str = "",
    lines: Sequence[tuple[np.ndarray, str]] = (),
    size: tuple[int, int] = (800, 600),
    direction=(1.0, -1.0, 0.8),
) -> np.ndarray:
    """One frame of an animation as an image (h, w, 3) uint8: meshes (vertices (n, 3) mm,
    faces (m, 3), colour, opacity), ``lines`` (segments (s, 2, 3) mm, colour), ``text`` in the
    upper left, ``caption`` along the bottom; the camera looks at the box ``bounds`` (2, 3) mm
    from ``direction`` — the same box for every frame, so that the frames line up."""
    pv, plotter = _plotter(size)
    try:
        _bodies(pv, plotter, meshes, lines, 2)
        if text:
            plotter.add_text(text, font_size=11, color=FOREGROUND, position="upper_left")
        if caption:
            plotter.add_text(caption, font_size=10, color=FOREGROUND, position="lower_right")
        _triad(plotter)
        _frame(plotter, bounds, direction)
        image = plotter.screenshot(None, return_img=True)
    finally:
        plotter.close()
    return np.asarray(image, dtype=np.uint8)
