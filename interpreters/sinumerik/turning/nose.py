"""Tool nose radius compensation on the lathe: G41/G42 with a turning tool's cutting edge
position (SL, Programming Manual Fundamentals, "Tool radius compensation": "Cutting edge
position" of turning tools).

The compensation (:mod:`interpreters.sinumerik.cutcom`) runs the nose circle's centre S at
the nose radius from the programmed contour. The control does not move S but the tool's
reference point P, the theoretical tip the SL names: P = S + (dx, dz) with, for nose radius
r, SL 1 (+r, +r), 2 (+r, −r), 3 (−r, −r), 4 (−r, +r), 5 (0, +r), 6 (+r, 0), 7 (0, −r),
8 (−r, 0), 9 (0, 0) (X a radius). So the compensated path is written for P, and the turned
part follows the drawn contour nose radius included. Only in G18 (Z-X) with a tool the library
describes with an edge position; any other tool keeps S (a milling cutter's centre).
"""

from __future__ import annotations

#: SL -> (dx, dz) of P from the nose centre, in nose radii
EDGE = {1: (1, 1), 2: (1, -1), 3: (-1, -1), 4: (-1, 1), 5: (0, 1), 6: (1, 0), 7: (0, -1),
        8: (-1, 0), 9: (0, 0)}


def shift(m) -> tuple[float, float]:
    """(dz, dx) from the nose centre to P in the G18 plane (first axis Z, second X), mm;
    (0, 0) for any other plane or a tool without a cutting edge position."""
    if m.plane != "G18" or m.tool_data_of is None or m.tool is None or m.edge == 0:
        return (0.0, 0.0)
    data = m.tool_data_of(m.tool, m.edge)
    sl = int(data.get("edge_position", 0)) if data else 0
    if sl not in EDGE:
        return (0.0, 0.0)
    r = m.cutcom.radius
    dx, dz = EDGE[sl]
    return (dz * r, dx * r)
