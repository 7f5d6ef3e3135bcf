"""Coordinate systems, axis offsets, reference points and tools.

G54..G59.3 select a coordinate system whose origin lives in parameters 5221.. (20 per
system, user units); G10 L2/L20 set them, G92/G52 shift all of them, G28/G30 go to the
reference points in 5161../5181.. (machine coordinates). Tools: T selects, M6 changes, M61
sets the loaded tool, G43/G49 apply or cancel the tool length offset, G10 L1/L10 edit the
table. Parameters 5400..5413 describe the loaded tool.
"""

from __future__ import annotations

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.state import Tool, rotate

_G5X = {540: 1, 550: 2, 560: 3, 570: 4, 580: 5, 590: 6, 591: 7, 592: 8, 593: 9}


class OffsetMixin:
    # -- tools --------------------------------------------------------------------------------

    def tool_index(self, tool: int) -> int:
        index = self.tools.index(tool)
        if index is None:
            raise NgcError("tool_not_found", tool=tool)
        return index

    def convert_tool_select(self, tool: int) -> None:
        index = self.tool_index(tool)
        self.out.select_tool(tool)
        self.s.selected_pocket = index
        self.s.selected_tool = tool
        self.s.t_seen = True

    def convert_tool_change(self) -> None:
        s = self.s
        out = self.out
        if s.selected_pocket < 0:
            raise NgcError("m6_without_tool")
        if s.comp_side:
            raise NgcError("comp_tool_change")
        out.simple("START_CHANGE")
        out.spindle("stop")
        s.spindle = "stop"
        # T0 M6 unloads the spindle: the canonical command says tool 0 (the trace keeps
        # LinuxCNC's CHANGE_TOOL(0))
        number = self.tools.entry(s.selected_pocket).number if s.selected_pocket else 0
        out.change_tool(s.selected_pocket, number)
        self.tools.load(s.selected_pocket)
        s.current_pocket = s.selected_pocket
        s.toolchange_flag = True
        self.set_tool_parameters()

    def convert_m61(self, block: blk.Block) -> None:
        q = block.q
        tool = int(q + 0.5) if q >= 0 else int(q - 0.5)
        if tool < 0:
            raise NgcError("m61_q_negative")
        index = self.tool_index(tool)
        s = self.s
        s.current_pocket = index
        s.toolchange_flag = True
        self.out.change_tool_number(index, tool)
        self.set_tool_parameters()

    def set_tool_parameters(self) -> None:
        t = self.tools.spindle
        num = self.pars.num
        num[5400] = float(t.number) if t.number > 0 else 0.0
        for i in range(9):
            num[5401 + i] = t.offset[i]
        num[5410] = t.diameter
        num[5411] = t.frontangle
        num[5412] = t.backangle
        num[5413] = float(t.orientation)

    def convert_tool_length_offset(self, code: int, block: blk.Block) -> None:
        s = self.s
        if s.comp_side:
            raise NgcError("comp_tool_offset")
        if code == 490:
            index = 0
            h = 0
        elif "h" in block.words:
            h = int(block.words["h"])
            index = self.tool_index(h)
        else:
            index = s.current_pocket if s.toolchange_flag else 0
            h = self.tools.entry(index).number
        t = self.tools.entry(index) if code != 490 else Tool(0, 0)
        new = [s.u2p(t.offset[0]), s.u2p(t.offset[1]), s.u2p(t.offset[2]),
               t.offset[3], t.offset[4], t.offset[5]]
        self.out.use_tool_length_offset(new, h if h > 0 else 0)
        old = s.tool_offset
        dx, dy = rotate(old[0] - new[0], old[1] - new[1], -s.rotation)
        pos = s.pos
        pos[0] += dx
        pos[1] += dy
        for i in (2, 3, 4, 5):
            pos[i] += old[i] - new[i]
        s.tool_offset = new

    # -- coordinate systems ------------------------------------------------------------------

    def current_in_system(self, system: int, with_tlo: bool = False) -> list[float]:
        """find_current_in_system: the current point seen from another coordinate system."""
        s = self.s
        p = self.pars.num
        cur = [s.pos[i] + s.axis_offset[i] for i in range(6)]
        cur[0], cur[1] = rotate(cur[0], cur[1], s.rotation)
        for i in range(6):
            cur[i] += s.origin[i]
            if with_tlo:
                cur[i] += s.tool_offset[i]
        base = 5201 + system * 20
        for i in range(6):
            cur[i] -= s.u2p(p[base + i]) if i < 3 else p[base + i]
        cur[0], cur[1] = rotate(cur[0], cur[1], -p[5210 + system * 20])
        if p[5210]:
            for i in range(6):
                cur[i] -= s.u2p(p[5211 + i]) if i < 3 else p[5211 + i]
        return cur

    def convert_coordinate_system(self, code: int) -> None:
        s = self.s
        out = self.out
        if s.comp_side:
            raise NgcError("comp_coord_system")
        origin = _G5X[code]
        if origin == s.origin_index:
            out.comment("interpreter: continuing to use same coordinate system")
            return
        s.pos = self.current_in_system(origin)
        s.origin_index = origin
        p = self.pars.num
        p[5220] = float(origin)
        base = 5201 + origin * 20
        s.origin = [s.u2p(p[base]), s.u2p(p[base + 1]), s.u2p(p[base + 2]),
                    p[base + 3], p[base + 4], p[base + 5]]
        s.rotation = p[5210 + origin * 20]
        out.set_g5x_offset(origin, s.origin)
        out.set_g92_offset(s.axis_offset)
        out.set_xy_rotation(s.rotation)

    # -- group 0 -------------------------------------------------------------------------------

    def convert_modal_0(self, code: int, block: blk.Block) -> None:
        if code == 100:
            if block.l in (1, 10, 11):
                self.convert_setup_tool(block)
            elif block.l in (2, 20):
                self.convert_setup(block)
        elif code in (280, 300):
            self.convert_home(code, block)
        elif code in (281, 301):
            self.convert_savehome(code)
        elif code in (520, 920):
            self.convert_axis_offsets(code, block)

    def convert_setup(self, block: blk.Block) -> None:
        """G10 L2 / L20: set the origin of coordinate system P."""
        w = block.words
        s = self.s
        p = self.pars.num
        if "i" in w or "j" in w:
            raise NgcError("g10_ij_with_l2")
        system = int(block.p + 0.0001)
        if system == 0:
            system = s.origin_index
        if s.comp_side and system == s.origin_index:
            raise NgcError("comp_active_system")
        l20 = block.l == 20
        cur = self.current_in_system(system)
        base = 5200 + system * 20
        if "r" in w:
            if l20:
                raise NgcError("g10_r_with_l20")
            r = w["r"]
            p[base + 10] = r
        else:
            r = p[base + 10]
        if l20:
            oldx, oldy = rotate(cur[0], cur[1], r)
            x, y = rotate(w.get("x", cur[0]), w.get("y", cur[1]), r)
            x = oldx + s.u2p(p[base + 1]) - x
            y = oldy + s.u2p(p[base + 2]) - y
            p[base + 1] = s.p2u(x)
            p[base + 2] = s.p2u(y)
            if system == s.origin_index:
                s.pos[0], s.pos[1] = rotate(s.pos[0], s.pos[1], s.rotation)
                s.rotation = 0.0
        else:
            if "x" in w:
                x = w["x"]
                p[base + 1] = s.p2u(x)
            else:
                x = s.u2p(p[base + 1])
            if "y" in w:
                y = w["y"]
                p[base + 2] = s.p2u(y)
            else:
                y = s.u2p(p[base + 2])
        rest = []
        for i, letter in ((2, "z"), (3, "a"), (4, "b"), (5, "c")):
            to_p = s.u2p if i < 3 else float
            to_u = s.p2u if i < 3 else float
            if letter in w:
                v = w[letter]
                if l20:
                    v = cur[i] + to_p(p[base + 1 + i]) - v
                p[base + 1 + i] = to_u(v)
            else:
                v = to_p(p[base + 1 + i])
            rest.append(v)
        new = [x, y, *rest]
        if system == s.origin_index:
            pos = s.pos
            pos[0], pos[1] = rotate(pos[0], pos[1], s.rotation)
            for i in range(6):
                pos[i] += s.origin[i] - new[i]
            s.origin = new
            self.out.set_g5x_offset(system, new)
            pos[0], pos[1] = rotate(pos[0], pos[1], -r)
            s.rotation = r
            self.out.set_xy_rotation(r)
        else:
            self.out.comment("interpreter: setting coordinate system origin")

    def convert_setup_tool(self, block: blk.Block) -> None:
        """G10 L1 (direct) / L10 (from the current position) / L11 (G59.3): tool table."""
        w = block.words
        s = self.s
        p = block.p
        tool = int(p + 0.5)
        index = self.tool_index(tool)
        if not any(c in w for c in "xyzabcrqij"):
            raise NgcError("g10_no_offsets")
        t = self.tools.entry(index)
        if block.l == 1:
            for i, letter in enumerate("xyzabc"):
                if letter in w:
                    t.offset[i] = s.p2u(w[letter]) if i < 3 else w[letter]
        else:
            system = 9 if block.l == 11 else s.origin_index
            cur = self.current_in_system(system, with_tlo=True)
            num = self.pars.num
            if block.l == 11 and num[5210]:
                for i in range(6):
                    cur[i] += s.u2p(num[5211 + i]) if i < 3 else num[5211 + i]
            rot = num[5210 + system * 20]
            if "x" in w and "y" in w:
                tx, ty = rotate(cur[0] - w["x"], cur[1] - w["y"], rot)
                t.offset[0], t.offset[1] = s.p2u(tx), s.p2u(ty)
            elif "x" in w or "y" in w:
                ox, oy = rotate(s.u2p(t.offset[0]), s.u2p(t.offset[1]), -rot)
                if "x" in w:
                    ox, oy = rotate(0.0, oy, rot)
                    tx, ty = rotate(cur[0] - w["x"], 0.0, rot)
                else:
                    ox, oy = rotate(ox, 0.0, rot)
                    tx, ty = rotate(0.0, cur[1] - w["y"], rot)
                t.offset[0], t.offset[1] = s.p2u(tx + ox), s.p2u(ty + oy)
            for i, letter in ((2, "z"), (3, "a"), (4, "b"), (5, "c")):
                if letter in w:
                    v = cur[i] - w[letter]
                    t.offset[i] = s.p2u(v) if i < 3 else v
        if "r" in w:
            t.diameter = s.p2u(w["r"]) * 2.0
        if "i" in w:
            t.frontangle = w["i"]
        if "j" in w:
            t.backangle = w["j"]
        if block.q != -1.0:
            q = block.q
            qi = int(q + 0.5)
            if abs(qi - q) >= 0.0001:
                raise NgcError("g10_q_integer")
            if qi > 9:
                raise NgcError("g10_orientation")
            t.orientation = qi
        self.out.set_tool_table_entry(index, t)
        if s.current_pocket == index:
            self.tools.load(index)
            self.set_tool_parameters()
            self.out.set_tool_table_entry(0, t)
        else:
            self.set_tool_parameters()

    def find_relative(self, machine: list[float]) -> list[float]:
        """Machine coordinates (program units) -> the current coordinate system."""
        s = self.s
        x = machine[0] - s.origin[0] - s.tool_offset[0]
        y = machine[1] - s.origin[1] - s.tool_offset[1]
        x, y = rotate(x, y, -s.rotation)
        out = [x - s.axis_offset[0], y - s.axis_offset[1],
               machine[2] - s.origin[2] - s.axis_offset[2] - s.tool_offset[2]]
        for i in (3, 4, 5):
            out.append(machine[i] - s.origin[i] - s.axis_offset[i])
        return out

    def convert_home(self, code: int, block: blk.Block) -> None:
        s = self.s
        end = self.find_ends(block)
        if s.comp_side:
            raise NgcError("comp_home")
        self.out.straight_traverse(end)
        s.pos = list(end)
        base = 5161 if code == 280 else 5181
        p = self.pars.num
        home = self.find_relative([s.u2p(p[base + i]) if i < 3 else p[base + i]
                                   for i in range(6)])
        w = block.words
        if block.has_axis():
            for i, letter in enumerate("xyzabc"):
                if letter in w:
                    end[i] = home[i]
        else:
            end = home
        self.out.straight_traverse(end)
        s.pos = list(end)

    def convert_savehome(self, code: int) -> None:
        s = self.s
        if s.comp_side:
            raise NgcError("comp_savehome")
        v = [s.pos[i] + s.axis_offset[i] for i in range(6)]
        v[0], v[1] = rotate(v[0], v[1], s.rotation)
        for i in range(6):
            v[i] += s.tool_offset[i] + s.origin[i]
        base = 5161 if code == 281 else 5181
        p = self.pars.num
        for i in range(6):
            p[base + i] = s.p2u(v[i]) if i < 3 else v[i]

    def convert_axis_offsets(self, code: int, block: blk.Block) -> None:
        s = self.s
        if s.comp_side:
            raise NgcError("comp_axis_offsets")
        p = self.pars.num
        w = block.words
        pos = s.pos
        off = s.axis_offset
        if code in (520, 920):
            p[5210] = 1.0
            for i, letter in enumerate("xyzabc"):
                if letter not in w:
                    continue
                if code == 520:
                    pos[i] += off[i] - w[letter]
                    off[i] = w[letter]
                else:
                    off[i] = pos[i] + off[i] - w[letter]
                    pos[i] = w[letter]
            self.out.set_g92_offset(off)
            for i in range(6):
                p[5211 + i] = s.p2u(off[i]) if i < 3 else off[i]
        elif code in (921, 922):
            p[5210] = 0.0
            for i in range(6):
                pos[i] += off[i]
            self.out.set_g92_offset([0.0] * 6)
            s.axis_offset = [0.0] * 6
            if code == 921:
                for i in range(6):
                    p[5211 + i] = 0.0
        else:  # G92.3
            p[5210] = 1.0
            new = [s.u2p(p[5211 + i]) if i < 3 else p[5211 + i] for i in range(6)]
            for i in range(6):
                pos[i] += off[i] - new[i]
            s.axis_offset = new
            self.out.set_g92_offset(new)
