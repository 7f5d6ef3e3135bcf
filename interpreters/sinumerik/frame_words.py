"""The programmable frame instructions of a block (TRANS, ROT, SCALE, MIRROR and their additive
forms, RPL=, the poles G110-G112) applied to the machine's frame chain: lengths in mm (inch
programs scaled), angles in degrees."""

from __future__ import annotations

from interpreters.sinumerik import increments, polar
from interpreters.sinumerik.frames import diagonal, matmul, rot_axis, rpy
from vmach.errors import ProgramError
from vmach.source import SourceRef

INCH = 25.4
#: the axis index (0 X, 1 Y, 2 Z) normal to each working plane: RPL= turns about it
PLANE_NORMAL = {"G17": 2, "G18": 1, "G19": 0}


def frame(self, v, src: SourceRef) -> None:
    """TRANS/ATRANS, ROT/AROT (axis angles or RPL=), SCALE/ASCALE, MIRROR/AMIRROR and the
    polar poles G110-G112: the programmable frame (or the pole) changed by one block. A
    method of :class:`Machine` (``Machine.frame``)."""
    fc = v.frame
    vals = v.frame_values
    scale = INCH if self.inch else 1.0
    if fc.name in polar.POLES:
        polar.set_pole(self, fc.name, vals, src.at(fc.col))
        return
    increments.frame_changes(self)
    if fc.name in ("SCALE", "ASCALE", "MIRROR", "AMIRROR"):
        g = self.geometry
        for k in vals:
            if k not in g:
                raise ProgramError("unsupported", f"{fc.name}: {k} is not a geometry axis; vmach "
                                   "scales and mirrors the geometry axes only", src.at(fc.col))
        if fc.name.endswith("MIRROR"):
            m = diagonal(tuple(-1.0 if n in vals else 1.0 for n in g))  # type: ignore[arg-type]
        else:
            if any(not val for val in vals.values()):
                raise ProgramError("invalid_value", f"{fc.name}: a scale factor of 0", src.at(fc.col))
            m = diagonal(tuple(vals.get(n, 1.0) for n in g))  # type: ignore[arg-type]
        if fc.name.startswith("A"):
            self.frames.rot_add(m)
        else:
            self.frames.linear_abs(m)
        if self.cutcom.engaged and not _unit_scale(self.frames.lin):
            raise ProgramError("cutcom", f"{fc.name} while tool radius compensation is active: "
                               "a scaled frame would scale the tool radius", src.at(fc.col))
    elif fc.name in ("TRANS", "ATRANS"):
        for k in vals:
            if k not in self.specs:
                self.add_axis(k)  # a loose axis (no strict axes): known from here on, as after a move
        d = {k: (val * scale if self.specs[k].kind == "linear" else val) for k, val in vals.items()}
        (self.frames.trans_abs if fc.name == "TRANS" else self.frames.trans_add)(d)
    else:
        if v.rpl is not None:
            if vals:
                raise ProgramError(
                    "syntax", f"{fc.name}: give RPL or axis angles, not both", src.at(fc.col)
                )
            m = rot_axis(PLANE_NORMAL[self.plane], v.rpl)
        else:
            g = self.geometry
            for k in vals:
                if k not in g:
                    raise ProgramError("syntax", f"{fc.name}: {k} is not a geometry axis", src.at(fc.col))
            m = rpy(vals.get(g[0], 0.0), vals.get(g[1], 0.0), vals.get(g[2], 0.0))
        if fc.name == "ROT":
            self.frames.rot_abs(m)
        else:
            self.frames.rot_add(m)
    self.emit_frame(src)


def _unit_scale(m) -> bool:
    """Whether the linear map m keeps lengths (a rotation, possibly mirrored)."""
    mt = matmul(m, tuple(tuple(m[j][i] for j in range(3)) for i in range(3)))
    return all(abs(mt[i][j] - (1.0 if i == j else 0.0)) < 1e-9 for i in range(3) for j in range(3))
