"""Motion: the canonical stream as a numpy move table (arcs linearised)."""

from vmach.motion.table import ARC, FEED, TRAVERSE, MoveTable, arc_points, build

__all__ = ["ARC", "FEED", "TRAVERSE", "MoveTable", "arc_points", "build"]
