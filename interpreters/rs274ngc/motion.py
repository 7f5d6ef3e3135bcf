# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""Motion: end points, straight moves, arcs (interp_convert.cc, interp_arc.cc, interp_find.cc).

Arcs are given by centre offsets (I J K, incremental unless G90.1) or by radius (R; negative
for more than half a turn); P is the number of turns. LinuxCNC's tolerances decide whether
the start and end radius agree (``Radius to end of arc differs from radius to start``) and
whether an R arc can reach its end point.
"""

from __future__ import annotations

import math

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.longdouble import minus_half_pi, plus_half_pi
from interpreters.rs274ngc.state import rotate

RADIUS_TOLERANCE_INCH = 0.00005
RADIUS_TOLERANCE_MM = RADIUS_TOLERANCE_INCH * 25.4
CENTER_ARC_RADIUS_TOLERANCE_INCH = 2 * 0.001 * math.sqrt(2.0)
CENTER_ARC_RADIUS_TOLERANCE_MM = 2 * 0.01 * math.sqrt(2.0)
SPIRAL_RELATIVE_TOLERANCE = 0.001
TINY = 1e-12

_ARC_AXES = {170: ("X", "Y"), 180: ("Z", "X"), 190: ("Y", "Z")}


_D2R = math.pi / 180.0


def polar_step(x: float, y: float, dr: float, dtheta: float,
               angle_kind: str = "polar_angle_at_origin") -> tuple[float, float]:
    """An incremental polar move from (x, y): the radius grows by ``dr``, then the angle by
    ``dtheta`` radians (LinuxCNC's order; either may be 0 = absent)."""
    if dr:
        if x == 0 and y == 0:
            raise NgcError("polar_at_origin")
        theta = math.atan2(y, x)
        radius = math.hypot(y, x) + dr
        x, y = radius * math.cos(theta), radius * math.sin(theta)
    if dtheta:
        if x == 0 and y == 0:
            raise NgcError(angle_kind)
        theta = math.atan2(y, x) + dtheta
        radius = math.hypot(y, x)
        x, y = radius * math.cos(theta), radius * math.sin(theta)
    return x, y


class MotionMixin:
    def find_ends(self, block: blk.Block) -> list[float]:
        """The end point of the block's motion in the current coordinate system."""
        s = self.s
        w = block.words
        pos = s.pos
        if "@" in w or "^" in w:
            return self._polar_ends(block)
        if block.g.get(0) == 530:
            cx, cy = rotate(pos[0] + s.axis_offset[0], pos[1] + s.axis_offset[1], s.rotation)
            px = w["x"] - s.origin[0] - s.tool_offset[0] if "x" in w else cx
            py = w["y"] - s.origin[1] - s.tool_offset[1] if "y" in w else cy
            px, py = rotate(px, py, -s.rotation)
            end = [px - s.axis_offset[0], py - s.axis_offset[1]]
            end.append(w["z"] - s.origin[2] - s.axis_offset[2] - s.tool_offset[2]
                       if "z" in w else pos[2])
            for i, letter in ((3, "a"), (4, "b"), (5, "c")):
                end.append(w[letter] - s.origin[i] - s.axis_offset[i] if letter in w else pos[i])
            return end
        if s.comp_side and not s.comp_first:
            # with cutter compensation, unnamed and incremental axes of the plane start from
            # the programmed point, not from the compensated tool position (X in both
            # planes, Y in XY, Z in XZ)
            pos = list(pos)
            pos[0] = s.comp_program[0]
            if s.plane == 170:
                pos[1] = s.comp_program[1]
            elif s.plane == 180:
                pos[2] = s.comp_program[2]
        if s.incremental:
            return [pos[0] + w.get("x", 0.0), pos[1] + w.get("y", 0.0), pos[2] + w.get("z", 0.0),
                    pos[3] + w.get("a", 0.0), pos[4] + w.get("b", 0.0), pos[5] + w.get("c", 0.0)]
        return [w.get("x", pos[0]), w.get("y", pos[1]), w.get("z", pos[2]),
                w.get("a", pos[3]), w.get("b", pos[4]), w.get("c", pos[5])]

    def _polar_ends(self, block: blk.Block) -> list[float]:
        """find_ends with ``@`` (radius) and ``^`` (angle, degrees) for X and Y, in G17;
        absolute about the origin, incremental (G91) from the current point."""
        s = self.s
        w = block.words
        if block.g.get(0) == 530:
            raise NgcError("polar_g53")
        pos = s.pos
        if s.comp_side and not s.comp_first:
            pos = [*s.comp_program, *pos[3:6]]
        x, y = pos[0], pos[1]
        if not s.incremental:
            if "@" in w and "^" in w:
                x, y = w["@"] * math.cos(w["^"] * _D2R), w["@"] * math.sin(w["^"] * _D2R)
            elif "@" in w:
                if x == 0 and y == 0:
                    raise NgcError("polar_angle_needed")
                theta = math.atan2(y, x)
                x, y = w["@"] * math.cos(theta), w["@"] * math.sin(theta)
            else:
                radius = math.hypot(y, x)
                x, y = radius * math.cos(w["^"] * _D2R), radius * math.sin(w["^"] * _D2R)
            rest = [w.get("z", pos[2]), w.get("a", pos[3]), w.get("b", pos[4]), w.get("c", pos[5])]
        else:
            x, y = polar_step(x, y, w.get("@", 0.0), w.get("^", 0.0) * _D2R)
            rest = [pos[2] + w.get("z", 0.0), pos[3] + w.get("a", 0.0), pos[4] + w.get("b", 0.0),
                    pos[5] + w.get("c", 0.0)]
        return [x, y, *rest]

    def convert_motion(self, motion: int, block: blk.Block) -> None:
        if motion not in blk.CYCLES:
            self.s.cycle_il = None
        if motion == 0 or motion == 10:
            self.convert_straight(motion, block)
        elif motion == 20 or motion == 30:
            self.convert_arc(motion, block)
        elif motion in (330, 331, 760):
            self.convert_threading(motion, block)
        elif 382 <= motion <= 385:
            self.convert_probe(motion, block)
        elif motion in (50, 51):
            self.convert_spline(motion, block)
        elif motion == 52:
            self.convert_nurbs(52, block)
        elif 700 <= motion <= 722:
            self.convert_g7x(motion, block)
        elif motion == 800:
            self.out.comment("interpreter: motion mode set to none")
            self.s.motion = 800
        else:
            self.convert_cycle(motion, block)

    def feed_for_output(self, block: blk.Block) -> float:
        """The feed vmach's canonical moves carry: mm/min, mm/rev or 1/min."""
        s = self.s
        if s.feed_mode == 1:
            return block.words.get("f", 0.0)
        return s.feed * (1.0 if s.metric else 25.4)

    def convert_straight(self, move: int, block: blk.Block) -> None:
        s = self.s
        if move == 10:
            if s.feed_mode == 0:
                if s.feed == 0.0:
                    raise NgcError("g1_zero_feed")
            elif s.feed_mode == 2:
                if s.feed == 0.0:
                    raise NgcError("g1_zero_feed")
                if s.speed == 0.0:
                    raise NgcError("zero_spindle_feed_per_rev")
            elif "f" not in block.words:
                raise NgcError("inverse_time_g1_feed")
        s.arc_not_allowed = False
        s.motion = move
        end = self.find_ends(block)
        if move == 10 and s.feed_mode == 1:
            pos = s.pos
            if s.comp_side and not s.comp_first:  # measured along the programmed path
                pos = s.comp_program + pos[3:6]
            if any(abs(pos[i] - end[i]) > 1e-7 for i in range(3)):
                length = math.sqrt(sum((end[i] - pos[i]) ** 2 for i in range(3)))
            else:
                length = math.sqrt(sum((end[i] - pos[i]) ** 2 for i in (3, 4, 5)))
            self._inverse_rate(length, block)
        if s.comp_side and s.comp_radius > 0.0:
            if block.g.get(0) == 530:
                raise NgcError("comp_g53")
            self.straight_compensated(move, block, end)
            return
        if move == 10:
            self.out.straight_feed(end, self.feed_for_output(block))
        else:
            self.out.straight_traverse(end)
        s.pos = end

    def straight_compensated(self, move: int, block: blk.Block, end: list[float]) -> None:
        """G0/G1 with cutter radius compensation: the entry move or a later one."""
        p1, p2, p3 = _plane_coords(self.s.plane, end)
        if self.s.comp_first:
            self.straight_comp1(move, block, p1, p2, p3, end[3:6])
        else:
            self.straight_comp2(move, block, p1, p2, p3, end[3:6])

    def _inverse_rate(self, length: float, block: blk.Block) -> None:
        rate = max(0.1, length * block.words["f"])
        self.out.set_feed_rate(rate)
        self.s.feed = rate

    # -- arcs -------------------------------------------------------------------------------------

    def convert_arc(self, move: int, block: blk.Block) -> None:
        s = self.s
        w = block.words
        if s.arc_not_allowed:
            raise NgcError("comp_arc_after_exit")
        ijk = "i" in w or "j" in w or "k" in w
        if "r" not in w and not ijk:
            raise NgcError("arc_words_missing")
        if "r" in w and ijk:
            raise NgcError("arc_mixed_format")
        if s.feed_mode == 0:
            if s.feed == 0.0:
                raise NgcError("arc_zero_feed")
        elif s.feed_mode == 2:
            if s.feed == 0.0:
                raise NgcError("arc_zero_feed")
            if s.speed == 0.0:
                raise NgcError("zero_spindle_feed_per_rev")
        elif "f" not in w:
            raise NgcError("inverse_time_arc_feed")
        plane = s.plane
        if ijk:
            first, second, other = {170: ("i", "j", "k"), 190: ("j", "k", "i"),
                                    180: ("k", "i", "j")}[plane]
            if other in w:
                raise NgcError({170: "arc_k_in_xy", 190: "arc_i_in_yz", 180: "arc_j_in_xz"}[plane])
            order = ("i", "j") if plane == 170 else (("j", "k") if plane == 190 else ("i", "k"))
            for letter in order:
                if letter not in w:
                    if s.ijk_absolute:
                        raise NgcError("arc_center_word_missing", letter=letter.upper())
                    break
            off1 = w.get(first, 0.0)
            off2 = w.get(second, 0.0)
        else:
            need = {170: ("x", "y", "arc_xy_missing"), 190: ("y", "z", "arc_yz_missing"),
                    180: ("x", "z", "arc_xz_missing")}[plane]
            if need[0] not in w and need[1] not in w and (
                    plane != 170 or ("@" not in w and "^" not in w)):
                raise NgcError(need[2])
            off1 = off2 = 0.0
        end = self.find_ends(block)
        s.motion = move
        pos = s.pos
        if plane == 170:
            c1, c2, c3, e1, e2, e3 = pos[0], pos[1], pos[2], end[0], end[1], end[2]
        elif plane == 180:
            c1, c2, c3, e1, e2, e3 = pos[2], pos[0], pos[1], end[2], end[0], end[1]
        else:
            c1, c2, c3, e1, e2, e3 = pos[1], pos[2], pos[0], end[1], end[2], end[0]
        turns = int(math.floor(w["p"] + 0.5)) if "p" in w else 1
        if s.metric:
            rtol, spiral = RADIUS_TOLERANCE_MM, CENTER_ARC_RADIUS_TOLERANCE_MM
        else:
            rtol, spiral = RADIUS_TOLERANCE_INCH, CENTER_ARC_RADIUS_TOLERANCE_INCH
        if s.comp_side and s.comp_radius > 0.0 and plane != 190:
            if s.comp_first:
                self.arc_comp1(move, block, e1, e2, e3, off1, off2, turns, end[3:6])
            else:
                self.arc_comp2(move, block, e1, e2, e3, off1, off2, turns, end[3:6])
            return
        if "r" in w:
            cx, cy, turn = arc_data_r(move, c1, c2, e1, e2, w["r"], turns, rtol)
        else:
            cx, cy, turn = arc_data_ijk(move, plane, c1, c2, e1, e2, s.ijk_absolute, off1, off2,
                                        turns, rtol, spiral)
        self.inverse_time_arc(c1, c2, c3, cx, cy, turn, e1, e2, e3, block)
        self.out.arc_feed(plane, e1, e2, cx, cy, turn, e3, end[3:6], self.feed_for_output(block))
        s.pos = end

    def inverse_time_arc(self, c1, c2, c3, cx, cy, turn, e1, e2, e3, block: blk.Block) -> None:
        """inverse_time_rate_arc: in G93 the feed rate of an arc from (c1, c2, c3) about
        (cx, cy) to (e1, e2, e3), plane coordinates."""
        if self.s.feed_mode != 1:
            return
        radius = math.hypot(cx - c1, cy - c2)
        theta = find_turn(c1, c2, cx, cy, turn, e1, e2)
        length = radius * abs(theta) if e3 == c3 else math.hypot(radius * theta, e3 - c3)
        self._inverse_rate(length, block)


def _plane_coords(plane: int, p: list[float]) -> tuple[float, float, float]:
    """x y z -> the (first, second, normal) coordinates of the plane."""
    if plane == 180:
        return p[2], p[0], p[1]
    return p[0], p[1], p[2]


def c_divide(a: float, b: float) -> float:
    """``a / b`` as C divides doubles: by zero it gives an infinity or NaN, no exception."""
    if b == 0.0:
        if a == 0.0 or a != a:
            return math.nan
        return math.copysign(math.inf, a) * math.copysign(1.0, b)
    return a / b


def arc_data_r(move, x1, y1, x2, y2, radius, turns, tolerance):
    """Centre of an R-format arc (interp_arc.cc arc_data_r)."""
    if x2 == x1 and y2 == y1:
        raise NgcError("arc_same_end")
    abs_radius = abs(radius)
    mid_x = (x2 + x1) / 2.0
    mid_y = (y2 + y1) / 2.0
    half_length = math.hypot(mid_x - x2, mid_y - y2)
    if half_length - abs_radius > tolerance:
        raise NgcError("arc_radius_too_small")
    if c_divide(half_length, abs_radius) > (1 - TINY):
        half_length = abs_radius
    if (move == 20 and radius > 0) or (move == 30 and radius < 0):
        theta = minus_half_pi(math.atan2(y2 - y1, x2 - x1))
    else:
        theta = plus_half_pi(math.atan2(y2 - y1, x2 - x1))
    turn2 = math.asin(c_divide(half_length, abs_radius))  # R0: NaN, as in LinuxCNC
    offset = abs_radius * math.cos(turn2)
    return (mid_x + offset * math.cos(theta), mid_y + offset * math.sin(theta),
            -turns if move == 20 else turns)


def arc_data_ijk(move, plane, x1, y1, x2, y2, absolute, i, j, turns, rtol, spiral):
    """Centre of an IJK-format arc with LinuxCNC's radius checks (arc_data_ijk)."""
    if absolute:
        cx, cy = i, j
    else:
        cx, cy = x1 + i, y1 + j
    r1 = math.hypot(cx - x1, cy - y1)
    r2 = math.hypot(cx - x2, cy - y2)
    a, b = _ARC_AXES[plane]
    fields = dict(a=a, b=b, sx="%.4f" % x1, sy="%.4f" % y1, cx="%.4f" % cx, cy="%.4f" % cy,
                  ex="%.4f" % x2, ey="%.4f" % y2, r1="%.4f" % r1, r2="%.4f" % r2)
    if r1 < rtol or r2 < rtol:
        raise NgcError("arc_zero_radius", **fields)
    abs_err = abs(r1 - r2)
    rel_err = abs_err / max(r1, r2)
    # 2.9: both must fail, or the absolute error alone exceed 100 times its tolerance
    if abs_err > 100.0 * spiral or (abs_err > spiral and rel_err > SPIRAL_RELATIVE_TOLERANCE):
        raise NgcError("arc_radius_mismatch", abs_err="%.4g" % abs_err,
                       rel_err="%.4f" % (rel_err * 100), **fields)
    return cx, cy, (-turns if move == 20 else turns)


def find_turn(x1, y1, cx, cy, turn, x2, y2) -> float:
    """Signed angle swept by an arc, radians (interp_find.cc find_turn)."""
    if turn == 0:
        return 0.0
    alpha = math.atan2(y1 - cy, x1 - cx)
    beta = math.atan2(y2 - cy, x2 - cx)
    if turn > 0:
        if beta <= alpha:
            beta += 2 * math.pi
        return beta - alpha + (turn - 1) * 2 * math.pi
    if alpha <= beta:
        alpha += 2 * math.pi
    return beta - alpha + (turn + 1) * 2 * math.pi
