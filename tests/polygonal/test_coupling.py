"""Sinumerik synchronous spindle coupling for polygonal turning (#34): COUPDEF(FS, LS, ÜFS, ÜLS,
block change, type), COUPON(FS, LS, POSFS), COUPOF/COUPOFS, COUPDEL, COUPRES (SINUMERIK
function manual S3 "Synchronous spindle": the ratio is ÜFS/ÜLS, FS turns per LS turn)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from nc import error_of, ok, run  # noqa: E402

from vmach.canon import Spindle, SpindleCoupling  # noqa: E402
from vmach.machine import load_model  # noqa: E402

TURNMILL = load_model("turnmill").control

HEAD = "G18 G90 DIAMON\nSETMS(1)\n"


def test_couple_at_two_to_one_with_an_offset_then_uncouple(tmp_path):
    r = ok(tmp_path, HEAD + 'COUPDEF(S2, S1, 2, 1, "FINE", "DV")\nS800 M3\nCOUPON(S2, S1, 15)\n'
                     "G1 X20 Z-5 F0.1\nCOUPOF(S2, S1)\nM30\n", TURNMILL)
    cp = [c for c in r.commands if isinstance(c, SpindleCoupling)]
    assert [(c.source.line, c.following, c.leading, c.ratio, c.active, c.offset, c.mode) for c in cp] == [
        (5, 2, 1, 2.0, True, 15.0, "DV"), (7, 2, 1, 2.0, False, None, "DV")]
    # while coupled the tool spindle turns at twice the main spindle's speed, the same way round
    s2 = [c for c in r.commands if isinstance(c, Spindle) and c.spindle == 2]
    assert [(c.source.line, c.speed, c.direction) for c in s2] == [(5, 1600.0, "cw")]


def test_a_negative_ratio_turns_the_follower_the_other_way_and_coupofs_stops_it(tmp_path):
    text = "COUPDEF(S2, S1, -3, 2)\nS600 M3\nCOUPON(S2, S1)\nCOUPOFS(S2, S1)\nM30\n"
    r = ok(tmp_path, HEAD + text, TURNMILL)
    cp = [c for c in r.commands if isinstance(c, SpindleCoupling)]
    assert (cp[0].ratio, cp[0].offset, cp[0].mode) == (-1.5, None, "DV")     # defaults: FINE, DV
    s2 = [(c.source.line, c.speed, c.direction) for c in r.commands
          if isinstance(c, Spindle) and c.spindle == 2]
    assert s2 == [(5, 900.0, "ccw"), (6, 0.0, "stop")]


def test_coupdef_keeps_what_it_does_not_give_and_coupres_forgets_the_pair(tmp_path):
    r = ok(tmp_path, HEAD + 'COUPDEF(S2, S1, 2, 1, "COARSE", "AV")\nCOUPDEF(S2, S1, 3)\nCOUPON(S2, S1, 0)\n'
                     "COUPOF(S2, S1, 0, 0)\nM30\n", TURNMILL)
    cp = [c for c in r.commands if isinstance(c, SpindleCoupling)][0]
    assert (cp.ratio, cp.mode) == (3.0, "AV")
    text = "COUPDEF(S2, S1, 2, 1)\nCOUPRES(S2, S1)\nCOUPON(S2, S1)\nM30\n"
    e = error_of(run(tmp_path, HEAD + text, TURNMILL))
    assert (e.kind, e.line) == ("coupling_undefined", 5)


@pytest.mark.parametrize("line, kind", [
    ("COUPON(S2, S1, 0)", "coupling_undefined"),                   # never defined
    ("COUPDEF(S2, S1, 2, 0)", "invalid_value"),                    # zero denominator
    ("COUPDEF(S2, S1, 0, 1)", "invalid_value"),                    # ratio 0
    ('COUPDEF(S2, S1, 2, 1, "SLOW")', "invalid_value"),            # no such block change behaviour
    ('COUPDEF(S2, S1, 2, 1, "FINE", "XX")', "invalid_value"),      # no such coupling type
    ("COUPDEF(S7, S1, 2, 1)", "unknown_spindle"),                  # the turn-mill has S1 and S2
    ("COUPDEF(S1, S1, 2, 1)", "invalid_value"),                    # a spindle cannot follow itself
    ("COUPDEF(X, S1, 2, 1)", "invalid_value"),                     # not a spindle name
    ("COUPDEF(S2, S1, 2, 1, \"FINE\", \"DV\", 1)", "syntax"),      # too many places
])
def test_bad_couplings_are_errors_at_their_line(tmp_path, line, kind):
    e = error_of(run(tmp_path, HEAD + line + "\nM30\n", TURNMILL))
    assert (e.kind, e.line) == (kind, 3)


def test_coupdef_of_an_active_pair_is_the_controls_alarm(tmp_path):
    e = error_of(run(tmp_path, HEAD + "COUPDEF(S2, S1, 2, 1)\nCOUPON(S2, S1)\nCOUPDEF(S2, S1, 3, 1)\nM30\n",
                     TURNMILL))
    assert (e.kind, e.line) == ("coupling_active", 5)
