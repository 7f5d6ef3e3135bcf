"""Inner fins: a placed pose of a flat-faced prism between two placed rotary steps cut as its
fin — the slab of the tool about the plane its neighbours do not reach.

Error bound: none beyond a sliver — the pose's fin holds what the pose adds to its
neighbours' fins (:func:`fins_cover` checks it per pose; a pose it cannot
show is cut whole). It exists because a fin is a few facets of the prism: far cheaper booleans.
"""

from __future__ import annotations

import math

import numpy as np

from vmach.stock import cusps, make
from vmach.stock.events import cylinder_boxes
from vmach.stock.path import NOTHING, Bound, Claim, Free, Path, Poses
from vmach.stock.view import View
from vmach.tooling.model import Tool
from vmach.tooling.solid import ToolSolid

NAME = "fins"
BOUND = Bound(under="a sliver: fins_cover's slack, 0.001 mm")


def claim(path: Path, free: Free, view: View, cover) -> Claim:
    """The poses still to place of a flat or face mill (one prism) between two free rotary
    steps, each cut as its fin where its neighbours' fins hold the rest of it
    (:func:`fin_widths`); with the setting ``trim`` and the true tool only."""
    tool, pr = path.true_tool, path.pr
    if not path.settings.trim or tool is None or pr is None or path.n < 3:
        return NOTHING
    half, k = fin_widths(tool, path.ts, path.frames, path.rotary & free.steps, np.nonzero(free.place)[0],
                         view)
    idx = np.nonzero(np.isfinite(half))[0]
    if len(idx) == 0:
        return NOTHING
    held = np.zeros(path.n, bool)
    held[idx] = True
    inf = np.full(len(idx), np.inf)
    poses = Poses(idx.astype(float), path.frames[idx], half[idx], inf, path.pose_rows(idx))
    return Claim(held=held, poses=poses, counts={"inner_fins": k})


def fin_widths(tool: Tool, ts: ToolSolid, fr: np.ndarray, steps: np.ndarray, poses: np.ndarray,
               view: View) -> tuple[np.ndarray, int]:
    """((n,) mm, count): the fin half-widths of the placed poses ``poses`` of a flat or face
    mill between two of the placed rotary ``steps`` (n-1,) bool — widths over the two steps,
    rounded as cut (:func:`vmach.stock.make.fin_bucket`) — whose neighbours' fins hold the rest
    of them; inf for every other pose (cut whole, or not placed)."""
    n = len(fr)
    out = np.full(n, np.inf)
    inner = np.zeros(n, bool)
    inner[1:-1] = steps[:-1] & steps[1:]
    placed = np.zeros(n, bool)
    placed[poses] = True
    # (poses whose tool's box misses the stock's are culled anyway)
    box = cylinder_boxes(fr[:, :, 3], fr[:, :, 2], 0.0, ts.length, ts.radius)
    lo, hi = view.bounds
    placed &= np.all(box[:, 0] <= hi, axis=1) & np.all(box[:, 1] >= lo, axis=1)
    idx = np.nonzero(inner & placed)[0]
    sd = cusps.side(tool)
    if len(idx) == 0 or len(sd.points) == 0:
        return out, 0
    normal = cusps.fin_normal(ts.segments)
    half = cusps.fin_widths(fr[idx], fr[idx - 1], fr[idx + 1], normal, np.full(len(idx), 2), sd,
                            view.holds, cusps.face_radius(tool))
    out[idx] = make.fin_bucket(half, ts.radius)
    idx = idx[np.isfinite(out[idx])]
    ok = fins_cover(tool, fr, out, idx, normal, view.holds)
    out[idx[~ok]] = np.inf
    return out, int(ok.sum())


def surface(tool: Tool) -> np.ndarray:
    """Points (p, 3), tool frame, on the true tool's surface: the side's samples
    (:func:`side`) and, for a flat end face, rings of it (cusps.AROUND per ring, 2 × cusps.SPACING apart)."""
    pts = [cusps.side(tool).points]
    zs, rs = cusps.outline(tool)
    if rs[0] > 0:
        ang = 2.0 * np.pi * (np.arange(cusps.AROUND) + 0.5) / cusps.AROUND
        for r in np.linspace(rs[0], 0.0, max(2, math.ceil(rs[0] / (2 * cusps.SPACING))), endpoint=False):
            pts.append(np.column_stack([r * np.cos(ang), r * np.sin(ang), np.zeros(cusps.AROUND)]))
    return np.concatenate(pts)


def fins_cover(tool: Tool, frames: np.ndarray, half: np.ndarray, which: np.ndarray, normal: np.ndarray,
               holds, slack: float = 1e-3) -> np.ndarray:
    """(w,) bool: which of the poses ``which`` (w,) int — of a path's poses (frames (n, 3, 4),
    tool to work, joined by motion in order), each to be cut as its fin of half-width ``half``
    (n,) mm (inf: whole; :func:`fin_widths`) — may be: every sample of the true tool's surface
    at the pose (:func:`surface`) that may lie in the material (``holds``) and lies outside its
    own slab ``|x·normal| <= half`` (tool frame) lies in the fin (or the whole tool) of another
    pose of the path, to ``slack`` mm — the poses on either side, outward until the samples
    are held or the next pose's tool lies beyond the tool's reach. The union of the fins then
    holds what the whole poses would remove — a fin lies inside the true tool, so a pose whose
    samples the others do not hold (a turn whose faces make a concave chain, a tool that also
    moves along its side) stays whole."""
    which = np.asarray(which, dtype=int)
    out = np.ones(len(which), bool)
    if len(which) == 0:
        return out
    pts = surface(tool)
    zs, rs = cusps.outline(tool)
    length = float(zs[-1])
    nn = np.asarray(normal, dtype=float)
    own = np.abs(pts @ nn)                                          # (p,) off the pose's plane
    rot, tip = frames[:, :, :3], frames[:, :, 3]
    reach = 2.0 * (length + float(rs.max()))
    for k, i in enumerate(which):
        off = own > half[i]
        if not off.any():
            continue
        p = pts[off] @ rot[i].T + tip[i]                            # work frame
        p = p[holds(p)]
        # the other poses, nearest in the path first (i-1, i+1, i-2, ...), up to the first
        # beyond the tool's reach
        for c in range(1, len(frames), 4):
            if len(p) == 0:
                break
            d = np.arange(c, c + 4)
            j = np.stack([i - d, i + d], axis=1).ravel()
            j = j[(j >= 0) & (j < len(frames))]
            if len(j) == 0:
                break
            if np.any(np.linalg.norm(tip[j] - tip[i], axis=1) > reach):
                break
            local = (p - tip[j][:, None]) @ rot[j]                      # (j, m, 3), tool frames
            z = local[..., 2]
            inside = ((z >= -slack) & (z <= length + slack)
                      & (np.hypot(local[..., 0], local[..., 1]) <= np.interp(z, zs, rs) + slack)
                      & (np.abs(local @ nn) <= half[j][:, None] + slack))
            p = p[~inside.any(axis=0)]
        out[k] = len(p) == 0
    return out

