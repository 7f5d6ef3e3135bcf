"""From a parsed line to a checked block (LinuxCNC ``read_items``, ``enhance_block``,
``check_items``).

Evaluating a line reads its items left to right with the parameter values *before* the line
(settings on the line take effect together, after it is read). Each word is checked as it is
read (duplicates, signs, integers, G/M code validity and modal groups); then the block as a
whole is checked: which motion the axis words belong to, and that every word has a code that
uses it.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.expr import to_integer
from interpreters.rs274ngc.lexer import Line, item_column  # noqa: F401 (re-exported)

_DATA = tomllib.loads(Path(__file__).with_name("modal_groups.toml").read_text(encoding="utf-8"))


def _code(key: str) -> int:
    return int(round(float(key) * 10))


G_GROUP: dict[int, int] = {_code(k): v for k, v in _DATA["g"].items()}
M_GROUP: dict[int, int] = {int(k): v for k, v in _DATA["m"].items()}
UNSUPPORTED_G: dict[int, str] = {_code(k): v for k, v in _DATA["unsupported_g"].items()}
UNSUPPORTED_M: dict[int, str] = {int(k): v for k, v in _DATA["unsupported_m"].items()}

CYCLES = frozenset((730, 740, 810, 820, 830, 840, 850, 860, 870, 880, 890))
AXES = "xyzabc"


class Block:
    """One block, read: words present, G/M codes by modal group, settings, comment.

    words : letter -> value of every word present (g, m excluded), in program units.
    g : modal group -> G code x10 (G59.1 -> 591).
    m : modal group -> M code.
    motion : the motion code the block executes (LinuxCNC motion_to_be), -1 for none.
    """

    __slots__ = ("words", "g", "m", "m_count", "motion", "comment", "settings",
                 "named", "user_m", "line")

    def __init__(self, line: Line):
        self.words: dict[str, float] = {}
        self.g: dict[int, int] = {}
        self.m: dict[int, int] = {}
        self.m_count = 0
        self.motion = -1
        self.comment: str | None = None
        self.settings: list[tuple[int, float]] = []
        self.named: list[tuple[str, float]] = []
        self.user_m = False
        self.line = line

    # LinuxCNC conventions: p/q/l default -1, h default -1
    @property
    def p(self) -> float:
        return self.words.get("p", -1.0)

    @property
    def q(self) -> float:
        return self.words.get("q", -1.0)

    @property
    def l(self) -> int:  # noqa: E743
        v = self.words.get("l")
        return -1 if v is None else int(v)

    def has_axis(self) -> bool:
        """Axis or polar (``@`` radius, ``^`` angle) words."""
        w = self.words
        return ("x" in w or "y" in w or "z" in w or "a" in w or "b" in w or "c" in w
                or "@" in w or "^" in w)


def _col(line: Line, k: int, col: int) -> int:
    return col if col else item_column(line, k)


def read_block(line: Line, ctx) -> Block:
    """Evaluate the items of ``line`` into a :class:`Block` and check it word by word."""
    block = Block(line)
    for k, item in enumerate(line.items):
        tag = item[0]
        if tag == "w":
            letter, v, col = item[1], item[2], item[3]
            if type(v) is not float:
                v = v(ctx)
            try:
                _word(block, letter, v)
            except NgcError as exc:
                if not exc.column:
                    exc.column = _col(line, k, col)
                raise
        elif tag == "c":
            block.comment = item[1]
        elif tag in "pi":
            index = item[1] if type(item[1]) is float else item[1](ctx)
            i = int(index)
            if i < 1 or i >= 5602:
                raise NgcError("parameter_range", item[3])
            if 5400 <= i <= 5413 or 5420 <= i <= 5428:
                raise NgcError("parameter_readonly", item[3])
            if tag == "p":
                v = item[2] if type(item[2]) is float else item[2](ctx)
                block.settings.append((i, v))
        elif tag == "n":
            ctx.declare_named(item[1])
            v = item[2] if type(item[2]) is float else item[2](ctx)
            block.named.append((item[1], v))
    if line.error is not None:
        raise line.error
    if "x" in block.words and ctx.s.diameter_mode:  # read_x in G7: a diameter
        block.words["x"] /= 2
    return block


def _word(block: Block, letter: str, v: float) -> None:
    words = block.words
    if letter == "g":
        _g_code(block, v)
        return
    if letter == "m":
        _m_code(block, v)
        return
    if letter in "pq":
        if words.get(letter, -1.0) > -1.0:
            raise NgcError("duplicate_word", letter=letter)
        words[letter] = v
        return
    if letter in words:
        raise NgcError("duplicate_word", letter=letter)
    if letter == "f":
        if v < 0.0:
            raise NgcError("negative_feed")
    elif letter == "s":
        if v < 0.0:
            raise NgcError("negative_speed")
    elif letter in "hlt":
        v = float(to_integer(v))
        if letter == "h" and v < -1:
            raise NgcError("negative_h_word")
        if letter == "l" and v < 0:
            raise NgcError("negative_l_word")
        if letter == "t" and v < 0:
            raise NgcError("negative_tool")
    words[letter] = v


def _g_code(block: Block, v: float) -> None:
    v10 = 10.0 * v
    code = math.floor(v10)
    if v10 - code > 0.999:
        code = math.ceil(v10)
    elif v10 - code > 0.001:
        raise NgcError("g_code_range")
    code = int(code)
    if code > 999:
        raise NgcError("g_code_range")
    if code < 0:
        raise NgcError("negative_g_code")
    group = G_GROUP.get(code)
    if group is None:
        raise NgcError("unknown_g_code")
    g = block.g
    if code == 800 and group in g:
        return
    if g.get(group, 800) != 800 and group in g:
        raise NgcError("modal_group_conflict")
    g[group] = code


def _m_code(block: Block, v: float) -> None:
    code = to_integer(v)
    if code < 0:
        raise NgcError("negative_m_code")
    if code > 199:
        raise NgcError("m_code_range", code=code)
    group = M_GROUP.get(code)
    if group is None:
        if code < 100:
            raise NgcError("unknown_m_code", code=code)
        group = 10
        block.user_m = True
    if group in block.m:
        raise NgcError("m_modal_group_conflict")
    block.m[group] = code
    block.m_count += 1


# --------------------------------------------------------------------------------------------
# enhance_block and check_items
# --------------------------------------------------------------------------------------------


_LATHE_CYCLES = frozenset((700, 710, 711, 712, 720, 721, 722))


def enhance(block: Block, motion_mode: int, plane: int = 170) -> None:
    """Decide the motion of the block and check axis words against it."""
    axis = block.has_axis()
    mode0 = block.g.get(0, -1)
    mode1 = block.g.get(1, -1)
    covets = mode0 in (100, 280, 300, 520, 920)
    w = block.words
    polar = "@" in w or "^" in w
    if polar:
        if plane != 170:
            raise NgcError("polar_plane")
        if "x" in w or "y" in w:
            raise NgcError("polar_with_x" if "x" in w else "polar_with_y")
        if mode0 == 920:
            raise NgcError("polar_not_motion")
    if mode1 != -1:
        if mode1 == 800:
            if axis and not covets:
                raise NgcError("axis_words_with_g80")
            if not axis and mode0 in (520, 920):
                raise NgcError("axis_words_missing_g92")
        else:
            if covets:
                raise NgcError("two_axis_g_codes")
            if not axis and mode1 not in (0, 10, 20, 30, 52) and mode1 not in _LATHE_CYCLES:
                raise NgcError("axis_words_missing")
        block.motion = mode1
    elif covets:
        if not axis and mode0 in (520, 920):
            raise NgcError("axis_words_missing_g92")
    elif axis:
        dynamic = block.g.get(8) in (431, 432)  # G43.1/G43.2 take the axis words
        if motion_mode in (-1, 800) and not dynamic:
            raise NgcError("axis_words_unused")
        if not dynamic:
            block.motion = motion_mode
    elif motion_mode in (20, 30) and any(c in block.words for c in "ijk"):
        block.motion = motion_mode


def check(block: Block, distance_incremental: bool) -> None:
    """check_g_codes, check_m_codes and check_other_codes."""
    w = block.words
    g = block.g
    mode0 = g.get(0, -1)
    mode1 = g.get(1, -1)
    motion = block.motion
    p = block.p
    if mode0 == 40:
        if p == -1.0:
            raise NgcError("dwell_missing")
        if mode1 in (20, 30):
            raise NgcError("g4_with_arc")
    elif mode0 == 100:
        l = block.l  # noqa: E741
        p_int = int(p + 0.5) if p >= 0 else int(p - 0.5)
        if l not in (1, 2, 10, 11, 20, 0):
            raise NgcError("g10_l_missing")
        if (p + 0.0001) - p_int > 0.0002:
            raise NgcError("g10_p_integer")
        if l in (2, 20) and (p_int < 0 or p_int > 9):
            raise NgcError("g10_p_range", l=l)
        if l in (1, 10, 11) and p_int < 1:
            raise NgcError("g10_p_tool_range", l=l)
    elif mode0 == 530:
        if motion not in (0, 10):
            raise NgcError("g53_motion")
        if g.get(3) == 910 or (g.get(3) != 900 and distance_incremental):
            raise NgcError("g53_incremental")
    if block.m_count > 4:
        raise NgcError("too_many_m_codes")
    cycle = motion in CYCLES
    if "a" in w and cycle:
        raise NgcError("cycle_axis_a")
    if "b" in w and cycle:
        raise NgcError("cycle_axis_b")
    if "c" in w and cycle:
        raise NgcError("cycle_axis_c")
    lathe = motion in _LATHE_CYCLES  # G70..G72.2: refused as unsupported when run
    if "d" in w and g.get(7) not in (410, 420, 411, 421) and g.get(14) != 960 and not lathe:
        raise NgcError("unused_d")
    if "e" in w and motion not in (760, 330, 331, 700) and block.m.get(5) not in (66, 67, 68):
        raise NgcError("unused_e")
    if "h" in w and g.get(8) not in (430, 432) and motion != 760:
        raise NgcError("unused_h")
    ijk_users = (20, 30, 50, 51, 760, 870)
    if "i" in w and motion not in ijk_users and motion != 331 and mode0 != 100 and not (
            lathe and motion != 700):
        raise NgcError("unused_i")
    if "j" in w and motion not in ijk_users and mode0 != 100:
        raise NgcError("unused_j")
    if "k" in w and motion not in (20, 30, 330, 331, 760, 870):
        raise NgcError("unused_k")
    if "l" in w and not (
        810 <= motion <= 890 or motion in (760, 52, 730) or mode0 == 100
        or g.get(7) in (410, 411, 420, 421) or block.m.get(5) == 66
    ):
        raise NgcError("unused_l")
    if "p" in w:
        if not (
            mode0 in (100, 40) or g.get(13) == 640
            or motion in (760, 820, 860, 880, 890, 50, 52, 20, 30, 740, 840, 700)
            or block.m.get(9) in (50, 51, 52, 53) or block.m.get(5) in (62, 63, 64, 65, 66)
            or block.m.get(7) == 19 or block.user_m
        ):
            raise NgcError("unused_p")
        p_value = int(math.floor(w["p"] + 0.5))
        if (motion in (20, 30) or block.m.get(7) == 19) and abs(p_value - w["p"]) > 0.001:
            raise NgcError("arc_p_integer")
        if block.m.get(7) == 19 and not 0 <= p_value <= 2:
            raise NgcError("m19_p_range")
        if motion in (20, 30) and p_value < 1:
            raise NgcError("arc_p_range")
    if block.q != -1.0 and not (
        motion in (830, 730, 50, 760) or lathe or block.m.get(5) in (66, 67, 68)
        or mode0 == 100 or block.m.get(6) == 61 or g.get(13) == 640 or block.m.get(7) == 19
        or block.user_m
    ):
        raise NgcError("unused_q")
    if "r" in w and not (
        motion in (20, 30, 760, 730, 740) or 810 <= motion <= 890 or (lathe and motion != 700)
        or g.get(7) in (411, 421) or mode0 == 100 or block.m.get(7) == 19
    ):
        raise NgcError("unused_r")
    if "r" in w and block.m.get(7) == 19 and not 0.0 <= w["r"] <= 360.0:
        raise NgcError("m19_r_range")
    if motion in (330, 331):
        if "k" not in w:
            raise NgcError("g33_k_missing")
        if "f" in w:
            raise NgcError("g33_f_used")
    elif motion == 760:
        if block.p == -1.0:
            raise NgcError("g76_p_missing")
        if "i" not in w or "j" not in w or "k" not in w:
            raise NgcError("g76_ijk_missing")
