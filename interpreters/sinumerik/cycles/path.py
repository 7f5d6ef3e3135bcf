"""Moves of an expanded cycle, in program coordinates of the working plane, written as
canonical commands that carry the calling block and the cycle's phase.

A point is (a, b, n): the plane's first and second axis and its normal (X, Y, Z for G17;
Z, X, Y for G18; Y, Z, X for G19), mm, program coordinates (the frames apply). A closed tool
path in the plane ("loop") is a start point and a list of segments, each ``("line", end)``
or ``("arc", end, centre, clockwise)`` with points (a, b); clockwise as seen from +n.
"""

from __future__ import annotations

import math

from interpreters.sinumerik import swivel
from vmach import canon
from vmach.errors import ProgramError
from vmach.source import PhasedRef, SourceRef

#: segments below this length (mm) are left out of a loop
TINY = 1e-9
#: most depth levels or offsets one list may hold (a MID or MIDA of 1e-12 must be an error,
#: not a list of a trillion levels)
MAX_STEPS = 20_000


class TooMany(ValueError):
    """More than MAX_STEPS levels or offsets; the cycle reports it at its call."""


class Path:
    """The tool's moves for one cycle call; ``phase`` names the part of the cycle the next
    moves belong to ("roughing depth 2 ring 3")."""

    def __init__(self, machine, src: SourceRef) -> None:
        self.machine, self.call_src = machine, src
        g = machine.geometry
        self.plane = machine.plane_axes
        self.ia, self.ib, self.inn = (g.index(n) for n in self.plane)
        self.src = PhasedRef(src.path, src.line, src.column, src.text)
        frames = machine.frames
        #: under TRAORI or CYCLE800 the moves are the tool tip in the (swivelled) plane
        self.oriented = machine.traori is not None
        if self.oriented:
            swivel.current(machine, src)              # a G54 … selected under CYCLE800
        if frames.rotated and not frames.similar(self.ia, self.ib) and not self.oriented:
            raise ProgramError("unsupported", "a cycle under a frame that scales the plane's axes "
                               "differently is not simulated", src)

    def phase(self, text: str) -> None:
        s = self.call_src
        self.src = PhasedRef(s.path, s.line, s.column, s.text, text)

    def here(self) -> tuple[float, float, float]:
        p = self.machine.program_point()
        return p[self.ia], p[self.ib], p[self.inn]

    def _target(self, a, b, n) -> dict:
        m = self.machine
        p = list(m.program_point())
        for i, v in ((self.ia, a), (self.ib, b), (self.inn, n)):
            if v is not None:
                p[i] = v
        self.last = p
        m.pos = m.machine_axes(m.pos, p)
        return dict(m.pos)

    def _oriented(self, motion: str, axes: dict, f: float = 0.0, **arc) -> None:
        """Under TRAORI or CYCLE800: the move as an OrientedMove in program coordinates of the
        active frame (``nan`` where the tip stays), the orientation kept."""
        m = self.machine
        axes = dict(axes)
        axes.update(zip(m.geometry, self.last, strict=True))
        for r in m.traori.rotaries:
            axes[r] = math.nan
        f = 0.0 if motion == "traverse" else f
        frames = m.frames
        frame = (*(frames.off.get(g, 0.0) for g in m.geometry), *frames.rotation_flat())
        m.sink.append(canon.OrientedMove(self.src, motion=motion, axes=axes, feed=f, frame=frame,
                                         interpolation=m.ori.interpolation, **arc))

    def rapid(self, a=None, b=None, n=None) -> None:
        before = dict(self.machine.pos)
        axes = self._target(a, b, n)
        if axes != before and self.oriented:
            self._oriented("traverse", axes)
        elif axes != before:
            self.machine.sink.append(canon.Traverse(self.src, axes=axes))

    def feed(self, f: float, a=None, b=None, n=None) -> None:
        axes = self._target(a, b, n)
        if self.oriented:
            self._oriented("feed", axes, f)
        else:
            self.machine.sink.append(canon.LinearFeed(self.src, axes=axes, feed=f))

    def probe(self, f: float, a=None, b=None, n=None) -> None:
        """A measuring move (the probe stops at contact; verify finds where)."""
        self.machine.sink.append(canon.ProbeMove(self.src, axes=self._target(a, b, n), feed=f))

    def arc(self, f: float, end, centre, clockwise: bool, n=None) -> None:
        """An arc (a helix when ``n`` is given) in the plane to ``end`` about ``centre``."""
        m = self.machine
        c3 = list(m.program_point())
        c3[self.ia], c3[self.ib] = centre
        cm = m.frames.to_machine(tuple(c3))
        axes = self._target(end[0], end[1], n)
        if self.oriented:
            self._oriented("arc", axes, f, plane=self.plane, center=tuple(centre), clockwise=clockwise)
            return
        m.sink.append(canon.ArcFeed(self.src, axes=axes, plane=self.plane,
                                    center=(cm[self.ia], cm[self.ib]),
                                    clockwise=m.machine_cw(clockwise), feed=f))

    def loop(self, f: float, start, segments) -> None:
        """Feed to ``start`` in the plane, then along the segments."""
        a, b, _ = self.here()
        if math.dist((a, b), start) > TINY:
            self.feed(f, *start)
        for seg in segments:
            if seg[0] == "line":
                if math.dist(self.here()[:2], seg[1]) > TINY:
                    self.feed(f, *seg[1])
            else:
                self.arc(f, seg[1], seg[2], seg[3])


def levels(top: float, bottom: float, mid: float) -> list[float]:
    """Depths from ``top`` down to ``bottom`` in equal steps of at most ``mid`` (0: one)."""
    span = top - bottom
    if span <= 0:
        return [bottom]
    n = 1 if mid <= 0 else max(1, math.ceil(span / mid - 1e-9))
    if n > MAX_STEPS:
        raise TooMany(f"more than {MAX_STEPS} depth levels")
    return [top - span * (k + 1) / n for k in range(n)]


def steps(span: float, step: float) -> list[float]:
    """Offsets 0 … ``span`` in equal steps of at most ``step`` (both ends included)."""
    if span <= TINY:
        return [0.0]
    n = max(1, math.ceil(span / step - 1e-9))
    if n > MAX_STEPS:
        raise TooMany(f"more than {MAX_STEPS} rings or passes")
    return [span * k / n for k in range(n + 1)]


def place(p, centre, angle: float):
    """Local point ``p`` turned by ``angle`` (radians) and moved to ``centre``."""
    c, s = math.cos(angle), math.sin(angle)
    return (centre[0] + c * p[0] - s * p[1], centre[1] + s * p[0] + c * p[1])


def rounded_rect(centre, hx: float, hy: float, rc: float, angle: float, clockwise: bool):
    """A rectangle of half-lengths hx × hy with corner radius rc about ``centre``, its length
    at ``angle`` (radians): its start (the middle of the +length side) and segments. hy = 0:
    the line along the length and back."""
    rc = max(0.0, min(rc, hx, hy))
    if hy <= TINY:
        pts = [("line", (-hx, 0.0)), ("line", (hx, 0.0))] if hx > TINY else []
        return place((hx, 0.0), centre, angle), [(k, place(p, centre, angle)) for k, p in pts]
    corners = [((hx - rc, hy - rc), (hx, hy - rc), (hx - rc, hy)),
               ((-hx + rc, hy - rc), (-hx + rc, hy), (-hx, hy - rc)),
               ((-hx + rc, -hy + rc), (-hx, -hy + rc), (-hx + rc, -hy)),
               ((hx - rc, -hy + rc), (hx - rc, -hy), (hx, -hy + rc))]
    segs = []                                   # counter-clockwise from (hx, 0)
    for c, p0, p1 in corners:
        segs.append(("line", p0))
        if rc > TINY:
            segs.append(("arc", p1, c))
    segs.append(("line", (hx, 0.0)))
    return _finish((hx, 0.0), segs, centre, angle, clockwise)


def rounded_polygon(centre, n: int, apothem: float, rc: float, angle: float, clockwise: bool):
    """A regular n-gon about ``centre`` whose flats lie ``apothem`` from it, the first flat's
    outward normal at ``angle`` (radians), its corners rounded with radius rc (at most the
    apothem): start (the middle of the first flat) and segments."""
    rc = max(0.0, min(rc, apothem))
    half = math.pi / n
    dist = (apothem - rc) / math.cos(half)          # corner centres from the centre
    normals = [(math.cos(2 * half * k), math.sin(2 * half * k)) for k in range(n + 1)]
    segs = []                                       # counter-clockwise from the first flat
    for k in range(n):
        c = (dist * math.cos(2 * half * k + half), dist * math.sin(2 * half * k + half))
        segs.append(("line", (c[0] + rc * normals[k][0], c[1] + rc * normals[k][1])))
        if rc > TINY:
            segs.append(("arc", (c[0] + rc * normals[k + 1][0], c[1] + rc * normals[k + 1][1]), c))
    segs.append(("line", (apothem, 0.0)))
    return _finish((apothem, 0.0), segs, centre, angle, clockwise)


def circle(centre, radius: float, clockwise: bool):
    """A full circle about ``centre`` from its point at angle 0: start and two half arcs."""
    if radius <= TINY:
        return centre, []
    return _finish((radius, 0.0), [("arc", (-radius, 0.0), (0.0, 0.0)), ("arc", (radius, 0.0), (0.0, 0.0))],
                   centre, 0.0, clockwise)


def stadium(p, q, w: float, clockwise: bool):
    """The loop at distance ``w`` about the straight centre line p → q (a slot's outline):
    start at p's side, segments. w = 0: the line there and back."""
    d = (q[0] - p[0], q[1] - p[1])
    length = math.hypot(*d)
    angle = math.atan2(d[1], d[0]) if length > TINY else 0.0
    mid = ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2)
    h = length / 2
    if w <= TINY:
        return place((-h, 0.0), mid, angle), [("line", place((h, 0.0), mid, angle)),
                                              ("line", place((-h, 0.0), mid, angle))]
    segs = [("line", (-h, -w)), ("line", (h, -w)), ("arc", (h, w), (h, 0.0)),
            ("line", (-h, w)), ("arc", (-h, -w), (-h, 0.0))]
    if length <= TINY:
        segs = [("arc", (0.0, w), (0.0, 0.0)), ("arc", (0.0, -w), (0.0, 0.0))]
    start = (-h, -w)
    return _finish(start, segs, mid, angle, clockwise)


def ring_arc(centre, radius: float, t0: float, t1: float, w: float, clockwise: bool):
    """The loop at distance ``w`` about the centre line on the circle ``radius`` about
    ``centre`` from angle t0 counter-clockwise to t1 (radians): a circumferential slot's outline."""
    def at(r, t):
        return (r * math.cos(t), r * math.sin(t))
    if w <= TINY:
        segs = [("arc", at(radius, t1), (0.0, 0.0)), ("arc", at(radius, t0), (0.0, 0.0), True)]
        start = at(radius, t0)
    else:
        ro, ri = radius + w, radius - w
        segs = [("arc", at(ro, t1), (0.0, 0.0)), ("arc", at(ri, t1), at(radius, t1)),
                ("arc", at(ri, t0), (0.0, 0.0), True), ("arc", at(ro, t0), at(radius, t0))]
        start = at(ro, t0)
    return _finish(start, segs, centre, 0.0, clockwise)


def _finish(start, segs, centre, angle, clockwise):
    """Counter-clockwise local segments (an arc's optional 4th item: clockwise in itself)
    placed, and reversed when ``clockwise``."""
    placed = []
    for s in segs:
        if s[0] == "line":
            placed.append(("line", place(s[1], centre, angle)))
        else:
            placed.append(("arc", place(s[1], centre, angle), place(s[2], centre, angle),
                           len(s) > 3 and s[3]))
    start = place(start, centre, angle)
    return reverse(start, placed) if clockwise else (start, placed)


def reverse(start, segs):
    """The loop run the other way: its start (the old end) and segments."""
    points = [start] + [s[1] for s in segs]
    out = []
    for i in range(len(segs) - 1, -1, -1):
        s = segs[i]
        out.append(("line", points[i]) if s[0] == "line" else ("arc", points[i], s[2], not s[3]))
    return points[-1], out
