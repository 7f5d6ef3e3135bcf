"""Cutter strategies: each claims part of a path and says how it is to be cut.

Every strategy is one module with one door (:mod:`vmach.stock.path` says it in full)::

    NAME = "fans"                       # its switch and its line in the table
    BOUND = Bound(over=..., under=...)  # what its cutters may differ from the true sweep
    def claim(path, free, view, cover) -> Claim

The planner (:mod:`vmach.stock.plan`) asks them in the order of its ``TABLE``, each over what
the ones before left (``free``):

1. :mod:`.revolved` — a turning tool's whole path while the workpiece turns (no other
   strategy sees it): its X–Z cross-section swept step by step, the pass united and revolved
   about the spindle axis (exact to the section's and the blank's chords).
2. :mod:`.polygonal` — a polygonal-turning path (a flywheel cutter coupled to the turning
   work) whole: the inserts' sweep relative to the work as one 2-D section, extruded along the
   axial feed (within ``tool_polygon`` of the exact sweep, either way: 1 µm per placement).
3. :mod:`.fans` — rotary runs of a flat-faced prism, and the slides between their turns: one
   fan cutter per run, or one column per sector of consecutive helix turns. The only milling
   strategy that may remove more than the true sweep: by at most ``tol.fan_overcut``,
   measured on every cutter made (:mod:`vmach.stock.make_fans`).
4. :mod:`.runs` — translation runs: the hull of the tool at a run's two ends *is* the swept
   volume of a straight move (exact); the placed poses on a run are left out; a run along the
   tool's own axis with the stock in front of its back is cut as the tool at its inner pose
   (exact: all it removes).
5. :mod:`.fins` — placed poses of a flat-faced prism between two placed rotary steps cut as
   their fin only where the neighbours' fins hold the rest (the same material, to a sliver).
6. :mod:`.cusps` — poses added inside placed rotary steps where a curved side (or a flat
   face's rim's feet) would leave cusps over the stock's ``cusp`` (leaves material only,
   within it).
7. :mod:`.placed` — every pose left, the tool placed there (exact at the poses; between them
   it leaves material only, within :func:`vmach.stock.sweep.scallop_bound`).

A strategy reads the stock only through :class:`vmach.stock.view.View` (a snapshot) and other
paths only through the optional coverage index ``cover`` (:class:`vmach.stock.sweeps.Coverage`,
None when the program is streamed path by path).
"""
