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
    #: Material below this volume (mm³) does not count as removed by a rapid or touched by a
    #: holder (boolean round-off on a cut stock is far smaller).
    removal_volume: float = 1e-3
    #: Largest stock or tool dimension accepted, mm (10 m: beyond any machine vmach models; a
    #: round blank's polygon and the trim slabs' 1 mm bins grow with size, so a mistyped
    #: ``d=60e6`` must be an error, not an attempt to allocate petabytes).
    max_size: float = 10_000.0
    #: Smallest stock or tool dimension accepted, mm (1 nm: far below any blank or cutter, and
    #: far above the sizes whose polygons divide by zero — ``d=1e-300`` must be an error).
    min_size: float = 1e-6
    #: Largest magnitude of any number read from a model or CL file, and of an arc's radius
    #: (mm, degrees, mm/min): far beyond any machine, small enough that squares and products
    #: stay finite.
    max_magnitude: float = 1e9
    #: Most rows a move table holds (arcs count as their chords; each row costs about 0.7 kB
    #: while the table is built): a helix of a billion turns (``TURN=1000000000``) must be an
    #: error, not an attempt to allocate terabytes.
    max_moves: int = 5_000_000
    #: Most sampled poses of one tool's path in the stock simulation (each costs ~30 kB on the
    #: way: a C1=IC(1EX6) turn, 500,000 poses, took 7.7 GB); the polygon-shaft program's
    #: longest path has 6,763.
    max_poses: int = 100_000
    #: Most poses the collision checks sample along the program (~3 kB each: a turn of a
    #: million degrees sampled 2.8 million and took 7.6 GB).
    max_samples: int = 1_000_000
    #: A convex blank read from a mesh is taken as its convex hull (fewer triangles: a CAD
    #: cylinder's side strips, cut along its length, merge) when every triangle of the mesh lies
    #: within this of a face plane of the hull, mm (:func:`vmach.stock.hull.as_hull`).
    blank_hull: float = 1e-4
    #: Largest NC program (or CL file) vmach reads, bytes, and longest line in it, characters
    #: (checked before parsing): far above real programs (a control's block is at most a few
    #: hundred characters; LinuxCNC's 256), small enough to be refused at once — a 200 MB
    #: program took 10 minutes and 1.7 GB, a 1 MB line 400 MB (benchmarks/limits.py).
    max_program_bytes: int = 32 * 1024 * 1024
    max_line_length: int = 10_000
    #: Largest machine model, tool library or setup file, bytes (real ones are a few kB).
    max_config_bytes: int = 1024 * 1024
    #: Default block limit for interpreters (infinite-loop guard): 3,000,000 blocks bite in
    #: about 3.5 CPU-s in the slowest loop (an RS274 ``while``; benchmarks/limits.py); the
    #: busiest real program of the corpus runs 1.2 million. ``--max-blocks`` may raise it up to
    #: ``max_blocks_ceiling``, beyond which a value is a usage error.
    max_blocks: int = 3_000_000
    max_blocks_ceiling: int = 100_000_000
    #: Most canonical commands one run makes (about 0.35 kB each: ~360 MB for ``vmach run``): a
    #: loop that moves stops here before it exhausts the memory; the busiest real program of the
    #: corpus makes 152,614. (``verify`` holds 0.7 kB more a move in its move table.)
    max_commands: int = 1_000_000
    #: Default subprogram call depth limit (Sinumerik allows 16 levels incl. main program).
    max_call_depth: int = 16
    #: Stock removal (docs/stock.md): largest rotation of the tool between two sampled poses
    #: of a rotary move, degrees. The pose-sampled sweep leaves scallops of at most
    #: r·(sec(δ/2) − 1) ≈ r·δ²/8 on faces cut by a flat tool face (0.0041 mm at r = 26.8, 2°).
    sweep_angle: float = 2.0
    #: Stock removal: largest tool-tip travel between two sampled poses of a rotary move, mm.
    sweep_step: float = 1.0
    #: Stock removal: largest cusp a curved tool side (cylinder, cone, ball) may leave between
    #: two placed poses of a rotary step, mm; steps that would leave more are cut into parts
    #: (:mod:`vmach.stock.cusps`).
    sweep_cusp: float = 0.01
    #: Polygonisation of revolved tool solids: largest radial deviation of the polygon from
    #: the true circle, mm (the polygon straddles the circle, so half of its sagitta). It bounds
    #: the error of surfaces made by a tool's side; a flat face is exact for any polygon. 0.01
    #: is half the booleans' time of 0.002 on the polygon shaft (docs/stock.md).
    tool_chord: float = 0.01
    #: Polygonisation of a round blank (``--stock cylinder:...``), mm, as ``tool_chord``.
    blank_chord: float = 0.002
    #: Stock removal: convex hull used for a move only while its rotation stays below this
    #: angle, degrees (above it the hull overcuts by about R·sin(δ/2); see docs/stock.md).
    hull_angle: float = 1e-6
    #: Stock removal: cutters are trimmed to the stock's bounding box grown by this much, mm
    #: (exact: the stock never grows; the margin keeps the trimmed faces off the stock).
    trim_margin: float = 0.5
    #: Stock removal, fan cutters (vmach/stock/fan.py): the most a fan cutter may remove beyond
    #: the true swept volume, mm — where a rotary run also moves along its rotation axis, the
    #: hull bridges the twisted surface the tool's side sweeps. The flat face's surface is
    #: unaffected (the tangent polygon of the sampled faces, as with placed poses).
    fan_overcut: float = 0.005
    #: Largest rotation of the tool axis within one fan cutter, degrees.
    fan_angle: float = 20.0
    #: Column cutters (vmach/stock/column.py): the angular sector of the tool axis they take
    #: of each turn of a helix, degrees (360 / it a whole number), and the most turns in one.
    column_sector: float = 15.0
    column_turns: int = 8


tol = Tolerances()


@dataclass(frozen=True)
class Accuracy:
    """A stock simulation's accuracy preset (``vmach verify --accuracy``): the tool polygon
    (mm, as ``Tolerances.tool_chord``), the side cusps between placed poses (mm, as
    ``Tolerances.sweep_cusp``) and whether a flat or face mill's polygon is round about the
    directions it is made exact toward (``rim_arcs``: :func:`vmach.tooling.solid.ring_points`;
    its face's rim makes the flank's foot where a side-made surface meets it). Error and time
    of each on the polygon-shaft program are measured in docs/stock.md
    (``benchmarks/stock_error.py --accuracy NAME``)."""

    tool_chord: float
    sweep_cusp: float
    rim_arcs: bool = False

    @property
    def stock(self) -> dict:
        """The preset as :class:`vmach.stock.Stock` keywords (``chord``, ``cusp``, ``arcs``)."""
        return {"chord": self.tool_chord, "cusp": self.sweep_cusp, "arcs": self.rim_arcs}


#: ``standard``: the defaults (6–8.5 s for the polygon-shaft program, within +0.0106 / −0.0093 mm
#: of a converged simulation). ``fine``: tools to 0.004 mm, side cusps (and a flat face's rim
#: feet) to 0.0035 mm, and flat or face mills round about the directions their poses are made
#: exact toward — within +0.0048 / −0.0035 mm, about 1.4 times the time (docs/stock.md).
ACCURACY = {
    "standard": Accuracy(tool_chord=tol.tool_chord, sweep_cusp=tol.sweep_cusp),
    "fine": Accuracy(tool_chord=0.004, sweep_cusp=0.0035, rim_arcs=True),
}
