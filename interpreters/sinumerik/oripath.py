"""The tool orientation relative to the path: LEAD and TILT (Programming Manual Job Planning,
"Programming the tool orientation with LEAD and TILT", "Orientations relative to the path").

Under TRAORI the block's end orientation follows from

- the path tangent T at the block's end (a line's direction; an arc's tangent at its end point),
- the surface normal N: ``A5= B5= C5=`` in the block (turned with a rotating frame under ORIWKS),
  else Z of the working plane's frame (the manual: "in the initial setting surface normal
  vectors point in the Z direction", whatever G17–G19),
- ``LEAD=`` the lead angle: N turned toward T (T's part normal to N), in the plane of N and T —
  positive leans the tool's upper end in the direction of travel,
- ``TILT=`` the tilt angle: that vector then turned about T (right-handed), in the plane normal
  to the path tangent.

LEAD and TILT are modal (0 at the start). With ORIPATH/ORIPATHS every motion block of the path
takes its end orientation so; otherwise only a block that programs LEAD or TILT does. Between
the previous orientation and the end orientation the vector turns on the great circle (the
manual's large-circle interpolation; for an arc the control keeps the angles to the changing
tangent along the block — vmach's rows reach them at the block's end only; the angle step
stays ``tol.angle_step``). ``A4= B4= C4=`` (the normal at the block's start), PO[PHI]/PO[PSI]
polynomials, THETA and ORIPATHS's smoothing of corners are not simulated (``unsupported`` for
the words; ORIPATHS runs as ORIPATH).
"""

from __future__ import annotations

import math

from vmach.errors import ProgramError
from vmach.source import SourceRef

#: the words of this module (parser kind "orient")
WORDS = ("LEAD", "TILT", "A4", "B4", "C4", "A5", "B5", "C5")
PLANE_AXES = {("X", "Y", "Z"): 2, ("Z", "X", "Y"): 1, ("Y", "Z", "X"): 0}


def _unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v), n


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _turn(v, k, deg):
    """v turned about unit k by deg degrees (Rodrigues)."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    kv = sum(a * b for a, b in zip(k, v, strict=True))
    kx = _cross(k, v)
    return tuple(v[i] * c + kx[i] * s + k[i] * kv * (1 - c) for i in range(3))


def take(machine, v, src: SourceRef) -> dict:
    """The block's words of this module (removed from ``v.interp``); LEAD/TILT kept modal."""
    words = {k: v.interp.pop(k) for k in WORDS if k in v.interp} if v.interp else {}
    if any(k in words for k in ("A4", "B4", "C4")):
        raise ProgramError("unsupported", "the surface normal at the block's start (A4 B4 C4) is not "
                           "simulated (the end's, A5 B5 C5, is)", src)
    for k in ("LEAD", "TILT"):
        if k in words:
            setattr(machine.ori, k.lower(), float(words[k][0]))
    return words


def vector(machine, words: dict, start, end, arc, src: SourceRef):
    """The block's end orientation from LEAD and TILT (workpiece frame), or None when the block
    does not take one. ``start``/``end``: the tip (workpiece frame); ``arc``: None or
    (plane, centre (2,), end point (3,) in the arc's coordinates, clockwise, linear map of
    those coordinates to the workpiece)."""
    relative = machine.ori.interpolation == "path"
    if not (relative or "LEAD" in words or "TILT" in words or any(k in words for k in WORDS[5:])):
        return None
    if arc is not None:
        plane, centre, p, cw, lin = arc
        ia, ib, n = ("XYZ".index(plane[0]), "XYZ".index(plane[1]), PLANE_AXES[tuple(plane)])
        radial = [0.0, 0.0, 0.0]
        radial[ia], radial[ib] = p[ia] - centre[0], p[ib] - centre[1]
        axis = [0.0, 0.0, 0.0]
        axis[n] = -1.0 if cw else 1.0
        t = _cross(tuple(axis), tuple(radial))
        t = tuple(sum(lin[i][j] * t[j] for j in range(3)) for i in range(3))
    else:
        t = tuple(e - s for s, e in zip(start, end, strict=True))
    if any(x != x for x in t):
        raise ProgramError("unsupported", "LEAD/TILT on a move whose start only the machine knows "
                           "(the first after TRAORI): program the start absolutely first", src)
    t, length = _unit(t) if any(t) else (t, 0.0)
    if length < 1e-9:
        if "LEAD" in words or "TILT" in words:
            raise ProgramError("invalid_value", "LEAD/TILT in a block without a path (no tangent)", src)
        return None                                   # ORIPATH: no path, the orientation stays
    lin = machine.frames.lin if machine.ori.workpiece and machine.frames.rotated else None
    if any(k in words for k in ("A5", "B5", "C5")):
        nv = tuple(float(words.get(k, (0.0, None))[0]) for k in ("A5", "B5", "C5"))
    else:
        nv = (0.0, 0.0, 1.0)
    if lin is not None:
        nv = tuple(sum(lin[i][j] * nv[j] for j in range(3)) for i in range(3))
    nv, ln = _unit(nv) if any(nv) else (nv, 0.0)
    if ln < 1e-12:
        raise ProgramError("invalid_value", "the surface normal is zero", src)
    tn = tuple(t[i] - sum(a * b for a, b in zip(t, nv, strict=True)) * nv[i] for i in range(3))
    tn, lt = _unit(tn) if any(tn) else (tn, 0.0)
    if lt < 1e-9:
        raise ProgramError("invalid_value", "LEAD/TILT: the path runs along the surface normal", src)
    lead, tilt = math.radians(machine.ori.lead), machine.ori.tilt
    o = tuple(math.cos(lead) * nv[i] + math.sin(lead) * tn[i] for i in range(3))
    return _turn(o, tn, tilt)
