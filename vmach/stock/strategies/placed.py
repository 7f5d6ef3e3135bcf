"""Placed poses: every pose no strategy before holds, cut as the tool placed there — the
last line of the planner's table, which always runs.

Error bound: exact at the poses; between two placed poses of a rotary step it leaves material
only, the scallop ``r·(sec(δ/2) − 1) + (r·δ)²·κ/8`` (:func:`vmach.stock.sweep.scallop_bound`,
``face_scallop`` in the report), and a curved side's cusps (``side_cusps``: what
:mod:`.cusps` brings within the stock's ``cusp``).
"""

from __future__ import annotations

import numpy as np

from vmach.stock.path import NOTHING, Bound, Claim, Free, Path, Poses
from vmach.stock.view import View

NAME = "placed"
BOUND = Bound(under="face_scallop")


def claim(path: Path, free: Free, view: View, cover) -> Claim:
    """The poses still to place, whole."""
    idx = np.nonzero(free.place)[0]
    if len(idx) == 0:
        return NOTHING
    inf = np.full(len(idx), np.inf)
    return Claim(held=free.place.copy(), poses=Poses(idx.astype(float), path.frames[idx], inf, inf,
                                                     path.pose_rows(idx)))
