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
    """``unknown_tool`` at every T the library (``lookup(name) -> Tool | None``) lacks — every
    T when there is no library (None): a tool nothing describes is never assumed. T0 (number
    0) deselects the tool and is never one. A library with a stand-in (``stood_in``,
    :class:`vmach.tooling.default.WithDefault`) makes each tool it replaces a ``default_tool``
    warning instead."""
    out = []
    for c in commands:
        if not isinstance(c, canon.ToolChange) or c.number == 0:
            continue
        data = {"tool": c.tool}
        if library is None:
            out.append(Finding("unknown_tool", "error", f'tool "{c.tool}": no tool library describes it '
                               "(give --tools, or --default-tool to stand in for it)", c.source, None, data))
        elif getattr(library, "stood_in", None) is not None and library.stood_in(c.tool):
            d = library.default
            out.append(Finding("default_tool", "warning", f'tool "{c.tool}" is not in a tool library: '
                               f"simulated as the stand-in {d.kind} Ø{d.diameter:g} mm, "
                               f"{d.cutting_length:g} mm cutting length, without shank or holder "
                               "(not checked for collisions)",
                               c.source, None, data))
        elif library.lookup(c.tool) is None:
            out.append(Finding("unknown_tool", "error", f'tool "{c.tool}" is not in the tool library '
                               f"{library.path}", c.source, None, data))
    return out


def spindle_off_cuts(table: MoveTable, tool_spindle: int | None, reach=None,
                     turning: np.ndarray | None = None, probe: np.ndarray | None = None) -> list[Finding]:
    """``spindle_off_cut`` for feed moves while the spindle driving the tool stands still.

    tool_spindle : the spindle that turns the cutter (the turn-mill's live-tool spindle 2);
        None means the master spindle of each row.
    reach : None when there is no stock to tell whether a move cuts (each such move is then a
        warning), else a function ``rows (k,) int -> (k,) bool``: whether those moves reach
        into the stock's envelope (:func:`vmach.checks.envelope.in_envelope`); only they are
        errors, a feed in the air is none.
    turning : (n,) bool or None — rows the workpiece's turning cuts (a turning tool, or no
        tool at all, on a machine with a tool spindle): their spindle is the master spindle
        (:func:`turning_rows`).
    probe : (n,) bool or None — rows of a touch probe (:func:`vmach.checks.probing.probe_rows`):
        it does not turn, and cuts nothing.
    """
    n = len(table)
    if n == 0:
        return []
    cutting = table.kind != TRAVERSE
    if probe is not None:
        cutting &= ~np.asarray(probe, bool)
    main = np.zeros(n, bool) if turning is None or tool_spindle is None else np.asarray(turning, bool)
    if tool_spindle is None:
        turning = table.master_state()[1] != 0
    elif tool_spindle in table.spindles:
        turning = table.direction[:, table.spindles.index(tool_spindle)] != 0
    else:
        turning = np.zeros(n, bool)
    turning = np.where(main, table.master_state()[1] != 0, turning)
    others = (table.direction != 0).any(axis=1) & ~turning
    off = cutting & ~turning
    if reach is not None and off.any():
        rows = np.flatnonzero(off)
        off[rows] = reach(rows)
    out = []
    for a, b in runs(off):
        wrong = bool(others[a])
        own = tool_spindle is not None and not main[a]
        which = f"spindle {tool_spindle}" if own else "the master spindle"
        msg = (
            f"feed move with {which} stopped"
            + (" while another spindle turns" if wrong else "")
            + (f" ({b - a + 1} moves, to line {int(table.line[b])})" if b > a else "")
            + (" (no stock to tell whether it cuts)" if reach is None else "")
        )
        out.append(
            Finding(
                "spindle_off_cut",
                "warning" if reach is None else "error",
                msg,
                table.source(a),
                a,
                {"moves": b - a + 1, "last_line": int(table.line[b]), "wrong_spindle": wrong},
            )
        )
    return out


def turning_rows(table: MoveTable, library) -> np.ndarray:
    """(n,) bool: rows whose tool is a turning tool (:class:`vmach.tooling.turning.TurningTool`)
    or that have no tool — on a turn-mill the main spindle's turning is what cuts there; a
    tool the library lacks is taken for a milling cutter, as before."""
    tool = np.asarray(table.tool)
    out = tool < 0
    if library is not None:
        for i, name in enumerate(table.tools):
            if getattr(library.lookup(name), "turning", False):
                out |= tool == i
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
