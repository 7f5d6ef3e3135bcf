"""CYCLE800 — swivel plane (SINUMERIK Operate, Milling cycles, "Swivel plane"), "3+2" machining.

``CYCLE800(_FR, _TC, _ST, _MODE, _X0, _Y0, _Z0, _A, _B, _C, _X1, _Y1, _Z1, _DIR, _FR_I,
_DMODE)``:

- the frame: the working plane is turned about the reference point (X0, Y0, Z0) by the rotation
  ``_MODE`` describes, then offset by (X1, Y1, Z1) in the turned coordinates:
  ``p_old = (X0, Y0, Z0) + R · ((X1, Y1, Z1) + p_new)``. ``_MODE`` bits 7–6 choose how R is
  given: 0 axis by axis (bits 1–0, 3–2, 5–4 name the axes of the first, second and third
  rotation, 1 X, 2 Y, 3 Z: 57 = X, Y, Z; each turns the coordinates already turned, by _A, _B,
  _C), 64 solid angles (about Z by _A, then about the new Y by _B), 128 projection angles (Xα, Yα:
  the new Z's projections make _A with Z in the Y/Z plane and _B in the Z/X plane, the new X
  lies in the old Z/X plane; then about the new Z by _C; the other projection positions are
  ``unsupported``), 192 direct (``_A``, ``_B`` the
  positions of rotary axes 1 and 2 of the swivel data; R turns as those axes turn the tool
  relative to the part, from ``$TC_CARR7…12`` and the kinematic type ``$TC_CARR23``).
  ``_ST`` units digit 0 replaces an active swivel, 1 adds to it.
- the retraction before swivelling, ``_FR``: 0 none, 1 Z, 2 Z then X Y to the swivel data's
  retraction positions ``$TC_CARR38…40`` (default: the travel's positive end of Z, X and Y
  stay); 4 (the most in the tool direction, up to the first travel limit) and 5 (``_FR_I`` in
  the tool direction): the tool's direction from the swivel data at the rotary positions (on a
  table-table machine machine +Z).
- the rotary positioning: the tool is turned normal to the new plane (Z for G17), the linear
  axes holding still, or with ``_ST``'s tens digit 1 (tool follow-up, the control's tracking
  with TRAORI) moving so that the tip stays on the part where it was; ``_DIR`` −1/+1
  takes the solution with the lower / higher value of the swivel data's direction reference
  axis (rotary axis 1), 0 does not position the rotary axes (the frame only).

After CYCLE800 the interpreter continues as under TRAORI (orientation.py): every move is an
:class:`vmach.canon.OrientedMove` of the tool tip in the workpiece frame with the tool
orientation kept, solved on the vmach side — the control's TCARR/TOROT result for the turned
part. ``CYCLE800()`` ends it (the frame is removed; the rotary axes stay). Swivel data record 1
only (the model's, derived from its chain: vmach/machine/machdata.py).
"""

from __future__ import annotations

import math

from interpreters.sinumerik.frames import IDENTITY, apply, inverse, matmul, rot_axis
from vmach import canon
from vmach.errors import ProgramError
from vmach.source import SourceRef

AXIS_BITS = {1: 0, 2: 1, 3: 2}      # _MODE's 2-bit axis codes → geometry axis index


def _arg(args, i: int, default=0.0):
    v = args[i] if i < len(args) and args[i] is not None else default
    if isinstance(v, str):
        return v
    return float(v)


def _rodrigues(u, deg: float):
    n = math.sqrt(sum(x * x for x in u))
    x, y, z = (c / n for c in u)
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    t = 1.0 - c
    return ((c + x * x * t, x * y * t - z * s, x * z * t + y * s),
            (y * x * t + z * s, c + y * y * t, y * z * t - x * s),
            (z * x * t - y * s, z * y * t + x * s, c + z * z * t))


def _carr(machine, n: int):
    md = machine.control.machine_data.get(f"$TC_CARR{n}", {})
    return md.get(1) if isinstance(md, dict) else None


def transpose(m):
    return tuple(tuple(m[j][i] for j in range(3)) for i in range(3))


def rotations(machine, pos: dict, src: SourceRef):
    """(R_tool, R_table) of swivel record 1 at the rotary positions ``pos`` (degrees): the
    tool's rotation and the table's, machine-parallel (identity for the one that does not turn)."""
    names = (_carr(machine, 35), _carr(machine, 36))
    values = [pos.get(n, float("nan")) for n in names]
    if any(v != v for v in values):
        raise ProgramError("unsupported", f"the position of {' and '.join(map(str, names))} is only "
                           "known to the machine (program the rotary axes first)", src)
    v1 = tuple(float(_carr(machine, k) or 0.0) for k in (7, 8, 9))
    v2 = tuple(float(_carr(machine, k) or 0.0) for k in (10, 11, 12))
    r1, r2 = _rodrigues(v1, values[0]), _rodrigues(v2, values[1])
    kind = _carr(machine, 23)
    if kind == "T":                     # both turn the tool: axis 1 carries axis 2
        return matmul(r1, r2), IDENTITY
    if kind == "P":                     # both turn the part; the vectors are the part's view
        return IDENTITY, transpose(matmul(r2, r1))
    return r1, transpose(r2)            # M: axis 1 the tool, axis 2 the table


def rotation(machine, mode: int, a: float, b: float, c: float, src: SourceRef):
    """R of ``_MODE`` and the angles (see the module docstring)."""
    how = mode & 0xC0
    if how == 0x00:
        m = IDENTITY
        for bits, angle in ((mode & 3, a), ((mode >> 2) & 3, b), ((mode >> 4) & 3, c)):
            if bits not in AXIS_BITS:
                raise ProgramError("invalid_value", f"CYCLE800: _MODE {mode} names no axis order", src)
            m = matmul(m, rot_axis(AXIS_BITS[bits], angle))
        return m
    if how == 0x40:
        return matmul(rot_axis(2, a), rot_axis(1, b))
    if how == 0x80:
        if (mode & 0x3F) not in (0, 0x39):
            raise ProgramError("unsupported", "CYCLE800 projection angles other than Xα, Yα (the new "
                               "Z's projections) are not simulated", src)
        nz = (math.tan(math.radians(b)), -math.tan(math.radians(a)), 1.0)
        ln = math.sqrt(sum(v * v for v in nz))
        z = tuple(v / ln for v in nz)
        lx = math.hypot(z[2], z[0])
        x = (z[2] / lx, 0.0, -z[0] / lx)
        y = (z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0])
        m = tuple(tuple(col[i] for col in (x, y, z)) for i in range(3))
        return matmul(m, rot_axis(2, c))  # type: ignore[arg-type]
    v1 = tuple(float(_carr(machine, k) or 0.0) for k in (7, 8, 9))
    v2 = tuple(float(_carr(machine, k) or 0.0) for k in (10, 11, 12))
    if not any(v1) or not any(v2):
        raise ProgramError("unsupported", "CYCLE800 direct: the machine has no swivel data "
                           "($TC_CARR7…12) for its rotary axes", src)
    r1, r2 = _rodrigues(v1, a), _rodrigues(v2, b)
    # head (T): axis 1 carries axis 2 and the tool; a table axis turns the part, so the one
    # nearer the part (2) acts first on the tool as the part sees it (P, and M's table)
    return matmul(r1, r2) if _carr(machine, 23) == "T" else matmul(r2, r1)


def cycle800(machine, args, src: SourceRef, orientation) -> list:
    """The commands of one CYCLE800 call (see the module docstring); ``orientation`` gives
    ``activate``, ``deactivate`` and ``forget`` of the orientation transformation."""
    out: list = []
    if not args or all(a is None for a in args):
        if getattr(machine, "swivel", None) is not None:
            machine.frames.set_settable(*machine.swivel)
            machine.swivel = None
            out.append(orientation.deactivate(machine, src))
            machine.emit_frame(src)
        return out
    fr, mode = int(_arg(args, 0, 1)), int(_arg(args, 3))
    st, follow = int(_arg(args, 2)) % 10, int(_arg(args, 2)) // 10 % 10 == 1
    ref = tuple(_arg(args, i) for i in (4, 5, 6))
    a, b, c = (_arg(args, i) for i in (7, 8, 9))
    zero = tuple(_arg(args, i) for i in (10, 11, 12))
    direction = int(_arg(args, 13, -1))
    if any(isinstance(v, str) for v in (fr, mode, *ref, a, b, c, *zero, direction)):
        raise ProgramError("type_error", "CYCLE800: the parameters after _TC are numbers", src)
    rot = tuple(x.name for x in machine.control.axes if x.kind == "rotary")
    if len(rot) != 2:
        raise ProgramError("unsupported", "CYCLE800: the machine has not two rotary axes to swivel "
                           f"with (it has {len(rot)})", src)
    if machine.cutcom.engaged or machine.tracyl is not None or machine.frames.rot != IDENTITY:
        raise ProgramError("unsupported", "CYCLE800 while tool radius compensation, TRACYL or a "
                           "programmed rotation is active is not simulated", src)
    if machine.traori is not None and getattr(machine, "swivel", None) is None:
        raise ProgramError("unsupported", "CYCLE800 while TRAORI is active (TRAFOOF first)", src)
    r = rotation(machine, mode, a, b, c, src)
    if fr in (1, 2, 4, 5):
        out.append(_retract(machine, fr, _arg(args, 14), src))
    active = getattr(machine, "swivel", None)
    base = active if active is not None else (dict(machine.frames.settable), machine.frames.slin)
    # new (_ST units 0): on the frame before any swivel; additive (1): on the active one
    settable, slin = (dict(machine.frames.settable), machine.frames.slin) if st == 1 else base
    g = machine.geometry
    move = apply(slin, tuple(ref[i] + apply(r, zero)[i] for i in range(3)))  # type: ignore[arg-type]
    offsets = dict(settable)
    for i, n in enumerate(g):
        offsets[n] = settable.get(n, 0.0) + move[i]
    if machine.traori is None:
        out.append(orientation.activate(machine, [], src, name="CYCLE800"))
    machine.swivel = base
    machine.frames.set_settable(offsets, matmul(slin, r))
    back = inverse(base[1])                          # the swivel relative to its base frame
    machine.swivel_rel = (apply(back, tuple(offsets.get(n, 0.0) - base[0].get(n, 0.0) for n in g)),
                          matmul(back, machine.frames.slin))
    machine.swivel_lin = machine.frames.slin         # a G54 … after it: reapply()
    machine.emit_frame(src)
    orientation.forget(machine)
    if mode & 0xC0 == 0xC0 or direction:
        out.append(_position(machine, rot, mode, a, b, direction, src, follow))
    return out


def current(machine, src: SourceRef) -> None:
    """Before a move under CYCLE800: :func:`reapply` when a settable frame was selected since."""
    if getattr(machine, "swivel", None) is not None and machine.frames.slin is not machine.swivel_lin:
        reapply(machine, src)


def reapply(machine, src: SourceRef) -> None:
    """A settable frame (G54 …) selected while CYCLE800 is active: the swivel stays, now on the
    new zero (the control keeps it in a system frame chained after the settable frame:
    ``p_old = zero_new + slin_new · (X0 + R · (X1 + p_new))``)."""
    move, r = machine.swivel_rel
    frames = machine.frames
    settable, slin = dict(frames.settable), frames.slin
    machine.swivel = (settable, slin)
    turned = apply(slin, move)
    offsets = dict(settable)
    for i, n in enumerate(machine.geometry):
        offsets[n] = settable.get(n, 0.0) + turned[i]
    frames.set_settable(offsets, matmul(slin, r))
    machine.swivel_lin = frames.slin
    machine.emit_frame(src)


def _retract(machine, fr: int, amount, src: SourceRef) -> canon.Traverse:
    """The retraction in machine coordinates before swivelling: _FR 1 Z, 2 Z then X Y to the
    retraction positions; 4 along the tool as far as the travel allows, 5 along the tool by
    _FR_I — the tool's direction from the swivel data at the rotary positions (machine +Z on a
    table-table machine)."""
    md = machine.control.machine_data
    plus = md.get("$MA_POS_LIMIT_PLUS", {})
    g = machine.geometry
    pos = dict(machine.pos)
    if fr in (4, 5):
        here = [machine.pos[n] for n in g]
        if any(v != v for v in here) or isinstance(amount, str):
            raise ProgramError("unsupported", f"CYCLE800 _FR={fr} from a position only the machine "
                               "knows (right after a swivel) is not simulated", src)
        k = (0.0, 0.0, 1.0)
        if _carr(machine, 23) != "P":
            tool, _ = rotations(machine, machine.pos, src)
            k = (tool[0][2], tool[1][2], tool[2][2])
        if fr == 5:
            t = float(amount)
        else:
            minus = md.get("$MA_POS_LIMIT_MINUS", {})
            ends = [((plus if c > 0 else minus).get(n, math.inf) - h) / c
                    for n, h, c in zip(g, here, k, strict=True) if abs(c) > 1e-12]
            t = min(ends)
            if not math.isfinite(t):
                raise ProgramError("unsupported", "CYCLE800 _FR=4: the machine data give no travel "
                                   "limit along the tool", src)
        for n, h, c in zip(g, here, k, strict=True):
            pos[n] = h + t * c
    else:
        z = _carr(machine, 40)
        pos[g[2]] = float(z) if z else float(plus.get(g[2], pos[g[2]]))
    if fr == 2:
        for i, k in ((0, 38), (1, 39)):
            v = _carr(machine, k)
            if v:
                pos[g[i]] = float(v)
    machine.pos = pos
    return canon.Traverse(src, axes=pos)


def _position(machine, rot, mode, a, b, direction, src: SourceRef,
              follow: bool = False) -> canon.OrientedMove:
    """Turn the tool normal to the new plane, the linear axes holding still — or, with tool
    follow-up (``follow``), moving so that the tip stays where it is on the part."""
    axes = dict(machine.pos)
    vec = None
    if mode & 0xC0 == 0xC0:                         # direct: the rotary positions themselves
        names = (_carr(machine, 35), _carr(machine, 36))
        for name, value in zip(names, (a, b), strict=True):
            if name in rot:
                axes[name] = value
        if not all(n in rot for n in names):
            axes[rot[0]], axes[rot[1]] = a, b
    else:
        normal = {"G17": (0.0, 0.0, 1.0), "G18": (0.0, 1.0, 0.0), "G19": (1.0, 0.0, 0.0)}[machine.plane]
        vec = apply(machine.frames.lin, normal)  # type: ignore[arg-type]
    ref = _carr(machine, 35)
    prefer = (ref, 1 if direction > 0 else -1) if direction and ref in rot else None
    return canon.OrientedMove(src, motion="traverse", axes=axes, vector=vec, interpolation="axes",
                              prefer=prefer, hold_axes=not follow)
