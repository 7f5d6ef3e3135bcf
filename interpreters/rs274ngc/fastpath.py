"""Fast paths for the blocks that make up most of a program.

CAM output is mostly lines of G0/G1, F and axis words; loops are mostly such lines and
parameter settings. These methods do exactly what the general path (read_block, enhance,
check, execute_block) does for those lines, with less work per line; each returns False
(or 0), before changing anything, when a line or the machine state needs the general path.

- :meth:`FastPathMixin.flat_run` executes runs of *flat* lines (constant G0/G1, F and axis
  words, optionally an N number) straight from words read for the whole file with one
  regular expression (:func:`flat_tokens`): no Line or Block object per line.
- :meth:`FastPathMixin.fast_move` and :meth:`FastPathMixin.simple_step` execute parsed
  lines of the same kind (inside loops and subroutines, where lines are parsed once).
- :meth:`FastPathMixin.assign` executes lines of parameter settings only.

``Interpreter.fast_paths = False`` switches them all off; ``tests/rs274ngc/test_fastpath.py``
compares both ways on the golden programs and on generated ones.
"""

from __future__ import annotations

import re

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.lexer import Line, n_label
from interpreters.rs274ngc.output import FEED_SETTERS, SOURCE_SETTERS, TRAVERSE_SETTERS
from vmach.canon import LinearFeed, Traverse
from vmach.source import SourceRef

_NUM = r"([+-]?(?:[0-9]++\.?+[0-9]*+|\.[0-9]++))"
_FEED = r"([0-9]++\.?+[0-9]*+|\.[0-9]++)"
#: one line of the reduced text (lower case, no blanks: lexer.reduce_line), flat or not.
#: A flat line holds an optional N number, then G0/G1, F and axis words in this order
#: (F before or after the axes), constants only; its groups are n g f x y z a b c f, and the
#: last group is empty. Any other line (comments, expressions, other words or another order)
#: matches the second branch, whose group is the line end. Each word starts with its own
#: letter, so a flat line splits into words one way only: the possessive quantifiers (no
#: backtracking) change the speed, not the result.
_FLAT = re.compile(
    rf"(?:n([0-9]++))?+(?:g([0-9]++\.?+[0-9]*+))?+(?:f{_FEED})?+"
    + "".join(f"(?:{c}{_NUM})?+" for c in "xyzabc")
    + rf"(?:f{_FEED})?+\n|[^\n]*+(\n)"
)
_REDUCE = str.maketrans("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz", " \t\r")
_LONGEST = 252  # longer lines may exceed LinuxCNC's line buffer (interp.MAX_LINE)
_NOT_FLAT = ("",) * 10 + ("\n",)
#: G0/G1 as flat lines write them most often -> motion code
_MOTION = {"0": 0, "00": 0, "1": 10, "01": 10}
# Output.straight_feed's trace line with A B C already formatted (they seldom change)
_FEED_LINE = "%5d %sSTRAIGHT_FEED(%.4f, %.4f, %.4f, %s)"
_TRAVERSE_LINE = "%5d %sSTRAIGHT_TRAVERSE(%.4f, %.4f, %.4f, %s)"
_ABC = "%.4f, %.4f, %.4f"
_RATE_LINE = "%5d %sSET_FEED_RATE(%.4f)"


def flat_tokens(text: str, raw: list[str]) -> list[tuple]:
    """The words of every line of a program text, read at once: one tuple of strings per
    line of ``raw`` (the text split into lines): the groups of :data:`_FLAT`, "" for an
    absent word, the last one non-empty when the line is not flat. Reducing the whole text
    at once is what lexer.reduce_line does line by line for lines without comments, the only
    ones that can be flat. A line too long for LinuxCNC's line buffer is not flat."""
    if not text.endswith("\n"):
        text += "\n"
    tokens = _FLAT.findall(text.translate(_REDUCE))
    for i in [i for i, line in enumerate(raw) if len(line) > _LONGEST]:
        tokens[i] = _NOT_FLAT
    return tokens


class FastPathMixin:
    def assign(self, line: Line) -> None:
        """A line of parameter settings only: read every value, then store them all."""
        values = []
        try:
            for item in line.items:
                if item[0] == "p":
                    i = int(item[1] if type(item[1]) is float else item[1](self))
                    if i < 1 or i >= 5602:
                        raise NgcError("parameter_range", item[3])
                    if 5400 <= i <= 5413 or 5420 <= i <= 5428:
                        raise NgcError("parameter_readonly", item[3])
                    key = i
                else:
                    key = item[1]
                    self.declare_named(key)
                v = item[2]
                values.append((key, v if type(v) is float else v(self)))
        except NgcError as exc:
            if not exc.column:
                exc.column = item[3]
            raise
        num = self.pars.num
        for key, v in values:
            if type(key) is int:
                num[key] = v
        for key, v in values:
            if type(key) is str:
                self.store_named(key, v)

    def fast_move(self, fast: tuple) -> bool:
        """The commonest block, inlined: constant G0/G1, F and absolute axis words, feed per
        minute. Same effect as :meth:`step`; returns False, before doing anything, when the
        block or the state needs the general path."""
        s = self.s
        if (s.feed_mode or s.incremental or s.toolchange_flag or s.comp_side or s.arc_not_allowed
                or s.diameter_mode):
            return False
        motion, words = fast
        if self.strict and not self.known_words.issuperset(words):
            return False  # an unknown axis: the general path's error
        f = words.get("f")
        if motion == -1:
            if len(words) > (f is not None):
                motion = s.motion
                if motion != 0 and motion != 10:
                    return False
        out = self.out
        if f is not None:
            s.feed = f
            out.set_feed_rate(f)
        if motion == -1:
            return True
        if motion == 10 and s.feed == 0.0:
            raise NgcError("g1_zero_feed")
        s.motion = motion
        s.cycle_il = None
        pos = s.pos
        get = words.get
        end = [get("x", pos[0]), get("y", pos[1]), get("z", pos[2]),
               get("a", pos[3]), get("b", pos[4]), get("c", pos[5])]
        if motion:
            out.straight_feed(end, s.feed if s.metric else s.feed * 25.4)
        else:
            out.straight_traverse(end)
        s.pos = end
        return True

    def simple_step(self, line: Line) -> bool:
        """Fast path for lines of only G0/G1, F and axis words (most of a CAM program).

        Does what read_block/enhance/check/execute_block do for such a line; returns False,
        before changing anything, when the line needs the general path after all.
        """
        fast = line.fast
        if fast is not None:
            motion, words = fast
        else:
            words = {}
            motion = -1
            for k, item in enumerate(line.items):
                v = item[2]
                if type(v) is not float:
                    try:
                        v = v(self)
                    except NgcError as exc:
                        if not exc.column:
                            exc.column = item[3] or 1
                        raise
                letter = item[1]
                if letter == "g":
                    motion = 0 if v == 0.0 else 10
                else:
                    if letter == "f" and v < 0.0:
                        raise NgcError("negative_feed", item[3] or blk.item_column(line, k))
                    words[letter] = v
            if self.fast_move((motion, words)):
                return True
        block = blk.Block(line)
        block.words = words
        if motion != -1:
            block.g[1] = motion
        return self._simple_execute(block, motion, words)

    def _simple_execute(self, block, motion: int, words: dict) -> bool:
        s = self.s
        if s.diameter_mode:  # X words are diameters: read_block halves them
            return False
        if motion == -1 and len(words) > ("f" in words):
            motion = s.motion
            if motion == -1 or motion == 800:
                raise NgcError("axis_words_unused")
            if motion != 0 and motion != 10:
                return False
        block.motion = motion
        if self.strict:
            self.check_axes(block)
        f = words.get("f")
        if f is not None and s.feed_mode != 1:
            s.feed = f
            self.out.set_feed_rate(f)
        if motion != -1:
            s.cycle_il = None
            self.convert_straight(motion, block)
        return True


    def flat_run(self, prog, pc: int) -> int:
        """Execute the run of flat lines that starts at line index ``pc`` of ``prog``, from
        the words :func:`flat_tokens` read for the whole file: no Line, Block or word dict.

        The effect is :meth:`fast_move`'s, line for line (the same trace lines, canonical
        commands, state and block count). The run stops, before changing anything for that
        line, at the first line that is not flat or that the state makes unsafe here (axis
        words without G0/G1 mode, G1 without feed, an axis a strict machine does not have,
        the block limit); the general path takes it from there. Returns the number of lines
        executed (0 when the state needs the general path: inverse time or per-rev feed,
        G91, a pending tool change, a pending spindle change).

        Commands and source references are built with the slot setters of
        :func:`interpreters.rs274ngc.output._slot_setters` when the classes allow it (the
        same objects as their constructors build, faster), else with the constructors.
        """
        s = self.s
        out = self.out
        if (s.feed_mode or s.incremental or s.toolchange_flag or out.spindle_dirty or s.comp_side
                or s.arc_not_allowed or s.diameter_mode):
            return 0
        # axes a strict machine does not have: such a line is left to the general path
        known = self.known_words if self.strict else "xyzabc"
        ux, uy, uz, ua, ub, uc = (letter not in known for letter in "xyzabc")
        unknown = ux or uy or uz or ua or ub or uc
        tokens = prog.flat
        if tokens is None:
            tokens = prog.flat = flat_tokens(prog.text, prog.raw)
        raws = prog.raw
        stop = min(len(raws), pc + self.options.max_blocks - self.blocks)
        trace = out.trace
        want = out.want
        lines = out.lines
        commands = out.commands
        refs = prog.refs
        path = prog.path
        count = out.count
        pos = s.pos
        motion_mode = s.motion
        feed = s.feed
        metric = s.metric
        rate = feed if metric else feed * 25.4
        # machine values in the common case: out.machine inlined, the same operations
        plain = out._xyz and not out.extra_used and out.abc_zero and not out.rotation
        plain_abc = plain and not (pos[3] or pos[4] or pos[5])
        unit = out.unit
        ox, oy, oz = out.g92[:3]
        gx, gy, gz = out.g5x[:3]
        abc = _ABC % (pos[3], pos[4], pos[5])
        quick = SOURCE_SETTERS and FEED_SETTERS and TRAVERSE_SETTERS
        if quick:
            new = object.__new__
            set_path, set_line, set_column, set_text = SOURCE_SETTERS
            set_source, set_axes, set_feed = FEED_SETTERS
            set_tsource, set_taxes = TRAVERSE_SETTERS
        moved = False
        nlabel = out.nlabel
        ref = out.src
        i = pc
        while i < stop:
            n, g, f1, x, y, z, a, b, c, f2, other = tokens[i]
            if other:
                break
            if g:
                motion = _MOTION.get(g)
                if motion is None:
                    v = float(g)
                    if v == 0.0:
                        motion = 0
                    elif v == 1.0:
                        motion = 10
                    else:
                        break
            elif x or y or z or a or b or c:
                if motion_mode != 0 and motion_mode != 10:
                    break
                motion = motion_mode
            else:
                motion = -1
            if unknown and ((x and ux) or (y and uy) or (z and uz) or (a and ua) or (b and ub)
                            or (c and uc)):
                break
            f = f1 or f2
            if f:
                if f1 and f2:
                    break
                fv = float(f)
                if motion == 10 and fv == 0.0:
                    break
            elif motion == 10 and feed == 0.0:
                break
            # the line is executed from here on
            if trace:
                nlabel = n_label(raws[i]) if n else "N..... "  # N as written (N 20 -> "N")
            if want:
                ref = refs[i]
                if ref is None:
                    if quick:
                        ref = new(SourceRef)
                        set_path(ref, path)
                        set_line(ref, i + 1)
                        set_column(ref, 1)
                        set_text(ref, raws[i].rstrip("\r"))
                    else:
                        ref = SourceRef(path, i + 1, 1, raws[i].rstrip("\r"))
                    refs[i] = ref
            i += 1
            if f:
                feed = fv
                rate = fv if metric else fv * 25.4
                if trace:
                    count += 1
                    lines.append(_RATE_LINE % (count, nlabel, fv))
            if motion == -1:
                continue
            motion_mode = motion
            moved = True
            pos = [float(x) if x else pos[0], float(y) if y else pos[1],
                   float(z) if z else pos[2], float(a) if a else pos[3],
                   float(b) if b else pos[4], float(c) if c else pos[5]]
            if a or b or c:
                abc = _ABC % (pos[3], pos[4], pos[5])
                plain_abc = plain and not (pos[3] or pos[4] or pos[5])
            if trace:
                count += 1
                lines.append((_FEED_LINE if motion else _TRAVERSE_LINE)
                             % (count, nlabel, pos[0], pos[1], pos[2], abc))
            if want:
                if plain_abc:
                    axes = {"X": (pos[0] + ox + gx) * unit, "Y": (pos[1] + oy + gy) * unit,
                            "Z": (pos[2] + oz + gz) * unit}
                else:
                    axes = out.machine(pos)
                    if out.extra_used:  # A B C joined the axes (Output.machine)
                        plain = plain_abc = False
                if not quick:
                    cmd = LinearFeed(ref, axes, rate) if motion else Traverse(ref, axes)
                elif motion:
                    cmd = new(LinearFeed)
                    set_source(cmd, ref)
                    set_axes(cmd, axes)
                    set_feed(cmd, rate)
                else:
                    cmd = new(Traverse)
                    set_tsource(cmd, ref)
                    set_taxes(cmd, axes)
                commands.append(cmd)
        if i == pc:
            return 0
        self.blocks += i - pc
        self.pc = i
        self.index = i - 1
        s.feed = feed
        out.count = count
        out.nlabel = nlabel
        out.src = ref
        if moved:
            s.motion = motion_mode
            s.cycle_il = None
            s.pos = pos
            out.ppos = list(pos)
        return i - pc
