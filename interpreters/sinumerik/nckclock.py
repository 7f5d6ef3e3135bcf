"""The NCK's clock for the main-run timers (``$AC_TIMER``, ``$AC_CYCLE_TIME`` ...).

An interpreter has no real time; this clock is its estimate of the machining time so far, from
the canonical commands it has emitted: feed moves at the programmed feed (per minute, per
revolution of the master spindle, inverse time), rapids at each axis' ``$MA_MAX_AX_VELO`` (the
slowest axis decides; the control's default 10 m/min where the model gives none), dwells for
their time or spindle revolutions. No acceleration, no tool change times: the motion planner's
cycle time (``vmach.motion``) is the precise figure; this one lets a warm-up program that waits
on ``$AC_TIMER`` — or on the control's clock (``$A_MINUTE`` …, which runs from a fixed start,
2000-01-01 00:00:00, by the same estimate) — end as it does on the machine. Read lazily: the
commands are scanned only when a timer is read, so a program that reads none pays nothing.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from datetime import datetime, timedelta
from typing import Any

from vmach import canon

DEFAULT_RAPID = 10000.0       # MD32000 MAX_AX_VELO default, mm/min
#: the interpolation cycle, s (MD10050/10070 as delivered): reading a main-run variable stops the
#: preprocessing until the main run has caught up, at least one cycle
IPO_CYCLE = 0.004
#: the instant a run starts at (its control's clock, ``$A_YEAR`` …): fixed, so a run is reproducible
START = datetime(2000, 1, 1)
CALENDAR = ("$A_YEAR", "$A_MONTH", "$A_DAY", "$A_HOUR", "$A_MINUTE", "$A_SECOND", "$A_MSECOND")
#: minutes since the control was switched on: the run starts with it
POWER_ON = ("$AN_SETUP_TIME", "$AN_POWERON_TIME")


def calendar(name: str, seconds: float) -> int:
    """The control's clock variable ``name`` ``seconds`` of machining time after START."""
    t = START + timedelta(seconds=seconds)
    return {"$A_YEAR": t.year, "$A_MONTH": t.month, "$A_DAY": t.day, "$A_HOUR": t.hour,
            "$A_MINUTE": t.minute, "$A_SECOND": t.second, "$A_MSECOND": t.microsecond // 1000}[name]


class Clock:
    """Seconds of machining time in ``commands`` (the interpreter's output list, growing).

    pos : start position per axis (machine values); rapid : ``{axis: mm/min or deg/min}``;
    geometry : the geometry axis names (path length of a feed move).
    """

    def __init__(self, commands: Sequence[Any], pos: Mapping[str, float], rapid: Mapping[str, float],
                 geometry: tuple[str, ...], master: int):
        self.commands = commands
        self.pos = dict(pos)
        self.rapid = rapid
        self.geometry = geometry
        self.seen = 0
        self.total = 0.0
        self.cutting = 0.0      # seconds of feed moves
        self.mode = "per_minute"
        self.speeds: dict[int, float] = {}
        self.master = master
        self.read_at = -1       # len(commands) at the last read of the clock by the program

    def read(self) -> float:
        """``now()`` as the program reads it: a read with nothing emitted since the last one
        (a loop that waits on the clock) comes one interpolation cycle later, as the implicit
        preprocessing stop makes it on the control."""
        if self.read_at == len(self.commands):
            self.total += IPO_CYCLE
        self.read_at = len(self.commands)
        return self.now()

    def now(self) -> float:
        """Seconds from the program start to the end of the last command emitted."""
        cmds = self.commands
        while self.seen < len(cmds):
            self.total += self._seconds(cmds[self.seen])
            self.seen += 1
        return self.total

    def _seconds(self, c: Any) -> float:
        if isinstance(c, canon.FeedMode):
            self.mode = c.mode
        elif isinstance(c, canon.Spindle):
            self.speeds[c.spindle] = c.speed if c.direction != "stop" else 0.0
        elif isinstance(c, canon.MasterSpindle):
            self.master = c.spindle
        elif isinstance(c, canon.Dwell):
            if c.seconds is not None:
                return c.seconds
            rpm = self.speeds.get(self.master, 0.0)
            return 60.0 * (c.revolutions or 0.0) / rpm if rpm else 0.0
        elif isinstance(c, canon.MOTIONS):
            start, self.pos = self.pos, {**self.pos, **c.axes}
            if isinstance(c, canon.Traverse):
                return max((abs(v - start.get(a, v)) / self.rapid.get(a, DEFAULT_RAPID) * 60.0
                            for a, v in c.axes.items()), default=0.0)
            seconds = self._feed_time(self._length(c, start), c.feed)
            self.cutting += seconds
            return seconds
        return 0.0

    def _length(self, c: Any, start: Mapping[str, float]) -> float:
        """Path length of a feed move: the geometry axes, else the other axes."""
        end = c.axes
        if isinstance(c, canon.ArcFeed):
            a, b, n = c.plane
            ca, cb = c.center
            sa, sb = start.get(a, 0.0) - ca, start.get(b, 0.0) - cb
            ea, eb = end.get(a, 0.0) - ca, end.get(b, 0.0) - cb
            sweep = math.atan2(eb, ea) - math.atan2(sb, sa)
            sweep = (-sweep if c.clockwise else sweep) % (2 * math.pi)
            if sweep == 0.0:
                sweep = 2 * math.pi
            sweep += 2 * math.pi * c.turns
            arc = sweep * 0.5 * (math.hypot(sa, sb) + math.hypot(ea, eb))
            return math.hypot(arc, end.get(n, 0.0) - start.get(n, 0.0))
        geo = [end.get(g, 0.0) - start.get(g, 0.0) for g in self.geometry if g in end]
        length = math.sqrt(sum(d * d for d in geo))
        if length == 0.0:
            length = math.sqrt(sum((v - start.get(k, v)) ** 2 for k, v in end.items()))
        return length

    def _feed_time(self, length: float, feed: float) -> float:
        if self.mode == "inverse_time":
            return 60.0 / feed if feed > 0 else 0.0
        rate = feed * self.speeds.get(self.master, 0.0) if self.mode == "per_rev" else feed
        return 60.0 * length / rate if rate > 0 else 0.0
