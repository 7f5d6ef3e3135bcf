"""CYCLE72 (contour milling): the tool follows a contour — a subprogram beside the program or a
section of this program between two labels — level by level, on it (_RL 40) or beside it with
the control's own tool radius compensation (_RL 41/42: G41/G42 at the tool radius plus _FAL,
:mod:`interpreters.sinumerik.cutcom`, so corners, roundings RND= and chamfers CHF= of the
contour are compensated as in a program).

The contour is read by a small reader of its own: blocks of G0/G1/G2/G3 (G90/G91) with the
working plane's axis words, I J K (the centre, incremental from the start) or CR= (negative:
more than a semicircle), CHF=/CHR=/RND=; N, F and the plane's G17/G18/G19 are read and left; a
subprogram's PROC line and its end (M17, M2, M30, RET) too. Anything else in a contour block (an
expression, a variable, another word) is ``unsupported`` naming the block. The first block is
the contour's start point.

Per level (at most _MID deep, equal, down to _DP + _FALD when roughing, _DP finishing):
over the approach point _LP1 before the start along the start tangent, down at _FFD, along
the contour at _FFP1 (the approach and retraction straight: a quarter or semicircle (_AS1/_AS2
2, 3) is simulated as the straight one, which ``cycle_simplified`` says), off _LP2 along the
end tangent at _FF3, up along the tool axis at _FF3 (by _SDIS, at most to the reference
plane), then back over the approach point as _VARI's hundreds say. Phases
``roughing depth i/n``, ``finishing depth i/n``; the cycle ends at the retraction plane.
"""

from __future__ import annotations

import math
import re
from pathlib import Path as FsPath

from interpreters.sinumerik.cycles.common import Context
from interpreters.sinumerik.cycles.path import TINY, levels
from vmach import canon
from vmach.files import contained, decode_text, read_program_bytes

_WORD = re.compile(r"\s*([A-Z]+)\s*(=?)\s*([-+]?(?:\d+\.?\d*|\.\d+))")
_LABEL = re.compile(r"^\s*([A-Z_][A-Z0-9_]*)\s*:(?!=)")
_ENDS = {"M17", "M2", "M02", "M30", "RET"}
_IGNORED_G = {17, 18, 19, 9, 60, 64, 94, 95, 71, 710}
#: most contour blocks a contour may have
MAX_BLOCKS = 10_000


def _lines(ctx: Context, kname: str) -> list[tuple[int, str]]:
    """(line number, upper-case text without comment) of the contour's blocks."""
    here = FsPath(ctx.src.path)
    if ":" in kname:
        first, last = (s.strip().upper() for s in kname.split(":", 1))
        text = _read(ctx, here)
        out, inside = [], False
        for n, raw in enumerate(text, 1):
            m = _LABEL.match(raw.upper())
            if m and m.group(1) == first:
                inside = True
            if inside:
                out.append((n, raw))
            if inside and m and m.group(1) == last:
                return out
        raise ctx.fail(f"the contour section {kname!r}: its labels are not both in this program")
    name = kname.strip().upper()
    if not re.fullmatch(r"[A-Z_][A-Z0-9_]*", name):
        raise ctx.fail(f"{kname!r} names no contour subprogram or section")
    directory = here.resolve().parent
    found = None
    for ext in (".SPF", ".MPF"):
        for entry in sorted(directory.iterdir()) if directory.is_dir() else []:
            if entry.name.upper() == name + ext and contained(entry, directory) and entry.is_file():
                found = entry
                break
        if found:
            break
    if found is None:
        raise ctx.fail(f"the contour subprogram {name} is not beside the program")
    out = []
    for n, raw in enumerate(_read(ctx, found), 1):
        t = raw.split(";", 1)[0].strip().upper()
        if t.startswith("PROC") or t.startswith("%"):
            continue
        out.append((n, raw))
        if t in _ENDS:
            break
    return out


def _read(ctx: Context, path: FsPath) -> list[str]:
    try:
        return decode_text(read_program_bytes(path, str(path))).splitlines()
    except Exception as exc:      # an unreadable contour is the cycle's error, not a traceback
        raise ctx.fail(f"the contour file cannot be read: {exc}") from None


def read_contour(ctx: Context, kname: str):
    """The contour's start point (a, b) and its elements, each (end (a, b), centre (a, b) or
    None, clockwise, corner words {CHF|CHR|RND: mm}), program coordinates of the plane, mm."""
    lines = _lines(ctx, kname)
    if len(lines) > MAX_BLOCKS:
        raise ctx.fail(f"the contour has more than {MAX_BLOCKS} blocks")
    names = ctx.machine.plane_axes[:2]
    centre_words = {"X": "I", "Y": "J", "Z": "K"}
    ci, cj = centre_words.get(names[0]), centre_words.get(names[1])
    plane_g = {("X", "Y"): 17, ("Z", "X"): 18, ("Y", "Z"): 19}.get(tuple(names))
    s = ctx.scale
    motion, absolute, cur, start, out = 1, True, None, None, []
    for n, raw in lines:
        t = raw.split(";", 1)[0].upper()
        m = _LABEL.match(t)
        if m:
            t = t[m.end():]
        t = t.strip().lstrip("/")
        if not t:
            continue
        if t in _ENDS:
            break
        words, pos = {}, 0
        gs = []
        while pos < len(t):
            w = _WORD.match(t, pos)
            if w is None:
                if t[pos:].strip() == "":
                    break
                raise ctx.fail(f"the contour's line {n} ({raw.strip()!r}) holds what vmach's contour "
                               "reader does not read (numbers and the plane's words only)", line=n)
            key, value = w.group(1), float(w.group(3))
            if key == "G":
                gs.append(int(value))
            else:
                words[key] = value
            pos = w.end()
        for g in gs:
            if g in (0, 1, 2, 3):
                motion = g
            elif g in (90, 91):
                absolute = g == 90
            elif g in (17, 18, 19) and g != plane_g:
                raise ctx.fail(f"the contour's line {n} changes the working plane", line=n)
            elif g not in _IGNORED_G:
                raise ctx.fail(f"the contour's line {n}: G{g} is not read in a contour", line=n)
        extra = set(words) - {names[0], names[1], ci, cj, "CR", "CHF", "CHR", "RND", "N", "F", "M"}
        if extra:
            raise ctx.fail(f"the contour's line {n}: {', '.join(sorted(extra))} not read in a contour",
                           line=n)
        if "M" in words and int(words["M"]) in (2, 17, 30):
            break
        base = cur if cur is not None else (0.0, 0.0)
        end = tuple((words[k] * s + (0.0 if absolute else base[i])) if k in words else base[i]
                    for i, k in enumerate(names))
        if cur is None:
            cur = start = end
            continue
        corner = {k: words[k] * s for k in ("CHF", "CHR", "RND") if k in words}
        if motion in (0, 1):
            if math.dist(cur, end) > TINY or corner:
                out.append((end, None, False, corner))
        else:
            cw = motion == 2
            if "CR" in words:
                centre = _centre(ctx, cur, end, words["CR"] * s, cw, n)
            else:
                centre = (cur[0] + words.get(ci, 0.0) * s, cur[1] + words.get(cj, 0.0) * s)
            out.append((end, centre, cw, corner))
        cur = end
    if start is None or not out:
        raise ctx.fail(f"the contour {kname!r} has no elements")
    return start, out


def _centre(ctx: Context, p, q, cr: float, cw: bool, n: int):
    """The centre of the arc p → q of radius |cr| (cr < 0: more than a semicircle)."""
    d = math.dist(p, q)
    r = abs(cr)
    if d <= TINY or d > 2 * r + 1e-9:
        raise ctx.fail(f"the contour's line {n}: no arc of radius {r:g} joins its ends", line=n)
    h = math.sqrt(max(r * r - d * d / 4, 0.0))
    mx, my = (p[0] + q[0]) / 2, (p[1] + q[1]) / 2
    ux, uy = (q[0] - p[0]) / d, (q[1] - p[1]) / d
    left = (cr > 0) != cw              # the centre left of p → q: G3 short or G2 long
    sign = 1.0 if left else -1.0
    return (mx - sign * uy * h, my + sign * ux * h)


def _tangent(p, end, centre, cw, at_end: bool):
    """Unit tangent of an element from p at its start (or end)."""
    if centre is None:
        d = (end[0] - p[0], end[1] - p[1])
    else:
        q = end if at_end else p
        u = (q[0] - centre[0], q[1] - centre[1])
        d = (u[1], -u[0]) if cw else (-u[1], u[0])
    n = math.hypot(*d)
    return (d[0] / n, d[1] / n)


def _send(ctx: Context, f: float, end, centre=None, cw: bool = False, words=None) -> None:
    """One contour move through chamfers, roundings and radius compensation, as a block."""
    m, p = ctx.machine, ctx.path
    start3 = m.program_point()
    if centre is None:
        cmd = canon.LinearFeed(p.src, axes=p._target(end[0], end[1], None), feed=f)
    else:
        c3 = list(start3)
        c3[p.ia], c3[p.ib] = centre
        cm = m.frames.to_machine(tuple(c3))
        cmd = canon.ArcFeed(p.src, axes=p._target(end[0], end[1], None), plane=p.plane,
                            center=(cm[p.ia], cm[p.ib]), clockwise=m.machine_cw(cw), feed=f)
    m.corners.take(cmd, start3, m.program_point(), centre, p.src, words or {}, m.send)


def mill(ctx: Context) -> None:
    """CYCLE72."""
    c = ctx.call
    start, elements = read_contour(ctx, c["KNAME"])
    h = ctx.heights(relative=False)
    r = ctx.tool_radius()
    vari = int(c["VARI"])
    unit, between, back = vari % 10, vari // 10 % 10, vari // 100 % 10
    if unit not in (1, 2) or between not in (0, 1) or back > 3:
        raise ctx.fail(f"_VARI {vari} is no machining type of the cycle", vari=vari)
    rl = int(c["RL"])
    if rl not in (40, 41, 42):
        raise ctx.fail(f"_RL {rl} is none of 40, 41, 42", rl=rl)
    if int(c["AS1"]) % 10 in (2, 3) or int(c["AS2"]) % 10 in (2, 3):
        ctx.simplified("the quarter or semicircle approach and retraction run straight along the "
                       "contour's tangent")
    if c["FS"]:
        ctx.simplified("chamfering the contour's edge (_FS) is not simulated")
    f_plane, f_depth, f3 = ctx.feed("FFP1"), ctx.feed("FFD", "FFP1"), ctx.feed("FF3", "FFP1")
    rough = unit == 1
    fal = abs(ctx.mm("FAL")) if rough else 0.0
    depths = levels(h.rfp, h.depth + (abs(ctx.mm("FALD")) if rough else 0.0), abs(ctx.mm("MID")))
    ctx.count(len(depths) * len(elements), "depth levels and contour elements")
    t0 = _tangent(start, *elements[0][:3], at_end=False)
    before = elements[-2][0] if len(elements) > 1 else start
    last = elements[-1]
    t1 = _tangent(before, last[0], last[1], last[2], at_end=True)
    lp1, lp2 = abs(ctx.mm("LP1")), abs(ctx.mm("LP2"))
    p_in = (start[0] - lp1 * t0[0], start[1] - lp1 * t0[1])
    p_out = (last[0][0] + lp2 * t1[0], last[0][1] + lp2 * t1[1])
    p, m = ctx.path, ctx.machine
    label = "roughing" if rough else "finishing"
    ctx.approach(h, *p_in)
    for i, z in enumerate(depths, 1):
        level = f"{label} depth {i}/{len(depths)}" if len(depths) > 1 else label
        p.phase(f"{level} infeed")
        p.feed(f_depth, n=z)
        p.phase(level)
        if rl != 40:
            m.cutcom.select("G41" if rl == 41 else "G42", r + fal, ctx.src)
        _send(ctx, f_plane, start)
        for end, centre, cw, words in elements:
            _send(ctx, f_plane, end, centre, cw, words)
        if rl != 40:
            m.cutcom.deselect()
        p.phase(f"{level} retraction")
        _send(ctx, f3, p_out)
        m.corners.flush(m.send)
        if back != 3:
            p.feed(f3, n=min(h.rfp, z + h.sdis))        # out of the cut along the tool axis
        if i == len(depths):
            break
        up = {0: h.rtp, 1: h.safe, 2: z + h.sdis, 3: z}[back]
        p.rapid(n=up)
        (p.feed if between else lambda f, *a: p.rapid(*a))(f3, *p_in)
    ctx.retract(h)
