"""Reading one RS274/NGC line into items, as LinuxCNC's ``read_text``/``read_items`` do.

A line is first *reduced* (``close_and_downcase``): blanks and tabs outside comments are
dropped and letters outside comments are lower-cased; ``(...)`` comments keep their text and
may not nest; ``;`` starts a comment to the end of the line. Then the items are read left to
right: an optional ``/`` (block delete) and ``N`` number first, then either an O-word control
line or words (``g1``, ``x[#1+2]``), parameter settings (``#5=2``, ``#<name>=#5``) and
comments.

Parsing happens once per source line. Values are constants or functions of the evaluation
context (see :mod:`interpreters.rs274ngc.expr`). A syntax error does not stop parsing at
once: it is kept in ``Line.error`` and raised when execution reaches that point of the line,
after the items before it have been evaluated, which is the order LinuxCNC reports errors in.
"""

from __future__ import annotations

import re

from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.expr import Reader, Value

# letters that start a word (LinuxCNC _readers[]); n and o only at the start of a line
WORD_LETTERS = frozenset("abcdefghijklmpqrstxyz")  # rs274 machine: no U V W
O_KINDS = (
    "sub", "endsub", "call", "do", "while", "repeat", "if", "elseif", "else", "endif",
    "break", "continue", "endwhile", "endrepeat", "return",
)
_UPPER = str.maketrans("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz")
_REDUCE = str.maketrans("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz", " \t\r")
_SIMPLE = re.compile(r"(?:[a-mp-txyz][+-]?(?:\d+\.?\d*|\.\d+))+")
_SIMPLE_WORD = re.compile(r"([a-z])([+-]?(?:\d+\.?\d*|\.\d+))")
_DIGITS = re.compile(r"\d*")
#: a line starting with M98 or M99 (LinuxCNC reads it as an O-line: read_items)
_FANUC = re.compile(r"m0*9[89](?:\.0*)?(?![0-9.])")


class OLine:
    """An O-word control line.

    kind : one of :data:`O_KINDS`.
    name : the label as written inside ``<>`` or the number as text ("100").
    col : source column of the ``o``.
    args : call arguments (values) for ``call``.
    value : the condition of while/if/elseif/repeat, or the return value of endsub/return.
    """

    __slots__ = ("kind", "name", "col", "args", "value", "comment", "value_error",
                 "trailing_error", "handler", "name_value", "loop", "dynamic")

    def __init__(self, kind, name, col, args=(), value=None, comment=None):
        self.kind = kind
        self.handler = "o_" + kind  # the interpreter's method (flow.py)
        self.name = name
        self.col = col
        self.args = args
        self.value = value
        self.comment = comment
        self.value_error = None  # a syntax error in the condition or the call arguments
        self.trailing_error = None  # text after the O-word command
        #: the number of ``o#1 call``/``o[...] call`` (or M98's P word): computed when read
        self.name_value = None
        self.loop = None  # M98's L word (repeat count), a value, or None
        #: the label is found when the line is read (name_value, or M99's running sub)
        self.dynamic = kind in ("m98", "m99")


class Line:
    """One source line, parsed.

    number : 1-based line number in its file.
    raw : the text without the line end.
    nlabel : LinuxCNC's N column for trace output ("N10    " or "N..... ").
    skip_error : error raised even when the line is skipped (comment and N-number format).
    blank : nothing to execute (empty after reduction, or a block-deleted line).
    slash : the line starts with ``/`` (block delete).
    percent : the line is a lone ``%``.
    items : words, settings and comments in reading order (see module docstring).
    error : the syntax error to raise after the items, if any.
    o : the O-word of a control line, else None.
    """

    # class-level defaults: a line only stores what differs (parsing is on the hot path)
    nlabel: str | None = None  # computed when a trace needs it (see n_label)
    skip_error: NgcError | None = None
    blank = False
    slash = False
    percent = False
    error: NgcError | None = None
    o: OLine | None = None
    const = False
    #: only G0/G1 (constant), F and axis words, each at most once: the fast path
    simple = False
    #: for simple lines of constants: (motion code or -1, {letter: value} without g)
    fast: tuple | None = None
    #: only parameter settings (``#1 = [#1 + 1]``)
    assign = False
    #: an O-line whose label (True) or command ("kind") is wrong: LinuxCNC reports that
    #: even when the line is skipped ("kind" not while a subroutine definition is skipped)
    o_error: bool | str = False

    def __init__(self, number: int, raw: str):
        self.number = number
        self.raw = raw

    def __getattr__(self, name: str):
        """``items`` (words, settings and comments in reading order) of a line of plain
        constant words, which the fast paths execute without them: built on first use."""
        if name != "items":
            raise AttributeError(name)
        items = self.items = [("w", a, float(b), 0) for a, b in self.__dict__.get("found", ())]
        return items


def n_label(raw: str) -> str:
    """The N column ``rs274`` prints for a line (saicanon print_nc_line_number)."""
    k = 0
    n = len(raw)
    while k < n and raw[k] in "\t /":
        k += 1
    if k < n and raw[k] in "nN":
        m = _DIGITS.match(raw, k + 1).group()
        return "N" + m + " " * max(0, 6 - len(m))
    return "N..... "


def column_map(raw: str) -> list[int]:
    """1-based source column of each character of the reduced line."""
    cols = []
    comment = semi = False
    for i, ch in enumerate(raw):
        if ch == ";" and not comment:
            semi = True
        if semi or comment:
            cols.append(i + 1)
            if comment and ch == ")":
                comment = False
            continue
        if ch in " \t\r":
            continue
        if ch == "(":
            comment = True
        cols.append(i + 1)
    return cols


def reduce_line(raw: str) -> str:
    """close_and_downcase: drop blanks and lower-case outside comments; check comments."""
    if "(" not in raw and ";" not in raw and ")" not in raw:
        return raw.translate(_REDUCE)
    out = []
    comment = semi = False
    for i, ch in enumerate(raw):
        if ch == ";" and not comment:
            semi = True
        if semi:
            out.append(ch)
            continue
        if comment:
            out.append(ch)
            if ch == ")":
                comment = False
            elif ch == "(":
                raise NgcError("nested_comment", i + 1)
        elif ch in " \t\r":
            continue
        elif "A" <= ch <= "Z":
            out.append(chr(ord(ch) + 32))
        else:
            if ch == "(":
                comment = True
            out.append(ch)
    if comment:
        raise NgcError("unclosed_comment", raw.find("(") + 1)
    return "".join(out)


def parse_line(number: int, raw: str) -> Line:
    """Parse one source line (without its line end)."""
    line = Line(number, raw)
    if raw.isascii() and "(" not in raw and ";" not in raw and ")" not in raw:
        text = raw.replace(" ", "")
        if "\t" in text or "\r" in text:
            text = text.replace("\t", "").replace("\r", "")
        text = text.lower()
    else:
        try:
            text = reduce_line(raw)
        except NgcError as exc:
            line.skip_error = exc
            return line
    if text == "%":
        line.percent = True
        return line
    if not text:
        line.blank = True
        return line
    if text[0] != "n" and _SIMPLE.fullmatch(text) and not (text[0] == "m" and _FANUC.match(text)):
        found = line.found = _SIMPLE_WORD.findall(text)
        line.const = True
        d = dict(found)
        if len(d) == len(found) and d.keys() <= _SIMPLE_LETTERS:
            g = d.pop("g", None)
            f = d.get("f")
            if (g is None or g in _G01) and (f is None or f[0] != "-"):
                line.simple = True
                words = {k: float(v) for k, v in d.items()}
                line.fast = (-1 if g is None else (0 if float(g) == 0.0 else 10), words)
        return line
    _parse_items(line, text)
    line.simple = _is_simple(line)
    if line.error is None and line.o is None and line.items and all(
            it[0] in "pn" for it in line.items):
        line.assign = True
    return line


_G01 = frozenset(("0", "1", "00", "01", "0.", "1.", "0.0", "1.0", "000", "001"))


_SIMPLE_LETTERS = frozenset("gxyzabcf")


def _is_simple(line: Line) -> bool:
    if line.error is not None or line.o is not None or line.slash or not line.items:
        return False
    seen = set()
    for item in line.items:
        if item[0] != "w":
            return False
        letter = item[1]
        if letter not in _SIMPLE_LETTERS or letter in seen:
            return False
        seen.add(letter)
        if letter == "g" and item[2] not in (0.0, 1.0):
            return False
        if letter == "f" and type(item[2]) is float and item[2] < 0.0:
            return False
    return True


def _parse_items(line: Line, text: str) -> None:
    reader = _LazyReader(text, line.raw)
    pos = 0
    if text[0] == "/":
        line.slash = True
        pos = 1
        if len(text) == 1:
            line.blank = True
            return
    if pos < len(text) and text[pos] == "n":
        try:
            pos = _n_number(reader, pos)
        except NgcError as exc:
            line.skip_error = exc
            return
    if pos >= len(text):
        line.blank = True
        return
    if text[pos] == "o":
        reader.defer = True
        try:
            _o_line(reader, pos, line)
        except NgcError as exc:
            line.error = exc
            if line.o_error is False and exc.kind != "unsupported":
                line.o_error = True  # errors in the label: LinuxCNC reports them even while skipping
        return
    if text[pos] == "m":
        fanuc = _fanuc_sub(reader, pos)
        if fanuc == 98:
            _m98_line(reader, pos, line)
            return
        if fanuc == 99:  # a return when in a call (decided when run), else M99 (a stop)
            line.o = OLine("m99", "", reader.col(pos))
    items = line.items = []
    reader.defer = True
    try:
        while pos < len(text):
            pos = _item(reader, pos, items)
    except NgcError as exc:
        line.error = exc
    if reader.deferred is not None:  # raised by its value, after the values before it
        line.error = reader.deferred
    line.const = line.error is None and all(
        it[0] == "w" and type(it[2]) is float for it in items
    )


class _LazyReader(Reader):
    """A :class:`Reader` that computes the column map only when a diagnostic needs it."""

    __slots__ = ("raw", "_cols")

    def __init__(self, text: str, raw: str):
        self.text = text
        self.raw = raw
        self._cols = None
        self.defer = False
        self.deferred = None

    @property
    def cols(self):  # type: ignore[override]
        if self._cols is None:
            self._cols = column_map(self.raw)
        return self._cols


def _n_number(reader: Reader, pos: int) -> int:
    m = _DIGITS.match(reader.text, pos + 1).group()
    if not m:
        raise reader.error("bad_line_number", pos + 1)
    pos += 1 + len(m)
    if pos < len(reader.text) and reader.text[pos] == ".":
        m = _DIGITS.match(reader.text, pos + 1).group()
        if not m:
            raise reader.error("bad_line_number", pos + 1)
        pos += 1 + len(m)
    return pos


def _fanuc_sub(reader: Reader, pos: int) -> int:
    """98 or 99 when the line's first word is M98 or M99 (LinuxCNC reads those lines as
    O-lines, read_items/read_o), else 0."""
    try:
        v, _ = reader.integer(pos + 1)
    except NgcError:
        return 0
    return int(v) if type(v) is float and v in (98.0, 99.0) else 0


def _m98_line(reader: Reader, pos: int, line: Line) -> None:
    """``M98 P<number> [L<count>]``: a Fanuc-style call, read as read_o reads it (all the
    words of the line, then the P word)."""
    o = line.o = OLine("m98", "", reader.col(pos))
    items: list = []
    pos = reader.integer(pos + 1)[1]
    reader.defer = True
    try:
        while pos < len(reader.text):
            pos = _item(reader, pos, items)
    except NgcError as exc:
        o.value_error = exc
    if reader.deferred is not None:
        o.value_error = reader.deferred
    if o.value_error is None:
        words = {it[1]: it[2] for it in items if it[0] == "w"}
        if "p" not in words:
            o.value_error = NgcError("m98_no_p")
        else:
            o.name_value = words["p"]
            o.loop = words.get("l")
            o.comment = next((it[1] for it in items if it[0] == "c"), None)
    line.error = o.value_error


def _item(reader: Reader, pos: int, items: list) -> int:
    text = reader.text
    c = text[pos]
    col = reader.col(pos)
    if c in WORD_LETTERS:
        if c != "g" and c != "m":
            _check_repeated(items, c, col)
        v, end = reader.real_value(pos + 1)
        items.append(("w", c, v, col))
        return end
    if c == "(":
        end = text.index(")", pos)
        items.append(("c", text[pos + 1 : end], col))
        return end + 1
    if c == ";":
        return len(text)
    if c == "#":
        return _setting(reader, pos, items, col)
    if c == "@" or c == "^":  # polar radius and angle (read_radius, read_theta)
        _check_repeated(items, c, col)
        v, end = reader.real_value(pos + 1)
        items.append(("w", c, v, col))
        return end
    if c == "$":
        raise NgcError("unsupported", col, what="spindle selection ($)")
    if c < " " or c > "z" or c == " ":
        raise NgcError("bad_character", col, char="\\%03o" % (ord(c) & 0xFF))
    raise NgcError("bad_character", col, char=c)


def _check_repeated(items: list, letter: str, col: int) -> None:
    """LinuxCNC refuses a second word of a letter before reading its value; a P, Q or L
    only counts when it was > -1 (read_p: ``p_number > -1.0``), known here if constant."""
    for item in items:
        if item[0] == "w" and item[1] == letter:
            v = item[2]
            if letter in "pql" and (type(v) is not float or v <= -1.0):
                continue  # decided when the block is read
            raise NgcError("duplicate_word", col, letter=letter)


def _setting(reader: Reader, pos: int, items: list, col: int) -> int:
    text = reader.text
    pos += 1
    if pos < len(text) and text[pos] == "<":
        name, pos = reader.name(pos)
        if pos >= len(text) or text[pos] != "=":
            raise reader.error("equal_sign_missing", pos)
        v, pos = reader.real_value(pos + 1)
        items.append(("n", name, v, col))
        return pos
    index, pos = reader.integer(pos)
    items.append(("i", index, None, col))  # checked (range, read-only) before reading '='
    if pos >= len(text) or text[pos] != "=":
        raise reader.error("equal_sign_missing", pos)
    v, pos = reader.real_value(pos + 1)
    items[-1] = ("p", index, v, col)
    return pos


def _o_line(reader: Reader, pos: int, line: Line) -> None:
    """Read an O-line as LinuxCNC's read_o does, in three stages whose errors LinuxCNC
    reports at different times: the label and command (always, even while skipping:
    ``line.error`` with ``line.o_error``), the condition or arguments (``o.value_error``,
    also while skipping to this label) and the text after them (``o.trailing_error``, only
    when the line is executed). Errors met while folding constants are deferred to the
    evaluation of the value (the first one still precedes later syntax errors)."""
    text = reader.text
    col = reader.col(pos)
    pos += 1
    if pos < len(text) and text[pos] == "<":
        name, pos = reader.name(pos)
    else:
        v, pos = reader.integer(pos)
        if reader.deferred is not None:
            raise reader.deferred
        if type(v) is not float:
            name = ""
        else:
            name = str(int(v))
    kind = next((k for k in O_KINDS if text.startswith(k, pos)), None)
    if kind is None:
        if pos < len(text) and text[pos] not in "(;":
            line.o_error = "kind"
            raise reader.error("unknown_o_command", pos)
        kind = "program"  # a bare Fanuc-style program number (O1000): no command
    else:
        pos += len(kind)
    o = line.o = OLine(kind, name, col)
    if not name:
        o.name_value = v
        o.dynamic = True
    try:
        if kind in ("while", "if", "elseif", "repeat"):
            if pos >= len(text) or text[pos] != "[":
                raise reader.error("o_bracket_missing", pos, what=kind)
            o.value, pos = reader.expression(pos)
        elif kind in ("endsub", "return"):
            if pos < len(text) and text[pos] == "[":
                o.value, pos = reader.expression(pos)
        elif kind == "call":
            args: list[Value] = []
            o.args = args
            while pos < len(text) and text[pos] in "[(":
                if text[pos] == "(":
                    end = text.index(")", pos)
                    o.comment = text[pos + 1 : end]
                    pos = end + 1
                    continue
                if len(args) >= 30:
                    raise reader.error("too_many_arguments", pos)
                v, pos = reader.expression(pos)
                args.append(v)
    except NgcError as exc:
        o.value_error = reader.deferred or exc
        line.error = o.value_error
        return
    while pos < len(text):
        if text[pos] == ";":
            break
        if text[pos] == "(":
            end = text.index(")", pos)
            o.comment = text[pos + 1 : end]
            pos = end + 1
            continue
        o.trailing_error = reader.error("text_after_o_word", pos)
        line.error = reader.deferred or o.trailing_error
        return
    if reader.deferred is not None:
        line.error = reader.deferred


def item_column(line: Line, k: int) -> int:
    """Source column of the k-th item of a line parsed by the fast path (columns unset)."""
    cols = column_map(line.raw)
    text = reduce_line(line.raw)
    seen = -1
    for i, ch in enumerate(text):
        if ch in WORD_LETTERS:
            seen += 1
            if seen == k:
                return cols[i]
    return 1
