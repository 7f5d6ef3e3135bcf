# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""Canned cycles G73 G74 G81 G82 G83 G84 G85 G86 G89 (interp_cycles.cc).

In the selected plane the cycle positions at (aa, bb) and drills along the third axis cc:
XY plane aa=X bb=Y cc=Z, XZ plane aa=Z bb=X cc=Y, YZ plane aa=Y bb=Z cc=X. R is the retract
plane, the cc word the bottom; G98 retracts to the initial level (the height before the first
cycle of a run of cycles), G99 to R. In G91, X/Y (aa, bb) are increments repeated L times, R
is relative to the initial level and the bottom relative to R. Cycles run in exact-path mode
and restore the previous motion control mode afterwards.
"""

from __future__ import annotations

import math

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.motion import polar_step

G83_RAPID_DELTA_INCH = 0.010
_D2R = math.pi / 180.0

# plane -> (aa, bb, cc) indices into x y z, depth letter, plane name in messages
_PLANES = {
    170: ((0, 1, 2), "z", "xy"),
    180: ((2, 0, 1), "y", "xz"),
    190: ((1, 2, 0), "x", "yz"),
}


#: most pecks one G73/G83 may make (a Q of 1e-9 mm made pecks until the memory ran out)
MAX_PECKS = 100_000


class CycleMixin:
    def convert_cycle(self, motion: int, block: blk.Block) -> None:
        s = self.s
        w = block.words
        if s.comp_side:
            raise NgcError("comp_cycle")
        if s.feed == 0.0:
            raise NgcError("cycle_zero_feed")
        if s.feed_mode == 1:
            raise NgcError("cycle_inverse_time")
        if "r" in w:
            r_number = w["r"]
        elif s.motion == motion:
            r_number = s.cycle["r"]
        else:
            raise NgcError("cycle_r_missing")
        repeats = block.l
        if repeats == 0:
            raise NgcError("cycle_zero_repeats")
        if repeats == -1:
            repeats = 1
        self._cycle_in_plane(motion, block, r_number, repeats)
        s.cycle["l"] = repeats
        s.cycle["r"] = r_number
        s.motion = motion

    def _cycle_in_plane(self, motion: int, block: blk.Block, r_number: float, repeats: int):
        s = self.s
        w = block.words
        out = self.out
        (ia, ib, ic), depth_letter, plane_name = _PLANES[s.plane]
        letters = "xyz"
        if s.motion != motion and depth_letter not in w:
            raise NgcError("cycle_depth_missing", axis=depth_letter.upper(), plane=plane_name)
        depth_word = w.get(depth_letter, s.cycle["cc"])
        pos = s.pos
        current_cc = pos[ic]
        if s.cycle_il is not None:
            old_cc = s.cycle_il
        else:
            old_cc = s.cycle_il = current_cc
        inc_r = inc_t = 0.0  # polar increments (G17 only: enhance refuses other planes)
        if not s.incremental:
            inc_a = inc_b = 0.0
            r = r_number
            cc = depth_word
            aa = w.get(letters[ia], pos[ia])
            bb = w.get(letters[ib], pos[ib])
            if "@" in w or "^" in w:
                radius = w["@"] if "@" in w else math.hypot(pos[1], pos[0])
                theta = w["^"] * _D2R if "^" in w else math.atan2(pos[1], pos[0])
                aa, bb = radius * math.cos(theta), radius * math.sin(theta)
        else:
            inc_a = w.get(letters[ia], 0.0)
            inc_b = w.get(letters[ib], 0.0)
            inc_r = w.get("@", 0.0)
            inc_t = w.get("^", 0.0) * _D2R
            r = r_number + old_cc
            cc = r + depth_word
            aa = pos[ia]
            bb = pos[ib]
        if r < cc:
            raise NgcError("cycle_r_below_bottom", axis=depth_letter, plane=plane_name)
        if old_cc < r:
            p = list(pos)
            p[ic] = r
            out.straight_traverse(p)
            old_cc = r
            current_cc = old_cc
        clear = r if s.retract_r else old_cc
        save = (out.mode, out.tolerance, out.naivecam)
        if save[0] != "exact_path":
            out.set_motion_control_mode("exact_path")

        dwell = q = 0.0
        if motion in (740, 840):  # tapping: P is optional (the last one, else 0)
            dwell = s.cycle["p"] if block.p == -1.0 else block.p
        elif motion in (820, 860, 890):
            if s.motion != motion and block.p == -1.0:
                raise NgcError("cycle_dwell_missing", code=motion // 10)
            dwell = s.cycle["p"] if block.p == -1.0 else block.p
        elif motion in (730, 830):
            if s.motion != motion and block.q == -1.0:
                raise NgcError("cycle_q_missing", code=motion // 10)
            q = s.cycle["q"] if block.q == -1.0 else block.q
        feed = self.feed_for_output(block)

        def move(a, b, c, rapid):
            p = list(s.pos)
            p[ia], p[ib], p[ic] = a, b, c
            if rapid:
                out.straight_traverse(p)
            else:
                out.straight_feed(p, feed)
            s.pos = p

        for repeat in range(repeats, 0, -1):
            if repeat < repeats:
                self._count_block()     # L1000000000 filled the memory
            aa += inc_a
            bb += inc_b
            if inc_r or inc_t:
                aa, bb = polar_step(aa, bb, inc_r, inc_t, "polar_at_origin")
            if repeat == repeats and current_cc > r:
                move(aa, bb, current_cc, True)
                move(aa, bb, r, True)
            else:
                move(aa, bb, clear, True)
                if clear > r:
                    move(aa, bb, r, True)
            self._cycle_body(motion, move, aa, bb, r, clear, cc, dwell, q)

        if motion in (740, 820, 840, 860, 890):
            s.cycle["p"] = dwell
        elif motion in (730, 830):
            s.cycle["q"] = q
        pos = s.pos
        pos[ia], pos[ib], pos[ic] = aa, bb, clear
        s.cycle["cc"] = depth_word
        if save[0] != "exact_path":
            out.set_motion_control_mode(save[0], save[1])
            out.set_naivecam_tolerance(save[2])

    def _count_block(self) -> None:
        """A cycle's further repeat or peck counts as a block against ``--max-blocks``."""
        self.blocks += 1
        if self.blocks > self.options.max_blocks:
            raise NgcError("block_limit", limit=self.options.max_blocks)

    def _cycle_body(self, motion, move, aa, bb, r, clear, bottom, dwell, q) -> None:
        out = self.out
        s = self.s
        if motion == 810:
            move(aa, bb, bottom, False)
            move(aa, bb, clear, True)
        elif motion == 820:
            move(aa, bb, bottom, False)
            out.dwell(dwell)
            move(aa, bb, clear, True)
        elif motion in (730, 830):
            if q <= 0.0:
                raise NgcError("cycle_q_not_positive")
            delta = G83_RAPID_DELTA_INCH * (25.4 if s.metric else 1.0)
            depth = r - q
            if (depth - bottom) / q > MAX_PECKS or depth - q == depth:
                raise NgcError("resource_limit", what=f"a peck cycle of {(r - bottom) / q:.6g} pecks",
                               limit=f"{MAX_PECKS} pecks")
            while depth > bottom:
                self._count_block()     # Q0.000001 made pecks without end
                move(aa, bb, depth, False)
                if motion == 830:
                    move(aa, bb, r, True)
                move(aa, bb, depth + delta, True)
                depth -= q
            move(aa, bb, bottom, False)
            move(aa, bb, clear, True)
        elif motion == 850:
            move(aa, bb, bottom, False)
            move(aa, bb, r, False)
            move(aa, bb, clear, True)
        elif motion == 860:
            if s.spindle not in ("cw", "ccw"):
                raise NgcError("cycle_spindle_stopped")
            move(aa, bb, bottom, False)
            out.dwell(dwell)
            out.spindle("stop")
            move(aa, bb, clear, True)
            out.spindle(s.spindle)
        elif motion == 890:
            move(aa, bb, bottom, False)
            out.dwell(dwell)
            move(aa, bb, clear, False)
        elif motion in (740, 840):
            self._tap(motion, move, aa, bb, clear, bottom, dwell)

    def _tap(self, motion, move, aa, bb, clear, bottom, dwell) -> None:
        """G84 (right hand, spindle clockwise) and G74 (left hand) floating-chuck tapping:
        feed in with the overrides off, reverse the spindle, dwell, feed out, restore."""
        s = self.s
        out = self.out
        code = "G%d" % (motion // 10)
        if s.spindle == "stop":
            raise NgcError("tap_spindle_stopped", code=code)
        forward = "cw" if motion == 840 else "ccw"
        if s.spindle != forward:
            raise NgcError("tap_spindle_direction", code=code,
                           direction="clockwise" if s.spindle == "cw" else "counterclockwise")
        reverse = "ccw" if forward == "cw" else "cw"
        feed_override, speed_override = s.feed_override, s.speed_override
        if out.trace:
            out._p("DISABLE_FEED_OVERRIDE()")
            out._p("DISABLE_SPEED_OVERRIDE(0)")
        # LinuxCNC passes the XZ and YZ points to its plane-mapping feed in another order
        # (interp_cycles.cc convert_cycle_g74_g84), so the axes of those planes come out
        # permuted: kept, since rs274 and the machine move so
        order = {170: lambda c: (aa, bb, c), 180: lambda c: (bb, c, aa),
                 190: lambda c: (c, aa, bb)}[s.plane]
        move(*order(bottom), False)
        out.spindle("stop")
        out.spindle(reverse)
        out.dwell(dwell)
        move(*order(clear), False)
        out.spindle("stop")
        out.spindle(forward)
        if out.trace:
            if feed_override:
                out._p("ENABLE_FEED_OVERRIDE()")
            if speed_override:
                out._p("ENABLE_SPEED_OVERRIDE(0)")
