# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""Spindle-synchronised motion: G33, G33.1 rigid tapping and the G76 threading cycle
(LinuxCNC 2.9 interp_convert.cc ``convert_straight``, ``convert_threading_cycle``), and
straight probing G38.2..G38.5 (``convert_probe``).

rs274 prints the synchronisation (``START_SPEED_FEED_SYNC(pitch,0)``) around the moves. In
vmach's canonical stream the synchronised moves are linear feeds at pitch × spindle speed
(mm/min), the feed a machine reaches when it follows the spindle: G33.1 is the feed in to
the end point and the feed back out to where it started (RIGID_TAP), G76 the passes of the
cycle. Lengths are in program units, G76's P is the pitch (length per revolution), its Q
the compound angle in degrees.
"""

from __future__ import annotations

import math

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError


class ThreadingMixin:
    """G33 G33.1 G76 for :class:`~interpreters.rs274ngc.interp.Interpreter`."""

    def convert_threading(self, motion: int, block: blk.Block) -> None:
        s = self.s
        if s.comp_side:
            raise NgcError("thread_comp", code="G76" if motion == 760 else "G33")
        s.arc_not_allowed = False
        s.motion = motion
        end = self.find_ends(block)
        if s.spindle == "stop":
            raise NgcError("thread_spindle_stopped",
                           code={330: "G33", 331: "G33.1", 760: "G76"}[motion])
        if motion == 330:
            pitch = block.words["k"]
            self._sync(pitch)
            self.out.straight_feed(end, self._synced_feed(pitch))
            self._unsync()
            s.pos = end
        elif motion == 331:
            pitch = block.words["k"]
            self._sync(pitch)
            self.out.rigid_tap(end, s.pos, self._synced_feed(pitch))
            self._unsync()
        else:
            if end[3:6] != s.pos[3:6]:
                raise NgcError("thread_rotary_axes")
            self._g76(block, end)

    def convert_probe(self, motion: int, block: blk.Block) -> None:
        """G38.2..G38.5 as rs274 runs them without a machine: the probe move goes to the
        programmed point and never trips (#5070 = 0, no error even for G38.2/G38.4, as
        rs274); #5061..#5066 become that point and the tool backs off 0.254 mm (0.01 in)
        towards the start. vmach's stream gets G38.2/G38.3 as a probe move to the point
        (canon.ProbeMove, required for G38.2: verify stops it at contact with the stock, where
        the machine stops; no back-off), G38.4/G38.5 as the feed and the back-off."""
        s = self.s
        if s.comp_side:
            raise NgcError("probe_comp")
        if s.feed == 0.0:
            raise NgcError("probe_zero_feed")
        if s.feed_mode == 2:
            raise NgcError("probe_per_rev")
        end = self.find_ends(block)
        if motion in (382, 384) and end == s.pos:
            raise NgcError("probe_too_close")
        out = self.out
        out.simple("TURN_PROBE_ON")
        if out.trace:
            out._p("STRAIGHT_PROBE(%.4f, %.4f, %.4f, %.4f, %.4f, %.4f)" % tuple(end))
        d = [s.pos[i] - end[i] for i in range(3)]
        length = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        back = list(end)
        if length:
            step = 0.254 if s.metric else 0.01
            for i in range(3):
                back[i] = end[i] + step * d[i] / length
        if motion in (382, 383):        # toward the part: verify stops it at contact
            out.probe_command(end, self.feed_for_output(block), motion == 382)
        else:                           # G38.4/G38.5 probe away from it: a plain feed
            out.straight_feed_command(end, self.feed_for_output(block))
            if length:
                out.traverse_command(back)
        out.ppos = back
        out.simple("TURN_PROBE_OFF")
        s.motion = motion
        num = self.pars.num
        num[5061:5067] = end
        num[5067:5071] = [0.0, 0.0, 0.0, 0.0]
        s.pos = back

    def _synced_feed(self, pitch: float) -> float:
        """The feed of a move at ``pitch`` per spindle revolution, for vmach's stream: mm/rev
        in G95, else mm/min at the programmed spindle speed."""
        s = self.s
        mm = abs(pitch) * (1.0 if s.metric else 25.4)
        return mm if s.feed_mode == 2 else mm * s.speed

    def _sync(self, pitch: float) -> None:
        if self.out.trace:
            self.out._p("START_SPEED_FEED_SYNC(%f,0)" % pitch)

    def _unsync(self) -> None:
        if self.out.trace:
            self.out._p("STOP_SPEED_FEED_SYNCH()")

    def _g76(self, block: blk.Block, end: list[float]) -> None:
        """convert_threading_cycle: passes of decreasing depth increments along Z in the XZ
        plane (X is the depth), the last one repeated H times (spring passes)."""
        s = self.s
        w = block.words
        i_number, j_number, k_number = w["i"], w["j"], w["k"]
        if i_number == 0.0:
            raise NgcError("g76_i_zero")
        if j_number <= 0.0:
            raise NgcError("g76_j_not_positive")
        if k_number <= j_number:
            raise NgcError("g76_k_not_above_j")
        if s.diameter_mode:
            i_number /= 2
            j_number /= 2
            k_number /= 2
        start_x, start_y, start_z = s.pos[0], s.pos[1], s.pos[2]
        boring = i_number > 0.0
        full_dia_depth = abs(i_number)
        cut_increment = abs(j_number)
        full_threadheight = abs(k_number)
        end_depth = full_threadheight + full_dia_depth
        pitch = block.p
        angle = block.q if block.q != -1.0 else 0.0
        angle = math.radians(angle)
        if end[2] > start_z:
            angle = -angle
        spring_cuts = int(w.get("h", 0))
        degression = w.get("r", 1.0)
        if degression < 1.0:
            degression = 1.0
        taper_dist = max(w.get("e", 0.0), 0.0)
        taper_pitch = pitch * math.hypot(taper_dist, full_threadheight) / taper_dist \
            if taper_dist > 0.0 else pitch
        if end[2] > start_z:
            taper_dist = -taper_dist
        flags = max(block.l, 0)
        job = _Passes(boring, start_x, end_depth, start_y, start_z, taper_dist,
                      bool(flags & 1), bool(flags & 2), taper_pitch, pitch,
                      full_threadheight, end[2] + full_threadheight * math.tan(angle))
        tan = math.tan(angle)
        depth = full_dia_depth + cut_increment
        passes = 1
        while depth < end_depth:
            self._count_block()
            self._thread_pass(job, depth, (depth - full_dia_depth) * tan)
            passes += 1
            depth = full_dia_depth + cut_increment * math.pow(passes, 1.0 / degression)
        zoff = (end_depth - full_dia_depth) * tan
        for _ in range(spring_cuts + 1):
            self._count_block()
            self._thread_pass(job, end_depth, zoff)
        p = list(s.pos)
        p[0:3] = end[0:3]
        self.out.straight_traverse(p)
        s.pos = p

    def _thread_pass(self, job: _Passes, depth: float, zoff: float) -> None:
        """threading_pass: back off, in (tapered or not), along, out."""
        out = self.out
        abc = self.s.pos[3:6]
        sign = 1.0 if job.boring else -1.0
        x = job.safe_x + sign * depth
        x_back = job.safe_x + sign * (depth - job.end_depth)
        x_crest = job.safe_x + sign * (depth - job.full_threadheight)
        feed = self._synced_feed(job.pitch)
        taper_feed = self._synced_feed(job.taper_pitch)

        def at(px, pz):
            return [px, job.start_y, pz, *abc]

        out.straight_traverse(at(x_back, job.start_z - zoff))
        if job.taper_dist and job.entry_taper:
            self._overrides(False)
            self._sync(job.taper_pitch)
            out.straight_feed(at(x_crest, job.start_z - zoff), taper_feed)
            out.straight_feed(at(x, job.start_z - zoff - job.taper_dist), taper_feed)
            self._sync(job.pitch)
        else:
            out.straight_traverse(at(x, job.start_z - zoff))
            self._overrides(False)
            self._sync(job.pitch)
        if job.taper_dist and job.exit_taper:
            out.straight_feed(at(x, job.target_z - zoff + job.taper_dist), feed)
            self._sync(job.taper_pitch)
            out.straight_feed(at(x_crest, job.target_z - zoff), taper_feed)
        else:
            out.straight_feed(at(x, job.target_z - zoff), feed)
        self._unsync()
        out.straight_traverse(at(x_back, job.target_z - zoff))
        self._overrides(True)

    def _overrides(self, enable: bool) -> None:
        if self.out.trace:
            self.out._p("ENABLE_FEED_OVERRIDE()" if enable else "DISABLE_FEED_OVERRIDE()")


class _Passes:
    """What every pass of one G76 cycle shares (threading_pass's arguments)."""

    __slots__ = ("boring", "safe_x", "end_depth", "start_y", "start_z", "taper_dist",
                 "entry_taper", "exit_taper", "taper_pitch", "pitch", "full_threadheight",
                 "target_z")

    def __init__(self, *values):
        for name, value in zip(self.__slots__, values, strict=True):
            setattr(self, name, value)
