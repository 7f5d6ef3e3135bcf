"""Constant cutting speed: ``G96 S… LIMS=…`` (on), ``G97`` / ``G94`` / ``G95`` (off).

Under G96 the master spindle's S is a cutting speed in m/min; the control turns the spindle at
n = 1000·S / (π·D) rev/min, D the transverse axis' diameter (twice canonical X, a radius), at
most ``LIMS`` (rev/min). vmach gives the state as :class:`vmach.canon.SurfaceSpeed` (the cycle
time follows X along every move: :func:`vmach.motion.timing.surface_speed`) and the spindle's
speed at the position where S was programmed as :class:`vmach.canon.Spindle` (so that the
spindle checks see it turn). G97 freezes the speed the spindle has there (SINUMERIK
programming manual, "Constant cutting rate (G96/G961/G962/G97/G971/G972/G973, LIMS, SCC)").
G961/G962 (the same with feed per minute) stay unsupported.
"""

from __future__ import annotations

import math

from vmach import canon
from vmach.source import SourceRef

#: rev/min taken on the spindle axis itself (r = 0) when no LIMS bounds the speed
NO_LIMIT_SPEED = 100000.0


class Surface:
    """The state of constant cutting speed: ``on``, ``speed`` m/min, ``limit`` rev/min (0: none)."""

    def __init__(self) -> None:
        self.on = False
        self.speed = 0.0
        self.limit = 0.0

    def rpm(self, m) -> float:
        """Rev/min at the transverse axis' present radius of machine ``m``."""
        axis = m.control.transverse or "X"
        r = abs(float(m.pos.get(axis, 0.0)))
        n = 1000.0 * self.speed / (2.0 * math.pi * r) if r > 0 else math.inf
        if self.limit > 0:
            n = min(n, self.limit)
        return n if math.isfinite(n) else NO_LIMIT_SPEED

    def emit(self, m, src: SourceRef) -> None:
        m.out.append(canon.SurfaceSpeed(src, spindle=m.master, speed=self.speed if self.on else 0.0,
                                        limit=self.limit, axis=m.control.transverse or "X"))


def feed_group(m, name: str, src: SourceRef) -> None:
    """A G code of group 15 in a block: G96 switches constant cutting speed on, any other off
    (the spindle keeps the speed it has at this position)."""
    s = m.surface
    if name == "G96" and not s.on:
        s.on = True
        if s.speed > 0:
            s.emit(m, src)
    elif name != "G96" and s.on:
        s.on = False
        st = m.spindles.get(m.master)
        if st is not None:
            st[0] = s.rpm(m)
            m.out.append(canon.Spindle(src, spindle=m.master, speed=st[0], direction=st[1]))
        s.emit(m, src)


def speed(m, spindle: int, value: float, src: SourceRef) -> float:
    """The rev/min an S word sets: under G96 on the master spindle ``value`` is m/min."""
    s = m.surface
    if not s.on or spindle != m.master:
        return value
    s.speed = value
    s.emit(m, src)
    return s.rpm(m)


def lims(m, value: float, src: SourceRef) -> None:
    """``LIMS=value``: the upper speed limit under G96 (rev/min)."""
    s = m.surface
    s.limit = max(0.0, float(value))
    if s.on and s.speed > 0:
        s.emit(m, src)
