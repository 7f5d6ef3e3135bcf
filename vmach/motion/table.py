"""The move table: the canonical stream as numpy arrays, one row per straight segment.

Arcs are broken into chords within ``tol.chord`` (mm); every other motion is one row. Rows keep
the index of the canonical command and its source line, so every finding downstream can name
the block it comes from. The arrays are read-only once built.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from vmach import canon
from vmach.canon import ControlSpec
from vmach.errors import ProgramError
from vmach.tol import tol

TRAVERSE, FEED, ARC, PROBE = 0, 1, 2, 3
KIND_NAMES = ("traverse", "feed", "arc")
FEED_MODES = ("per_minute", "per_rev", "inverse_time")
DIRECTIONS = {"stop": 0, "cw": 1, "ccw": -1}


@dataclass(frozen=True, eq=False)
class MoveTable:
    """Struct of arrays, n rows (segments), k axes.

    axes : (k,) str — machine axis names, the column order of ``start`` and ``end``
    rotary : (k,) bool — which axes are rotary (degrees)
    start, end : (n, k) float — axis values, mm and degrees (modulo axes unwrapped)
    kind : (n,) int8 — TRAVERSE, FEED, ARC (a chord of an arc) or PROBE (a measuring move,
        canon.ProbeMove: a feed that stops at contact)
    feed : (n,) float — programmed feed in the unit ``feed_mode`` gives; NaN for traverses
    feed_mode : (n,) int8 — index into FEED_MODES
    tool : (n,) int16 — index into ``tools``; -1 before the first tool change and after T0
    offset : (n,) int16 — active tool offset (D/H number; 0 = none)
    spindles : (s,) int — spindle numbers, the columns of ``speed`` and ``direction``
    speed : (n, s) float — rev/min of each spindle during the move
    direction : (n, s) int8 — +1 cw, -1 ccw, 0 stopped
    master : (n,) int8 — master spindle number (the one plain S/M3 address)
    exact_stop : (n,) bool — the axes stop at the end of this row: exact stop (G60, G9) was
        active for its command and the row is the command's last (an arc's inner chords never)
    command : (n,) int32 — index of the canonical command in ``commands``
    line : (n,) int32 — 1-based source line; file : (n,) int16 — index into ``files``
    surface : (n, 3) float — constant cutting speed (G96) of the master spindle during the move:
        m/min (0: off), its limit rev/min (0: none), the column of the axis whose radius sets
        the speed (:class:`vmach.canon.SurfaceSpeed`); None when the program has none
    """

    axes: tuple[str, ...]
    rotary: np.ndarray
    start: np.ndarray
    end: np.ndarray
    kind: np.ndarray
    feed: np.ndarray
    feed_mode: np.ndarray
    tool: np.ndarray
    offset: np.ndarray
    spindles: tuple[int, ...]
    speed: np.ndarray
    direction: np.ndarray
    master: np.ndarray
    exact_stop: np.ndarray
    command: np.ndarray
    line: np.ndarray
    file: np.ndarray
    tools: tuple[str, ...]
    files: tuple[str, ...]
    commands: Sequence[canon.Command]
    surface: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.kind)

    def column(self, axis: str) -> int:
        return self.axes.index(axis)

    def source(self, row: int) -> canon.SourceRef:
        return self.commands[int(self.command[row])].source

    def columns(
        self, axes: Sequence[str], defaults: Sequence[float], values: np.ndarray | None = None
    ) -> np.ndarray:
        """(n, len(axes)) axis values in another axis order (a machine model's), taking
        ``defaults`` for axes the table does not have; ``values`` defaults to ``end``."""
        v = self.end if values is None else values
        cols = [
            v[:, self.axes.index(a)] if a in self.axes else np.full(len(v), float(d))
            for a, d in zip(axes, defaults, strict=True)
        ]
        return np.stack(cols, axis=1) if cols else np.zeros((len(v), 0))

    def master_state(self) -> tuple[np.ndarray, np.ndarray]:
        """Speed (n,) rev/min and direction (n,) of each row's master spindle (0 when the master
        is not one of ``spindles``)."""
        col = {s: i for i, s in enumerate(self.spindles)}
        c = np.array([col.get(int(m), -1) for m in self.master], dtype=int)
        rows = np.arange(len(self))
        ok = c >= 0
        speed = np.where(ok, self.speed[rows, np.maximum(c, 0)] if len(self.spindles) else 0.0, 0.0)
        direction = np.where(ok, self.direction[rows, np.maximum(c, 0)] if len(self.spindles) else 0, 0)
        return speed, direction

    def lengths(self) -> np.ndarray:
        """(n,) float — Euclidean length over the linear axes, mm."""
        d = self.end[:, ~self.rotary] - self.start[:, ~self.rotary]
        return np.sqrt((d * d).sum(axis=1))


def build(commands: Sequence[canon.Command], control: ControlSpec, chord: float = tol.chord,
          max_moves: int = tol.max_moves) -> MoveTable:
    """Turn a canonical stream into a MoveTable (arcs linearised to ``chord`` mm); more than
    ``max_moves`` rows is a ``resource_limit`` ProgramError at the command that passes it."""
    names: list[str] = [a.name for a in control.axes]
    for g in control.geometry:
        if g not in names:
            names.append(g)
    for c in commands:  # axes a loose control met on the way
        if isinstance(c, canon.MOTIONS):
            for a in c.axes:
                if a not in names:
                    names.append(a)
    col = {a: i for i, a in enumerate(names)}
    homes = {a.name: a.home for a in control.axes}
    pos = np.array([homes.get(a, 0.0) for a in names], dtype=float)

    spindles = sorted({*control.spindles, *(c.spindle for c in commands if isinstance(c, canon.Spindle))})
    scol = {s: i for i, s in enumerate(spindles)}
    speed = np.zeros(len(spindles))
    direction = np.zeros(len(spindles), dtype=np.int8)
    master = control.master_spindle
    tools: list[str] = []
    tool = -1
    offset = 0
    feed_mode = 0
    exact = False  # canon.PathMode: continuous path until told otherwise
    files: list[str] = []
    file_ix: dict[str, int] = {}

    starts, ends, kinds, feeds, modes, tls, offs, spd, drs, mst, cmds, lines, fls, stops = (
        [] for _ in range(14)
    )
    css = (0.0, 0.0, -1.0)        # G96: m/min, rev/min limit, the transverse axis' column
    srf: list = []

    def add(a, b, k, f, ci, c, last=True):
        starts.append(a)
        ends.append(b)
        kinds.append(k)
        feeds.append(f)
        modes.append(feed_mode)
        tls.append(tool)
        offs.append(offset)
        spd.append(speed.copy())
        drs.append(direction.copy())
        mst.append(master)
        stops.append(exact and last)
        srf.append(css)
        cmds.append(ci)
        lines.append(c.source.line)
        p = c.source.path
        if p not in file_ix:
            file_ix[p] = len(files)
            files.append(p)
        fls.append(file_ix[p])

    for ci, c in enumerate(commands):
        if isinstance(c, canon.Traverse | canon.LinearFeed):
            if len(starts) >= max_moves:
                raise ProgramError("resource_limit", f"the program makes more than {max_moves} moves "
                                   "(vmach's limit)", c.source)
            end = pos.copy()
            for a, v in c.axes.items():
                end[col[a]] = v
            if isinstance(c, canon.Traverse):
                add(pos, end, TRAVERSE, math.nan, ci, c)
            elif isinstance(c, canon.ProbeMove):
                add(pos, end, PROBE, c.feed, ci, c)
            else:
                add(pos, end, FEED, c.feed, ci, c)
            pos = end
        elif isinstance(c, canon.ArcFeed):
            end = pos.copy()
            for a, v in c.axes.items():
                end[col[a]] = v
            pts = arc_points(pos, end, c, col, chord, max_moves - len(starts))
            m = len(pts) - 1
            for j, (a, b) in enumerate(zip(pts[:-1], pts[1:], strict=True)):
                add(a, b, ARC, c.feed, ci, c, j == m - 1)
            pos = end
        elif isinstance(c, canon.ToolChange):
            if c.number == 0:               # T0 (Sinumerik T0/T00, RS274 T0 M6): no tool
                tool = -1
            else:
                if c.tool not in tools:
                    tools.append(c.tool)
                tool = tools.index(c.tool)
            if c.offset is not None:
                offset = c.offset
        elif isinstance(c, canon.ToolOffset):
            offset = c.offset
        elif isinstance(c, canon.Spindle):
            speed[scol[c.spindle]] = c.speed
            direction[scol[c.spindle]] = DIRECTIONS[c.direction]
        elif isinstance(c, canon.MasterSpindle):
            master = c.spindle
        elif isinstance(c, canon.SurfaceSpeed):
            css = (c.speed, c.limit, float(col.get(c.axis, -1)))
        elif isinstance(c, canon.FeedMode):
            feed_mode = FEED_MODES.index(c.mode)
        elif isinstance(c, canon.PathMode):
            exact = c.mode == "exact"

    k, s = len(names), len(spindles)
    n = len(kinds)

    def arr(values, dtype, shape):
        a = np.array(values, dtype=dtype) if n else np.zeros(shape, dtype=dtype)
        a.setflags(write=False)
        return a

    rotary = np.array(
        [(control.axis(a).kind == "rotary") if control.axis(a) else a[0] in "ABC" for a in names], dtype=bool
    )
    rotary.setflags(write=False)
    if n:
        # a linear position beyond any machine (a TRANS or G92 of 1e16 mm) would make every
        # later stage sample an absurd path: vmach's limit, at the first move that reaches it
        ends_linear = np.abs(np.asarray(ends, float)[:, ~rotary])
        far = ~(ends_linear <= tol.max_size)
        if far.any():
            row, col_ix = np.argwhere(far)[0]
            axis = [a for a, r in zip(names, rotary, strict=True) if not r][col_ix]
            value = ends[row][col[axis]]
            raise ProgramError("resource_limit", f"{axis} = {value:.6g} mm is beyond any machine (vmach's "
                               f"limit: {tol.max_size:g} mm)", commands[cmds[row]].source)
    return MoveTable(
        axes=tuple(names),
        rotary=rotary,
        start=arr(starts, float, (0, k)),
        end=arr(ends, float, (0, k)),
        kind=arr(kinds, np.int8, (0,)),
        feed=arr(feeds, float, (0,)),
        feed_mode=arr(modes, np.int8, (0,)),
        tool=arr(tls, np.int16, (0,)),
        offset=arr(offs, np.int16, (0,)),
        spindles=tuple(spindles),
        speed=arr(spd, float, (0, s)),
        direction=arr(drs, np.int8, (0, s)),
        master=arr(mst, np.int8, (0,)),
        exact_stop=arr(stops, bool, (0,)),
        command=arr(cmds, np.int32, (0,)),
        line=arr(lines, np.int32, (0,)),
        file=arr(fls, np.int16, (0,)),
        tools=tuple(tools),
        files=tuple(files),
        commands=tuple(commands),
        surface=arr(srf, float, (0, 3)) if any(c[0] > 0 for c in srf) else None,
    )


def arc_points(
    start: np.ndarray, end: np.ndarray, arc: canon.ArcFeed, col: dict[str, int], chord: float = tol.chord,
    most: int = tol.max_moves,
) -> np.ndarray:
    """Points along an arc or helix, start and end included.

    start, end : (k,) float — every axis; the plane axes turn about ``arc.center``, all other
    axes (the helix axis among them) move linearly with the angle.
    Returns (m + 1, k) float with m chords whose sagitta stays below ``chord`` mm; more than
    ``most`` chords is a ``resource_limit`` ProgramError at the arc.
    """
    ia, ib = col[arc.plane[0]], col[arc.plane[1]]
    ca, cb = arc.center
    a0 = math.atan2(start[ib] - cb, start[ia] - ca)
    a1 = math.atan2(end[ib] - cb, end[ia] - ca)
    r0 = math.hypot(start[ia] - ca, start[ib] - cb)
    r1 = math.hypot(end[ia] - ca, end[ib] - cb)
    sweep = a1 - a0
    if arc.clockwise:
        if sweep >= -1e-12:
            sweep -= 2 * math.pi
        sweep -= 2 * math.pi * arc.turns
    else:
        if sweep <= 1e-12:
            sweep += 2 * math.pi
        sweep += 2 * math.pi * arc.turns
    r = max(r0, r1)
    if not r <= tol.max_magnitude:
        raise ProgramError("resource_limit", f"an arc of radius {r:.6g} mm (vmach's limit: "
                           f"{tol.max_magnitude:g} mm)", arc.source)
    if r <= chord:
        step = math.pi / 2
    else:
        # (for chord/r below ~1e-16 acos rounds to 0: its series, 2·sqrt(2·chord/r))
        step = 2 * math.acos(max(-1.0, 1 - chord / r)) or 2 * math.sqrt(2 * chord / r)
    m = max(1, math.ceil(abs(sweep) / step))
    if m > most:
        raise ProgramError("resource_limit", f"an arc of {abs(sweep) / (2 * math.pi):.6g} turns needs {m} "
                           f"chords of {chord:g} mm, more than the move table holds (vmach's limit: "
                           f"{tol.max_moves} moves)", arc.source)
    t = np.linspace(0.0, 1.0, m + 1)
    pts = start[None, :] + t[:, None] * (end - start)[None, :]
    ang = a0 + t * sweep
    rad = r0 + t * (r1 - r0)
    pts[:, ia] = ca + rad * np.cos(ang)
    pts[:, ib] = cb + rad * np.sin(ang)
    pts[-1] = end
    return pts
