"""Chamfers and roundings between contour elements: CHF=, CHR=, RND=, RNDM= (Programming
Manual Fundamentals, "Chamfer, rounding").

A block with ``RND=ρ`` ends before its end point P, and a tangent arc of radius ρ joins it to
the next block in the working plane; ``CHF=l`` joins them with a straight chamfer of length l,
``CHR=l`` with one whose legs along both elements are l; ``RNDM=ρ`` rounds every following
corner until ``RNDM=0``; ``FRC=`` (this block) or ``FRCM=`` (modal, 0 off) is the insert's
feed, else the block's. For two straight elements meeting at P with a turn θ the element ends
and the next begins

    d = ρ·tan(|θ|/2)  (RND),   d = l / (2·cos(|θ|/2))  (CHF),   d = l  (CHR)

from P along each (mm). Where an arc takes part, RND's circle has its centre where both
elements, offset by ρ toward the inside of the turn, meet, and touches each at the foot of
that centre; CHF/CHR next to an arc are ``unsupported``. An insert that does not fit on the
elements is ``corner_insert``.

The block is held until the next motion is known; its place in the command stream is kept by
a :class:`Slot`, and what it becomes is handed on to tool radius compensation (or written)
exactly as an unmodified block would be.
"""

from __future__ import annotations

import math
from dataclasses import replace

from interpreters.sinumerik.cutcom import Element, Slot, angle_along, cw_of, intersections, sweep
from vmach import canon
from vmach.errors import ProgramError
from vmach.source import SourceRef

#: turn (radians) below which two elements are taken as tangent: nothing is inserted
TANGENT = 1e-9
WORDS = ("CHF", "CHR", "RND", "RNDM", "FRC", "FRCM")


class Corners:
    """The held block and the modal rounding (RNDM) of one channel."""

    def __init__(self, machine) -> None:
        self.m = machine
        self.modal = 0.0                # RNDM radius, mm (0: off)
        self.feed_modal = 0.0           # FRCM feed (0: the block's)
        self.held: tuple | None = None  # (slot, cmd, start3, end3, centre, src, kind, value)

    @property
    def holding(self) -> bool:
        return self.held is not None

    def take(self, cmd, start3, end3, centre, src: SourceRef, words: dict, send) -> None:
        """One motion of the program; ``words`` its CHF/CHR/RND/RNDM values (mm, already in
        the block's units); ``send(cmd, start3, end3, centre, src)`` passes a move on."""
        kind, value = None, 0.0
        for k in ("CHF", "CHR", "RND"):
            if k in words:
                if kind is not None:
                    raise ProgramError("syntax", f"{kind}= and {k}= in one block", src)
                kind, value = k, float(words[k])
        if kind is None and self.modal > 0:
            kind, value = "RND", self.modal
        ia, ib = self.m.cutcom.plane
        in_plane = centre is not None or math.hypot(end3[ia] - start3[ia], end3[ib] - start3[ib]) > 1e-9
        if self.held is not None:
            start3 = self._release(cmd, start3, end3, centre, src, in_plane, send)
        if kind is None or value <= 0 or not in_plane:
            send(cmd, start3, end3, centre, src)
            return
        if centre is not None and kind != "RND":
            raise ProgramError("unsupported", f"{kind}= after an arc is not simulated (chamfers "
                               "between straight elements only)", src)
        slot = Slot()
        self.m.sink.append(slot)
        self.m.placeholders = True
        feed = words.get("FRC") or self.feed_modal or None
        self.held = (slot, cmd, start3, end3, centre, src, kind, value, feed)

    def flush(self, send) -> None:
        """No further element (program end): the held block runs to its end point."""
        if self.held is not None:
            slot, cmd, start3, end3, centre, src = self.held[:6]
            self.held = None
            self._into(slot, send, cmd, start3, end3, centre, src)

    def _release(self, cmd, start3, end3, centre, src, in_plane: bool, send):
        """Shorten the held block and this one at their corner and send the held block and
        the insert; returns this block's start (the insert's end, or ``start3``)."""
        slot, a_cmd, a0, a1, a_centre, a_src, kind, value, insert_feed = self.held
        self.held = None
        if not in_plane:
            if self.modal > 0 and kind == "RND":
                self._into(slot, send, a_cmd, a0, a1, a_centre, a_src)   # no corner to round
                return start3
            raise ProgramError("unsupported", f"{kind}= before a block without motion in the plane "
                               "is not simulated", src)
        if kind == "RND" and (centre is not None or a_centre is not None):
            return self._round_arcs(slot, send, (a_cmd, a0, a1, a_centre, a_src), value, insert_feed,
                                    (cmd, start3, end3, centre, src))
        if centre is not None or not isinstance(cmd, (canon.LinearFeed, canon.Traverse)):
            raise ProgramError("unsupported", f"{kind}= before an arc is not simulated (chamfers "
                               "between straight elements only)", a_src)
        ia, ib = self.m.cutcom.plane
        p = (a1[ia], a1[ib])
        ua, la = _direction((a0[ia], a0[ib]), p)
        ub, lb = _direction(p, (end3[ia], end3[ib]))
        turn = math.atan2(ua[0] * ub[1] - ua[1] * ub[0], ua[0] * ub[0] + ua[1] * ub[1])
        if abs(turn) < TANGENT:
            self._into(slot, send, a_cmd, a0, a1, a_centre, a_src)
            return start3
        half = abs(turn) / 2.0
        d = {"RND": value * math.tan(half), "CHF": value / (2.0 * math.cos(half)), "CHR": value}[kind]
        if d > la + 1e-9 or d > lb + 1e-9:
            raise ProgramError(
                "corner_insert",
                f"{kind}={value:g} does not fit: it needs {d:.4f} mm of both elements, they are "
                f"{la:.4f} and {lb:.4f} mm long", a_src, needs=d, lengths=[la, lb])
        q0 = _moved(a1, ia, ib, (p[0] - d * ua[0], p[1] - d * ua[1]))
        q1 = _moved(a1, ia, ib, (p[0] + d * ub[0], p[1] + d * ub[1]))
        feed = insert_feed or getattr(a_cmd, "feed", None) or self.m.feed
        first = replace(a_cmd, axes=self.m.machine_axes(a_cmd.axes, q0))
        end = self.m.machine_axes(a_cmd.axes, q1)
        if kind == "RND":
            side = 1.0 if turn > 0 else -1.0
            c = (q0[ia] - side * ua[1] * value, q0[ib] + side * ua[0] * value)
            insert = canon.ArcFeed(a_src, axes=end, plane=self.m.plane_axes,
                                   center=self.m.machine_plane(c, a1),
                                   clockwise=self.m.machine_cw(turn < 0), turns=0, feed=feed)
            insert_centre = c
        elif isinstance(a_cmd, canon.Traverse):
            insert, insert_centre = canon.Traverse(a_src, axes=end), None
        else:
            insert, insert_centre = canon.LinearFeed(a_src, axes=end, feed=feed), None
        self._into(slot, send, first, a0, q0, None, a_src)
        self._into(slot, send, insert, q0, q1, insert_centre, a_src)
        return tuple(q1)

    def _round_arcs(self, slot: Slot, send, a, rho: float, insert_feed, b):
        """RND=ρ where an arc takes part: the rounding circle's centre is where both elements,
        offset by ρ toward the inside of the turn, meet (nearest the corner); it touches each
        element at the foot of the centre (a line) or on the line through both centres (an
        arc). Returns b's new start."""
        a_cmd, a0, a1, a_centre, a_src = a
        b_cmd, b0, b1, b_centre, _ = b
        ia, ib = self.m.cutcom.plane
        ea = _element(self.m, a_cmd, a0, a1, a_centre, ia, ib)
        eb = _element(self.m, b_cmd, b0, b1, b_centre, ia, ib)
        ta, tb = ea.tangent(True), eb.tangent(False)
        turn = math.atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1])
        if abs(turn) < TANGENT:
            self._into(slot, send, a_cmd, a0, a1, a_centre, a_src)
            return b0
        side = 1.0 if turn > 0 else -1.0
        corner = ea.p1
        found = sorted(intersections(_offset_path(ea, side, rho), _offset_path(eb, side, rho)),
                       key=lambda x: math.hypot(x[0] - corner[0], x[1] - corner[1]))
        touch = [(c, _foot(ea, c), _foot(eb, c)) for c in found]
        touch = [t for t in touch if _on(ea, t[1], before=True) and _on(eb, t[2], before=False)]
        if not touch:
            raise ProgramError("corner_insert", f"RND={rho:g} does not fit between these elements",
                               a_src, radius=rho)
        c, qa, qb = touch[0]
        q0, q1 = _moved(a1, ia, ib, qa), _moved(a1, ia, ib, qb)
        first = replace(a_cmd, axes=self.m.machine_axes(a_cmd.axes, q0))
        feed = insert_feed or getattr(a_cmd, "feed", None) or self.m.feed
        end = self.m.machine_axes(a_cmd.axes, q1)
        insert = canon.ArcFeed(a_src, axes=end, plane=self.m.plane_axes, center=self.m.machine_plane(c, a1),
                               clockwise=self.m.machine_cw(turn < 0), turns=0, feed=feed)
        self._into(slot, send, first, a0, q0, a_centre, a_src)
        self._into(slot, send, insert, q0, q1, c, a_src)
        return tuple(q1)

    def _into(self, slot: Slot, send, cmd, start3, end3, centre, src) -> None:
        """Send a move with the command stream's sink pointed at the held block's place."""
        sink = self.m.sink
        self.m.sink = slot.commands
        try:
            send(cmd, tuple(start3), tuple(end3), centre, src)
        finally:
            self.m.sink = sink



def _element(machine, cmd, start3, end3, centre, ia: int, ib: int) -> Element:
    """A plane element (cutcom's) for corner geometry."""
    return Element((start3[ia], start3[ib]), (end3[ia], end3[ib]), tuple(end3), cmd, cmd.source, Slot(),
                   centre, machine.machine_cw(cw_of(cmd)), int(getattr(cmd, "turns", 0)))


def _offset_path(e: Element, side: float, rho: float):
    """e moved by ρ to its left (side +1) or right (−1): a line or a concentric circle."""
    if e.centre is None:
        t = e.tangent(False)
        return ("line", (e.p0[0] - side * rho * t[1], e.p0[1] + side * rho * t[0]), t)
    sigma = -1.0 if e.cw else 1.0
    return ("circle", e.centre, e.radius - side * sigma * rho)


def _foot(e: Element, c) -> tuple[float, float]:
    """The point of e's line or circle nearest c (where a circle about c touches it)."""
    if e.centre is None:
        t = e.tangent(False)
        s = (c[0] - e.p0[0]) * t[0] + (c[1] - e.p0[1]) * t[1]
        return (e.p0[0] + s * t[0], e.p0[1] + s * t[1])
    d = (c[0] - e.centre[0], c[1] - e.centre[1])
    n = math.hypot(*d)
    return (e.centre[0] + e.radius * d[0] / n, e.centre[1] + e.radius * d[1] / n) if n > 0 else e.p0


def _on(e: Element, q, before: bool) -> bool:
    """Whether q (on e's line or circle) lies on e: between its start and the corner (its end)
    when ``before``, else between the corner (its start) and its end."""
    if e.centre is None:
        d = (e.p1[0] - e.p0[0], e.p1[1] - e.p0[1])
        length = math.hypot(*d)
        s = ((q[0] - e.p0[0]) * d[0] + (q[1] - e.p0[1]) * d[1]) / length
        return -1e-9 <= s <= length + 1e-9
    full = sweep(e)
    ang = angle_along(e.centre, e.p0, q, e.cw)
    return ang <= full + 1e-9 or (not before and ang < 1e-9)


def _direction(p, q) -> tuple[tuple[float, float], float]:
    dx, dy = q[0] - p[0], q[1] - p[1]
    n = math.hypot(dx, dy)
    return (dx / n, dy / n) if n > 0 else (0.0, 0.0), n


def _moved(base3, ia: int, ib: int, q) -> list[float]:
    out = list(base3)
    out[ia], out[ib] = q[0], q[1]
    return out
