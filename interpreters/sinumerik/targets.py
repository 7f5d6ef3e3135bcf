"""Where a block's axis words send the axes: machine-coordinate targets (mm, degrees) from the
programmed values, the frame chain, G90/G91 and AC/IC/ACP/ACN/DC, inch and diameter
programming, and SD42440's offset traverse for an incremental move after a frame change. Both
functions are methods of :class:`Machine` (``Machine._plain_targets`` and ``Machine._targets``)."""

from __future__ import annotations

from interpreters.sinumerik.frames import modulo_target
from vmach.errors import ProgramError
from vmach.source import SourceRef

INCH = 25.4


def plain_targets(self, words: list) -> dict | None:
    """Targets when no rotation, diameter or inch mode is active: value + offset.
    None when a word needs the general path."""
    pos = self.pos
    new = pos.copy()
    off = self.frames.off
    specs = self.specs
    absolute = self.absolute
    stale = self.stale
    for word, value in words:
        cls = value.__class__
        if cls is not float and cls is not int:
            return None
        name = word.name
        spec = specs.get(name)
        if spec is None:
            return None
        mode = word.mode
        if stale and name in stale and (mode == "IC" or (mode is None and not absolute)):
            return None  # the frame changed since this axis moved: the general path
        if spec.modulo is None:
            if mode is None:
                new[name] = value + off.get(name, 0.0) if absolute else pos[name] + value
            elif mode == "AC":
                new[name] = value + off.get(name, 0.0)
            elif mode == "IC":
                new[name] = pos[name] + value
            else:
                return None  # ACP/ACN/DC on a non-modulo axis: the general path reports it
            continue
        if mode is None:
            mode = "AC" if absolute else "IC"
        if mode == "IC":
            new[name] = pos[name] + value
            continue
        if mode == "AC" and spec.g90_mode == "dc":
            mode = "DC"
        new[name] = modulo_target(pos[name], value + off.get(name, 0.0), mode, spec.modulo)
    return new

def targets(self, v, src: SourceRef, suppress: bool) -> dict:
    """The block's axis targets in machine coordinates (mm, degrees) through frames, inch,
    diameter programming and SD42440's offset traverse; ``suppress`` (G53/G153/SUPA) skips the
    frames."""
    pos = self.pos
    new = dict(pos)
    g = self.geometry
    frames = self.frames
    geo_words = []
    scale = INCH if self.inch else 1.0
    for word, value in v.axes:
        name = word.name
        spec = self.specs.get(name)
        if spec is None:
            self.add_axis(name)
            spec = self.specs[name]
            new[name] = 0.0
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            if hasattr(value, "what"):       # syncact.Unknown: a synchronised action's variable
                raise ProgramError("unsupported", value.what, src.at(word.col))
            raise ProgramError("type_error", f"{name} needs a number", src.at(word.col))
        mode = word.mode
        if name in g:
            geo_words.append((word, float(value)))
            continue
        value = float(value)
        if spec.kind == "linear":
            value *= scale
        if spec.modulo and mode in ("ACP", "ACN", "DC"):
            off = 0.0 if suppress else frames.offset(name)
            new[name] = modulo_target(pos[name], value + off, mode, spec.modulo)
        elif mode in ("ACP", "ACN", "DC"):
            raise ProgramError(
                "invalid_value",
                f"{mode} needs a modulo rotary axis; {name} is not one",
                src.at(word.col),
            )
        elif mode == "IC" or (mode is None and not self.absolute):
            new[name] = pos[name] + value
            if name in self.stale and not suppress:   # SD42440: the offset change too
                new[name] += frames.offset(name) - self.stale[name].offset(name)
        else:
            off = 0.0 if suppress else frames.offset(name)
            if spec.modulo:
                new[name] = modulo_target(
                    pos[name], value + off, "DC" if spec.g90_mode == "dc" else "AC", spec.modulo
                )
            else:
                new[name] = value + off
    transverse = self.control.transverse or ("X" if not self.control.strict_axes else None)
    if geo_words:
        cur = tuple(pos[n] for n in g)
        p = list(cur) if suppress else list(frames.to_program(cur))
        for word, value in geo_words:
            i = g.index(word.name)
            inc = word.mode == "IC" or (word.mode is None and not self.absolute)
            value *= scale
            if self.diameter and word.name == transverse and not (inc and self.diam90):
                value /= 2.0
            if inc and not suppress and word.name in self.stale:  # SD42440: from the point as
                p[i] = self.stale[word.name].to_program(cur)[i]   # programmed, offset traversed
            p[i] = p[i] + value if inc else value
        m = p if suppress else frames.to_machine(tuple(p))
        for i, n in enumerate(g):
            new[n] = m[i]
    return new
