"""Cutter radius compensation beyond the golden traces: static checks, canonical commands.

The traces themselves are compared with rs274 by ``test_golden.py`` (``comp_*.ngc``).
"""

from __future__ import annotations

from pathlib import Path

from interpreters.rs274ngc import check, run
from vmach.canon import Comment, LinearFeed

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "rs274ngc"


def test_check_accepts_every_compensation_code(tmp_path):
    path = tmp_path / "comp.ngc"
    path.write_text("G20 T1 M6\nG41 G1 X1 F10\nG40\nG42 G1 X2\nG40\nG41.1 D0.1 G1 X3\nG40\n"
                    "G42.1 D0.1 G1 X4\nG40\nM2\n", encoding="utf-8")
    assert check(path) == []
    result = run(path)
    assert result.completed, [f.render() for f in result.findings]


def test_held_back_move_keeps_its_line_and_comes_after_later_comments():
    """N70's move waits for N90 to decide its end; the comment of N80 is issued meanwhile
    and waits behind it, as in rs274's trace."""
    result = run(FIXTURES / "comp_lines.ngc")
    assert result.completed
    commands = result.commands
    feed = next(i for i, c in enumerate(commands)
                if isinstance(c, LinearFeed) and c.source.line == 8)
    after = commands[feed + 1]
    assert isinstance(after, Comment) and after.source.line == 9
    # 0.125 in tool on the left of X0 -> X2 at Y0: the tool centre runs 1/16 in above
    assert abs(commands[feed].axes["Y"] - 0.0625 * 25.4) < 1e-9


def test_error_stops_with_the_queue_unprinted(tmp_path):
    path = tmp_path / "gouge.ngc"
    path.write_text("G20 T3 M6\nG0 X0 Y0\nG41 G1 X1 F10\nY1\nX0.9\nY0\nM2\n", encoding="utf-8")
    result = run(path)
    assert not result.completed
    finding = result.findings[-1]
    assert finding.kind == "comp_feed_concave"
    assert finding.source.line == 6
    # each concave corner released the move before it; the move to X0.9 was still held
    # back when the corner after it failed: it is never emitted
    assert [c.source.line for c in result.commands if isinstance(c, LinearFeed)] == [3, 4]
