"""Process checks on the move table: tools the library lacks, cutting with the tool's spindle
stopped (or only another spindle turning), feed moves at zero feed.

Consecutive offending rows of one kind are reported once, at the first row, with the number of
rows and the last line in ``data``, so a stopped spindle under a 4,000-move loop is one finding.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from vmach import canon
from vmach.findings import Finding
from vmach.motion.table import FEED_MODES, TRAVERSE, MoveTable


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[(first, last)] row ranges where ``mask`` (n,) bool is True, inclusive."""
    if not mask.any():
        return []
    m = np.concatenate(([False], mask, [False])).astype(np.int8)
    d = np.diff(m)
    starts = np.flatnonzero(d == 1)
    ends = np.flatnonzero(d == -1) - 1
    return list(zip(starts.tolist(), ends.tolist(), strict=True))


def unknown_tools(commands: Sequence[canon.Command], library) -> list[Finding]:
    """``unknown_tool`` at every T the library (``lookup(name) -> Tool | None``) lacks."""
    out = []
    for c in commands:
        if isinstance(c, canon.ToolChange) and library.lookup(c.tool) is None:
            out.append(
                Finding(
                    "unknown_tool",
                    "error",
                    f'tool "{c.tool}" is not in the tool library {library.path}',
                    c.source,
                    None,
                    {"tool": c.tool},
                )
            )
    return out


def spindle_off_cuts(table: MoveTable, tool_spindle: int | None) -> list[Finding]:
    """``spindle_off_cut`` for feed moves while the spindle driving the tool stands still.

    tool_spindle : the spindle that turns the cutter (the turn-mill's live-tool spindle 2);
        None means the master spindle of each row.
    """
    n = len(table)
    if n == 0:
        return []
    cutting = table.kind != TRAVERSE
    if tool_spindle is None:
        turning = table.master_state()[1] != 0
    elif tool_spindle in table.spindles:
        turning = table.direction[:, table.spindles.index(tool_spindle)] != 0
    else:
        turning = np.zeros(n, bool)
    others = (table.direction != 0).any(axis=1) & ~turning
    out = []
    for a, b in runs(cutting & ~turning):
        wrong = bool(others[a])
        which = f"spindle {tool_spindle}" if tool_spindle is not None else "the master spindle"
        msg = (
            f"feed move with {which} stopped"
            + (" while another spindle turns" if wrong else "")
            + (f" ({b - a + 1} moves, to line {int(table.line[b])})" if b > a else "")
        )
        out.append(
            Finding(
                "spindle_off_cut",
                "error",
                msg,
                table.source(a),
                a,
                {"moves": b - a + 1, "last_line": int(table.line[b]), "wrong_spindle": wrong},
            )
        )
    return out


def zero_feeds(table: MoveTable) -> list[Finding]:
    """``zero_feed`` for feed moves whose effective feed is zero (F0, or per-revolution feed with
    the master spindle stopped)."""
    n = len(table)
    if n == 0:
        return []
    cutting = table.kind != TRAVERSE
    feed = np.nan_to_num(table.feed, nan=0.0)
    per_rev = table.feed_mode == FEED_MODES.index("per_rev")
    master_speed = table.master_state()[0]
    zero = cutting & ((feed <= 0) | (per_rev & (master_speed <= 0)))
    out = []
    for a, b in runs(zero):
        why = "F0" if feed[a] <= 0 else "feed per revolution with the spindle at 0 rev/min"
        out.append(
            Finding(
                "zero_feed",
                "error",
                f"feed move at zero feed ({why})",
                table.source(a),
                a,
                {"moves": b - a + 1, "last_line": int(table.line[b])},
            )
        )
    return out
