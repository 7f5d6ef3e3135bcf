"""CYCLE60 (engraving): a text engraved with the tool's centre along the strokes of vmach's
stroke font (``strokes.toml``, a cell 4 × 6 units, capitals 6 high), scaled so a capital is
_CHARH high.

- Linear (_VARI tens 0): the base line through the reference point (_PA, _PO) at _STA; the
  characters _CHARS apart (0: a third of the height); the reference point is the base line's
  left end, centre or right end (_VARI units 0, 1, 2).
- On an arc (tens 1, 2) about (_CPA, _CPO) through the reference point: each character is
  placed upright on the arc (turned, not bent), outside it reading clockwise (1) or inside
  reading counter-clockwise (2); _CHARS is then the angle between characters' centres
  (0: the linear spacing along the arc).

Each stroke: rapid over its start at the safety clearance, down to _DP at _FFD, along it at
_FFP1, up to the reference plane at _FFD and on at rapid. Phases ``character k/n 'C'``; the
cycle ends at the retraction plane.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from types import MappingProxyType

from interpreters.sinumerik.cycles.common import Context
from interpreters.sinumerik.cycles.path import place

_FONT = tomllib.loads(Path(__file__).with_name("strokes.toml").read_text(encoding="utf-8"))
#: the font cell, units
CELL_W, CELL_H = float(_FONT["width"]), float(_FONT["height"])
#: character -> strokes, each a tuple of (u, v) points in cell units
GLYPHS = MappingProxyType({
    ch: tuple(tuple(tuple(float(x) for x in pt.split(",")) for pt in stroke.split()) for stroke in strokes)
    for ch, strokes in _FONT["chars"].items()})
#: most characters one call engraves
MAX_CHARS = 200


def layout(ctx: Context, text: str) -> list[tuple[str, list[list[tuple[float, float]]]]]:
    """The characters of ``text`` and their strokes in program coordinates of the plane (mm)."""
    c = ctx.call
    height = abs(ctx.mm("CHARH"))
    if height <= 0:
        raise ctx.fail("give the character height _CHARH")
    s = height / CELL_H
    vari = int(c["VARI"])
    ref, form = vari % 10, vari // 10 % 10
    if ref not in (0, 1, 2) or form not in (0, 1, 2):
        raise ctx.fail(f"_VARI {vari} is no alignment of the cycle", vari=vari)
    chars = text.upper()
    bad = sorted({ch for ch in chars if ch not in GLYPHS})
    if bad:
        raise ctx.fail(f"vmach's stroke font has no {''.join(bad)!r}", characters="".join(bad))
    n = len(chars)
    if n == 0 or n > MAX_CHARS:
        raise ctx.fail(f"the text must have 1 to {MAX_CHARS} characters", length=n)
    point = (ctx.mm("PA"), ctx.mm("PO"))
    w = CELL_W * s
    gap = abs(ctx.mm("CHARS")) if form == 0 and c["CHARS"] else height / 3
    if form == 0:
        total = n * w + (n - 1) * gap
        start = -total * ref / 2
        angle = math.radians(c["STA"])
        return [(ch, [[place((start + k * (w + gap) + u * s, v * s), point, angle) for u, v in stroke]
                      for stroke in GLYPHS[ch]]) for k, ch in enumerate(chars)]
    centre = (ctx.mm("CPA"), ctx.mm("CPO"))
    radius = math.dist(point, centre)
    if radius <= w:
        raise ctx.fail("the arc through the reference point is too small for the text", radius=radius)
    step = math.radians(abs(c["CHARS"])) if c["CHARS"] else (w + gap) / radius
    if step * (n - 1) >= 2 * math.pi:
        raise ctx.fail("the text does not fit once round the arc")
    sense = -1.0 if form == 1 else 1.0                  # 1: clockwise, outside; 2: inside
    t0 = math.atan2(point[1] - centre[1], point[0] - centre[0])
    t0 += sense * (w / 2 / radius - step * (n - 1) * ref / 2 - w / radius * ref / 2)
    out = []
    for k, ch in enumerate(chars):
        t = t0 + sense * step * k
        up = (math.cos(t), math.sin(t)) if form == 1 else (-math.cos(t), -math.sin(t))
        along = (up[1], -up[0])                         # the base line's direction
        base = (centre[0] + radius * math.cos(t), centre[1] + radius * math.sin(t))
        out.append((ch, [[(base[0] + (u * s - w / 2) * along[0] + v * s * up[0],
                           base[1] + (u * s - w / 2) * along[1] + v * s * up[1]) for u, v in stroke]
                         for stroke in GLYPHS[ch]]))
    return out


def engrave(ctx: Context) -> None:
    """CYCLE60."""
    if ctx.machine.cutcom.engaged:
        raise ctx.fail("engraving while tool radius compensation is active (G40 first)")
    h = ctx.heights(relative=False)
    chars = layout(ctx, ctx.call["TEXT"])
    f_plane = ctx.feed("FFP1")
    f_depth = ctx.feed("FFD", "FFP1")
    ctx.count(sum(len(strokes) for _, strokes in chars), "strokes")
    p = ctx.path
    first = next((st[0][0] for _, st in chars if st), None)
    if first is None:
        return
    ctx.approach(h, *first)
    for k, (ch, strokes) in enumerate(chars, 1):
        p.phase(f"character {k}/{len(chars)} {ch!r}")
        for stroke in strokes:
            p.rapid(n=h.safe)
            p.rapid(*stroke[0])
            p.feed(f_depth, n=h.depth)
            for q in stroke[1:]:
                p.feed(f_plane, *q)
            p.feed(f_depth, n=h.rfp)
            p.rapid(n=h.safe)
    ctx.retract(h)
