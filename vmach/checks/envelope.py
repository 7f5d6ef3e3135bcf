"""Which moves reach into the blank's envelope: the box around the stock as it was before any
cut, against the box around the tool's cutting part at a move's ends (and its middle, where a
rotary axis turns). A move outside it cannot cut; one inside may (``spindle_off_cut`` is an
error only there — a G1 in the air after M5 is not one)."""

from __future__ import annotations

import numpy as np

from vmach.stock.events import cylinder_boxes, overlaps


def in_envelope(table, model, library, box: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """(len(rows),) bool: whether move ``rows`` (int array) of ``table`` may reach the blank.

    model : kinematics (``axes``, ``home``, ``fk``); library : ``lookup(name) -> Tool | None``
        or None (a tool nothing describes is taken as its tip alone); box : (2, 3) mm, the
        blank's bounds in the workpiece frame.
    """
    rows = np.asarray(rows, dtype=int)
    if len(rows) == 0:
        return np.zeros(0, bool)
    radius = np.zeros((len(rows), 1))
    length = np.zeros((len(rows), 1))
    for i, ti in enumerate(np.asarray(table.tool)[rows]):
        tool = library.lookup(table.tools[ti]) if library is not None and ti >= 0 else None
        if tool is not None:
            radius[i], length[i] = tool.radius, tool.cutting_length
    q0 = table.columns(model.axes, model.home, table.start[rows])
    q1 = table.columns(model.axes, model.home, table.end[rows])
    hit = np.zeros(len(rows), bool)
    for q in (q0, q1, (q0 + q1) / 2.0):
        pose = model.fk(q)
        boxes = cylinder_boxes(np.asarray(pose.tip, float), np.asarray(pose.axis, float), 0.0, length, radius)
        hit |= overlaps(boxes, np.asarray(box, float))
    return hit
