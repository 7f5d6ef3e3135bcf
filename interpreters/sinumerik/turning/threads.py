"""Thread cutting on the lathe: ``G33`` (constant lead), ``G34``/``G35`` (lead growing or
shrinking by F mm/rev² along the block), as SINUMERIK runs them (Programming Manual,
Fundamentals, "Thread cutting with constant lead (G33)", "G34, G35").

The lead is I (transverse X), J or K (longitudinal Z), mm per revolution of the master
spindle, measured along that axis: K for a longitudinal or a taper thread under 45°, I for a
face thread or a steeper taper; it stays in force for the next thread blocks. ``SF=`` (start
angle) is read and has no effect on the geometry vmach simulates. A thread block moves
synchronised with the spindle: in the canonical stream it is a linear feed whose feed is
the path length per revolution (G95 units), or that times the spindle speed under G94.

The stock: a turning tool moving with the spindle turning cuts the solid of revolution of its
insert along the path, so a thread pass takes the material down to the pass's depth all
round; the helix itself (the flanks left between the turns) is not modelled. vmach says so
once per program (``thread_envelope``, info): there the exported part lies at the root of
the thread, the thread's depth inside its true shape.
"""

from __future__ import annotations

import math

from vmach import canon
from vmach.errors import ProgramError
from vmach.findings import info
from vmach.source import SourceRef

INCH = 25.4
_LETTERS = {"X": "I", "Y": "J", "Z": "K"}


def say_envelope(m, src: SourceRef) -> None:
    """The one ``thread_envelope`` note of a program (see the module doc)."""
    if not any(f.kind == "thread_envelope" for f in m.notes):
        m.notes.append(info(
            "thread_envelope", "thread passes cut the solid of revolution of the insert's path: "
            "the helix is not modelled, the part lies at each pass's depth all round", src))


def spindle_rpm(m, what: str, src: SourceRef) -> float:
    """The master spindle's speed (rev/min); a stopped spindle is ``thread_spindle``."""
    speed, direction = m.spindles.get(m.master, (0.0, "stop"))
    if m.surface.on:
        speed = m.surface.rpm(m)
    if direction == "stop" or speed <= 0:
        raise ProgramError("thread_spindle", f"{what} with the master spindle stopped: the feed "
                           "follows the spindle (M3/M4 S... first)", src)
    return speed


def path_feed(m, lead: float, along: float, length: float, what: str, src: SourceRef) -> float:
    """The feed of a thread move of ``length`` mm whose lead (mm/rev) is measured along an axis
    the move travels ``along`` mm: per revolution (G95, G96) or per minute (G94)."""
    per_rev = lead * length / along
    if m.feed_mode == "per_minute":
        return per_rev * spindle_rpm(m, what, src)
    spindle_rpm(m, what, src)
    return per_rev


def move(m, v, src: SourceRef, new: dict) -> canon.LinearFeed:
    """The canonical move of a G33/G34/G35 block to ``new`` (machine axes)."""
    what = m.motion
    scale = INCH if m.inch else 1.0
    given = [(letter, float(v.interp[letter][0]) * scale) for letter in ("I", "J", "K")
             if letter in v.interp]
    if len(given) > 1:
        raise ProgramError("thread_lead", f"{what}: give one lead (I, J or K), not "
                           + " and ".join(letter for letter, _ in given), src)
    if given:
        m.thread_lead = given[0]
    if m.thread_lead is None:
        raise ProgramError("thread_lead", f"{what} needs the lead: I, J or K", src)
    letter, lead = m.thread_lead
    if lead <= 0:
        raise ProgramError("thread_lead", f"{what}: the lead {letter}{lead:g} must be positive", src)
    axis = next(a for a, k in _LETTERS.items() if k == letter)
    d = {a: new.get(a, 0.0) - m.pos.get(a, 0.0) for a in m.geometry}
    length = math.sqrt(sum(x * x for x in d.values()))
    along = abs(d.get(axis, 0.0))
    if along <= 1e-9:
        raise ProgramError("thread_lead", f"{what}: the lead {letter} is along {axis}, which this "
                           "block does not move", src)
    if what != "G33":  # G34/G35: the lead changes by F (mm/rev²) along the block
        rate = m.feed
        end2 = lead * lead + (2 if what == "G34" else -2) * rate * along
        if end2 <= 0:
            raise ProgramError("thread_lead", f"{what}: the lead falls to 0 before the block's end "
                               f"(lead {lead:g}, change F{rate:g} mm/rev² over {along:g} mm)", src)
        lead = (lead + math.sqrt(end2)) / 2  # the mean lead over the block's revolutions
    say_envelope(m, src)
    return canon.LinearFeed(src, axes=new, feed=path_feed(m, lead, along, length, what, src))
