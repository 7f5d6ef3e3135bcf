"""The contour elements of LinuxCNC's lathe cycles G70/G71/G72 (2.9, ``interp_g7x.cc``).

A point of the X-Z half-plane is a complex number ``z + 1j*x`` (program units, X a radius).
An element knows how it meets a horizontal line ``x = const`` (the roughing passes run along
Z), how the tool dives along it or climbs it, how it is offset sideways (the allowance) and
how it is trimmed against its neighbour. Fillets (``A``) and chamfers (``C``) on a contour
corner are elements that take their shape from both neighbours (``do_finish``).

The results must agree with rs274's to its printed 4 decimals, so the tolerances and the
order of operations follow LinuxCNC's behaviour; the code is vmach's own.
"""

from __future__ import annotations

import copy
import math

TOL = 1e-6


class G7xError(Exception):
    """A contour the cycle cannot cut (LinuxCNC's "G7X error: ...")."""


class Sink:
    """Where a cycle's moves go: ``rapid(p)``, ``feed(p)``, ``arc(ccw, centre, p)``."""

    def rapid(self, p: complex) -> None:
        raise NotImplementedError

    def feed(self, p: complex) -> None:
        raise NotImplementedError

    def arc(self, ccw: bool, centre: complex, p: complex) -> None:
        raise NotImplementedError


def sc(f: float, c: complex) -> complex:
    """``f * c`` component by component, as C++ multiplies a complex by a real (Python
    would multiply by ``complex(f, 0)``, which can change the sign of a zero)."""
    return complex(f * c.real, f * c.imag)


def dv(c: complex, f: float) -> complex:
    """``c / f`` component by component (see :func:`sc`)."""
    return complex(c.real / f, c.imag / f)


def _norm(c: complex) -> float:
    return c.real * c.real + c.imag * c.imag


class Segment:
    """start/end: complex points; ``finish``: a corner's fillet radius or chamfer size."""

    def __init__(self, start: complex, end: complex):
        self.start = start
        self.end = end
        self.finish = 0.0

    def dup(self) -> Segment:
        return copy.copy(self)

    def monotonic(self) -> bool:
        return (self.end - self.start).real <= 1e-3

    def do_finish(self, prev: Segment, nxt: Segment) -> None:
        return None

    def flip_imag(self) -> None:
        self.start, self.end = self.start.conjugate(), self.end.conjugate()

    def flip_real(self) -> None:
        self.start, self.end = -self.start.conjugate(), -self.end.conjugate()

    def rotate(self) -> None:
        self.start, self.end = (-self.start) * 1j, (-self.end) * 1j

    def move(self, d: complex) -> None:
        self.start += d
        self.end += d

    def trim(self, nxt: Segment) -> None:
        """Move this element's end and ``nxt``'s start to where the two meet."""
        if isinstance(self, Arc):
            nxt.trim_after_arc(self)
        else:
            nxt.trim_after_line(self)

    def corner(self, prev: Segment, nxt: Segment) -> complex:
        """Shape a corner element between ``prev`` and ``nxt`` offset by ``finish``; returns
        the centre of the rounding (the middle of the offset corner)."""
        p, n = prev.dup(), nxt.dup()
        p.offset(self.finish)
        n.offset(self.finish)
        if (p.end - n.start).real > 1e-2:
            self.finish = -self.finish
            p, n = prev.dup(), nxt.dup()
            p.offset(self.finish)
            n.offset(self.finish)
        if (p.end - n.start).real > 1e-2:
            raise G7xError(f"Corner finish failed at {cpp(prev.end)}")
        p.trim(n)
        centre = dv(p.end + n.start, 2.0)
        p.offset(-self.finish)
        n.offset(-self.finish)
        self.start = prev.end = p.end
        self.end = nxt.start = n.start
        return centre


def _line_circle(a: complex, b: complex, on: complex, centre: complex, near: complex) -> complex:
    """Where the line through ``a`` and ``b`` meets the circle about ``centre`` through ``on``:
    of the two points, the one nearer ``near`` (worked in the frame of the line at ``b``)."""
    rot = dv((a - b).conjugate(), abs(a - b))
    pe = (on - b) * rot
    pc = (centre - b) * rot
    h = _norm(pc - pe) - pc.imag * pc.imag
    h = 0.0 if h < 0 else math.sqrt(h)
    s1 = (pc.real + h) / rot + b
    s2 = (pc.real - h) / rot + b
    return s1 if abs(near - s1) < abs(near - s2) else s2


def cpp(c: complex) -> str:
    """A complex as C++ streams print it: ``(re,im)`` with 6 significant digits."""
    return f"({c.real:g},{c.imag:g})"


class Line(Segment):
    def intersections(self, x: float) -> list[float]:
        s, e = self.start, self.end
        if min(s.imag, e.imag) > x + TOL or max(s.imag, e.imag) < x - TOL:
            return []
        if abs((s - e).imag) < TOL:
            return [s.real, e.real]
        return [(x - s.imag) / (e.imag - s.imag) * (e.real - s.real) + s.real]

    def climb(self, loc: complex, out: Sink) -> tuple[bool, complex]:
        """Follow the element upwards; (True, loc) when it does not climb."""
        if self.end.imag + TOL < self.start.imag:
            return True, loc
        if abs(loc - self.start) > TOL:
            raise G7xError("How did we get here?")
        out.feed(self.end)
        return False, self.end

    def climb_only(self, loc: complex, out: Sink) -> complex:
        if self.end.imag < self.start.imag:
            return loc
        hits = self.intersections(loc.imag)
        if not hits:
            return loc
        loc = complex(hits[0], loc.imag)
        out.feed(loc)
        out.feed(self.end)
        return self.end

    def dive(self, loc: complex, x: float, out: Sink, fast: bool) -> tuple[bool, complex]:
        """Follow the element down to level ``x``; (True, loc) when it does not dive."""
        if self.start.imag <= self.end.imag + TOL:
            return True, loc
        move = out.rapid if fast else out.feed
        if x < self.end.imag:
            move(self.end)
            return False, self.end
        hits = self.intersections(x)
        if not hits:
            raise G7xError("x too large in straight dive")
        p = complex(hits[0], x)
        move(p)
        return False, p

    def draw(self, out: Sink) -> None:
        out.feed(self.end)

    def offset(self, distance: float) -> None:
        d = dv(complex(0.0 * distance, distance) * (self.start - self.end),
               abs(self.start - self.end))
        self.start += d
        self.end += d

    def radius(self) -> float:
        return abs(self.start - self.end)

    def trim_after_line(self, p: Line) -> None:
        rot = dv((self.start - self.end).conjugate(), abs(self.start - self.end))
        ps = (p.start - self.end) * rot
        pe = (p.end - self.end) * rot
        if (ps - pe).imag == 0:
            raise G7xError("Cannot intersect parallel lines")
        f = ps.imag / (ps - pe).imag
        point = (ps + sc(f, pe - ps)) / rot + self.end
        self.start = p.end = point

    def trim_after_arc(self, p: Arc) -> None:
        if abs(self.start - p.end) < TOL:
            return
        self.start = p.end = _line_circle(self.start, self.end, p.end, p.centre, self.start)


class Arc(Segment):
    def __init__(self, ccw: bool, start: complex, centre: complex, end: complex):
        super().__init__(start, end)
        self.ccw = bool(ccw)
        self.centre = centre

    def _on(self, p: complex) -> bool:
        a = ((self.start - self.centre).conjugate() * (p - self.centre)).imag
        b = ((self.end - self.centre).conjugate() * (p - self.centre)).imag
        if self.ccw:
            return a >= -TOL and b <= TOL
        return a <= TOL and b >= -TOL

    def intersections(self, x: float) -> list[float]:
        r = abs(self.start - self.centre)
        c = self.centre
        s = -(x - r - c.imag) * (x + r - c.imag)
        if s < -TOL:
            return []
        s = math.sqrt(max(s, 0.0))
        hits = []
        for z in (c.real + s, c.real - s):
            if self._on(complex(z, x)):
                hits.append(z)
        return hits

    def _top(self) -> complex:
        """Where a G3 climb stops: its end, or the top of the circle if it goes past it."""
        if self.end.real < self.centre.real:
            return complex(self.centre.real, self.centre.imag + abs(self.start - self.centre))
        return self.end

    def climb(self, loc: complex, out: Sink) -> tuple[bool, complex]:
        if not self.ccw:
            if loc.real > self.centre.real:
                return True, loc
            if abs(loc - self.end) > 1e-3:
                out.arc(False, self.centre, self.end)
            return False, self.end
        if loc.real < self.centre.real:
            return True, loc
        ep = self._top()
        if abs(loc - ep) > 1e-3:
            out.arc(True, self.centre, ep)
        return True, ep

    def dive(self, loc: complex, x: float, out: Sink, fast: bool) -> tuple[bool, complex]:
        if abs(loc - self.end) < TOL or (loc - self.end).real <= TOL:
            return False, self.end
        hits = self.intersections(x)
        if not hits:
            hits = self.intersections(x - TOL)
        c = self.centre
        if self.ccw:
            if loc.real - TOL > c.real:
                return True, loc
            if not hits or hits[-1] > c.real:
                out.arc(True, c, self.end)
                return False, self.end
            ep = complex(hits[-1], x)
            out.arc(True, c, ep)
            return False, ep
        if loc.real <= c.real:
            return True, loc
        if not hits:
            out.arc(False, c, self.end)
            return False, self.end
        if hits[0] < c.real:
            return False, loc  # only the back of the arc is hit: the pocket goes down
        ep = complex(hits[0], x)
        out.arc(False, c, ep)
        return False, ep

    def climb_only(self, loc: complex, out: Sink) -> complex:
        hits = self.intersections(loc.imag)
        if not hits:
            return loc
        if not self.ccw:
            if hits[-1] > self.centre.real:
                return loc
            loc = complex(hits[-1], loc.imag)
            out.feed(loc)
            if abs(loc - self.end) > 1e-3:
                out.arc(False, self.centre, self.end)
            return self.end
        if hits[0] < self.centre.real:
            return loc
        loc = complex(hits[0], loc.imag)
        out.feed(loc)
        ep = self._top()
        if abs(loc - ep) > 1e-3:
            out.arc(True, self.centre, ep)
        return ep

    def draw(self, out: Sink) -> None:
        out.arc(self.ccw, self.centre, self.end)

    def offset(self, distance: float) -> None:
        r = abs(self.start - self.centre)
        factor = (r + (1 if self.ccw else -1) * distance) / r
        self.start = sc(factor, self.start - self.centre) + self.centre
        self.end = sc(factor, self.end - self.centre) + self.centre

    def radius(self) -> float:
        return min(abs(self.start - self.end), abs(self.start - self.centre))

    def flip_imag(self) -> None:
        self.ccw = not self.ccw
        super().flip_imag()
        self.centre = self.centre.conjugate()

    def flip_real(self) -> None:
        self.ccw = not self.ccw
        super().flip_real()
        self.centre = -self.centre.conjugate()

    def rotate(self) -> None:
        super().rotate()
        self.centre = (-self.centre) * 1j

    def move(self, d: complex) -> None:
        super().move(d)
        self.centre += d

    def monotonic(self) -> bool:
        if self.finish != 0:
            return True
        entry = (self.start - self.centre).imag
        leave = (self.end - self.centre).imag
        dz = (self.end - self.start).real
        if self.ccw:
            return entry >= -1e-3 and leave >= -1e-3 and dz <= -1e-3
        return entry <= 1e-3 and leave <= 1e-3 and dz <= -1e-3

    def trim_after_line(self, p: Line) -> None:
        if abs(self.start - p.end) < TOL:
            return
        self.start = p.end = _line_circle(p.start, p.end, self.end, self.centre, self.start)

    def trim_after_arc(self, p: Arc) -> None:
        a = abs(self.start - self.centre)
        b = abs(p.start - p.centre)
        c = abs(self.centre - p.centre)
        cos_b = (c * c + a * a - b * b) / 2.0 / a / c
        cos_b2 = min(cos_b * cos_b, 1.0)
        rot = complex(cos_b, math.sqrt(1 - cos_b2))
        point = sc(a, dv(rot * (p.centre - self.centre), c)) + self.centre
        p.end = self.start = point


class Fillet(Arc):
    """``A`` on a contour block: a rounding of that corner, radius ``finish``."""

    def __init__(self, size: float, at: complex):
        super().__init__(False, at, at, at)
        self.finish = size

    def do_finish(self, prev: Segment, nxt: Segment) -> None:
        self.centre = self.corner(prev, nxt)
        self.ccw = (self.start - self.centre).imag > 0 or (self.end - self.centre).imag > 0
        self.finish = 0.0


class Chamfer(Line):
    """``C`` on a contour block: a chamfer of that corner, size ``finish``."""

    def __init__(self, size: float, at: complex):
        super().__init__(at, at)
        self.finish = size

    def do_finish(self, prev: Segment, nxt: Segment) -> None:
        self.corner(prev, nxt)
