"""The demo's animation: frames of a small cut decoded back from the GIF and the MP4 differ,
and the stock loses material from frame to frame."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from vmach.demo.animation import cut_frames, frame_rows, rows_of, write_animation
from vmach.verify import VerifyOptions, verify

iio = pytest.importorskip("imageio.v3")

ROOT = Path(__file__).resolve().parents[2]

#: three plunges of a Ø10 end mill into a 30 x 30 x 10 block, then a slot between two of them
PROGRAM = """N10 G17 G90 G54
N20 T="EM10" D1
N30 S3000 M3
N40 G0 Z20
N50 G0 X-8 Y-8
N60 G1 Z-4 F300
N70 G0 Z5
N80 G0 X8 Y-8
N90 G1 Z-4 F300
N100 G0 Z5
N110 G0 X8 Y8
N120 G1 Z-4 F300
N130 G1 X-8 F600
N140 G0 Z20
N150 M30
"""


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    d = tmp_path_factory.mktemp("anim")
    shutil.copyfile(ROOT / "fixtures" / "milling" / "tools.toml", d / "tools.toml")
    (d / "vmach.toml").write_text('machine = "s5d"\ntools = "tools.toml"\nstock = "box:x=30,y=30,z=10"\n')
    (d / "CUT.MPF").write_text(PROGRAM)
    return verify(d / "CUT.MPF", VerifyOptions(images=False))


def test_frames_spread_over_the_cycle_time():
    rows = frame_rows(np.array([1.0, 0.0, 1.0, 2.0]), 4)
    assert rows.tolist() == [0, 2, 3]                  # 1 s, 2 s, 3 s (none at 0 s), 4 s
    assert frame_rows(np.zeros(3), 3).tolist() == [0, 1, 2]


def test_rows_of_keeps_the_table_whole(report):
    t = report.table
    part = rows_of(t, 2, 5)
    assert len(part) == 3 and part.tools == t.tools and np.array_equal(part.end, t.end[2:5])
    assert part.source(0) == t.source(2)


def test_animation_decodes_and_shows_material_going(report, tmp_path):
    frames = list(cut_frames(report, frames=4, size=(320, 240)))
    assert len(frames) >= 3
    vol = [f.volume for f in frames]
    assert vol[0] < 30 * 30 * 10 and all(b < a for a, b in zip(vol, vol[1:], strict=False))
    assert frames[-1].volume == pytest.approx(report.part.volume, rel=1e-6)
    assert all(f.line > 0 for f in frames) and frames[-1].file == "CUT.MPF"
    files = write_animation(frames, tmp_path, stem="cut", fps=4)
    gif = iio.imread(tmp_path / files["gif"], index=None)
    mp4 = iio.imread(tmp_path / files["mp4"], index=None, plugin="FFMPEG")
    assert gif.shape[0] == len(frames) and mp4.shape[0] == len(frames)
    for movie in (gif[..., :3], mp4):
        m = movie.astype(float)
        diffs = [np.abs(m[i + 1] - m[i]).mean() for i in range(len(m) - 1)]
        assert min(diffs) > 0.2                          # each frame differs from the one before
    # the block's top face (flat shaded: one colour, the most frequent one not background in
    # the first frame) shows fewer pixels at the end: the holes and the slot took them (the tool
    # stands over the block in the first frame and hides some of it too)
    first, last = gif[0][..., :3].astype(int), gif[-1][..., :3].astype(int)
    px = first.reshape(-1, 3)
    px = px[px.sum(axis=1) < 720]
    colours, counts = np.unique(px, axis=0, return_counts=True)
    top = colours[np.argmax(counts)]

    def top_pixels(img):
        return int((np.abs(img - top).sum(axis=2) <= 12).sum())

    assert top_pixels(last) < 0.9 * top_pixels(first)


def test_the_view_holds_where_the_moves_cut():
    from vmach.demo.animation import cut_view

    blank = np.array([[-8.0, -8.0, -72.0], [8.0, 8.0, 0.0]])       # a Ø16 bar, 72 long
    tips = np.array([[0.0, 0.0, -12.0], [0.0, 0.0, 8.0]])          # moves at its end only
    view = cut_view(blank, tips, pad=0.0)
    assert view[0, 2] == -20.0 and view[1, 2] == 0.0 and view[0, 0] == -8.0
    assert cut_view(blank, np.zeros((0, 3)), pad=0.0)[0, 2] == -72.0
