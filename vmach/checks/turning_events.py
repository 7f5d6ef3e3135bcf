"""A turning path cut move by move, with its checks: rapids into the stock and the holder (or
boring bar) in the stock, measured on the stock as it is cut (``simulate(..., checks=True)``).

The workpiece turns, so whatever lies at a point of the X–Z half-plane lies there at every
angle: a rapid removes material when the insert's revolved sweep meets the stock
(``rapid_into_stock``), the holder runs into the stock when its cross-section's revolved sweep
does (``holder_collision``, part ``holder`` or ``boring_bar``). Each move is screened by the
stock's bounds first; only moves that reach them are measured, exactly, on the stock inside the
cutter's box (:meth:`vmach.stock.Stock.local`).
"""

from __future__ import annotations

import numpy as np

from vmach.findings import Finding
from vmach.motion.table import TRAVERSE
from vmach.stock import engine
from vmach.stock.stock import Stock
from vmach.tol import tol


def turn_checked(stock: Stock, tool, table, rows: np.ndarray, tips: np.ndarray, res) -> None:
    """Cut the turning path of ``tool`` (a :class:`vmach.tooling.turning.TurningTool`) with
    poses ``tips`` (n, 3) and their table ``rows`` (n,) int (a step belongs to the row it ends
    in), move by move, into ``stock``; findings go to ``res.findings``."""
    section = tool.section(stock.turn_chord)
    holder = tool.holder_section()
    part = "boring_bar" if tool.kind == "boring" else "holder"
    kind = np.asarray(table.kind)
    i = 0
    n = len(tips)
    while i < n - 1:
        row = int(rows[i + 1])
        j = i + 1
        while j < n - 1 and rows[j + 1] == row:
            j += 1
        seg, seg_rows = tips[i : j + 1], rows[i : j + 1]
        cutters = stock.turned(section, seg, seg_rows)
        if kind[row] == TRAVERSE and cutters:
            _rapid(stock, cutters, table, row, res)
        stock.queue(cutters)
        if len(holder) and tool.holder_length + tool.bar_length > 0:
            _holder(stock, holder, seg, table, row, part, res)
        i = j


def _reaches(stock: Stock, box: np.ndarray) -> bool:
    lo, hi = stock.bounds
    return bool(np.all(box[0] <= hi) and np.all(box[1] >= lo))


def _rapid(stock: Stock, cutters, table, row: int, res) -> None:
    cut = engine.union([c.solid for c in cutters])
    box = engine.bounds(cut)
    if not _reaches(stock, box):
        return
    local = stock.local(box[0], box[1])
    removed = engine.volume(local) - engine.volume(engine.subtract(local, [cut]))
    if removed > tol.removal_volume:
        res.findings.append(Finding(
            "rapid_into_stock", "error", f"rapid move removes {removed:.3f} mm³ of material (turning)",
            table.source(row), row, {"volume_mm3": round(removed, 4)}))


def _holder(stock: Stock, holder: np.ndarray, seg: np.ndarray, table, row: int, part: str, res) -> None:
    for c in stock.turned(holder, seg):
        if not _reaches(stock, c.box):
            continue
        local = stock.local(c.box[0], c.box[1])
        vol = engine.volume(engine.intersect(local, c.solid))
        if vol > tol.removal_volume:
            res.findings.append(Finding(
                "holder_collision", "error", f"the tool's {part} runs {vol:.3f} mm³ into the stock",
                table.source(row), row, {"part": part, "volume_mm3": round(vol, 4)}))
            return
