# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""M70..M73: saving and restoring the modal state in the call frame, as LinuxCNC 2.9 does.

LinuxCNC (interp_convert.cc ``save_settings``/``restore_settings``) keeps the state as
three arrays: G codes by slot (plane, compensation, units, distance mode, feed mode,
coordinate system, tool offset, retract mode, control mode, spindle mode, IJK mode, lathe
mode, G92 applied), M codes by slot (spindle, mist, flood, overrides) and numbers (feed,
speed, G64 tolerances). Restoring compares the saved arrays with the current ones and
*runs G-code* for the differences — G20/G21 first on its own, then one line of F, S and G
words followed by the M codes, one per line — so the canonical calls and interpreter
comments are those of running that code. M70 saves into the current call level, M73 also
marks it to be restored when the subroutine returns, M71 invalidates it, M72 restores it.
"""

from __future__ import annotations

from interpreters.rs274ngc.diag import NgcError
from interpreters.rs274ngc.lexer import parse_line

VALID = 1
RESTORE_ON_RETURN = 2


def _control(s) -> int:
    return {"continuous": 640, "exact_path": 610}.get(s.control, 611)


class ContextMixin:
    """M70..M73 for :class:`~interpreters.rs274ngc.interp.Interpreter`."""

    def modal_snapshot(self) -> tuple[dict[int, int], dict[int, int], list[float]]:
        """(G slots, M slots, [feed, speed, tolerance, naive CAM tolerance]) as LinuxCNC's
        write_g_codes/write_m_codes/write_settings fill them (codes x10 for G)."""
        s = self.s
        oi = s.origin_index
        g = {
            3: s.plane,
            4: (400, 410, 420)[s.comp_side],
            5: 210 if s.metric else 200,
            6: 910 if s.incremental else 900,
            7: (940, 930, 950)[s.feed_mode],
            8: 530 + 10 * oi if oi < 7 else 584 + oi,
            9: 430 if any(s.tool_offset) else 490,
            10: 990 if s.retract_r else 980,
            11: _control(s),
            13: 970,
            14: 901 if s.ijk_absolute else 911,
            15: 70 if s.diameter_mode else 80,
            16: 923 if self.pars.num[5210] else 922,
        }
        if s.mist:
            mist = 7
        else:
            mist = -1 if s.flood else 9
        overrides = (48 if s.speed_override else 50) if s.feed_override else (
            51 if s.speed_override else 49)
        m = {2: {"stop": 5, "cw": 3}.get(s.spindle, 4), 4: mist, 5: 8 if s.flood else -1,
             6: overrides, 7: -1, 8: -1}
        return g, m, [s.feed, s.speed, s.tolerance, s.naivecam]

    def convert_context(self, code: int) -> None:
        """M70 (save), M71 (invalidate), M72 (restore), M73 (save, restore on return)."""
        frame = self.frames[-1]
        if code in (70, 73):
            frame.context = self.modal_snapshot()
            frame.context_status |= VALID
            if code == 73 and len(self.frames) > 1:
                frame.context_status |= RESTORE_ON_RETURN
        elif code == 71:
            frame.context_status &= ~VALID
        else:
            if not frame.context_status & VALID:
                raise NgcError("context_invalid")
            self.restore_context(frame.context)

    def restore_context(self, saved) -> None:
        """restore_settings: run the G-code that brings the state back to ``saved``."""
        sg, sm, sf = saved
        g, _, _ = self.modal_snapshot()
        if g[5] != sg[5]:
            self._run_text("G%d" % (sg[5] // 10))
        g, m, f = self.modal_snapshot()
        cmd = []
        g64_changed = False
        if sf[0] != f[0]:
            cmd.append(" F%.1f" % sf[0])
        if sf[1] != f[1]:
            cmd.append(" S%.0f" % sf[1])
        if sf[2] != f[2] or sf[3] != f[3]:
            g64_changed = True
        for slot in sorted(sg):
            val = sg[slot]
            if val == g[slot] or slot == 5:
                continue
            if slot == 11:
                if val == 640:
                    g64_changed = True
                else:
                    cmd.append(" G61" if val == 610 else " G61.1")
            else:
                cmd.append(" G%d.%d" % (val // 10, val % 10) if val % 10 else " G%d" % (val // 10))
        if sg[11] == 640 and g64_changed:
            cmd.append(" G64 P%f Q%f" % (sf[2], sf[3]))
        for slot in sorted(sm):
            val = sm[slot]
            if val != m[slot] and val != -1:
                cmd.append("M%d\n" % val)
        for text in "".join(cmd).split("\n"):
            if text:
                self._run_text(text)

    def _run_text(self, text: str) -> None:
        """Interp::execute(command): one line of G-code run in the middle of a block."""
        out = self.out
        label = out.nlabel
        out.nlabel = "N..... "
        try:
            self.step(parse_line(0, text))
        finally:
            out.nlabel = label
