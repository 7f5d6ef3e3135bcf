"""CYCLE802 (arbitrary positions): up to nine points of the working plane, each reached at
rapid at the present height, where the cycle ``MCALL`` made modal runs (as HOLES1/HOLES2 do).

A position is the pair (_Xi, _Yi). _XYZA and _XYZB say by their digits which values are given
(digit i from the right for position i: 1 given, 0 not); a value not given keeps the
position's coordinate from the point before it. Where a mask is 0 (or left out) every value
the call writes counts as given. A position neither of whose values is given is no position.
Each rapid carries the phase ``position i/n``.
"""

from __future__ import annotations

from interpreters.sinumerik.cycles.common import Context

#: positions CYCLE802 takes
POSITIONS = 9


def positions(ctx: Context, modal) -> None:
    """CYCLE802; ``modal(machine, src)`` runs the modal cycle at a position."""
    c = ctx.call
    masks = [int(c["XYZA"]), int(c["XYZB"])]
    if min(masks) < 0:
        raise ctx.fail("_XYZA and _XYZB are masks of 0 and 1 digits", xyza=masks[0], xyzb=masks[1])
    p = ctx.path
    a, b, _ = p.here()
    points = []
    for i in range(POSITIONS):
        given = []
        for k, name in enumerate((f"X{i}", f"Y{i}")):
            digit = masks[k] // 10**i % 10
            given.append(c.has(name) and (masks[k] == 0 or digit == 1))
        if not any(given):
            continue
        a = ctx.mm(f"X{i}") if given[0] else a
        b = ctx.mm(f"Y{i}") if given[1] else b
        points.append((a, b))
    if not points:
        raise ctx.fail("no position is given")
    for k, q in enumerate(points, 1):
        p.phase(f"position {k}/{len(points)}")
        p.rapid(*q)
        if ctx.machine.mcall is not None:
            modal(ctx.machine, p.src)
