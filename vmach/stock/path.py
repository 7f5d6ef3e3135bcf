"""A tool path as the cutter strategies see it, what is left of it, and what a strategy claims.

Every strategy (:mod:`vmach.stock.strategies`) is one module with

    NAME: str                  # its switch (vmach.stock.plan.WITHOUT) and its line in the table
    BOUND: Bound               # what its cutters may differ from the true sweep
    def claim(path: Path, free: Free, view: View, cover: Coverage | None) -> Claim

and, if it makes its own kind of job, ``JOB`` (the job's type) and ``make(job, maker) ->
Cutter | None``. The planner (:mod:`vmach.stock.plan`) asks them in the order of its table;
each sees only what the ones before left (``free``) and returns what it takes. Poses are
indexed 0..n-1, step i joins pose i to pose i + 1. All lengths mm; frames (3, 4) tool → work.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from vmach.stock.jobs import Job, span
from vmach.stock.sweep import SweepPlan, plan
from vmach.tol import tol
from vmach.tooling.model import Tool
from vmach.tooling.solid import ToolSolid, across, frames, lateral, spun


@dataclass(frozen=True)
class Bound:
    """What a strategy's cutters may differ from the true sweep: ``over`` — the most they may
    remove beyond it, ``under`` — the most they may leave of it; each "" (none: exact) or the
    name of the error bound that holds it (``simulation.error_bounds_mm`` in the report:
    ``fan_overcut``, ``face_scallop``, ``side_cusps``, ``tool_polygon``, ``blank_polygon``)."""

    over: str = ""
    under: str = ""


class Path:
    """One path: the tool's poses ``tips``, ``axes`` (n, 3) work frame (``unit``: the axes
    normalised), joined by motion in order; the source row of each pose ``rows`` (n,) int or
    None; ``between`` the poses inside a step (:meth:`vmach.stock.Stock.cut`) or None;
    ``settings`` the planner's (:class:`vmach.stock.plan.Settings`).

    A milling path has its tool ``tool`` (the true :class:`~vmach.tooling.model.Tool`, or only
    a :class:`~vmach.tooling.solid.ToolSolid`), its polygon solid ``ts`` and, for a one-piece
    flat-faced tool, the prism ``pr`` (:func:`vmach.stock.fan.prism`; else None). A turning
    path has instead the turning tool's X–Z cross-section ``section`` (k, 2) mm, and no axes
    of its own. A polygonal-turning path has ``coupled``: (flywheel tool, spindle coupling)
    (:mod:`vmach.stock.strategies.polygonal`), its ``tips`` the flywheel's point P in the
    machine frame.
    """

    def __init__(self, tips: np.ndarray, axes: np.ndarray, rows: np.ndarray | None, settings, *,
                 tool: Tool | ToolSolid | None = None, ts: ToolSolid | None = None, pr=None,
                 between=None, section: np.ndarray | None = None, coupled=None):
        self.tips, self.axes, self.rows, self.settings = tips, axes, rows, settings
        self.tool, self.ts, self.pr, self.between, self.section = tool, ts, pr, between, section
        self.coupled = coupled
        self.unit = axes / np.linalg.norm(axes, axis=1, keepdims=True)

    @property
    def n(self) -> int:
        return len(self.tips)

    @property
    def true_tool(self) -> Tool | None:
        """The true tool, when the path was given one (not only its polygon solid)."""
        return self.tool if isinstance(self.tool, Tool) else None

    @cached_property
    def sweep(self) -> SweepPlan:
        """Its steps as straight runs and placed poses (:func:`vmach.stock.sweep.plan`)."""
        return plan(self.tips, self.axes)

    @cached_property
    def rotary(self) -> np.ndarray:
        """(n-1,) bool: the steps that turn the tool axis (more than ``tol.hull_angle``)."""
        return self.sweep.angles > tol.hull_angle

    @cached_property
    def sides(self) -> np.ndarray:
        """(n, 3): each pose's lateral direction (axis × travel) its polygon is turned for."""
        return lateral(self.tips, self.axes)

    @cached_property
    def frames(self) -> np.ndarray:
        """(n, 3, 4): each pose's frame, its polygon turned for its ``sides``
        (:func:`vmach.tooling.solid.spun`)."""
        return spun(frames(self.tips, self.axes), self.sides, self.ts.segments)

    def turn_for(self, poses: np.ndarray, steps: np.ndarray) -> None:
        """Turn ``poses`` (k,) int for the travel ``steps`` (k, 3) instead of their own (a
        fan's end poses, for its own steps rather than the move beyond it)."""
        self.sides[poses] = across(self.unit[poses], steps)
        self.frames[poses] = spun(frames(self.tips[poses], self.axes[poses]), self.sides[poses],
                                  self.ts.segments)

    def row_span(self, first: int, last: int) -> tuple[int, int]:
        """The rows (first, last) of poses first..last (:func:`vmach.stock.jobs.span`)."""
        return span(self.rows, first, last)

    def pose_rows(self, poses: np.ndarray) -> np.ndarray:
        """(m, 2) int: the rows of poses (m,) int (-1 without rows)."""
        if self.rows is None:
            return np.full((len(poses), 2), -1)
        return np.repeat(self.rows[poses][:, None], 2, axis=1)


@dataclass
class Free:
    """What no strategy has claimed yet: ``steps`` (n-1,) bool — steps none cuts yet;
    ``place`` (n,) bool — poses that would be placed whole (the last strategy places them)."""

    steps: np.ndarray
    place: np.ndarray

    def any(self) -> bool:
        return bool(self.steps.any() or self.place.any())


@dataclass(frozen=True)
class Poses:
    """Placed poses a strategy makes: where they lie along the path ``at`` (m,) float (pose
    index, or step + fraction for a pose inside a step), frames (m, 3, 4), fin half-widths
    ``fins`` (m,) mm (inf: the whole tool), heights ``tall`` (m,) mm (inf: the whole length)
    and ``rows`` (m, 2) int."""

    at: np.ndarray
    frames: np.ndarray
    fins: np.ndarray
    tall: np.ndarray
    rows: np.ndarray


@dataclass(frozen=True)
class Groups:
    """Translation hulls a strategy makes, one per group of runs: ``at`` (g,) float where each
    starts, ``ends`` the extreme poses (i, j) of each run of each group, ``rows`` (g, 2) int."""

    at: np.ndarray
    ends: list[list[tuple[int, int]]]
    rows: np.ndarray


@dataclass(frozen=True)
class Claim:
    """What a strategy takes of a path: ``steps`` (n-1,) bool it cuts (None: none); ``held``
    (n,) bool poses its cutters hold, no longer to be placed (None: none); ``place`` (k,) int
    poses that now are to be placed whole (an axial run's inner pose); what it makes —
    ``poses``, ``groups``, and single ``jobs`` (each (where it starts along the path, the
    job)); ``counts``: figures for :class:`vmach.stock.stats.CutStats` (name -> amount). A
    strategy may turn the poses it holds for its own travel (:meth:`Path.turn_for`)."""

    steps: np.ndarray | None = None
    held: np.ndarray | None = None
    place: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    poses: Poses | None = None
    groups: Groups | None = None
    jobs: list[tuple[float, Job]] = field(default_factory=list)
    counts: dict = field(default_factory=dict)


NOTHING = Claim()
