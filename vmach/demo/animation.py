"""An animation of a program's cut: the stock as the program removes it, the tool with its
shank and holder where the frame's last move leaves it, the tool path so far, and the block
being run (file, line and text).

The moves are cut again, frame by frame, on a fresh stock through vmach.stock's public API
(``Stock`` and ``simulate`` on consecutive slices of the move table), so each frame shows the
stock exactly as it was after that move. Frames are spaced evenly over the cycle time (a
lecture sees the program in its own proportions: the long finishing pass takes most of them).
Frames are rendered by :func:`vmach.report.render.frame_rgb` and encoded by imageio (GIF with
Pillow, MP4 with imageio-ffmpeg's ffmpeg).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vmach.errors import InputError


@dataclass(frozen=True)
class Frame:
    """One picture of the cut: ``image`` (h, w, 3) uint8, after move-table row ``row`` (the
    block at ``line`` of ``file``), the stock's volume then (mm³)."""

    image: np.ndarray
    row: int
    file: str
    line: int
    volume: float


def rows_of(table, a: int, b: int):
    """The move table's rows a..b-1 as a table of their own (the same tools and commands)."""
    per_row = {f.name: getattr(table, f.name) for f in dataclasses.fields(table)
               if isinstance(getattr(table, f.name), np.ndarray) and f.name != "rotary"}
    return dataclasses.replace(table, **{k: v[a:b] for k, v in per_row.items()})


def frame_rows(row_seconds: np.ndarray, frames: int) -> np.ndarray:
    """The row after which each frame is shown: frames evenly spaced over the cycle time
    (``row_seconds`` (n,) s), strictly increasing, the last row last. Returns (k,) int, k ≤ frames."""
    n = len(row_seconds)
    if n == 0:
        return np.zeros(0, dtype=int)
    t = np.cumsum(np.maximum(np.asarray(row_seconds, float), 0.0))
    if t[-1] <= 0:
        t = np.arange(1, n + 1, dtype=float)
    marks = np.linspace(t[-1] / frames, t[-1], frames)
    rows = np.minimum(np.searchsorted(t, marks - 1e-9), n - 1)
    return np.unique(rows)


def block_text(path: str, line: int, cache: dict) -> str:
    """The text of line ``line`` of ``path`` (the program or a subprogram), stripped."""
    if path not in cache:
        try:
            cache[path] = Path(path).read_text(encoding="utf-8", errors="replace").splitlines()
        except OSError:
            cache[path] = []
    lines = cache[path]
    return lines[line - 1].strip() if 0 < line <= len(lines) else ""


def cut_view(blank: np.ndarray, feed_tips: np.ndarray, pad: float = 0.35) -> np.ndarray:
    """The box (2, 3) mm every frame looks at: the blank's bounds ``blank`` (2, 3), along Z
    only where the feed moves go (a blank's far end, which no move touches, is left out; the
    tips (n, 3) widened by the blank's width), grown by ``pad`` of its largest side."""
    box = np.array(blank, float)
    width = float(np.max(box[1, :2] - box[0, :2]))
    if len(feed_tips):
        lo = max(box[0, 2], float(feed_tips[:, 2].min()) - 0.5 * width)
        hi = min(box[1, 2], float(feed_tips[:, 2].max()) + 0.5 * width)
        if lo < hi:
            box[:, 2] = lo, hi
    span = float(np.max(box[1] - box[0]))
    return np.stack([box[0] - pad * span, box[1] + pad * span])


def cut_frames(report, frames: int = 48, size: tuple[int, int] = (800, 600)) -> Iterator[Frame]:
    """The frames of ``report``'s program (a :class:`vmach.verify.Report` whose stock was
    simulated: table, model, library, stock_spec, timing)."""
    from vmach.checks.collisions import tool_cylinders
    from vmach.motion.table import TRAVERSE
    from vmach.report import render
    from vmach.report.pictures import cylinder_mesh, transformed
    from vmach.stock import Stock
    from vmach.stock.simulate import simulate
    from vmach.tol import ACCURACY

    table, model, lib = report.table, report.model, report.library
    if report.part is None or lib is None or table is None:
        raise InputError(f"{report.program}: the animation needs a simulated stock (a stock and a "
                         "tool library in vmach.toml)", kind="usage")
    stock = Stock.from_spec(report.stock_spec, **ACCURACY[report.accuracy].stock)
    try:
        # the tip's path, a chord per feed row (rapids are left out: they would cross the view)
        tips0 = model.fk(table.columns(model.axes, model.home, table.start)).tip
        tips1 = model.fk(table.columns(model.axes, model.home, table.end)).tip
        seg = np.stack([tips0, tips1], axis=1)
        feed = np.asarray(table.kind) != TRAVERSE
        view = cut_view(np.asarray(stock.initial_bounds, float), tips1[feed])
        marks = frame_rows(report.timing.row_seconds if report.timing is not None
                           else np.ones(len(table)), frames)
        cache: dict = {}
        name = Path(report.program).name
        start = 0
        colours = {"cutter": "gold", "shank": "silver", "holder": "sienna"}
        for row in marks:
            row = int(row)
            if row + 1 > start:
                simulate(rows_of(table, start, row + 1), model, lib, stock)
                start = row + 1
            v, f = stock.mesh("part")
            meshes = [(v, f, "lightsteelblue", 1.0)]
            ti = int(table.tool[row])
            tname = table.tools[ti] if ti >= 0 else None
            tool = lib.lookup(tname) if tname is not None else None
            if tool is not None:
                q = table.columns(model.axes, model.home, table.end[row:row + 1])
                t2w = model.tool2work(q)[0]
                for c in tool_cylinders(tool):
                    cv, cf = cylinder_mesh(c.radius, c.z0, c.z1)
                    meshes.append((transformed(cv, t2w), cf, colours.get(c.part, "gold"), 1.0))
            src = table.source(row)
            fname = Path(str(src.path)).name
            line = int(table.line[row])
            text = (f"{name}   tool {tname or '-'}\n{fname}:{line}  {block_text(str(src.path), line, cache)}")
            done = seg[: row + 1][feed[: row + 1]]
            t = float(np.sum(report.timing.row_seconds[: row + 1])) if report.timing is not None else 0.0
            image = render.frame_rgb(meshes, view, text=text, caption=f"t = {t / 60:.2f} min",
                                     lines=[(done, "darkgreen")], size=size)
            yield Frame(image, row, fname, line, float(stock.volume))
    finally:
        stock.close()


def write_animation(frames: list[Frame], out_dir: Path, stem: str = "cut", fps: int = 8) -> dict[str, str]:
    """Encode the frames as ``stem.gif`` (looping) and ``stem.mp4`` (H.264, yuv420p: plays in
    browsers and presentation programs); returns kind -> file name. Each written whole."""
    try:
        import imageio.v3 as iio
    except ImportError:
        raise InputError("the animation needs imageio: pip install 'imageio>=2.31' 'imageio-ffmpeg>=0.4.9'",
                         kind="usage") from None
    from vmach.output import atomic_writer

    images = [f.image for f in frames]
    if not images:
        raise InputError("no frames to write: the program has no moves", kind="usage")
    out: dict[str, str] = {}
    gif = iio.imwrite("<bytes>", np.stack(images), extension=".gif", duration=1000 / fps, loop=0)
    with atomic_writer(out_dir / f"{stem}.gif", "wb") as fh:
        fh.write(gif)
    out["gif"] = f"{stem}.gif"
    target = out_dir / f"{stem}.mp4"
    part = out_dir / f".{stem}.part.mp4"          # ffmpeg writes a file: renamed when whole
    try:
        iio.imwrite(part, np.stack(images), plugin="FFMPEG", fps=fps, codec="libx264",
                    pixelformat="yuv420p", macro_block_size=8)
        os.replace(part, target)
    finally:
        part.unlink(missing_ok=True)
    out["mp4"] = f"{stem}.mp4"
    return out
