# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""Executing one block in LinuxCNC's order (interp_execute.cc ``execute_block``).

1. comment (MSG, DEBUG, PRINT ...)       6. M codes: tool change, spindle, coolant, overrides
2. feed mode G93/G94/G95                 7. G codes in the order of :meth:`convert_g`
3. feed rate F                           8. stops M0 M1 M2 M30 M60
4. spindle speed S
5. tool selection T
"""

from __future__ import annotations

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.state import rotate

END = 1



def _num(v: float, fmt: str = "%f") -> str:
    """A parameter in a DEBUG/PRINT/LOG text: ``%lf`` (or the format a ``%d``, ``%f`` or
    ``%.Nf`` before it chose) into LinuxCNC's 30-byte buffer."""
    text = fmt % (0.0 if abs(v) < 0.0001 else v)
    return text if len(text) < 30 else "######"


class ExecuteMixin:
    """execute_block and the non-motion conversions."""

    def execute_block(self, block: blk.Block):
        g = block.g
        m = block.m
        if g or m:
            self._check_supported(block)
        if block.comment:  # LinuxCNC skips an empty comment "()"
            self.convert_comment(block.comment)
        words = block.words
        s = self.s
        out = self.out
        if 5 in g:
            self.convert_feed_mode(g[5])
        if "f" in words and s.feed_mode != 1:
            s.feed = words["f"]
            out.set_feed_rate(s.feed)
        if "s" in words:
            s.speed = words["s"]
            out.set_spindle_speed(s.speed)
        if "t" in words:
            self.convert_tool_select(int(words["t"]))
        if m:
            self.convert_m(block)
        if g or block.motion != -1:
            self.convert_g(block)
        if 4 in m:
            return self.convert_stop(block)
        return None

    def _check_supported(self, block: blk.Block) -> None:
        for code in block.g.values():
            what = blk.UNSUPPORTED_G.get(code)
            if what is not None:
                raise NgcError("unsupported", what=what)
        for code in block.m.values():
            what = blk.UNSUPPORTED_M.get(code)
            if what is not None:
                raise NgcError("unsupported", what=what)

    # -- comments -----------------------------------------------------------------------------

    def convert_comment(self, comment: str) -> None:
        start = len(comment) - len(comment.lstrip(" \t\n\r\f\v"))
        lc = comment[start : start + 256].lower()
        out = self.out
        if lc.startswith("msg,"):
            out.message(comment[start + 4 :])
        elif lc.startswith("debug,"):
            text = self.expand_parameters(comment[start + 6 :])
            if self.pars.num[5599] > 0.0:
                out.message(text)
        elif lc.startswith("print,"):
            out.print_text(self.expand_parameters(comment[start + 6 :]))
        elif lc.startswith("log,"):
            if out.trace:
                out._p('LOG("%s")' % self.expand_parameters(comment[start + 4 :]))
        elif lc.startswith("logopen,"):
            if out.trace:
                out._p('LOGOPEN("%s")' % comment[start + 8 :])
        elif lc.startswith("logappend,"):
            if out.trace:
                out._p('LOGAPPEND("%s")' % comment[start + 10 :])
        elif lc.startswith(("py,", "pyrun,", "pyreload")):
            raise NgcError("unsupported", what="embedded Python (PY, PYRUN, PYRELOAD)")
        elif lc.startswith("abort,"):
            raise NgcError("abort", text=self.expand_parameters(comment[start + 6 :]))
        elif lc == "logclose":
            out.simple("LOGCLOSE")
        else:
            out.comment(comment[start:], program=True)

    def expand_parameters(self, text: str) -> str:
        """convert_param_comment: ``#5`` and ``#<name>`` replaced by their values, ``%lf``
        until ``%d`` (``%.0f``), ``%f`` (``%.4f``) or ``%.Nf`` chooses another format for the
        rest of the text; those format words are not printed."""
        out = []
        i = 0
        n = len(text)
        fmt = "%f"
        while i < n:
            ch = text[i]
            if ch == "%":
                i += 1
                nxt = text[i] if i < n else ""
                if nxt == "d":
                    fmt = "%.0f"
                    i += 1
                elif nxt == "f":
                    fmt = "%.4f"
                    i += 1
                elif nxt == ".":
                    i += 1
                    if i + 1 < n and text[i].isdigit() and text[i + 1] == "f":
                        fmt = "%." + text[i] + "f"
                        i += 2
                    else:
                        out.append(".")
                else:
                    out.append("%")
                continue
            if ch != "#":
                out.append(ch)
                i += 1
                continue
            i += 1
            if i >= n:
                raise NgcError("named_parameter_unterminated")
            if text[i].isdigit():
                j = i
                while j < n and text[j].isdigit():
                    j += 1
                index = int(text[i:j])
                i = j
                if 0 <= index < 5602:
                    out.append(_num(self.par(index) if index else 0.0, fmt))
                else:
                    out.append("######")
            elif text[i] == "<":
                i += 1
                name = []
                while i < n and text[i] != ")" and text[i] != ">":
                    if not text[i].isspace():
                        name.append(text[i].lower())
                    i += 1
                if i >= n or text[i] != ">":
                    raise NgcError("named_parameter_unterminated")
                i += 1
                v = self.named_value("".join(name))
                out.append("######" if v is None else _num(v, fmt))
            else:
                out.append("#")
        return "".join(out)

    # -- modes ----------------------------------------------------------------------------------

    def convert_feed_mode(self, code: int) -> None:
        s = self.s
        out = self.out
        if code == 930:
            out.comment("interpreter: feed mode set to inverse time")
            s.feed_mode = 1
            out.set_feed_mode(0, 1)
        elif code == 940:
            out.comment("interpreter: feed mode set to units per minute")
            s.feed_mode = 0
            out.set_feed_mode(0, 0)
            s.feed = 0.0
            out.set_feed_rate(0.0)
        else:
            out.comment("interpreter: feed mode set to units per revolution")
            s.feed_mode = 2
            out.set_feed_mode(1, 2)
            s.feed = 0.0
            out.set_feed_rate(0.0)

    def convert_m(self, block: blk.Block) -> None:
        m = block.m
        s = self.s
        out = self.out
        code = m.get(5)
        if code is not None:
            self.convert_io(code, block)
        code = m.get(6)
        if code == 6:
            self.convert_tool_change()
        elif code == 61:
            self.convert_m61(block)
        code = m.get(7)
        if code == 3:
            out.spindle("cw")
            s.spindle = "cw"
        elif code == 4:
            out.spindle("ccw")
            s.spindle = "ccw"
        elif code == 5:
            out.spindle("stop")
            s.spindle = "stop"
        elif code == 19:
            self.convert_orient(block)
        elif code is not None and code >= 70:
            self.convert_context(code)
        code = m.get(8)
        if code == 7:
            out.coolant(mist=True)
            s.mist = True
        elif code == 8:
            out.coolant(flood=True)
            s.flood = True
        elif code == 9:
            out.coolant(mist=False, flood=False)
            s.mist = s.flood = False
        code = m.get(9)
        if code is not None and s.comp_side:
            raise NgcError("comp_overrides_on" if code == 48 else "comp_overrides_off")
        if code == 48:
            out.overrides(True)
            s.feed_override = s.speed_override = True
        elif code == 49:
            out.overrides(False)
            s.feed_override = s.speed_override = False
        code = m.get(10)
        if code is not None:
            raise NgcError("unknown_m_code", code=code)

    def convert_g(self, block: blk.Block) -> None:
        g = block.g
        s = self.s
        out = self.out
        mode0 = g.get(0, -1)
        if mode0 == 40:
            out.dwell(block.p)
        code = g.get(2)
        if code is not None:
            if s.comp_side:
                if code != s.plane:
                    raise NgcError("comp_plane")
                if code == 190:
                    raise NgcError("comp_plane_xy_xz")
            out.select_plane(code)
            s.plane = code
        code = g.get(6)
        if code is not None:
            self.convert_length_units(code == 210)
        code = g.get(15)
        if code is not None:
            self.convert_diameter_mode(code == 70, block)
        code = g.get(7)
        if code is not None:
            self.convert_cutter_compensation(code, block)
        code = g.get(8)
        if code is not None:
            self.convert_tool_length_offset(code, block)
        code = g.get(12)
        if code is not None:
            self.convert_coordinate_system(code)
        code = g.get(13)
        if code is not None:
            self.convert_control_mode(code, block)
        code = g.get(3)
        if code is not None:
            if code == 900 and s.incremental:
                out.comment("interpreter: distance mode changed to absolute")
                s.incremental = False
            elif code == 910 and not s.incremental:
                out.comment("interpreter: distance mode changed to incremental")
                s.incremental = True
        code = g.get(4)
        if code is not None:
            if code == 901 and not s.ijk_absolute:
                out.comment("interpreter: IJK distance mode changed to absolute")
                s.ijk_absolute = True
            elif code == 911 and s.ijk_absolute:
                out.comment("interpreter: IJK distance mode changed to incremental")
                s.ijk_absolute = False
        code = g.get(10)
        if code is not None:
            if s.comp_side:
                raise NgcError("comp_retract_mode")
            if code == 980:
                out.comment("interpreter: retract mode set to old_z")
                s.retract_r = False
            else:
                out.comment("interpreter: retract mode set to r_plane")
                s.retract_r = True
        if mode0 != -1:
            self.convert_modal_0(mode0, block)
        code = g.get(11)  # G92.1 G92.2 G92.3 (LinuxCNC 2.9 skips them with compensation on)
        if code is not None and not s.comp_side:
            self.convert_axis_offsets(code, block)
        if block.motion != -1:
            self.convert_motion(block.motion, block)

    def convert_diameter_mode(self, diameter: bool, block: blk.Block) -> None:
        """G7 (X words are diameters) and G8 (radii): the block's X, read in the old mode,
        is rescaled, as are G76's I J K (convert_lathe_diameter_mode)."""
        s = self.s
        if diameter == s.diameter_mode:
            return
        f = 0.5 if diameter else 2.0
        self.out.comment("interpreter: Lathe diameter mode changed to "
                         + ("diameter" if diameter else "radius"))
        w = block.words
        if "x" in w:
            w["x"] *= f
        if block.motion == 760:
            for letter in "ijk":
                if letter in w:
                    w[letter] *= f
        s.diameter_mode = diameter

    def convert_control_mode(self, code: int, block: blk.Block) -> None:
        s = self.s
        out = self.out
        if s.comp_side:
            raise NgcError("comp_control_mode")
        if code == 610:
            out.set_motion_control_mode("exact_path")
            s.control = "exact_path"
        elif code == 611:
            out.set_motion_control_mode("exact_stop")
            s.control = "exact_stop"
        else:
            p, q = block.p, block.q
            s.tolerance = p if p >= 0 else 0.0
            out.set_motion_control_mode("continuous", s.tolerance)
            s.naivecam = q if q >= 0 else s.tolerance
            out.set_naivecam_tolerance(s.naivecam)
            s.control = "continuous"

    def convert_length_units(self, metric: bool) -> None:
        s = self.s
        self.out.use_length_units(metric)
        if s.metric == metric:
            return
        # LinuxCNC converts positions and offsets; the tool offset and the feed rate are
        # re-read from the (saicanon) machine, which keeps them unconverted.
        f = 25.4 if metric else 1.0 / 25.4
        s.metric = metric
        for lst in (s.pos, s.comp_program, s.axis_offset, s.origin):
            for i in range(3):
                lst[i] *= f
        s.comp_radius *= f
        self.comp_scale(f)

    # -- stopping ---------------------------------------------------------------------------------

    def convert_stop(self, block: blk.Block):
        code = block.m[4]
        out = self.out
        s = self.s
        cx, cy, _ = self.comp_current() if s.plane in (170, 180) else (0.0, 0.0, 0.0)
        self.move_endpoint_and_flush(cx, cy)
        self.dequeue()
        if code == 0:
            out.program_stop(False)
            return None
        if code == 60:
            out.simple("PALLET_SHUTTLE")
            out.program_stop(False)
            return None
        if code == 1:
            out.program_stop(True)
            return None
        pos = s.pos
        for i in range(6):
            pos[i] += s.origin[i]
        pos[0], pos[1] = rotate(pos[0], pos[1], s.rotation)
        s.origin_index = 1
        num = self.pars.num
        num[5220] = 1.0
        s.origin = [s.u2p(num[5221]), s.u2p(num[5222]), s.u2p(num[5223]),
                    num[5224], num[5225], num[5226]]
        s.rotation = num[5230]
        pos[0], pos[1] = rotate(pos[0], pos[1], -s.rotation)
        for i in range(6):
            pos[i] -= s.origin[i]
        out.set_g5x_offset(1, s.origin)
        out.set_xy_rotation(s.rotation)
        if s.plane != 170:
            out.select_plane(170)
            s.plane = 170
        s.incremental = False
        s.feed_mode = 0
        out.set_feed_mode(0, 0)
        s.feed = 0.0
        out.set_feed_rate(0.0)
        if not s.feed_override:
            out.simple("ENABLE_FEED_OVERRIDE")
            s.feed_override = True
        s.speed_override = True  # LinuxCNC 2.9 re-enables only the feed override here
        s.comp_side = 0
        s.comp_first = True
        out.spindle("stop")
        s.spindle = "stop"
        out.set_spindle_mode()
        s.motion = 10
        if s.mist or s.flood:
            out.coolant(mist=False if s.mist else None, flood=False if s.flood else None)
            s.mist = s.flood = False
        if code == 30:
            out.simple("PALLET_SHUTTLE")
        out.program_end("M30" if code == 30 else "M2")
        if self.percent and not any(r.strip() == "%" for r in self.prog.raw[self.pc :]):
            out.nlabel = "N..... "  # LinuxCNC notes it after the block, without its N number
            out.comment("interpreter: percent sign missing from end of file")
        self.ended = True
        return END
