"""The rim of a fan's flat face: where it leaves a foot the hull would take
(:func:`rim_standoff`), and which rim bands other paths' true tools sweep anyway
(:func:`rims_covered`, with the coverage index :class:`vmach.stock.sweeps.Coverage`).
See :mod:`vmach.stock.fan`. Lengths mm.
"""

from __future__ import annotations

import numpy as np

from vmach.stock.sweeps import by_axis

#: A rim band is covered by another pose's face only where that face reaches this far (mm)
#: beyond the tip along the face line: the stretch of the chain a rim must cut lies within
#: about 1 mm of its tip on the polygon shaft (the program's Y approximates the contact point).
RIM_REACH = 1.5
#: points across (along the face line) and up (heights) of a rim's band tried against other
#: paths' sweeps (:func:`rims_covered`)
RIM_SAMPLES = (3, 2)


def rim_standoff(tips: np.ndarray, axes: np.ndarray, angle: np.ndarray, reach: int = 2) -> np.ndarray:
    """(n-1,) mm: for each step, how far the path of the face's rim stands off the face chain.

    A face is a disc: toward its rim along omega it narrows to the point tip ± R·omega, whose
    projection along omega is the tip. Near the rim the tool reaches the chain of face lines
    only where the tips' path runs along it; where a tip lies beyond its own stretch of the
    chain (the tool centre ahead of or behind the contact: a Y that only approximates the
    profile) or above it (the higher pose of a slide), the material between the chain and the
    path is left by the true tool in a thin band at the rim — and would be taken by H minus M,
    which cuts to the chain at every height. Measured as the largest ``n_j·x − h_j`` over the
    face planes j of the poses within ``reach`` of each step, at both tips x and the chord's
    midpoint, the latter raised by the arc's sagitta ``(c/2)·tan(δ/4)`` (a rotating tip runs on
    an arc outside its chord)."""
    n = len(tips)
    h = np.einsum("ij,ij->i", tips, axes)
    mid = 0.5 * (tips[:-1] + tips[1:])
    sag = 0.5 * np.linalg.norm(tips[1:] - tips[:-1], axis=1) * np.tan(np.radians(angle) / 4.0)
    out = np.zeros(n - 1)
    for off in range(-reach, reach + 2):
        j = np.clip(np.arange(n - 1) + off, 0, n - 1)
        for x, extra in ((tips[:-1], 0.0), (tips[1:], 0.0), (mid, sag)):
            out = np.maximum(out, np.einsum("ij,ij->i", x, axes[j]) - h[j] + extra)
    return out


def rim_band(s_fwd: np.ndarray, s_back: np.ndarray, turn: np.ndarray, radius: float) -> np.ndarray:
    """(n-1,) mm: the height of the band at a face's rim in which its disc is too narrow to
    reach the ends of its stretch of the face chain. The stretch runs from crease to crease,
    at most S = max(|s_fwd|, |s_back|) from the tip; the disc is at least that wide up to
    ``R − √(R² − S²)`` from its rim. A step without a turn (a slide) takes the larger band of
    the turns on either side of it. Whatever the rim leaves lies within this band, so it is
    also a bound of the error the rim can make."""
    big = np.minimum(np.maximum(np.abs(s_fwd), np.abs(s_back)), radius)   # no crease: the radius
    band = radius - np.sqrt(radius**2 - big**2)
    prev, nxt = _turns_around(turn)
    left = np.where(prev >= 0, band[np.maximum(prev, 0)], radius)
    right = np.where(nxt < len(band), band[np.minimum(nxt, len(band) - 1)], radius)
    return np.where(turn, band, np.maximum(left, right))


def _turns_around(turn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each step (turn (m,) bool), the last turning step at or before it (-1: none) and
    the first at or after it (m: none)."""
    idx = np.arange(len(turn))
    prev = np.maximum.accumulate(np.where(turn, idx, -1))
    nxt = np.minimum.accumulate(np.where(turn, idx, len(turn))[::-1])[::-1]
    return prev, nxt


def rims_covered(tips: np.ndarray, axes: np.ndarray, w: np.ndarray, turn: np.ndarray, band: np.ndarray,
                  rim: float, radius: float, which: np.ndarray, inner: float,
                  box: np.ndarray | None = None, cover=None) -> np.ndarray:
    """(n-1,) bool: of the steps ``which``, those whose rim bands the path cuts anyway, or
    that lie beyond the stock's bounding ``box`` (2, 3) along omega (the tool's inscribed
    radius ``inner`` from the tip: the least the true rim reaches), or that the true tools of
    other paths sweep (``cover``: the coverage index, :meth:`vmach.stock.sweeps.Coverage.swept`,
    or None) above the height ``rim`` that a band may have
    anyway — points of the face chain across the band's stretch (``RIM_SAMPLES``) at heights
    from ``rim`` to the band's, just on the tool's side of the face.

    Whatever a fan takes in the band at a face's rim (:func:`rim_standoff`) is taken by the
    true motion too if the path passes the same place again with the face at full width
    there: another pose, its axis within 1° and its face plane within ``rim`` of the tip,
    lying along omega beyond the band, and wide enough at the band's level
    (``sqrt(2Rd − d²)`` for a pose d away) to reach ``RIM_REACH`` beyond the tip. A finishing
    helix's next turn, 2 mm lower, does that for every turn but the last (whose lower rims
    stay to be judged) and its previous turn for every turn but the first (upper rims). Both
    rims of both poses of a step must be covered."""
    n = len(tips)
    steps = np.nonzero(which)[0]
    if len(steps) == 0:
        return np.zeros(n - 1, bool)
    # each step's omega: its own, or a neighbouring turn's (a slide); each pose takes the
    # omega and the (larger) band of the steps it belongs to
    prev, nxt = _turns_around(turn)
    src = np.where(turn, np.arange(n - 1), np.where(prev >= 0, prev, np.minimum(nxt, n - 2)))
    pose_om = w[src[np.minimum(np.arange(n), n - 2)]]
    pose_band = np.maximum(np.r_[band[:1], band], np.r_[band, band[-1:]])
    qs = np.unique(np.r_[steps, steps + 1])
    lower, upper = _cut_again(tips, axes, qs, pose_om, pose_band, rim, radius)
    if box is not None:
        # a rim whose whole band lies beyond the stock along omega leaves its foot in the air
        # (the first turns of a helix that starts above the end face); the true rim is at
        # least the polygon's inscribed radius out
        box = np.asarray(box, dtype=float)
        reach = np.einsum("ij,ij->i", tips, pose_om)
        top = np.maximum(box[0] * pose_om, box[1] * pose_om).sum(axis=1)
        bottom = np.minimum(box[0] * pose_om, box[1] * pose_om).sum(axis=1)
        upper |= reach + inner - pose_band >= top
        lower |= reach - inner + pose_band <= bottom
    if cover is not None:
        for sign, done in ((-1.0, lower), (1.0, upper)):
            need = qs[~done[qs] & np.any(pose_om[qs], axis=1) & (pose_band[qs] > rim)]
            if len(need):
                # from the true rim: halfway between the straddling polygon's vertices and its
                # inscribed circle
                done[need] = _swept_by_others(tips, axes, need, pose_om[need], sign, pose_band[need],
                                              rim, 0.5 * (radius + inner), cover)
    both = lower & upper & np.any(pose_om, axis=1)
    out = np.zeros(n - 1, bool)
    out[steps] = both[steps] & both[steps + 1]
    return out


def _cut_again(tips: np.ndarray, axes: np.ndarray, qs: np.ndarray, pose_om: np.ndarray,
               pose_band: np.ndarray, rim: float, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) (n,) bool: poses ``qs`` whose lower / upper rim band another pose of the
    path cuts again at full width (turned alike, its face plane within ``rim`` of the tip,
    beyond the band along omega, wide enough to reach RIM_REACH beyond the tip)."""
    n = len(tips)
    h = np.einsum("ij,ij->i", tips, axes)
    # other poses turned alike: axes within 1 degree (in blocks: problems × poses)
    cos1 = np.cos(np.radians(1.0))
    pairs = [np.nonzero(axes[qs[b : b + 256]] @ axes.T >= cos1) for b in range(0, len(qs), 256)]
    q = np.concatenate([qs[b + r] for b, (r, _) in zip(range(0, len(qs), 256), pairs, strict=True)])
    j = np.concatenate([c for _, c in pairs])
    om = pose_om[q]
    keep = np.abs(np.einsum("ij,ij->i", axes[j], tips[q]) - h[j]) <= rim   # face plane near the tip
    d = np.einsum("ij,ij->i", tips[q] - tips[j], om)                   # > 0: the other pose is lower
    side = np.abs(np.einsum("ij,ij->i", tips[j] - tips[q], np.cross(om, axes[q])))  # along the face line
    # at the level of q's rim, a pose d lower (or higher) is sqrt(2Rd - d²) wide
    width = np.sqrt(np.maximum(2 * radius * np.abs(d) - d * d, 0.0))
    cover = keep & (np.abs(d) >= pose_band[q] + 1e-3) & (side <= width - RIM_REACH)
    lower = np.zeros(n, bool)
    upper = np.zeros(n, bool)
    lower[q[cover & (d > 0)]] = True
    upper[q[cover & (d < 0)]] = True
    return lower, upper


def _swept_by_others(tips: np.ndarray, axes: np.ndarray, which: np.ndarray, om: np.ndarray, sign: float,
                     band: np.ndarray, rim: float, radius: float, cover) -> np.ndarray:
    """(w,) bool: of the poses ``which`` (w,) of a path (tips, unit axes (n, 3)), each with its
    omega (w, 3) and its rim's band (heights (w,) mm), those whose rim toward ``sign``·omega
    has the band swept above ``rim`` by other paths' true tools (``cover``). The band lies on
    the face chain — what a fan cuts to, the lowest of the face planes of the poses within
    two of it — across its stretch (as wide as the disc is at the band's top) at heights from
    ``rim`` to the band's above the true rim (``radius``): those points, 0.001 mm above the
    chain, are asked as one group (:meth:`vmach.stock.sweeps.Coverage.swept`: every point
    swept), the middle one first."""
    across, up = RIM_SAMPLES
    t, a = tips[which], axes[which]
    half = np.sqrt(np.maximum(2.0 * radius * band - band * band, 0.0))             # (w,)
    line = np.cross(om, a)
    u = np.linspace(0.0, 1.0, up)[None, :] * (band - rim)[:, None] + rim              # (w, up)
    s = np.linspace(-1.0, 1.0, across)[None, :] * half[:, None]                        # (w, across)
    pts = (t + sign * radius * om)[:, None, None] - sign * u[:, None, :, None] * om[:, None, None] \
        + s[:, :, None, None] * line[:, None, None]                                   # (w, across, up, 3)
    # down to the chain: the lowest face plane of the poses around (n·x <= h below each)
    h = np.einsum("ij,ij->i", tips, axes)
    depth = np.zeros(pts.shape[:3])
    for off in range(-2, 3):
        j = np.clip(which + off, 0, len(tips) - 1)
        depth = np.maximum(depth, np.einsum("wabi,wi->wab", pts, axes[j]) - h[j][:, None, None])
    pts = pts - (depth - 1e-3)[..., None] * a[:, None, None]
    # the middle sample first: the index looks a group up by its first point
    mid = across // 2 * up + up // 2
    flat = pts.reshape(len(which), -1, 3)
    flat = np.concatenate([flat[:, mid : mid + 1], np.delete(flat, mid, axis=1)], axis=1)
    out = np.zeros(len(which), bool)
    for o, grp in by_axis(om):
        out[grp] = cover.swept(flat[grp], o)
    return out
