"""Cycle time of a move table on a machine model (docs/cycle_time.md).

Motion: each row is timed by :mod:`vmach.motion.planner` — path speed from the programmed feed
(G94 mm/min, G95 mm/rev × the row's master spindle speed, G93 inverse time) or, for rapids, from
the axes' rates; capped so that no axis exceeds its ``max_rate``; trapezoidal ramps within every
axis' ``max_accel``; zero speed at exact stops (G60, G9) and wherever a timed event (dwell, tool
change, spindle, cycle, stop) lies between two moves; a corner speed from the per-axis velocity
jump rule in continuous-path mode (G64).

Feed with rotary axes (Sinumerik default, FGROUP of the geometry axes): F is the path speed of
the linear axes; the rotary axes follow in proportion, which may lower the path speed to keep
them within their rate. A row that turns rotary axes only reads F in degrees/min.

Events: dwells, tool changes, spindle starts/stops/speed changes and machine cycles take the
times in the model's ``[timing]`` table; M0/M1 are counted as 0 s with a note.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from vmach import canon
from vmach.machine.spec import TimingSpec
from vmach.motion import planner
from vmach.motion.table import TRAVERSE, MoveTable
from vmach.tol import tol

PER_MINUTE, PER_REV, INVERSE_TIME = 0, 1, 2
NO_TOOL = "(no tool)"


def _seconds(value: float) -> float | None:
    """A time for JSON, s: rounded to ms, or None when it is not finite (JSON has no Infinity)."""
    return round(value, 3) if math.isfinite(value) else None


@dataclass(frozen=True)
class Event:
    """A timed non-motion command.

    kind : ``dwell``, ``tool_change``, ``spindle_start``, ``spindle_stop``, ``spindle_change``,
        ``cycle`` or ``pause``. seconds : its time. command : index in ``table.commands``.
    what : a short description (``"G4 2 s"``, ``"spindle 2 cw 640 rpm"``).
    """

    kind: str
    seconds: float
    command: int
    file: str
    line: int
    what: str


@dataclass(frozen=True)
class Operation:
    """The stretch of a program between tool changes.

    tool : the tool's name, or ``"(no tool)"`` before the first change. file, line : the block
    that starts it (the tool change). rows : (first, stop) row range of its moves. seconds : its
    total; feed_s, rapid_s, event_s : the parts of it.
    """

    tool: str
    file: str
    line: int
    rows: tuple[int, int]
    seconds: float
    feed_s: float
    rapid_s: float
    event_s: float

    @property
    def name(self) -> str:
        return f"{self.tool} @ {Path(self.file).name}:{self.line}"


@dataclass(frozen=True)
class Timing:
    """Cycle time of a program.

    row_seconds : (n,) float, s — time of each move-table row.
    entry_speed, exit_speed : (n,) float — path speed at the row's start and end (mm/s, or
        degrees/s for rows that turn rotary axes only); 0 for rows that do not move.
    events : timed non-motion commands, in program order.
    operations : per tool change, in program order. per_tool : ``{tool: s}``.
    total_s = feed_s + rapid_s + event_s. notes : what was assumed or not counted.
    acceleration : False when ramps and corners were ignored (feeds and rates only).
    """

    row_seconds: np.ndarray
    entry_speed: np.ndarray
    exit_speed: np.ndarray
    events: tuple[Event, ...]
    operations: tuple[Operation, ...]
    per_tool: Mapping[str, float]
    total_s: float
    feed_s: float
    rapid_s: float
    event_s: float
    notes: tuple[str, ...] = ()
    acceleration: bool = True
    by_kind: Mapping[str, float] = field(default_factory=dict)

    @property
    def event_seconds(self) -> np.ndarray:
        """(e,) float, s — the events' times."""
        return np.array([e.seconds for e in self.events], float)

    def to_json(self) -> dict[str, Any]:
        return {
            "total_s": _seconds(self.total_s),
            "feed_s": _seconds(self.feed_s),
            "rapid_s": _seconds(self.rapid_s),
            "events_s": {k: _seconds(v) for k, v in self.by_kind.items()},
            "acceleration": self.acceleration,
            "per_tool": {k: _seconds(v) for k, v in self.per_tool.items()},
            "operations": [
                {"name": o.name, "tool": o.tool, "file": o.file, "line": o.line,
                 "seconds": _seconds(o.seconds), "feed_s": _seconds(o.feed_s),
                 "rapid_s": _seconds(o.rapid_s), "events_s": _seconds(o.event_s)}
                for o in self.operations
            ],
            "notes": list(self.notes),
        }


def format_seconds(seconds: float) -> str:
    """A cycle time for people: ``928.04`` → ``"15 min 28.0 s"``, ``5.26`` → ``"5.3 s"``;
    beyond 1e9 s (a program that never ends in practice) ``"1.2e+12 s"``."""
    if not seconds < 1e9:
        return f"{seconds:.3g} s"
    m, s = divmod(round(seconds, 1), 60)
    return f"{int(m)} min {s:04.1f} s" if m else f"{s:.1f} s"


# ------------------------------------------------------------------------------------------------


def cycle_time(table: MoveTable, model: Any, *, acceleration: bool = True,
               timing: TimingSpec | None = None) -> Timing:
    """Estimate how long ``table`` runs on ``model`` (a :class:`vmach.machine.Model`).

    acceleration : False ignores ramps and corners (every row at its capped speed).
    timing : overrides ``model.timing`` (tool-change, spindle, corner data).
    """
    timing = model.timing if timing is None else timing
    notes: list[str] = []
    if not timing.stated:
        notes.append(f"model {model.name} has no [timing] table: tool changes, spindle starts "
                     "and cycles counted as 0 s")
    rate, accel = _axis_limits(table, model, notes, acceleration)
    events, stop_cmds = _events(table.commands, timing, model.control.master_spindle, notes)
    seconds, v0, v1 = _motion(table, rate, accel, timing, stop_cmds, notes, acceleration)
    _surface_note(table, notes)

    rapid = table.kind == TRAVERSE
    op_starts = [e.command for e in events if e.kind == "tool_change"]
    ops = _operations(table, seconds, rapid, events, op_starts)
    per_tool: dict[str, float] = {}
    for o in ops:
        per_tool[o.tool] = per_tool.get(o.tool, 0.0) + o.seconds
    by_kind: dict[str, float] = {}
    for e in events:
        by_kind[e.kind] = by_kind.get(e.kind, 0.0) + e.seconds
    feed_s = float(seconds[~rapid].sum())
    rapid_s = float(seconds[rapid].sum())
    event_s = float(sum(e.seconds for e in events))
    for a in (seconds, v0, v1):
        a.setflags(write=False)
    return Timing(
        row_seconds=seconds, entry_speed=v0, exit_speed=v1, events=tuple(events),
        operations=tuple(ops), per_tool=per_tool, total_s=feed_s + rapid_s + event_s,
        feed_s=feed_s, rapid_s=rapid_s, event_s=event_s, notes=tuple(notes),
        acceleration=acceleration, by_kind=by_kind,
    )


def _axis_limits(table: MoveTable, model: Any, notes: list[str],
                 acceleration: bool) -> tuple[np.ndarray, np.ndarray]:
    """(k,) rate in units/s and (k,) acceleration in units/s² per table column (inf = none)."""
    rates = np.full(len(table.axes), np.inf)
    accels = np.full(len(table.axes), np.inf)
    mr, ma = model.max_rates, model.max_accel
    no_rate, no_accel = [], []
    for i, a in enumerate(table.axes):
        j = model.axes.index(a) if a in model.axes else None
        if j is not None and np.isfinite(mr[j]):
            rates[i] = mr[j] / 60.0
        else:
            no_rate.append(a)
        if j is not None and np.isfinite(ma[j]):
            accels[i] = ma[j]
        else:
            no_accel.append(a)
    moved = np.any(table.end != table.start, axis=0) if len(table) else np.zeros(len(table.axes), bool)
    no_rate = [a for a in no_rate if moved[table.axes.index(a)]]
    no_accel = [a for a in no_accel if moved[table.axes.index(a)]]
    if no_rate:
        notes.append(f"no max_rate for axis {' '.join(no_rate)}: its speed is not limited")
    if no_accel and acceleration:
        notes.append(f"no max_accel for axis {' '.join(no_accel)}: its acceleration is not limited")
    if not acceleration:
        accels[:] = np.inf
    return rates, accels


def _motion(table: MoveTable, rate: np.ndarray, accel: np.ndarray, timing: TimingSpec,
            stop_cmds: np.ndarray, notes: list[str], acceleration: bool):
    """Per-row seconds, entry and exit speeds."""
    n = len(table)
    seconds, v_in, v_out = np.zeros(n), np.zeros(n), np.zeros(n)
    if n == 0:
        return seconds, v_in, v_out
    d = table.end - table.start
    s = path_lengths(table)
    linear_path = np.sqrt((d[:, ~table.rotary] ** 2).sum(axis=1)) > tol.merge
    moving = s > tol.merge

    programmed = _programmed_speed(table, s)
    vcap = np.minimum(programmed, planner.axis_limited(_shares(d, s, moving), rate))
    untimed = moving & ~(vcap > 0)
    if untimed.any():
        first = int(np.flatnonzero(untimed)[0])
        notes.append(f"{int(untimed.sum())} feed move(s) without a usable feed (zero feed, or G95 "
                     f"with the spindle stopped) counted as 0 s; first at "
                     f"{Path(table.files[table.file[first]]).name}:{int(table.line[first])}")
    rows = np.flatnonzero(moving & ~untimed)
    if len(rows) == 0:
        return seconds, v_in, v_out
    u = _shares(d[rows], s[rows], np.ones(len(rows), bool))
    length, cap = s[rows], vcap[rows]
    a_path = planner.axis_limited(u, accel)
    if not acceleration:
        seconds[rows] = np.where(np.isfinite(cap), length / cap, 0.0)
        v_in[rows] = v_out[rows] = np.where(np.isfinite(cap), cap, 0.0)
        return seconds, v_in, v_out

    # junctions that must stop: exact stop, a timed event or a skipped row between the two
    # moves, or a change of path unit (mm ↔ degrees)
    cmd = table.command[rows]
    between = (np.searchsorted(stop_cmds, cmd[1:], "left")
               - np.searchsorted(stop_cmds, cmd[:-1], "right")) > 0
    gap = np.diff(rows) > 1
    skipped = gap & (np.cumsum(untimed)[rows[1:] - 1] - np.cumsum(untimed)[rows[:-1]] > 0)
    stop = (table.exact_stop[rows[:-1]] | between | skipped
            | (linear_path[rows[1:]] != linear_path[rows[:-1]]))
    jump = accel * (timing.corner_overload - 1.0) * timing.ipo_cycle_s
    vj = planner.junction_limits(u, jump, stop)
    v = planner.plan(length, cap, a_path, vj)
    seconds[rows] = planner.segment_times(length, cap, a_path, v[:-1], v[1:])
    v_in[rows], v_out[rows] = v[:-1], v[1:]
    return seconds, v_in, v_out


def _shares(d: np.ndarray, s: np.ndarray, moving: np.ndarray) -> np.ndarray:
    """(m, k) axis units per path unit (0 for rows that do not move)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(moving[:, None], d / np.where(moving, s, 1.0)[:, None], 0.0)


def path_lengths(table: MoveTable) -> np.ndarray:
    """(n,) path length per row: mm over the linear axes, or degrees for rotary-only rows."""
    d = table.end - table.start
    l_lin = np.sqrt((d[:, ~table.rotary] ** 2).sum(axis=1))
    l_rot = np.sqrt((d[:, table.rotary] ** 2).sum(axis=1))
    return np.where(l_lin > tol.merge, l_lin, l_rot)


def programmed_seconds(table: MoveTable) -> np.ndarray:
    """(n,) duration of each feed row at the feed the program asks for, before any axis limit
    (NaN for rapids and rows without a usable feed): what rate checks compare against."""
    s = path_lengths(table)
    v = _programmed_speed(table, s)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where((table.kind != TRAVERSE) & (v > 0) & np.isfinite(v), s / v, np.nan)
    return t


def _programmed_speed(table: MoveTable, s: np.ndarray) -> np.ndarray:
    """(n,) path units/s the program asks for; inf for rapids (axis rates decide).

    G93: the whole block (all chords of an arc) takes 1/F minutes.
    """
    feed = np.nan_to_num(table.feed, nan=0.0)
    block_length = np.bincount(table.command, s)[table.command]
    master_speed = surface_speed(table, table.master_state()[0])
    mode = table.feed_mode
    v = np.select(
        [mode == PER_MINUTE, mode == PER_REV, mode == INVERSE_TIME],
        [feed / 60.0, feed * master_speed / 60.0, block_length * feed / 60.0],
        default=0.0,
    )
    return np.where(table.kind == TRAVERSE, np.inf, v)


# ------------------------------------------------------------------------------------------------


def surface_speed(table: MoveTable, speed: np.ndarray) -> np.ndarray:
    """(n,) rev/min: the master spindle's ``speed`` (n,), where constant cutting speed (G96)
    is on the speed that gives each move its time: n(r) = 1000·v / (2π·r), at most the limit,
    follows the transverse axis' radius r along the move, and a feed per revolution f takes
    ∫ ds / (f·n(r)) — so the move's speed is 1 / mean(1/n) over it (exact: 1/n is the larger of
    1/limit and 2π·r/(1000·v), linear in r, and r is linear along a move; a move across the
    axis is taken in its two halves)."""
    if table.surface is None or not len(table):
        return speed
    v, limit, col = table.surface[:, 0], table.surface[:, 1], table.surface[:, 2].astype(int)
    on = (v > 0) & (col >= 0)
    if not on.any():
        return speed
    rows = np.flatnonzero(on)
    c = col[rows]
    r0, r1 = table.start[rows, c], table.end[rows, c]
    a = np.where(limit[rows] > 0, 1.0 / np.where(limit[rows] > 0, limit[rows], 1.0), 0.0)
    b = 2.0 * math.pi / (1000.0 * v[rows])
    across = r0 * r1 < 0
    t0 = np.where(across, np.abs(r0) / np.maximum(np.abs(r0) + np.abs(r1), 1e-300), 1.0)
    whole = _mean_max(a, b * np.abs(r0), np.where(across, 0.0, b * np.abs(r1)))
    rest = _mean_max(a, np.zeros_like(r0), b * np.abs(r1))
    inv = np.where(across, t0 * whole + (1.0 - t0) * rest, whole)
    out = np.array(speed, dtype=float)
    out[rows] = np.where(inv > 0, 1.0 / np.where(inv > 0, inv, 1.0), np.inf)
    return out


def _surface_note(table: MoveTable, notes: list[str]) -> None:
    """Say how constant cutting speed (G96) was timed, with the speeds it reached."""
    if table.surface is None:
        return
    on = (table.surface[:, 0] > 0) & (table.kind != TRAVERSE) & (table.feed_mode == PER_REV)
    if not on.any():
        return
    n = surface_speed(table, table.master_state()[0])[on]
    limited = int((table.surface[on, 1] > 0).sum())
    notes.append(f"G96 constant cutting speed on {int(on.sum())} feed move(s): the spindle speed follows "
                 "the transverse axis, n = 1000·v/(π·D)" + (", at most LIMS" if limited else "")
                 + f" ({n.min():.0f}–{n.max():.0f} rev/min, each move timed at 1/mean(1/n) along it)")


def _mean_max(a: np.ndarray, g0: np.ndarray, g1: np.ndarray) -> np.ndarray:
    """(k,) the mean over t in [0, 1] of max(a, g0 + (g1 − g0)·t)."""
    lo, hi = np.minimum(g0, g1), np.maximum(g0, g1)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(hi > lo, (hi - a) / (hi - lo), 0.0)        # the share where the line is above a
    part = (1.0 - f) * a + f * (a + hi) / 2.0
    return np.where(lo >= a, (g0 + g1) / 2.0, np.where(hi <= a, a, part))


def _events(commands, timing: TimingSpec, master: int,
            notes: list[str]) -> tuple[list[Event], np.ndarray]:
    """Timed non-motion commands, and the sorted command indices where motion must stop."""
    events: list[Event] = []
    stops: list[int] = []
    spindles: dict[int, tuple[float, str]] = {}
    pauses = 0
    unknown: dict[str, int] = {}

    def add(kind, sec, ci, c, what):
        events.append(Event(kind, float(sec), ci, c.source.path, c.source.line, what))

    for ci, c in enumerate(commands):
        if isinstance(c, canon.MOTIONS):
            continue
        if isinstance(c, canon.Dwell):
            stops.append(ci)
            if c.seconds is not None:
                add("dwell", c.seconds, ci, c, f"G4 {c.seconds:g} s")
            else:
                sp = spindles.get(master, (0.0, "stop"))
                running = sp[1] != "stop" and sp[0] > 0
                sec = 60.0 * (c.revolutions or 0.0) / sp[0] if running else 0.0
                if not running:
                    notes.append(f"dwell of {c.revolutions:g} revolutions with the master spindle "
                                 f"stopped at {Path(c.source.path).name}:{c.source.line}: 0 s")
                add("dwell", sec, ci, c, f"G4 {c.revolutions:g} rev")
        elif isinstance(c, canon.ToolChange):
            stops.append(ci)
            add("tool_change", timing.tool_change_s, ci, c, f"T={c.tool}")
        elif isinstance(c, canon.MasterSpindle):
            master = c.spindle
        elif isinstance(c, canon.Spindle):
            old_speed, old_dir = spindles.get(c.spindle, (0.0, "stop"))
            was = old_dir != "stop" and old_speed > 0
            now = c.direction != "stop" and c.speed > 0
            spindles[c.spindle] = (c.speed, c.direction)
            what = f"spindle {c.spindle} {c.direction} {c.speed:g} rpm"
            if now and not was:
                add("spindle_start", timing.spindle_start_s, ci, c, what)
            elif was and not now:
                add("spindle_stop", timing.spindle_stop_s, ci, c, what)
            elif was and now and old_dir != c.direction:
                add("spindle_change", timing.spindle_stop_s + timing.spindle_start_s, ci, c, what)
            elif was and now and old_speed != c.speed:
                add("spindle_change", timing.spindle_change_s, ci, c, what)
            else:
                continue
            stops.append(ci)
        elif isinstance(c, canon.CycleCall):
            if c.name in timing.cycles:
                sec = timing.cycles[c.name]
            else:
                sec = 0.0
                unknown[c.name] = unknown.get(c.name, 0) + 1
            if c.name not in timing.cycles or sec > 0:
                stops.append(ci)  # a cycle of unknown duration still stops the path
            if sec > 0 or c.name not in timing.cycles:
                add("cycle", sec, ci, c, c.name)
        elif isinstance(c, canon.Pause):
            stops.append(ci)
            pauses += 1
            add("pause", 0.0, ci, c, "M1 optional stop" if c.optional else "M0 stop")
        elif isinstance(c, canon.ProgramEnd):
            stops.append(ci)
    if pauses:
        notes.append(f"{pauses} program stop(s) M0/M1 counted as 0 s (the operator's time)")
    if unknown:
        names = ", ".join(f"{k} ×{v}" for k, v in unknown.items())
        notes.append(f"cycles without a time in [timing.cycles] counted as 0 s: {names}")
    return events, np.array(sorted(stops), dtype=np.int64)


def _operations(table: MoveTable, seconds: np.ndarray, rapid: np.ndarray, events: list[Event],
                starts: list[int]) -> list[Operation]:
    """Split rows and events at tool changes (command indices ``starts``)."""
    bounds = np.array(starts, dtype=np.int64)
    k = len(starts) + 1  # slot 0: before the first tool change
    row_op = np.searchsorted(bounds, table.command, "right")
    ev_op = np.searchsorted(bounds, np.array([e.command for e in events], np.int64), "right")
    feed = np.bincount(row_op, np.where(rapid, 0.0, seconds), minlength=k)
    rap = np.bincount(row_op, np.where(rapid, seconds, 0.0), minlength=k)
    evs = np.bincount(ev_op, np.array([e.seconds for e in events], float), minlength=k)
    first_row = np.searchsorted(row_op, np.arange(k), "left")
    stop_row = np.searchsorted(row_op, np.arange(k), "right")
    changes = {e.command: e for e in events if e.kind == "tool_change"}
    tools = {ci: table.commands[ci].tool for ci in changes}
    out = []
    for i in range(k):
        if i == 0:
            if feed[0] + rap[0] + evs[0] == 0:
                continue  # nothing timed before the first tool change
            if stop_row[0] > 0:
                file, line = table.files[table.file[0]], int(table.line[0])
            else:
                file, line = events[0].file, events[0].line
            tool = NO_TOOL
        else:
            e = changes[starts[i - 1]]
            tool, file, line = tools[starts[i - 1]], e.file, e.line
        total = float(feed[i] + rap[i] + evs[i])
        out.append(Operation(tool, file, line, (int(first_row[i]), int(stop_row[i])), total,
                             float(feed[i]), float(rap[i]), float(evs[i])))
    return out
