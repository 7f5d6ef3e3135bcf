"""Tool radius compensation: G41 / G42 / G40 with NORM approach and retract, G450 / G451 at
outside corners (Programming Manual Fundamentals, "Tool radius compensation").

The tool centre runs at the D offset's radius r to the left (G41) or right (G42) of the
programmed contour in the working plane (G17 X/Y, G18 Z/X, G19 Y/Z), in program coordinates
(mm; the frame is applied afterwards, so a ROT turns the compensated path with the contour):

- **Approach (NORM).** The first block with motion in the plane after G41/G42 runs in a
  straight line from the uncompensated position to its end point moved by r along the normal
  of the *next* contour element's start tangent.
- **Contour.** A line is moved by r along its normal, an arc becomes the concentric arc of
  radius R ∓ r (an arc whose compensated radius would not be positive is a ``cutcom_radius``
  error). Where two elements meet at an *inside* corner both end at the intersection of their
  compensated paths (none on both elements: ``cutcom_collision``, the tool does not fit);
  at an *outside* corner G450 (the default) inserts a transition arc of radius r about the
  corner point, G451 runs both paths on to the intersection of their tangents.
- **Retract (NORM).** The block with G40 starts where the last element's compensated path
  ends (r along the normal of its end tangent) and runs straight to its programmed end point.

The compensated end of an element depends on the next one, so each element's commands are
written into a :class:`Slot` that keeps its place in the command stream and is filled when
the next element is known; blocks moving only other axes (Z, C1) while compensation is active
keep their place too and run at the compensated end of the element before them. Everything
is decided here; the machine state (``execute.Machine``) hands over each motion.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from vmach import canon
from vmach.errors import ProgramError
from vmach.source import SourceRef

#: turn between two elements below which they meet tangentially (radians)
TANGENT = 1e-9
#: a point counts as lying on an element within this, mm
ON = 1e-7

Point = tuple[float, float]


class Slot:
    """A place in the command stream filled later with the commands of one compensated block."""

    __slots__ = ("commands",)

    def __init__(self) -> None:
        self.commands: list[canon.Command] = []


def flatten(out: list) -> list:
    """The command stream with every :class:`Slot` replaced by its commands (slots nest: a
    held chamfer's slot holds the compensation's)."""
    if not any(isinstance(c, Slot) for c in out):
        return out
    flat: list = []
    for c in out:
        if isinstance(c, Slot):
            flat.extend(flatten(c.commands))
        else:
            flat.append(c)
    return flat


@dataclass
class Element:
    """One programmed block with motion in the plane, in program coordinates.

    p0, p1 : programmed start and end in the plane (a, b), mm. centre : arc centre or None.
    cw, turns : arc direction and extra full turns. start3, end3 : programmed start and end,
    all three geometry axes. cmd : the programmed (uncompensated) command. slot : its place.
    q0 : compensated start (a, b), set when the element before it was resolved.
    r : the tool radius it is compensated with (a D change while compensating applies from the
    next element on; a straight line joins paths of different radii).
    """

    p0: Point
    p1: Point
    end3: tuple[float, float, float]
    cmd: canon.Command
    src: SourceRef
    slot: Slot
    centre: Point | None = None
    cw: bool = False
    turns: int = 0
    q0: Point | None = None
    r: float = 0.0
    before: list[canon.Command] = field(default_factory=list)   # transition from the last element

    def tangent(self, at_end: bool) -> Point:
        """Unit tangent of the programmed path at its start or end."""
        if self.centre is None:
            return _unit((self.p1[0] - self.p0[0], self.p1[1] - self.p0[1]))
        p = self.p1 if at_end else self.p0
        u = (p[0] - self.centre[0], p[1] - self.centre[1])
        return _unit((u[1], -u[0]) if self.cw else (-u[1], u[0]))

    @property
    def radius(self) -> float:
        assert self.centre is not None
        return math.hypot(self.p0[0] - self.centre[0], self.p0[1] - self.centre[1])


def _unit(v: Point) -> Point:
    n = math.hypot(v[0], v[1])
    return (v[0] / n, v[1] / n) if n > 0 else (0.0, 0.0)


def _cross(a: Point, b: Point) -> float:
    return a[0] * b[1] - a[1] * b[0]


class Compensator:
    """State of the tool radius compensation of one channel.

    side : +1 G41 (left), −1 G42 (right), 0 off. radius : r, mm. corner : "G450" or "G451".
    plane : indices (a, b) of the working plane's axes among the geometry axes.
    """

    def __init__(self, machine) -> None:
        self.m = machine
        self.side = 0
        self.radius = 0.0
        self.corner = "G450"
        self.approach = "NORM"
        self.state = "off"
        self.pending: Element | None = None
        self.waiting: list[tuple[Slot, canon.Command]] = []   # other-axis moves after pending
        self.approach_block = False     # the pending element is the approach (G41/G42 block)
        #: from the nose centre to the turning tool's reference point P, program plane (mm):
        #: with a cutting edge position the compensated path is written for P (turning/nose.py)
        self.shift: Point = (0.0, 0.0)

    @property
    def state(self) -> str:
        """off | selecting | on | deselecting."""
        return self._state

    @state.setter
    def state(self, value: str) -> None:
        self._state = value
        self.engaged = value != "off"     # read on every fast-path move: a plain attribute

    # -- G41 / G42 / G40 -----------------------------------------------------------------
    def select(self, code: str, radius: float, src: SourceRef) -> None:
        side = 1 if code == "G41" else -1
        if self.state == "on" and side == self.side:
            self.radius = radius                # G41 again: a new radius from here on
            return
        if self.state in ("on", "deselecting"):
            self.finish()                       # the other side: retract here, approach again
        if self.approach != "NORM":
            raise ProgramError("unsupported", f"{code} with {self.approach}: vmach approaches the "
                               "contour with NORM only", src)
        self.side, self.radius = side, radius
        self.state = "selecting"

    def deselect(self) -> None:
        if self.state == "selecting":
            self.state = "off"
        elif self.state == "on":
            self.state = "deselecting"

    # -- motion --------------------------------------------------------------------------
    def take(self, cmd: canon.Command, start3, end3, centre: Point | None, src: SourceRef) -> None:
        """One programmed motion (program coordinates ``start3``/``end3``, arc ``centre`` in
        the plane); writes the commands it can already decide."""
        ia, ib = self.plane
        p0, p1 = (start3[ia], start3[ib]), (end3[ia], end3[ib])
        in_plane = centre is not None or math.hypot(p1[0] - p0[0], p1[1] - p0[1]) > ON
        out = self.m.sink
        if not in_plane:
            if self.state == "selecting":
                out.append(cmd)
            else:                               # runs at the compensated end of the element before
                slot = Slot()
                out.append(slot)
                self.m.placeholders = True
                self.waiting.append((slot, cmd))
            return
        if self.state == "deselecting":
            if not isinstance(cmd, (canon.Traverse, canon.LinearFeed)):
                raise ProgramError("cutcom", "G40 must be deselected in a G0/G1 block", src)
            self._resolve(None)
            out.append(cmd)
            self.state = "off"
            return
        slot = Slot()
        out.append(slot)
        self.m.placeholders = True
        elem = Element(p0, p1, tuple(end3), cmd, src, slot, centre, self.m.machine_cw(cw_of(cmd)),
                       int(getattr(cmd, "turns", 0)), r=self.radius)
        if centre is not None and self._offset_radius(elem) <= ON:
            raise ProgramError(
                "cutcom_radius",
                f"the arc's radius {elem.radius:.4f} mm is not larger than the tool radius "
                f"{elem.r:.4f} mm on the side the tool runs",
                src, arc_radius=elem.radius, tool_radius=elem.r)
        if self.state == "selecting":
            if centre is not None:
                raise ProgramError("cutcom", "G41/G42 must be selected in a G0/G1 block", src)
            elem.q0 = p0                        # the approach starts uncompensated
            self.pending = elem
            self.approach_block = True
            self.state = "on"
            return
        self._resolve(elem)
        self.pending = elem

    def finish(self) -> None:
        """End of compensation without a retract block (program end, change of side)."""
        if self.state in ("on", "deselecting"):
            self._resolve(None)
        self.state = "off"

    # -- geometry ------------------------------------------------------------------------
    def _offset(self, t: Point, r: float) -> Point:
        """The tool centre's offset from the contour for a path of unit tangent t (mm)."""
        s = self.side * r
        return (-t[1] * s, t[0] * s)

    def _offset_radius(self, e: Element) -> float:
        """Radius of the compensated arc: R − r where the tool runs inside."""
        sigma = -1.0 if e.cw else 1.0
        return e.radius - self.side * sigma * e.r

    def _resolve(self, nxt: Element | None) -> None:
        """Fix the pending element's compensated end (and ``nxt``'s start and transition),
        then write its commands and those of the moves waiting after it."""
        a = self.pending
        if a is None:
            return
        approach, self.approach_block = self.approach_block, False
        if nxt is None:
            end = _add(a.p1, self._offset(a.tangent(True), a.r))
        elif approach:
            end = _add(nxt.p0, self._offset(nxt.tangent(False), nxt.r))
            nxt.q0 = end
        else:
            end = self._corner(a, nxt)
        self._write(a, end, approach)
        for slot, cmd in self.waiting:
            slot.commands.append(replace(cmd, axes=self._axes(cmd, end)))
        self.waiting = []
        self.pending = None

    def _corner(self, a: Element, b: Element) -> Point:
        """Compensated end of a and start of b where they meet (p = a.p1 = b.p0)."""
        ta, tb = a.tangent(True), b.tangent(False)
        qa, qb = _add(a.p1, self._offset(ta, a.r)), _add(b.p0, self._offset(tb, b.r))
        turn = math.atan2(_cross(ta, tb), ta[0] * tb[0] + ta[1] * tb[1])
        if a.r != b.r:                          # a new radius: straight from one path to the other
            b.q0 = qb
            b.before.append(self._link(a, qb, b))
            return qa
        if abs(turn) < TANGENT:
            b.q0 = qa
            return qa
        outside = self.side * turn < 0 or abs(abs(turn) - math.pi) < TANGENT
        if not outside:
            x = self._meet(a, b, qa, qb)
            if x is None:
                raise ProgramError(
                    "cutcom_collision",
                    f"the tool (radius {b.r:.4f} mm) does not fit into the inside corner "
                    f"with line {a.src.line}: the compensated paths do not meet",
                    b.src, tool_radius=b.r, other_line=a.src.line)
            b.q0 = x
            return x
        if self.corner == "G451" and abs(abs(turn) - math.pi) > 1e-6:
            # on to where the compensated paths, extended (a line as a line, an arc on its
            # circle), meet: the meeting point nearest the corner
            # that lies on a's side beyond qa and on b's before qb (else the G450 circle)
            near = sorted((x for x in intersections(self._path(a), self._path(b))
                           if _dot(_sub(x, qa), ta) >= -ON and _dot(_sub(x, qb), tb) <= ON),
                          key=lambda x: math.hypot(x[0] - a.p1[0], x[1] - a.p1[1]))
            if near:
                b.q0 = near[0]
                return near[0]
        b.q0 = qb
        b.before.append(self._transition(a, qa, qb, b))
        return qa

    def _link(self, a: Element, q: Point, b: Element) -> canon.Command:
        """A straight move to q at the corner, as the next block moves (traverse or feed)."""
        axes = self._axes(b.cmd, q)
        if isinstance(b.cmd, canon.Traverse):
            return canon.Traverse(b.src, axes=axes)
        return canon.LinearFeed(b.src, axes=axes, feed=b.cmd.feed)

    def _transition(self, a: Element, qa: Point, qb: Point, b: Element) -> canon.Command:
        """The G450 arc of radius r about the corner from qa to qb (a straight traverse when
        the next block is G0: the canonical stream has no rapid arcs)."""
        axes = self._axes(b.cmd, qb)
        if isinstance(b.cmd, canon.Traverse):
            return canon.Traverse(b.src, axes=axes)
        centre = self.m.machine_plane(_add(a.p1, self.shift), a.end3)
        return canon.ArcFeed(b.src, axes=axes, plane=self.m.plane_axes, center=centre,
                             clockwise=self.m.machine_cw(self.side > 0), turns=0, feed=b.cmd.feed)

    def _meet(self, a: Element, b: Element, qa: Point, qb: Point) -> Point | None:
        """Intersection of a's and b's compensated paths lying on both, nearest the corner."""
        best, best_d = None, math.inf
        for x in intersections(self._path(a), self._path(b)):
            if self._on(a, x, qa, end=True) and self._on(b, x, qb, end=False):
                d = math.hypot(x[0] - qa[0], x[1] - qa[1])
                if d < best_d:
                    best, best_d = x, d
        return best

    def _path(self, e: Element):
        if e.centre is None:
            off = self._offset(e.tangent(False), e.r)
            return ("line", _add(e.p0, off), e.tangent(False))
        return ("circle", e.centre, self._offset_radius(e))

    def _on(self, e: Element, x: Point, q_corner: Point, end: bool) -> bool:
        """Whether x lies on e's compensated path between its other end and the corner."""
        if end:
            start = e.q0 if e.q0 is not None else _add(e.p0, self._offset(e.tangent(False), e.r))
            far, near = start, q_corner
        else:
            far, near = _add(e.p1, self._offset(e.tangent(True), e.r)), q_corner
        if e.centre is None:
            d = (far[0] - near[0], far[1] - near[1])
            length2 = d[0] * d[0] + d[1] * d[1]
            if length2 <= ON * ON:
                return math.hypot(x[0] - near[0], x[1] - near[1]) <= ON
            t = ((x[0] - near[0]) * d[0] + (x[1] - near[1]) * d[1]) / length2
            return -ON <= t * math.sqrt(length2) <= math.sqrt(length2) + ON
        c = e.centre
        full = math.hypot(e.p1[0] - e.p0[0], e.p1[1] - e.p0[1]) <= ON
        start = far if end else near
        stop = near if end else far
        limit = sweep(e) if full else angle_along(c, start, stop, e.cw) + 2 * math.pi * e.turns
        return angle_along(c, start, x, e.cw) <= limit + ON / max(self._offset_radius(e), ON)

    # -- commands ------------------------------------------------------------------------
    def _write(self, e: Element, end: Point, approach: bool) -> None:
        cmd = e.cmd
        axes = self._axes(cmd, end)
        if isinstance(cmd, canon.ArcFeed):
            new = replace(cmd, axes=axes, center=self.m.machine_plane(_add(e.centre, self.shift), e.end3))
        else:
            new = replace(cmd, axes=axes)
        e.slot.commands.extend(e.before)
        e.slot.commands.append(new)

    def _axes(self, cmd: canon.Command, q: Point) -> dict:
        """The command's axes (it carries every axis) with the plane's geometry axes at the
        compensated point q."""
        ia, ib = self.plane
        p = list(self.m.frames.to_program(tuple(cmd.axes[n] for n in self.m.geometry)))
        p[ia], p[ib] = q[0] + self.shift[0], q[1] + self.shift[1]
        return self.m.machine_axes(cmd.axes, p)

    @property
    def plane(self) -> tuple[int, int]:
        g = self.m.geometry
        a, b = self.m.plane_axes[:2]
        return g.index(a), g.index(b)


def cw_of(cmd: canon.Command) -> bool:
    """An arc command's machine direction (False for lines); :meth:`Machine.machine_cw` turns it
    back into the program's (the map is its own inverse)."""
    return bool(getattr(cmd, "clockwise", False))


def _add(p: Point, v: Point) -> Point:
    return (p[0] + v[0], p[1] + v[1])


def _sub(p: Point, q: Point) -> Point:
    return (p[0] - q[0], p[1] - q[1])


def _dot(p: Point, q: Point) -> float:
    return p[0] * q[0] + p[1] * q[1]


def _lines(p: Point, d: Point, q: Point, e: Point) -> Point | None:
    """Intersection of the lines p + s·d and q + t·e (None when parallel)."""
    den = _cross(d, e)
    if abs(den) < 1e-12:
        return None
    s = _cross((q[0] - p[0], q[1] - p[1]), e) / den
    return (p[0] + s * d[0], p[1] + s * d[1])


def intersections(f, g) -> list[Point]:
    """Intersections of two compensated paths given as ("line", point, unit direction) or
    ("circle", centre, radius), as full lines and circles."""
    if f[0] == "line" and g[0] == "line":
        x = _lines(f[1], f[2], g[1], g[2])
        return [] if x is None else [x]
    if f[0] == "circle" and g[0] == "line":
        f, g = g, f
    if f[0] == "line":
        (_, p, d), (_, c, r) = f, g
        w = (p[0] - c[0], p[1] - c[1])
        bq = w[0] * d[0] + w[1] * d[1]
        disc = bq * bq - (w[0] * w[0] + w[1] * w[1] - r * r)
        if disc < -ON:
            return []
        root = math.sqrt(max(disc, 0.0))
        return [(p[0] + s * d[0], p[1] + s * d[1]) for s in (-bq - root, -bq + root)]
    (_, c1, r1), (_, c2, r2) = f, g
    dx, dy = c2[0] - c1[0], c2[1] - c1[1]
    d = math.hypot(dx, dy)
    if d < 1e-12 or d > r1 + r2 + ON or d < abs(r1 - r2) - ON:
        return []
    along = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
    h = math.sqrt(max(r1 * r1 - along * along, 0.0))
    mx, my = c1[0] + along * dx / d, c1[1] + along * dy / d
    return [(mx - h * dy / d, my + h * dx / d), (mx + h * dy / d, my - h * dx / d)]


def sweep(e: Element) -> float:
    """Angle (radians, > 0) the programmed arc turns through."""
    a0 = math.atan2(e.p0[1] - e.centre[1], e.p0[0] - e.centre[0])
    a1 = math.atan2(e.p1[1] - e.centre[1], e.p1[0] - e.centre[0])
    d = (a0 - a1) if e.cw else (a1 - a0)
    d %= 2 * math.pi
    if d < 1e-12:
        d = 2 * math.pi
    return d + 2 * math.pi * e.turns


def angle_along(c: Point, start: Point, x: Point, cw: bool) -> float:
    """Angle from ``start`` to ``x`` about c in the arc's direction, in [0, 2π)."""
    a0 = math.atan2(start[1] - c[1], start[0] - c[0])
    a1 = math.atan2(x[1] - c[1], x[0] - c[0])
    d = (a0 - a1) if cw else (a1 - a0)
    d %= 2 * math.pi
    if d > 2 * math.pi - 1e-9:
        d = 0.0
    return d
