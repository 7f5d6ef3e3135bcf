"""What the planners and cutter makers may read of the stock: a snapshot, never the live solid.

The stock's bounds and trim slabs (:mod:`vmach.stock.slabs`) are taken at retakes, each from the
stock as the retake before asked for it (the blank at the first two): a stale snapshot is only
looser (the stock shrinks), and the cutters — so the part — never depend on how far the
booleans have got, in this process or in the worker. All lengths mm.
"""

from __future__ import annotations

import numpy as np

from vmach.stock.blank import Blank
from vmach.stock.events import cylinder_boxes
from vmach.stock.fan import back_clear
from vmach.stock.queue import Queue
from vmach.stock.slabs import Slabs
from vmach.tol import tol


class View:
    """The snapshot of the stock that cutters are made against.

    SLAB_REFRESH : batches after which the trim slabs are taken again.
    FRESH_AFTER : batches' worth of cutters after which a new path retakes them.
    SLABS : trim to the stock's extent per Z range (False: one box, for comparison).
    """

    SLAB_REFRESH = 32
    FRESH_AFTER = 4
    SLABS = True

    def __init__(self, queue: Queue, blank: Blank):
        self.queue = queue
        self.blank = blank
        self.slabs: Slabs | None = None
        self._slabs_at = -1         # batches done when the slabs were taken
        self._next: list | None = None
        #: (c, 2, 3) the pieces' boxes the cutters are made against (as at the last retake)
        self.seen = queue.boxes()

    @property
    def trimming(self) -> Slabs | None:
        """The trim slabs, when they are taken and used."""
        return self.slabs if self.SLABS else None

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float — bounds of the stock as the last retake saw it (conservative)."""
        return np.stack([self.seen[:, 0].min(axis=0), self.seen[:, 1].max(axis=0)])

    def trim_box(self) -> np.ndarray:
        """(2, 3) float — :attr:`bounds` grown by ``tol.trim_margin`` so that no trimmed face
        touches the stock."""
        b = self.bounds
        return np.stack([b[0] - tol.trim_margin, b[1] + tol.trim_margin])

    def boxes(self, zlo: np.ndarray, zhi: np.ndarray, fresh: bool = False, force: bool = False) -> np.ndarray:
        """Trim boxes (k, 2, 3) for cutters spanning Z ranges [zlo, zhi] (k,): the stock's
        extent within the range, inside :meth:`trim_box`. The slabs are taken again after
        every SLAB_REFRESH batches, and for a new path (``fresh``) once FRESH_AFTER batches'
        worth of cutters were made since — or one, with ``force`` (a path that may make fans,
        which judge the tool's back by the stock) — the pending cutters then handed to the
        booleans. Each retake reads the stock as the retake before left it and asks for the
        stock as it is now for the next."""
        q = self.queue
        done = q.batches
        since = q.made - self._slabs_at
        if (fresh and self.SLABS and self.slabs is not None
                and (since >= self.FRESH_AFTER or (force and since >= 1))):
            q.send()
            done = q.batches
            stale = True
        else:
            stale = done - self._slabs_at >= self.SLAB_REFRESH
        if self.SLABS and (self.slabs is None or stale):
            self._retake(done)
        outer = self.trim_box()
        if self.slabs is None or not self.SLABS:
            return np.broadcast_to(outer, (len(zlo), 2, 3)).copy()
        return self.slabs.boxes(zlo, zhi, outer)

    def _retake(self, done: int) -> None:
        now = self.queue.snapshots()       # for the next retake
        view = [s.get() for s in (self._next or now)]
        self._next = now
        self.seen = np.array([s[2] for s in view])
        meshes = [(s[0], s[1].astype(np.int64)) for s in view if len(s[1])]
        if meshes:
            offset = np.cumsum([0] + [len(m[0]) for m in meshes])[:-1]
            faces = [m[1] + o for m, o in zip(meshes, offset, strict=True)]
            self.slabs = Slabs.from_mesh(np.concatenate([m[0] for m in meshes]), np.concatenate(faces))
        self._slabs_at = done

    # ----------------------------------------------------------------------------------------
    def holds(self, points: np.ndarray) -> np.ndarray:
        """(...) bool: points (..., 3) that may lie in the stock (a superset: the trim slabs'
        extents, :meth:`vmach.stock.slabs.Slabs.holds`, or the stock's bounds)."""
        if self.trimming is not None:
            return self.slabs.holds(points)
        b = self.bounds
        return np.all((points >= b[0]) & (points <= b[1]), axis=-1)

    def behind(self, tips: np.ndarray, axes: np.ndarray, tool, zlo: np.ndarray,
               zhi: np.ndarray) -> np.ndarray:
        """(n,) bool: poses (tips, unit axes (n, 3)) with the stock in front of the plane
        ``tool.length`` behind the tip (the tool's back; a Prism or a ToolSolid): the whole
        blank (:func:`vmach.stock.fan.back_clear`), or — with the trim slabs — the stock
        within the Z ranges [zlo, zhi] (n,) (:meth:`vmach.stock.slabs.Slabs.support`)."""
        clear = back_clear(tips, axes, tool, self.blank.hull.corners)
        if self.trimming is not None:
            reach = np.einsum("ij,ij->i", tips, axes) + tool.length
            clear |= self.slabs.support(zlo, zhi, axes) <= reach
        return clear

    def back_clear(self, tips: np.ndarray, axes: np.ndarray, pr) -> np.ndarray:
        """(n,) bool: poses whose prism's back face has the stock behind it where the fans it
        may join could fill a notch: the stock within the Z range of this pose's tool and its
        neighbours' (:meth:`behind`)."""
        if len(tips) == 0:
            return np.zeros(0, bool)
        box = cylinder_boxes(tips, axes, 0.0, pr.length, pr.radius)
        lo, hi = box[:, 0, 2], box[:, 1, 2]
        lo = np.minimum(lo, np.minimum(np.r_[lo[:1], lo[:-1]], np.r_[lo[1:], lo[-1:]]))
        hi = np.maximum(hi, np.maximum(np.r_[hi[:1], hi[:-1]], np.r_[hi[1:], hi[-1:]]))
        return self.behind(tips, axes, pr, lo, hi)

    def apart(self, points: list, axes: np.ndarray) -> np.ndarray:
        """(m,) bool: cutters (their points (p, 3) each, or None) that lie wholly beyond the
        stock along their tool's axis (m, 3) — every point further out along it than the
        stock reaches within the cutter's Z range, by the trim slabs: a tool moved away from the
        part whose box still meets the stock's box."""
        out = np.zeros(len(points), bool)
        if self.trimming is None:
            return out
        idx = [j for j, q in enumerate(points) if q is not None and len(q)]
        if not idx:
            return out
        a = np.asarray(axes, dtype=float)[idx]
        a = a / np.linalg.norm(a, axis=1, keepdims=True)
        near = np.array([float((points[j] @ a[i]).min()) for i, j in enumerate(idx)])
        zlo = np.array([points[j][:, 2].min() for j in idx])
        zhi = np.array([points[j][:, 2].max() for j in idx])
        out[idx] = near > self.slabs.support(zlo, zhi, a) + 1e-9
        return out
