"""Tolerances and limits in one place (trimesh's ``tol`` idea).

Every module that needs a tolerance imports it from here, so a change is made once and a test
can name the number it relies on.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Tolerances:
    #: Sinumerik compares REAL values for *relative* equality (Programming Manual, "Precision
    #: correction on comparison errors"): |a - b| <= 1e-12 * max(|a|, |b|).
    compare_relative: float = 1e-12
    #: Maximum chord error when an arc is broken into straight segments, mm.
    chord: float = 0.001
    #: Maximum angular step when rotary motion is subdivided, degrees.
    angle_step: float = 0.5
    #: Distance below which two points are the same, mm.
    merge: float = 1e-9
    #: Clearance below which a rapid move is reported as a near miss, mm.
    near_miss: float = 1.0
    #: Default block limit for interpreters (infinite-loop guard).
    max_blocks: int = 10_000_000
    #: Default subprogram call depth limit (Sinumerik allows 16 levels incl. main program).
    max_call_depth: int = 16


tol = Tolerances()
