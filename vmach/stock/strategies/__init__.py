"""Cutter strategies: each claims part of a path and says how it is to be cut.

The planner (:mod:`vmach.stock.plan`) runs them in this priority order; what none claims is
cut as the tool placed at each sampled pose (exact at the poses; between them it leaves
material only, within :func:`vmach.stock.sweep.scallop_bound`).

1. :mod:`.runs` — translation runs: the hull of the tool at a run's two ends *is* the swept
   volume of a straight move (exact); the placed poses on a run are left out; a run along the
   tool's own axis with the stock in front of its back is cut as the tool at its inner pose
   (exact: all it removes); runs that stack along the axis share one hull (exact: their union).
2. :mod:`.fans` — rotary runs of a flat-faced prism: one fan cutter per run, or one column per
   sector of consecutive helix turns. The only strategy that may remove more than the true
   sweep: by at most ``tol.fan_overcut``, measured on every cutter made
   (:mod:`vmach.stock.make_fans`).
3. :mod:`.fins` — placed poses of a flat-faced prism between two rotary steps cut as their
   fin only where the neighbours' fins hold the rest (the same material, to a sliver).
4. :mod:`.cusps` — poses added inside rotary steps where a curved side (or a flat face's
   rim's feet) would leave cusps over the stock's ``cusp`` (leaves material only, within it).
5. :mod:`.revolved` — a turning tool's whole path while the workpiece turns (not a milling
   path: no other strategy sees it): its X–Z cross-section swept step by step, the pass
   united and revolved about the spindle axis (exact to the section's and the blank's chords).
6. :mod:`.polygonal` — a flywheel cutter's path while its spindle is coupled to the turning
   work (polygonal turning; no other strategy sees it): the inserts' sweep relative to the
   work as a 2-D section, extruded along the feed (within 1.3 µm measured, its stated bound).

A strategy reads the stock only through :class:`vmach.stock.view.View` (a snapshot) and other
paths only through the optional coverage index (:class:`vmach.stock.sweeps.Others`).
"""
