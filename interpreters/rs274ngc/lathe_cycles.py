"""G70, G71, G71.1, G71.2, G72, G72.1, G72.2: LinuxCNC 2.9's lathe finishing and roughing
cycles along a contour given as an O-word subroutine (``G7x Q<sub> X Z D I R ...``).

As LinuxCNC runs them (``Interp::convert_g7x``): a rapid to the block's X Z (read in
absolute mode), then the subroutine is read, not executed: its O-word control flow and
parameter settings run, its moves (G0/G1/G2/G3 with X Z, U W increments, I K or R, A fillet
and C chamfer on a corner) become the contour, and the current point follows them (so
``#<_x>`` works inside); then the cycle's moves are executed as G0/G1/G2/G3 with X Z I K in
absolute mode (:mod:`interpreters.rs274ngc.g7x_path`), carrying the cycle's line. Words:
D allowance (G71/G72) or first distance (G70), E last distance, P passes (G70), I depth of
cut, R retract, U W shift. Lengths in program units, X a radius (after G7's halving).
"""

from __future__ import annotations

import math

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.g7x_path import MAX_STEPS, G7xPath, G7xRunaway
from interpreters.rs274ngc.g7x_segments import Arc, Chamfer, Fillet, G7xError, Line, Sink, dv
from interpreters.rs274ngc.lexer import n_label, parse_line

#: the most moves one cycle may make: LinuxCNC 2.9 loops for ever on some contours (its
#: test g71-endless-loop); vmach stops with an error instead
MAX_MOVES = 200_000


class _Machine(Sink):
    """The cycle's moves as blocks executed by the interpreter (G0/G1/G2/G3, X Z I K)."""

    def __init__(self, it, line):
        self.it = it
        self.line = line
        self.moves = 0

    def _block(self, p: complex) -> blk.Block:
        self.moves += 1
        if self.moves > MAX_MOVES:
            raise NgcError("g7x_too_many_moves", limit=f"{MAX_STEPS} steps or {MAX_MOVES}")
        b = blk.Block(self.line)
        b.words["x"] = p.imag
        b.words["z"] = p.real
        return b

    def rapid(self, p: complex) -> None:
        self.it.convert_straight(0, self._block(p))

    def feed(self, p: complex) -> None:
        self.it.convert_straight(10, self._block(p))

    def arc(self, ccw: bool, centre: complex, p: complex) -> None:
        pos = self.it.s.pos
        if abs(pos[2] - p.real) < 1e-4 and abs(pos[0] - p.imag) < 1e-4:
            return  # LinuxCNC skips an arc that ends where it starts
        b = self._block(p)
        b.words["i"] = centre.imag
        b.words["k"] = centre.real
        self.it.convert_arc(30 if ccw else 20, b)


class LatheCycleMixin:
    """G70..G72.2 for :class:`~interpreters.rs274ngc.interp.Interpreter`."""

    def convert_g7x(self, motion: int, block: blk.Block) -> None:
        s = self.s
        w = block.words
        cycle, sub = divmod(motion, 10)
        if "q" not in w:
            raise NgcError("g7x_q_missing")
        if s.comp_side and cycle != 70:
            raise NgcError("g7x_comp", code=f"G{cycle}.{sub}")
        if s.plane != 180:
            raise NgcError("g7x_plane", code=f"G{cycle}.{sub}")
        incremental, ijk_absolute = s.incremental, s.ijk_absolute
        s.incremental, s.ijk_absolute = False, True
        try:
            self._g7x(cycle, sub, block, incremental, ijk_absolute)
        finally:
            s.incremental, s.ijk_absolute = incremental, ijk_absolute

    def _g7x(self, cycle: int, sub: int, block: blk.Block, incremental: bool,
             ijk_absolute: bool) -> None:
        s = self.s
        w = dict(block.words)
        x, z = s.pos[0], s.pos[2]
        if incremental:
            x += w.get("x", 0.0)
            z += w.get("z", 0.0)
        else:
            x, z = w.get("x", x), w.get("z", z)
        self.convert_straight(0, block)
        here = (self.prog, self.index, self.line, self.out.src)
        segs = self._g7x_contour(w["q"], complex(z, x), incremental, ijk_absolute)
        self.prog, self.index, self.line, self.out.src = here
        if len(segs) <= 1:
            return
        i = w.get("i", 1.0)
        if i <= 0:
            raise NgcError("g7x_error", text="I must be greater than zero.")
        path = G7xPath(segs)
        if self.out.trace:
            path.say = self.out.lines.append
        out = _Machine(self, block.line)
        d, e, r = w.get("d", 0.0), w.get("e", 0.0), w.get("r", 0.5)
        u, ww = w.get("u", 0.0), w.get("w", 0.0)
        try:
            if cycle == 70:
                path.finish(out, x, z, d, e, w.get("p", 1.0))
            else:
                path.rough(out, sub, x, z, u, ww, d, i, r, turn=cycle == 72)
        except G7xRunaway:
            raise NgcError("g7x_too_many_moves", limit=f"{MAX_STEPS} steps or {MAX_MOVES}") from None
        except G7xError as exc:
            raise NgcError("g7x_error", text=str(exc)) from None

    def _g7x_contour(self, q: float, start: complex, incremental: bool,
                     ijk_absolute: bool) -> list:
        """Read the subroutine ``q`` as a contour from ``start`` (see the module doc)."""
        s = self.s
        out = self.out
        if q != int(q):
            raise NgcError("g7x_error", text="Q must name an O-word subroutine")
        exit_level = len(self.frames)
        self.control(parse_line(self.line.number if self.line else 1, f"O{int(q)} CALL"))
        segs: list = []
        limit = self.options.max_blocks
        while True:
            prog, pc = self.prog, self.pc
            if pc >= len(prog.raw):
                self.end_of_file()
            line = prog.line(pc)
            self.pc, self.index, self.line = pc + 1, pc, line
            if out.trace:
                out.nlabel = line.nlabel or _nlabel(line)
            self.blocks += 1
            if self.blocks > limit:
                raise NgcError("block_limit", limit=limit)
            if line.skip_error is not None:
                raise line.skip_error
            if line.blank or line.percent or (line.slash and self.block_delete):
                continue
            if line.o is not None or (line.error is not None and not line.items):
                if line.o is None:
                    raise line.error
                self.control(line)
                if len(self.frames) == exit_level:
                    break
                continue
            b = blk.read_block(line, self)
            blk.enhance(b, s.motion, s.plane)
            blk.check(b, s.incremental)
            for i, v in b.settings:
                self.pars.num[i] = v
            for name, v in b.named:
                self.store_named(name, v)
            start = self._g7x_element(b, start, segs, incremental, ijk_absolute)
        return segs

    def _g7x_element(self, b: blk.Block, start: complex, segs: list, incremental: bool,
                     ijk_absolute: bool) -> complex:
        """Add the element of one contour block; returns its end point."""
        s = self.s
        w = b.words
        end = 0j if incremental else start
        if "u" in w:
            if incremental:
                raise NgcError("g7x_error", text="Cannot use U in incremental mode (G91)")
            if "x" in w:
                raise NgcError("g7x_error", text="Cannot use U and X in the same block")
            end += 1j * (w["u"] / 2 if s.diameter_mode else w["u"])
        elif "x" in w:
            end = complex(end.real, w["x"])
        if "w" in w:
            if incremental:
                raise NgcError("g7x_error", text="Cannot use W in incremental mode (G91)")
            if "z" in w:
                raise NgcError("g7x_error", text="Cannot use W and Z in the same block")
            end += w["w"]
        elif "z" in w:
            end = complex(w["z"], end.imag)
        centre = complex(w.get("k", 0.0), w.get("i", 0.0))
        if incremental:
            end += start
        mode = b.g.get(1)
        if mode is not None:
            s.motion = mode
        mode = s.motion
        if start == end:
            return start
        if mode in (0, 10):
            segs.append(Line(start, end))
        elif mode in (20, 30):
            if "r" in w:
                if "i" in w or "k" in w:
                    raise NgcError("g7x_error", text="both R and I or K flag used for arc")
                r = w["r"]
                centre = dv(start + end, 2.0)
                chord = end - start
                n = chord.real * chord.real + chord.imag * chord.imag
                q = (r * r - n / 4) / n
                root = math.sqrt(q) if q >= 0 else math.nan
                d = complex(0.0 * root, root) * chord
                centre = centre + d if mode == 30 else centre - d
            else:
                if "i" not in w and "k" not in w:
                    raise NgcError("g7x_error", text="either I or K must be present for arc")
                if not ijk_absolute:
                    centre += start
            segs.append(Arc(mode == 30, start, centre, end))
        if mode in (0, 10, 20, 30):
            if "a" in w and "c" in w:
                raise NgcError("g7x_error", text="Both A and C parameters on a corner")
            if "a" in w:
                segs.append(Fillet(w["a"], end))
            if "c" in w:
                segs.append(Chamfer(w["c"], end))
        s.pos[0], s.pos[2] = end.imag, end.real
        return end


def _nlabel(line) -> str:
    line.nlabel = n_label(line.raw)
    return line.nlabel
