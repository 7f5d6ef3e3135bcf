# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""M codes that talk to the machine's I/O and spindle orientation, as rs274 runs them
without a machine (interp_convert.cc ``convert_m``): M19, M62..M68.
"""

from __future__ import annotations

from interpreters.rs274ngc import block as blk
from interpreters.rs274ngc.diag import NgcError


def _round(v: float) -> int:
    """round_to_int: to the nearest integer, halves away from zero."""
    return int(v + 0.5) if v >= 0 else int(v - 0.5)


class MCodeMixin:
    """M19 and M62..M68 for :class:`~interpreters.rs274ngc.interp.Interpreter`."""

    def convert_io(self, code: int, block: blk.Block) -> None:
        """M62..M65 digital outputs (motion-synchronised or immediate), M66 wait for an
        input, M67/M68 analog outputs, as rs274 runs them without a machine: the calls are
        printed; M66 returns at once, #5399 = 1 for a digital input when it was not 0
        (rs274 hands back the previous value), an analog input keeps #5399."""
        s = self.s
        out = self.out
        w = block.words
        if code in (62, 63, 64, 65):
            if s.comp_side:
                raise NgcError("io_comp", code=code)
            if block.p == -1.0:
                raise NgcError("io_p_missing", code=code)
            if out.trace:
                name = ("SET_MOTION_OUTPUT_BIT", "CLEAR_MOTION_OUTPUT_BIT", "SET_AUX_OUTPUT_BIT",
                        "CLEAR_AUX_OUTPUT_BIT")[code - 62]
                out._p("%s(%d)" % (name, _round(block.p)))
        elif code == 66:
            p, e, q, l = block.p, w.get("e"), block.q, block.l  # noqa: E741
            if p != -1.0 and e is not None:
                raise NgcError("wait_both_inputs")
            if q <= 0 and l != -1 and l > 0:
                raise NgcError("wait_zero_timeout")
            if e is not None and l != -1 and l != 0:
                raise NgcError("wait_analog_type")
            if (p != -1.0 and _round(p) < 0) or (e is not None and _round(e) < 0) or (
                    p == -1.0 and e is None):
                raise NgcError("wait_input_missing")
            if s.comp_side:
                raise NgcError("wait_comp", what="digital" if p != -1.0 else "analog")
            num = self.pars.num
            if p != -1.0:
                num[5399] = 1.0 if num[5399] != 0.0 else 0.0
        else:
            if s.comp_side:
                raise NgcError("io_comp", code=code)
            e = w.get("e")
            if e is None or _round(e) < 0:
                raise NgcError("io_analog_index", code=code)
            if out.trace:
                name = "SET_MOTION_OUTPUT_VALUE" if code == 67 else "SET_AUX_OUTPUT_VALUE"
                out._p("%s(%d,%f)" % (name, _round(e), block.q))

    def convert_orient(self, block: blk.Block) -> None:
        """M19: orient the spindle to R degrees (plus the INI's ORIENT_OFFSET), P the
        direction, Q the seconds to wait; the spindle counts as stopped."""
        s = self.s
        s.spindle = "stop"
        w = block.words
        if "r" in w or block.p != -1.0:
            angle = w.get("r", 0.0) + s.orient_offset
            self.out.orient_spindle(angle, int(block.p) if block.p != -1.0 else 0)
        if block.q != -1.0:
            if block.q <= 0.0:
                raise NgcError("m19_q_not_positive")
            self.out.wait_orient(block.q)
