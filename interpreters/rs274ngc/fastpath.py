"""Fast paths for the blocks that make up most of a program.

CAM output is mostly lines of G0/G1, F and axis words; loops are mostly such lines and
parameter settings. These methods do exactly what the general path (read_block, enhance,
check, execute_block) does for those lines, with less work per line; each returns False,
before changing anything, when a line or the machine state needs the general path.
The golden and fuzz tests run through both paths.
"""

from __future__ import annotations

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.lexer import Line


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
        if s.feed_mode or s.incremental or s.toolchange_flag or self.strict:
            return False
        motion, words = fast
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
        block = blk.Block(line)
        fast = line.fast
        if fast is not None:
            motion, words = fast
            block.words = words
            if motion != -1:
                block.g[1] = motion
            return self._simple_execute(block, motion, words)
        words = block.words
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
                block.g[1] = motion
            else:
                if letter == "f" and v < 0.0:
                    raise NgcError("negative_feed", item[3] or blk.item_column(line, k))
                words[letter] = v
        return self._simple_execute(block, motion, words)

    def _simple_execute(self, block, motion: int, words: dict) -> bool:
        s = self.s
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

