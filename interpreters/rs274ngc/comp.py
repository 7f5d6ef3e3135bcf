# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""Cutter radius compensation G40 G41 G42 G41.1 G42.1 (interp_convert.cc, interp_queue.cc).

Compensation works in the XY plane (G17) or the XZ plane (G18). All geometry here is written
in *plane coordinates* (p1, p2, p3) as LinuxCNC's cutter comp is: XY plane (x, y, z), XZ plane
(z, x, y). Lengths are in program units, angles in radians.

The tool radius comes from the tool table (the loaded tool, or the tool named by D) or, with
G41.1/G42.1, from D as a diameter; a negative radius switches the side. The first move after
G41/G42 is the *entry* (``comp1``): the tool goes to the point one radius beside the programmed
end, perpendicular to the tangent from the current point. Later moves (``comp2``) keep the tool
one radius left/right of the programmed path: a convex corner gets an arc around the programmed
corner point, a concave corner moves the end of the previous move to where the two offset
paths meet. Because of that last case LinuxCNC holds each compensated move back in a queue
(with the comments, feed, spindle and coolant calls issued after it) until the next move
decides its end point; this module keeps that queue (``Output.queue``) and flushes it at the
same moments, so the trace shows the calls in rs274's order. G40 flushes the queue; the next
move leaves from the programmed point and must be straight.

LinuxCNC mixes x87 ``long double`` constants (``M_PIl``) into some angles; those operations
are reproduced exactly (:mod:`interpreters.rs274ngc.longdouble`), the rest is double precision.
"""

from __future__ import annotations

import math
from fractions import Fraction

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.longdouble import PI_2L, PI_L, plus_pi_halves, round_ld, sin_ld
from interpreters.rs274ngc.motion import (
    CENTER_ARC_RADIUS_TOLERANCE_INCH,
    CENTER_ARC_RADIUS_TOLERANCE_MM,
    RADIUS_TOLERANCE_INCH,
    RADIUS_TOLERANCE_MM,
    arc_data_ijk,
    arc_data_r,
    find_turn,
)
from interpreters.rs274ngc.state import MM_PER_INCH

LEFT = 1
RIGHT = 2
#: radians: a corner turning by less than this counts as straight on
TOLERANCE_CONCAVE_CORNER = 0.05
TOLERANCE_EQUAL = 0.0001
_SMALL = Fraction(TOLERANCE_CONCAVE_CORNER)
_HALF_PI = float(PI_2L)  # M_PI_2l stored in a double


class LdConstant:
    """A long double constant compared exactly with doubles (as C compares a double with a
    long double); the doubles next to it decide most comparisons without rationals."""

    __slots__ = ("value", "lo", "hi")

    def __init__(self, value: Fraction):
        self.value = value
        near = float(value)
        self.lo = math.nextafter(near, -math.inf)
        self.hi = math.nextafter(near, math.inf)

    def less_than(self, x: float) -> bool:
        """``constant < x`` (False for NaN)."""
        if x > self.hi:
            return True
        if x < self.lo or x != x:
            return False
        return Fraction(x) > self.value

    def greater_than(self, x: float) -> bool:
        """``constant > x`` (False for NaN)."""
        if x < self.lo:
            return True
        if x > self.hi or x != x:
            return False
        return Fraction(x) < self.value


_PI_PLUS_SMALL = LdConstant(round_ld(PI_L + _SMALL))
_PI_MINUS_SMALL = LdConstant(round_ld(PI_L - _SMALL))
_THREE_HALF_PI = LdConstant(round_ld(PI_L * 3 / 2))
_MINUS_HALF_PI = LdConstant(-PI_2L)


def _near_pi(beta: float) -> bool:
    """``fabs(beta - M_PIl) < TOLERANCE_CONCAVE_CORNER`` in long double."""
    if not math.isfinite(beta):
        return False
    gap = abs(beta - math.pi)
    if gap < TOLERANCE_CONCAVE_CORNER - 1e-9:
        return True
    if gap > TOLERANCE_CONCAVE_CORNER + 1e-9:
        return False
    return abs(round_ld(Fraction(beta) - PI_L)) < _SMALL

# plane -> indices of (p1, p2, p3) in x y z
_PLANE_INDEX = {170: (0, 1, 2), 180: (2, 0, 1)}


# -- long double steps ---------------------------------------------------------------------


def ld_plus(x: float, pi_halves: int) -> float:
    """``x + pi_halves * M_PI_2l`` in long double, stored to double (an infinity or NaN,
    which huge coordinates can produce, stays what it is)."""
    if not math.isfinite(x):
        return x
    return plus_pi_halves(x, pi_halves)


def _sinl_times(r: float, beta: float) -> float:
    """``r * sin(beta - M_PI_2l)`` with x87 ``sinl``, stored to double."""
    if not (math.isfinite(r) and math.isfinite(beta)):
        return r * -math.cos(beta)
    return float(round_ld(Fraction(r) * sin_ld(round_ld(Fraction(beta) - PI_2L))))


def _c_int(x: float) -> int:
    """C's ``(int)`` of a double on x86: truncated; out of range, INT_MIN."""
    if -2147483648.0 <= x < 2147483648.0:
        return int(x)
    return -2147483648


def _inside(side: int, turn: int) -> bool:
    """TOOL_INSIDE_ARC: the tool runs on the inside of an arc turning ``turn``."""
    return (side == LEFT and turn > 0) or (side == RIGHT and turn < 0)


class QMove:
    """A move held in the queue, in plane coordinates (LinuxCNC ``queued_canon``).

    kind : "feed", "traverse" or "arc". d1 d2 : direction of the programmed straight move
    (for the concave corner check). e1 e2 e3 : end point. c1 c2, turn, sweep : arc centre,
    turns (as ARC_FEED's rotation) and the programmed sweep in radians (0: never checked).
    """

    __slots__ = ("kind", "plane", "d1", "d2", "e1", "e2", "e3", "c1", "c2", "turn", "sweep",
                 "abc", "feed", "src")

    def __init__(self, kind, plane, e1, e2, e3, abc, feed, src, d1=0.0, d2=0.0,
                 c1=0.0, c2=0.0, turn=0, sweep=0.0):
        self.kind = kind
        self.plane = plane
        self.d1, self.d2 = d1, d2
        self.e1, self.e2, self.e3 = e1, e2, e3
        self.c1, self.c2 = c1, c2
        self.turn = turn
        self.sweep = sweep
        self.abc = abc
        self.feed = feed
        self.src = src


class CompMixin:
    """Cutter radius compensation: G40/G41/G42, the compensated moves and the queue."""

    # -- state in plane coordinates ----------------------------------------------------------

    def comp_current(self) -> tuple[float, float, float]:
        i, j, k = _PLANE_INDEX[self.s.plane]
        pos = self.s.pos
        return pos[i], pos[j], pos[k]

    def comp_set_current(self, p1: float, p2: float, p3: float) -> None:
        i, j, k = _PLANE_INDEX[self.s.plane]
        pos = self.s.pos
        pos[i], pos[j], pos[k] = p1, p2, p3

    def comp_programmed(self) -> tuple[float, float, float]:
        i, j, k = _PLANE_INDEX[self.s.plane]
        prog = self.s.comp_program
        return prog[i], prog[j], prog[k]

    def comp_set_programmed(self, p1: float, p2: float, p3: float) -> None:
        i, j, k = _PLANE_INDEX[self.s.plane]
        prog = self.s.comp_program
        prog[i], prog[j], prog[k] = p1, p2, p3

    # -- G40 G41 G42 ---------------------------------------------------------------------------

    def convert_cutter_compensation(self, code: int, block: blk.Block) -> None:
        if code == 400:
            self.comp_off()
        else:
            self.comp_on(LEFT if code in (410, 411) else RIGHT, code, block)

    def comp_off(self) -> None:
        """G40: flush the queue with the last move ending where it is; the next move starts
        at the programmed point and may not be an arc."""
        s = self.s
        self.out.comment("interpreter: cutter radius compensation off")
        if s.comp_side and s.comp_radius > 0.0 and not s.comp_first:
            cx, cy, _ = self.comp_current()
            self.move_endpoint_and_flush(cx, cy)
            self.dequeue()
            s.pos[0:3] = s.comp_program
            s.arc_not_allowed = True
        s.comp_side = 0
        s.comp_first = True

    def comp_on(self, side: int, code: int, block: blk.Block) -> None:
        """G41/G42 (radius from the tool table) and G41.1/G42.1 (D is the diameter)."""
        s = self.s
        w = block.words
        if s.plane not in (170, 180):
            raise NgcError("comp_plane_xy_xz")
        if s.comp_side:
            raise NgcError("comp_already_on")
        name = code // 10
        if code in (411, 421):
            if "d" not in w:
                raise NgcError("comp_no_d", code=name)
            radius = w["d"] / 2
            if "l" in w:
                if s.plane != 180:
                    raise NgcError("comp_l_not_g18", code=name)
                orientation = int(w["l"])
            else:
                orientation = 0
        else:
            index = 0
            if "d" in w:
                tool = _c_int(w["d"] + 0.5)
                if abs(tool - w["d"]) >= 0.0001:
                    raise NgcError("comp_d_integer", code=name)
                index = self.tool_index(tool)
            entry = self.tools.entry(index)
            radius = s.u2p(entry.diameter) / 2.0
            lookup = self.options.tool_radius      # vmach's tool library (verify, run --tools)
            if lookup is not None:
                mm = lookup(str(entry.number), 1)
                if mm is None:
                    raise NgcError("comp_no_library_radius", code=name, tool=entry.number)
                radius = mm if s.metric else mm / MM_PER_INCH
            orientation = entry.orientation
            if s.plane != 180 and orientation not in (0, 9):
                raise NgcError("comp_lathe_tool", code=name)
        if radius < 0.0:
            radius = -radius
            side = LEFT if side == RIGHT else RIGHT
        self.out.comment("interpreter: cutter radius compensation on right" if side == RIGHT
                         else "interpreter: cutter radius compensation on left")
        s.comp_radius = radius
        s.comp_orientation = orientation
        s.comp_side = side

    # -- the queue (interp_queue.cc) -----------------------------------------------------------

    def set_endpoint(self, x: float, y: float) -> None:
        self.comp_endpoint = (x, y)
        self.comp_endpoint_valid = True

    def queue_front(self) -> QMove | None:
        """``qc().front()``: the first queued move. LinuxCNC reads it unguarded in concave
        corners; after a flush (M0, M1) the cleared vector still holds the first move it
        had, and LinuxCNC uses that: so does this."""
        queue = self.out.queue
        return queue[0] if queue else self.comp_stale_front

    def enqueue(self, move: QMove) -> None:
        self.out.queue.append(move)

    def dequeue(self) -> None:
        """dequeue_canons: emit everything queued, in order."""
        self.comp_endpoint_valid = False
        out = self.out
        items = out.queue
        if not items:
            return
        out.queue = []
        self.comp_stale_front = items[0]
        src = out.src
        for item in items:
            out.src = item.src
            if type(item) is QMove:
                self._emit(item)
            else:
                item.emit(out)
        out.src = src

    def _lathe(self, p1: float, p2: float) -> tuple[float, float]:
        """latheorigin_z/latheorigin_x: a lathe tool's controlled point is not the centre
        of its nose radius (XZ plane only); returns the shifted (z, x)."""
        s = self.s
        if s.plane != 180:
            return p1, p2
        o = s.comp_orientation
        r = s.comp_radius
        if o in (2, 7, 3):
            p1 -= r
        if o in (1, 5, 4):
            p1 += r
        if o in (2, 6, 1):
            p2 -= r
        if o in (3, 8, 4):
            p2 += r
        return p1, p2

    def _emit(self, q: QMove) -> None:
        out = self.out
        if q.kind == "arc":
            e1, e2 = self._lathe(q.e1, q.e2)
            c1, c2 = self._lathe(q.c1, q.c2)
            out.arc_feed(q.plane, e1, e2, c1, c2, q.turn, q.e3, q.abc, q.feed)
            return
        e1, e2 = self._lathe(q.e1, q.e2)
        if q.plane == 170:
            p = [e1, e2, q.e3, *q.abc]
        else:
            p = [e2, q.e3, e1, *q.abc]
        if q.kind == "feed":
            out.straight_feed(p, q.feed)
        else:
            out.straight_traverse(p)

    def move_endpoint_and_flush(self, x: float, y: float) -> None:
        """Move the end of every queued move to (x, y), checking that no move turns back
        (the tool cannot reach the corner), then flush the queue."""
        queue = self.out.queue
        if not queue:
            return
        ex, ey = self.comp_endpoint
        valid = self.comp_endpoint_valid
        for q in queue:
            if type(q) is not QMove:
                continue
            if q.kind == "arc":
                r1 = math.hypot(q.e1 - q.c1, q.e2 - q.c2)
                r2 = math.hypot(x - q.c1, y - q.c2)
                sweep = find_turn(ex, ey, q.c1, q.c2, q.turn, x, y)
                if abs(r1 - r2) > 0.01:
                    raise NgcError("comp_bug_arc_radii", r1="%f" % r1, r2="%f" % r2)
                slack = 0.0254 if self.s.metric else 0.001  # LinuxCNC's, radians all the same
                if q.sweep and valid and abs(sweep) > abs(q.sweep) + slack:
                    raise NgcError("comp_arc_concave")
            else:
                dot = q.d1 * (x - ex) + q.d2 * (y - ey)
                if valid and dot < 0:
                    raise NgcError("comp_traverse_concave" if q.kind == "traverse"
                                   else "comp_feed_concave")
            q.e1, q.e2 = x, y
        self.dequeue()
        self.set_endpoint(x, y)

    def comp_scale(self, factor: float) -> None:
        """qc_scale: G20/G21 with moves queued converts them (and, as LinuxCNC does, the
        saved end point once per queued call)."""
        queue = self.out.queue
        for q in queue:
            ex, ey = self.comp_endpoint
            self.comp_endpoint = (ex * factor, ey * factor)
            if type(q) is QMove:
                q.e1 *= factor
                q.e2 *= factor
                q.e3 *= factor
                if q.kind == "arc":
                    q.c1 *= factor
                    q.c2 *= factor

    def _qmove(self, kind: str, block: blk.Block, e1, e2, e3, abc, **more) -> QMove:
        feed = self.feed_for_output(block) if kind != "traverse" else 0.0
        return QMove(kind, self.s.plane, e1, e2, e3, tuple(abc), feed, self.out.src, **more)

    # -- straight moves -------------------------------------------------------------------------

    def straight_comp1(self, move: int, block: blk.Block, px: float, py: float, pz: float,
                       abc) -> None:
        """The entry move: to one radius beside (px, py), square to the tangent from the
        current point (plane coordinates, program units)."""
        s = self.s
        radius = s.comp_radius
        cx, cy, _ = self.comp_current()
        if math.hypot(px - cx, py - cy) <= radius:
            raise NgcError("comp_entry_short")
        direction = math.atan2(py - cy, px - cx)
        alpha = ld_plus(direction, 1 if s.comp_side == LEFT else -1)
        end_x = px + radius * math.cos(alpha)
        end_y = py + radius * math.sin(alpha)
        self.set_endpoint(cx, cy)
        kind = "traverse" if move == 0 else "feed"
        self.enqueue(self._qmove(kind, block, end_x, end_y, pz, abc,
                                 d1=math.cos(alpha), d2=math.sin(alpha)))
        s.comp_first = False
        self.comp_set_current(end_x, end_y, pz)
        s.pos[3:6] = abc
        self.comp_set_programmed(px, py, pz)

    def straight_comp2(self, move: int, block: blk.Block, px: float, py: float, pz: float,
                       abc) -> None:
        """A compensated straight move after the entry (plane coordinates)."""
        s = self.s
        kind = "traverse" if move == 0 else "feed"
        cx, cy, _ = self.comp_current()
        opx, opy, _ = self.comp_programmed()
        end_x, end_y = cx, cy
        if py == opy and px == opx:  # no motion in the plane: the tool stays where it is
            self.enqueue(self._qmove(kind, block, cx, cy, pz, abc, d1=px - opx, d2=py - opy))
        else:
            end_x, end_y = self._straight_corner(move, block, px, py, abc)
            self.enqueue(self._qmove(kind, block, end_x, end_y, pz, abc, d1=px - opx,
                                     d2=py - opy))
        self.comp_set_current(end_x, end_y, pz)
        s.pos[3:6] = abc
        self.comp_set_programmed(px, py, pz)

    def _straight_corner(self, move: int, block: blk.Block, px: float, py: float,
                         abc) -> tuple[float, float]:
        """The corner before a compensated straight move to (px, py): an arc (or, for G0, a
        traverse) around a convex corner, the previous move cut short in a concave one.
        Returns the tool's end point of the straight move."""
        s = self.s
        side = s.comp_side
        radius = s.comp_radius
        cx, cy, cz = self.comp_current()
        opx, opy, _ = self.comp_programmed()
        theta = math.atan2(cy - opy, cx - opx)  # from the programmed point to the tool
        alpha = math.atan2(py - opy, px - opx)  # the new direction
        if side == LEFT:
            if theta < alpha:
                theta = ld_plus(theta, 4)
            beta = ld_plus(theta - alpha, -1)
            gamma = _HALF_PI
        else:
            if alpha < theta:
                alpha = ld_plus(alpha, 4)
            beta = ld_plus(alpha - theta, -1)
            gamma = -_HALF_PI
        end = (px + radius * math.cos(alpha + gamma), py + radius * math.sin(alpha + gamma))
        mid_x = opx + radius * math.cos(alpha + gamma)
        mid_y = opy + radius * math.sin(alpha + gamma)
        concave = self._straight_concave(beta)
        if not concave and beta > TOLERANCE_CONCAVE_CORNER:  # convex: an arc around
            self.move_endpoint_and_flush(cx, cy)
            if move == 10:
                self.enqueue(self._qmove("arc", block, mid_x, mid_y, cz, abc, c1=opx, c2=opy,
                                         turn=-1 if side == LEFT else 1))
            else:  # no arc traverse: a traverse to the arc's end
                self.enqueue(self._qmove("traverse", block, mid_x, mid_y, cz, abc))
            self.dequeue()
            self.set_endpoint(mid_x, mid_y)
        elif concave:
            front = self.queue_front()
            if front is None or front.kind != "arc":
                self._line_line_corner(beta, theta, gamma, cx, cy)
            else:
                self._arc_line_corner(front, px, py, opx, opy)
        else:  # straight on, or a tangent arc to line
            self.dequeue()
            self.set_endpoint(cx, cy)
        return end

    def _straight_concave(self, beta: float) -> bool:
        """Is the corner before a straight move concave? ``beta`` is its turn, radians (less
        than 0 or more than pi: concave); near pi after an arc the tool stays outside ("h"
        shape: above and beside rather than looping around)."""
        side = self.s.comp_side
        if beta < -TOLERANCE_CONCAVE_CORNER or _PI_PLUS_SMALL.less_than(beta):
            return True
        queue = self.out.queue
        front = queue[0] if queue else None
        return (_PI_MINUS_SMALL.less_than(beta) and type(front) is QMove and front.kind == "arc"
                and ((side == RIGHT and front.turn > 0) or (side == LEFT and front.turn < 0)))

    def _line_line_corner(self, beta: float, theta: float, gamma: float, cx: float,
                          cy: float) -> None:
        """Concave corner between two lines: the previous move ends where the two offset
        lines cross."""
        half = ld_plus(beta, 2) if not math.isfinite(beta) else float(
            round_ld(Fraction(beta) + PI_L) / 2)
        if half == 0.0:
            raise NgcError("comp_zero_corner")
        retreat = self.s.comp_radius / math.tan(half)
        self.move_endpoint_and_flush(cx + retreat * math.cos(theta + gamma),
                                     cy + retreat * math.sin(theta + gamma))

    def _arc_line_corner(self, prev: QMove, px, py, opx, opy) -> None:
        """Concave corner from an arc (queued, compensated) to a line: the arc ends where
        it meets the offset line."""
        s = self.s
        side = s.comp_side
        radius = s.comp_radius
        oldrad = math.hypot(prev.c2 - prev.e2, prev.c1 - prev.e1)
        base_dir = math.atan2(py - opy, px - opx)
        theta = ld_plus(base_dir, 1 if prev.turn > 0 else -1)
        phi = math.atan2(prev.c2 - opy, prev.c1 - opx)
        inside = _inside(side, prev.turn)
        oldrad_uncomp = oldrad + radius if inside else oldrad - radius
        d = oldrad_uncomp * math.cos(theta - phi)
        d2 = d - radius if inside else d + radius
        ratio = d2 / oldrad
        if ratio > 1.0 or ratio < -1.0:
            raise NgcError("comp_arc_line_gouge")
        if inside == (prev.turn > 0):
            angle = -math.acos(ratio) + theta
        else:
            angle = math.acos(ratio) + theta
        angle = ld_plus(angle, 2)
        self.move_endpoint_and_flush(prev.c1 + oldrad * math.cos(angle),
                                     prev.c2 + oldrad * math.sin(angle))

    # -- arcs ---------------------------------------------------------------------------------

    def _tolerances(self) -> tuple[float, float]:
        if self.s.metric:
            return RADIUS_TOLERANCE_MM, CENTER_ARC_RADIUS_TOLERANCE_MM
        return RADIUS_TOLERANCE_INCH, CENTER_ARC_RADIUS_TOLERANCE_INCH

    def _comp_arc_data(self, move, block, x1, y1, x2, y2, off1, off2, turns):
        """arc_data_comp_r / arc_data_comp_ijk: the arc's centre and turn, refusing an arc
        the tool cannot fit inside."""
        s = self.s
        w = block.words
        rtol, spiral = self._tolerances()
        inside = (s.comp_side == LEFT and move == 30) or (s.comp_side == RIGHT and move == 20)
        if "r" in w:
            if abs(w["r"]) <= s.comp_radius and inside:
                raise NgcError("comp_tool_radius_arc")
            return arc_data_r(move, x1, y1, x2, y2, w["r"], turns, rtol)
        cx, cy, turn = arc_data_ijk(move, s.plane, x1, y1, x2, y2, s.ijk_absolute, off1, off2,
                                    turns, rtol, spiral)
        if math.hypot(cx - x1, cy - y1) <= s.comp_radius and inside:
            raise NgcError("comp_tool_radius_arc")
        return cx, cy, turn

    def arc_comp1(self, move, block, end_x, end_y, end_z, off1, off2, turns, abc) -> None:
        """An arc as the entry move: the tool ends one radius off the programmed end, on an
        arc through its current point about a shifted centre."""
        s = self.s
        side = s.comp_side
        radius = s.comp_radius
        _, spiral = self._tolerances()
        cx, cy, cz = self.comp_current()
        if math.hypot(end_x - cx, end_y - cy) <= radius:
            raise NgcError("comp_entry_arc_short")
        center_x, center_y, turn = self._comp_arc_data(move, block, cx, cy, end_x, end_y,
                                                       off1, off2, turns)
        self.inverse_time_arc(cx, cy, cz, center_x, center_y, turn, end_x, end_y, end_z, block)
        if _inside(side, turn):
            gamma = math.atan2(center_y - end_y, center_x - end_x)
        else:
            gamma = math.atan2(end_y - center_y, end_x - center_x)
        s.comp_first = False
        self.comp_set_programmed(end_x, end_y, end_z)
        end_x += radius * math.cos(gamma)
        end_y += radius * math.sin(gamma)
        b_len = math.hypot(cy - end_y, cx - end_x) / 2.0
        ab_ang = math.atan2(center_y - end_y, center_x - end_x)
        a_ang = math.atan2(cy - end_y, cx - end_x) - ab_ang
        if abs(math.cos(a_ang)) < TOLERANCE_EQUAL:
            raise NgcError("comp_tool_radius_arc")
        c_len = b_len / math.cos(a_ang)
        center_x = end_x + c_len * math.cos(ab_ang)
        center_y = end_y + c_len * math.sin(ab_ang)
        if abs(math.hypot(center_x - end_x, center_y - end_y)
               - math.hypot(center_x - cx, center_y - cy)) > spiral:
            raise NgcError("comp_bug")
        if s.comp_orientation not in (0, 9):  # a lathe tool moves its origin first
            self.enqueue(self._qmove("feed", block, cx, cy, cz, abc))
            self.set_endpoint(cx, cy)
        self.enqueue(self._qmove("arc", block, end_x, end_y, end_z, abc, c1=center_x,
                                 c2=center_y, turn=turn,
                                 sweep=find_turn(cx, cy, center_x, center_y, turn, end_x, end_y)))
        self.comp_set_current(end_x, end_y, end_z)
        s.pos[3:6] = abc

    def arc_comp2(self, move, block, end_x, end_y, end_z, off1, off2, turns, abc) -> None:
        """A compensated arc after the entry: the arc about the same centre, one radius in
        or out, with a corner arc before it (convex) or the previous move cut short
        (concave). Plane coordinates, program units."""
        s = self.s
        radius = s.comp_radius
        rtol, spiral = self._tolerances()
        opx, opy, opz = self.comp_programmed()
        w = block.words
        if "r" in w:
            centerx, centery, turn = arc_data_r(move, opx, opy, end_x, end_y, w["r"], turns,
                                                rtol)
        else:
            centerx, centery, turn = arc_data_ijk(move, s.plane, opx, opy, end_x, end_y,
                                                  s.ijk_absolute, off1, off2, turns, rtol,
                                                  spiral)
        self.inverse_time_arc(opx, opy, opz, centerx, centery, turn, end_x, end_y, end_z,
                              block)
        arc_radius = math.hypot(centerx - end_x, centery - end_y)
        if (s.comp_side == LEFT and move == 30) or (s.comp_side == RIGHT and move == 20):
            gamma = math.atan2(centery - end_y, centerx - end_x)  # the tool inside
            if arc_radius <= radius:
                raise NgcError("comp_tool_radius_arc")
        else:
            gamma = math.atan2(end_y - centery, end_x - centerx)
        new_end_x = end_x + radius * math.cos(gamma)
        new_end_y = end_y + radius * math.sin(gamma)
        self._arc_corner(move, block, centerx, centery, arc_radius, turn, abc)
        self.enqueue(self._qmove("arc", block, new_end_x, new_end_y, end_z, abc, c1=centerx,
                                 c2=centery, turn=turn,
                                 sweep=find_turn(opx, opy, centerx, centery, turn, end_x, end_y)))
        self.comp_set_programmed(end_x, end_y, end_z)
        self.comp_set_current(new_end_x, new_end_y, end_z)
        s.pos[3:6] = abc

    def _arc_corner(self, move, block, centerx, centery, arc_radius, turn, abc) -> None:
        """The corner before a compensated arc about (centerx, centery): concave (the
        previous move cut short), convex (an arc around the programmed corner) or tangent."""
        s = self.s
        side = s.comp_side
        radius = s.comp_radius
        opx, opy, _ = self.comp_programmed()
        cx, cy, cz = self.comp_current()
        theta = ld_plus(math.atan2(cy - opy, cx - opx), -1 if side == LEFT else 1)
        delta = math.atan2(centery - opy, centerx - opx)
        alpha = ld_plus(delta, -1 if move == 30 else 1)  # the arc's direction at its start
        beta = theta - alpha if side == LEFT else alpha - theta
        if _THREE_HALF_PI.less_than(beta):
            beta = ld_plus(beta, -4)
        elif _MINUS_HALF_PI.greater_than(beta):
            beta = ld_plus(beta, 4)
        if not ((side == LEFT and move == 30) or (side == RIGHT and move == 20)):
            delta = ld_plus(delta, 2)
        if (beta < -TOLERANCE_CONCAVE_CORNER or _PI_PLUS_SMALL.less_than(beta)
                or (_near_pi(beta) and not _inside(side, turn))):
            front = self.queue_front()
            if front is not None and front.kind == "arc":
                self._arc_arc_corner(front, centerx, centery, arc_radius, turn)
            else:
                self._line_arc_corner(centerx, centery, arc_radius, turn, beta, theta)
        elif beta > TOLERANCE_CONCAVE_CORNER:  # convex: two arcs
            midx = opx + radius * math.cos(delta)
            midy = opy + radius * math.sin(delta)
            self.dequeue()
            self.enqueue(self._qmove("arc", block, midx, midy, cz, abc, c1=opx, c2=opy,
                                     turn=-1 if side == LEFT else 1))
            self.dequeue()
            self.set_endpoint(midx, midy)
        else:  # tangent
            self.dequeue()
            self.set_endpoint(cx, cy)

    def _line_arc_corner(self, centerx, centery, arc_radius, turn, beta, theta) -> None:
        """Concave corner from a line to an arc: the line ends where it meets the offset
        arc."""
        s = self.s
        radius = s.comp_radius
        offset = _sinl_times(arc_radius, beta)
        if _inside(s.comp_side, turn):
            dist = arc_radius - radius
            ratio = (offset + radius) / dist
            if ratio > 1.0 or ratio < -1.0:
                raise NgcError("comp_arc_concave")
            angle = theta + math.asin(ratio) if turn > 0 else theta - math.asin(ratio)
        else:
            dist = arc_radius + radius
            ratio = (offset - radius) / dist
            if ratio > 1.0 or ratio < -1.0:
                raise NgcError("comp_arc_concave")
            turned = -math.asin(ratio) if turn > 0 else math.asin(ratio)
            if math.isfinite(theta) and math.isfinite(turned):
                angle = float(round_ld(round_ld(Fraction(theta) + PI_L) + Fraction(turned)))
            else:
                angle = theta + math.pi + turned
        self.move_endpoint_and_flush(centerx + dist * math.cos(angle),
                                     centery + dist * math.sin(angle))

    def _arc_arc_corner(self, prev: QMove, centerx, centery, arc_radius, turn) -> None:
        """Concave corner between two arcs: the previous arc ends where the offset arcs
        cross."""
        s = self.s
        radius = s.comp_radius
        oldrad = math.hypot(prev.c2 - prev.e2, prev.c1 - prev.e1)
        newrad = arc_radius - radius if _inside(s.comp_side, turn) else arc_radius + radius
        arc_cc = math.hypot(prev.c2 - centery, prev.c1 - centerx)
        if oldrad == 0 or arc_cc == 0:
            raise NgcError("comp_arc_same_center")
        a = (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (2 * oldrad * arc_cc)
        if a > 1.0 or a < -1.0:
            raise NgcError("comp_arc_arc_gouge")
        pullback = math.acos(a)
        cc_dir = math.atan2(centery - prev.c2, centerx - prev.c1)
        if _inside(s.comp_side, prev.turn) == (turn > 0):
            direction = cc_dir + pullback
        else:
            direction = cc_dir - pullback
        self.move_endpoint_and_flush(prev.c1 + oldrad * math.cos(direction),
                                     prev.c2 + oldrad * math.sin(direction))
