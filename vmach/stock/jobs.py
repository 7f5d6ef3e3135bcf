"""Jobs: what a planner asks the cutter makers for, as typed values.

Every job names the program rows that made it (``rows``: first and last, -1 when the path
was cut without rows), so that each cutter — and so each piece of removed material — can be
traced to its line. Frames are (3, 4) tool → work, mm; the tool piece ``piece`` indexes
``ToolSolid.pieces``; fans and columns are made of piece 0 (a one-piece prism).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vmach.stock import engine
from vmach.stock.column import Column

NO_ROWS = (-1, -1)


@dataclass(frozen=True, eq=False)
class Placed:
    """Piece ``piece`` placed at each of ``frames`` (m, 3, 4); where ``fins`` (m,) mm is finite
    only the pose's fin of that half-width, up to ``tall`` (m,) mm along the axis (inf: the whole
    length). ``rows`` (m, 2) int: each pose's rows."""

    piece: int
    frames: np.ndarray
    fins: np.ndarray
    tall: np.ndarray
    rows: np.ndarray


@dataclass(frozen=True, eq=False)
class Runs:
    """Translation hulls of piece ``piece``, one per group of runs (each run the frames of its
    two extreme poses; a group of several runs stacks, so the hull of all is their union).
    ``rows`` (g, 2) int: each group's rows."""

    piece: int
    groups: list[list[tuple[np.ndarray, np.ndarray]]]
    rows: np.ndarray


@dataclass(frozen=True, eq=False)
class Fan:
    """One candidate fan run of rotary steps about ``omega`` (3,): its poses' ``tips``, unit
    ``axes`` (n, 3) and ``frames`` (n, 3, 4); ``path``: the whole path's tips and unit axes (what
    else it cuts)."""

    tips: np.ndarray
    axes: np.ndarray
    omega: np.ndarray
    frames: np.ndarray
    path: tuple[np.ndarray, np.ndarray]
    rows: tuple[int, int] = NO_ROWS


@dataclass(frozen=True, eq=False)
class ColumnJob:
    """One column (:class:`vmach.stock.column.Column`) over the whole path's ``tips``, unit
    ``axes`` (n, 3) and ``frames`` (n, 3, 4)."""

    column: Column
    tips: np.ndarray
    axes: np.ndarray
    frames: np.ndarray
    path: tuple[np.ndarray, np.ndarray]
    rows: tuple[int, int] = NO_ROWS


@dataclass(frozen=True, eq=False)
class Revolved:
    """A turning pass (:mod:`vmach.stock.strategies.revolved`): the convex 2-D point sets
    ``hulls``, each (k, 2) ``(r, z)`` mm — a turning tool's cross-section at the two ends of a
    step — whose union, revolved about the spindle axis, is what the pass removes."""

    hulls: list[np.ndarray]
    rows: tuple[int, int] = NO_ROWS


@dataclass(frozen=True, eq=False)
class Polygonal:
    """A polygonal-turning pass (:mod:`vmach.stock.strategies.polygonal`): the convex 2-D point
    sets ``hulls``, each (k, 2) ``(x, y)`` mm in the work frame — the inserts of a flywheel
    cutter coupled to the main spindle at consecutive angles — whose union, extruded along Z
    from ``z0`` to ``z1`` mm, is what the pass removes."""

    hulls: list[np.ndarray]
    z0: float
    z1: float
    rows: tuple[int, int] = NO_ROWS


Job = Placed | Runs | Fan | ColumnJob | Revolved | Polygonal


@dataclass(frozen=True, eq=False)
class Cutter:
    """A made cutter: its solid, box (2, 3) mm, and the rows of the job that made it."""

    solid: engine.Solid
    box: np.ndarray
    rows: tuple[int, int] = NO_ROWS


def span(rows: np.ndarray | None, first: int, last: int) -> tuple[int, int]:
    """The rows (first, last) of poses first..last of a path whose poses have ``rows`` (n,):
    a step belongs to the row of the pose it ends at, a lone pose to its own row."""
    if rows is None:
        return NO_ROWS
    lo = min(first + 1, last) if last > first else first
    return int(rows[lo:last + 1].min()), int(rows[lo:last + 1].max())
