"""A lathe cycle's contour and the passes of G70 (finishing) and G71/G72 (roughing), as
LinuxCNC 2.9 cuts them (``interp_g7x.cc``).

The contour is normalised before cutting: G72 (and a G70 whose contour only fits that way)
turns it by 90°, then it is mirrored so that X and Z decrease along it; the moves are mapped
back on output (:class:`_Mapped`). Roughing (:meth:`G7xPath.rough`) cuts horizontal passes
``delta`` apart from the start level down, each ending where it meets the contour, with a
45° retract of ``escape``; pockets (the contour dipping and rising again) are cut in turn
unless the cycle is G7x.1 (no pockets) or G7x.2 (only pockets). Points are complex
``z + 1j*x`` in program units (X a radius).
"""

from __future__ import annotations

from interpreters.rs274ngc.g7x_segments import TOL, Arc, G7xError, Line, Segment, Sink, cpp, dv, sc

#: the most passes of :meth:`G7xPath._pocket`'s loop one cycle may take: on some contours
#: LinuxCNC 2.9 loops for ever without moving (vmach stops with :class:`G7xRunaway`)
MAX_STEPS = 200_000


class G7xRunaway(G7xError):
    """A cycle that would not end (LinuxCNC 2.9 loops for ever on it)."""


class _Mapped(Sink):
    """Undo the normalisation of the contour (``state``: bit 0 Z mirrored, bit 1 X
    mirrored, bit 2 turned by 90°) on each move."""

    _MAPS = {
        0: (lambda p: p, False),
        1: (lambda p: -p.conjugate(), True),
        2: (lambda p: p.conjugate(), True),
        3: (lambda p: -p, False),
        4: (lambda p: 1j * p, False),
        5: (lambda p: (1j * p).conjugate(), True),
        6: (lambda p: -(1j * p).conjugate(), True),
        7: (lambda p: -1j * p, False),
    }

    def __init__(self, out: Sink, state: int):
        self.out = out
        self.map, self.flip = self._MAPS[state]

    def rapid(self, p: complex) -> None:
        self.out.rapid(self.map(p))

    def feed(self, p: complex) -> None:
        self.out.feed(self.map(p))

    def arc(self, ccw: bool, centre: complex, p: complex) -> None:
        self.out.arc(ccw != self.flip, self.map(centre), self.map(p))


class G7xPath:
    """The contour: ``segs`` from the cycle's start point along the subprogram's moves."""

    def __init__(self, segs: list[Segment] | None = None):
        self.segs: list[Segment] = segs if segs is not None else []
        self.delta = 0.5
        self.escape = complex(0.3, 0.3)
        self.state = 0
        self.pocket_starts: list[complex] = []
        #: where LinuxCNC's own debugging line goes when it drops an element that turned
        #: back ("Oops (dz,dx)" on rs274's stdout), or None
        self.say = None
        self.steps = 0

    def copy(self) -> G7xPath:
        other = G7xPath([s.dup() for s in self.segs])
        other.delta, other.escape, other.state = self.delta, self.escape, self.state
        other.say = self.say
        return other

    # -- normalisation --------------------------------------------------------------------

    def rotate(self) -> None:
        for s in self.segs:
            s.rotate()
        self.state ^= 4

    def swap(self) -> None:
        """Mirror so that X and Z decrease from the first element's end to the last's."""
        d = self.segs[0].end - self.segs[-1].end
        if d.imag > 0:
            for s in self.segs:
                s.flip_imag()
            self.state ^= 2
        if d.real < 0:
            for s in self.segs:
                s.flip_real()
            self.state ^= 1

    def check_monotonic(self) -> None:
        first = self.segs[0]
        if (first.end - first.start).real > 0:
            first.start = complex(first.end.real, first.start.imag)
        for s in self.segs:
            if not s.monotonic():
                raise G7xError("Not monotonic")

    def finish_corners(self) -> None:
        segs = self.segs
        for i in range(1, len(segs) - 1):
            segs[i].do_finish(segs[i - 1], segs[i + 1])
        self.segs = [s for s in segs if s.radius() >= 1e-3]

    # -- allowance ------------------------------------------------------------------------

    def add_distance(self, distance: float) -> None:
        """Offset the contour (all but the approach element) by ``distance`` away from the
        material, in steps of at most half the shortest element, bridging opened corners
        with arcs and trimming closed ones; the approach then ends where the offset starts."""
        segs = self.segs
        v1 = segs[0].end - segs[0].start
        v2 = segs[-1].start - segs[0].start
        if (v1 / v2).imag < 0:
            distance = -distance
        approach = segs.pop(0)
        current = 0.0
        while current != distance:
            step = min([1e9] + [s.radius() / 2 for s in segs])
            step = min(step, abs(distance - current))
            if distance < 0:
                step = -step
            i = 0
            while i < len(segs):
                segs[i].offset(step)
                if segs[i].radius() < 1e-3:
                    del segs[i]
                    continue
                i += 1
            i = 0
            while i < len(segs) - 1:
                p, n = segs[i], segs[i + 1]
                if (p.end - n.start).real > 1e-2:  # an opened corner: bridge it
                    s, e = p.dup(), n.dup()
                    s.offset(-step)
                    e.offset(-step)
                    segs.insert(i + 1, Arc(distance > 0, p.end, dv(s.end + e.start, 2.0), n.start))
                    i += 1
                i += 1
            i = 0
            while i < len(segs) - 1:
                if not segs[i].monotonic():
                    if self.say is not None:
                        self.say(f"Oops {cpp(segs[i].start - segs[i].end)}")
                    j = i - 1 if i > 0 else len(segs) - 1
                    del segs[i if segs[i].radius() < segs[j].radius() else j]
                    i = 0
                if segs[i].radius() < 1e-3:
                    del segs[i]
                    i = 0
                else:
                    segs[i].trim(segs[i + 1])
                i += 1
            current += step
        for i in range(len(segs) - 1):
            mid = dv(segs[i].end + segs[i + 1].start, 2.0)
            segs[i].end = segs[i + 1].start = mid
        approach.end = segs[0].start
        segs.insert(0, approach)

    # -- cycles ---------------------------------------------------------------------------

    def finish(self, out: Sink, x: float, z: float, d: float, e: float, p: float) -> None:
        """G70: ``p`` passes from distance ``d`` down to ``e``, each from the start point."""
        self.segs[0].start = complex(z, x)
        trial = self.copy()
        trial.segs.pop(0)
        trial.swap()
        if not all(s.monotonic() for s in trial.segs):
            trial.rotate()
            trial.swap()
        trial.check_monotonic()
        if trial.state & 4:
            self.rotate()
        self.swap()
        self.finish_corners()
        self.check_monotonic()
        mapped = _Mapped(out, self.state)
        passes = int(p)
        for k in range(passes, 0, -1):
            distance = (k - 1) * (d - e) / p + e
            path = self.copy()
            path.add_distance(distance)
            mapped.rapid(path.segs[0].start)
            mapped.rapid(path.segs[0].end)
            for s in path.segs[1:]:
                s.draw(mapped)

    def rough(self, out: Sink, cycle: int, x: float, z: float, u: float, w: float,
              d: float, i: float, r: float, turn: bool = False) -> None:
        """G71 (``turn`` False) / G72: cut the material outside the contour plus ``d``;
        ``cycle`` 0 all, 1 no pockets, 2 only what 1 left; ``i`` depth of cut, ``r`` the
        retract; ``u``/``w`` shift the contour."""
        self.segs[0].start = complex(z, x)
        if turn:
            self.rotate()
        self.swap()
        self.finish_corners()
        self.check_monotonic()
        self.add_distance(d)
        shift = complex(w, u)
        for s in self.segs:
            s.move(shift)
        mapped = _Mapped(out, self.state)
        self.delta = max(i, 2 * TOL)
        self.escape = sc(r, complex(1, 1))
        first = self.segs[0].start
        mapped.rapid(first)
        last = self.segs[-1].end
        if last.imag < first.imag:
            self.segs.append(Line(last, complex(last.real, first.imag)))
        self.pocket_starts.append(first)
        self._pocket(cycle, first, 0, mapped)

    def _pocket(self, cycle: int, loc: complex, k: int, out: Sink) -> None:
        segs = self.segs
        x = self.pocket_starts[-1].imag
        if cycle == 2:  # skip the first roughing pass
            while k < len(segs):
                stop, loc = segs[k].dive(loc, -1e9, out, k == 0)
                if stop:
                    break
                k += 1
            cycle = 3
        while k < len(segs):
            self.steps += 1
            if self.steps > MAX_STEPS:
                raise G7xRunaway(f"more than {MAX_STEPS} steps")
            while x - TOL > loc.imag:
                x -= self.delta
            stop, loc = segs[k].dive(loc, x, out, k == 0)
            if stop:
                if cycle == 1:  # along the contour to the end
                    while k < len(segs):
                        loc = segs[k].climb_only(loc, out)
                        k += 1
                    return
                while k < len(segs):  # along the contour to the next pocket
                    stop, loc = segs[k].climb(loc, out)
                    if stop:
                        starts = self.pocket_starts
                        if cycle == 3:
                            if loc.imag > starts[-1].imag and len(starts) > 1:
                                starts.pop()
                            if len(starts) == 1:
                                starts.append(loc)
                        self._pocket(cycle, loc, k, out)
                        return
                    k += 1
                return
            if abs(loc.imag - x) > TOL:  # below this element: on to the next
                k += 1
                continue
            for j in range(k, len(segs)):
                hits = segs[j].intersections(loc.imag)
                if not hits:
                    continue
                dest_z = hits[0] if j != k else hits[-1]
                dist = abs(dest_z - loc.real)
                if dest_z - TOL > loc.real:
                    continue  # meets the diving element at its start only
                if dist < TOL:
                    if j == k:
                        continue
                    if abs(loc - segs[j].start) < TOL:
                        k = j
                        break
                    x -= self.delta
                    break
                dest = complex(dest_z, loc.imag)
                out.feed(dest)
                scale = min(1.0, dist / 2 / self.escape.real)
                dest += sc(scale, self.escape)
                out.rapid(dest)
                out.rapid(loc - sc(scale, self.escape).conjugate())
                if k == 0:
                    out.rapid(loc)
                else:
                    out.feed(loc)
                x -= self.delta
                break
