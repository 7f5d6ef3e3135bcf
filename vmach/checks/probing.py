"""Touch-probe moves in verify (measuring cycles, canon.ProbeMove; rows of kind PROBE).

A probe's measuring move should stop where its stylus touches the part, and a probe that
meets nothing on its measuring path (``probe_no_contact``) or hits the part while
positioning (a collision) should be reported at the move's line. That contact check on the
simulated stock is not built yet: until it is, the stock simulation runs a measuring move to
its end like a feed of the active tool, and this module says so (never a silent pass).
"""

from __future__ import annotations

import numpy as np

from vmach.findings import Finding, warning
from vmach.motion.table import PROBE


def unchecked(table, simulated: bool) -> list[Finding]:
    """One ``probe_unchecked`` warning at the first measuring move when the stock is cut."""
    rows = np.nonzero(np.asarray(table.kind) == PROBE)[0] if len(table) else []
    if not simulated or len(rows) == 0:
        return []
    return [warning("probe_unchecked", f"{len(rows)} measuring move(s) of a probe: verify does not "
                    "stop a probe at contact with the stock yet; they are cut like feeds of the active "
                    "tool to the end of their measuring path", table.source(int(rows[0])),
                    moves=int(len(rows)))]
