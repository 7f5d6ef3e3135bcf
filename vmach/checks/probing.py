"""Touch-probe moves in verify: the probe stops where its stylus touches the simulated stock.

A measuring move (``canon.ProbeMove``, move-table kind PROBE) runs the probe along its whole
measuring path; on the machine it stops at contact. Here a probe is a library tool of type
``probe`` (its diameter the stylus ball's): its moves remove no material. Each of its moves is
swept against the stock as cut so far (the stock inside a box about the move, as a triangle
mesh) with the stylus ball, exactly (:func:`sweep_contact`):

- a measuring move stops at the first contact, and the probe's next move starts there; no
  contact within the path is ``probe_no_contact`` (error, the control's alarm) when the move
  requires one;
- any other move of the probe (positioning, rapids, the way back) that touches the part is
  ``probe_collision`` (error): the probe would deflect outside its measuring range and the
  control would stop (or the stylus break).

Only the stylus ball is swept; the probe's shank and body are not checked. Measuring moves of a
tool that is not a probe are cut like feeds, which ``probe_unchecked`` (warning) says.
"""

from __future__ import annotations

import numpy as np

from vmach.findings import Finding, error, warning
from vmach.motion.table import PROBE
from vmach.stock import engine

#: a contact closer than this to a surface the probe starts on (mm) is the same contact: the
#: way back from a contact point does not touch again
EPS = 1e-4


def _roots(a, b, c):
    """The smaller root of a t² + b t + c = 0 per element (nan where none or a = 0)."""
    disc = b * b - 4 * a * c
    with np.errstate(invalid="ignore", divide="ignore"):
        t = (-b - np.sqrt(disc)) / (2 * a)
    return np.where((disc >= 0) & (a > 1e-18), t, np.nan)


def sweep_contact(c0: np.ndarray, d: np.ndarray, r: float, tris: np.ndarray) -> float | None:
    """First t in [0, 1] at which a ball of radius ``r`` (mm) centred at c0 + t·d (both (3,),
    mm) touches the triangles ``tris`` (m, 3, 3), mm: 0 when it overlaps them at the start,
    None when it never touches them."""
    if len(tris) == 0:
        return None
    best = np.inf
    v = tris.reshape(-1, 3)
    w = c0 - v                                                       # vertices: |w + t d| = r
    c = np.einsum("ij,ij->i", w, w) - r * r
    if (c < 0).any():
        return 0.0
    t = _roots(np.full(len(v), d @ d), 2 * w @ d, c)
    ok = (t >= 0) & (t <= 1)
    if ok.any():
        best = min(best, t[ok].min())
    for i, k in ((0, 1), (1, 2), (2, 0)):                             # edges: the cylinders
        p, e = tris[:, i], tris[:, k] - tris[:, i]
        ll = np.einsum("ij,ij->i", e, e)
        good = ll > 1e-18
        p, e, ll = p[good], e[good], ll[good]
        w = c0 - p
        m0 = w - (np.einsum("ij,ij->i", w, e) / ll)[:, None] * e
        md = d - ((e @ d) / ll)[:, None] * e
        c = np.einsum("ij,ij->i", m0, m0) - r * r
        s0 = np.einsum("ij,ij->i", w, e) / ll
        if ((c < 0) & (s0 >= 0) & (s0 <= 1)).any():
            return 0.0
        t = _roots(np.einsum("ij,ij->i", md, md), 2 * np.einsum("ij,ij->i", m0, md), c)
        s = (np.einsum("ij,ij->i", w, e) + np.nan_to_num(t) * (e @ d)) / ll
        ok = (t >= 0) & (t <= 1) & (s >= 0) & (s <= 1)
        if ok.any():
            best = min(best, t[ok].min())
    a, b, cc = tris[:, 0], tris[:, 1], tris[:, 2]                   # faces
    n = np.cross(b - a, cc - a)
    norm = np.linalg.norm(n, axis=1)
    good = norm > 1e-18
    a, b, cc, n = a[good], b[good], cc[good], n[good] / norm[good, None]
    s0 = np.einsum("ij,ij->i", c0 - a, n)
    sd = n @ d
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(np.abs(s0) <= r, 0.0, (s0 - np.sign(s0) * r) / -sd)
    t = np.where(np.isfinite(t), t, np.nan)
    q = c0 + np.nan_to_num(t)[:, None] * d - (s0 + np.nan_to_num(t) * sd)[:, None] * n
    ok = (t >= 0) & (t <= 1) & _inside(q, a, b, cc)
    if ok.any():
        best = min(best, t[ok].min())
    return None if not np.isfinite(best) else float(best)


def _inside(q, a, b, c) -> np.ndarray:
    """Whether the points q (m, 3), in the triangles' planes, lie in the triangles."""
    v0, v1, v2 = c - a, b - a, q - a
    d00, d01, d11 = (np.einsum("ij,ij->i", x, y) for x, y in ((v0, v0), (v0, v1), (v1, v1)))
    d02, d12 = np.einsum("ij,ij->i", v0, v2), np.einsum("ij,ij->i", v1, v2)
    den = d00 * d11 - d01 * d01
    with np.errstate(invalid="ignore", divide="ignore"):
        u = (d11 * d02 - d01 * d12) / den
        w = (d00 * d12 - d01 * d02) / den
    return (u >= -1e-12) & (w >= -1e-12) & (u + w <= 1 + 1e-12)


def first_contact(stock, centres: np.ndarray, r: float) -> tuple[int, float] | None:
    """(segment, t) of the first contact of the ball of radius r swept along the polyline of
    ``centres`` (p, 3) with the stock as it is now; None if it touches nothing."""
    lo, hi = centres.min(0) - r - 1.0, centres.max(0) + r + 1.0
    local = stock.local(lo, hi)
    if engine.is_empty(local):
        return None
    verts, faces = engine.to_mesh(local)
    tris = np.asarray(verts, float)[np.asarray(faces)]
    for s in range(len(centres) - 1):
        t = sweep_contact(centres[s], centres[s + 1] - centres[s], r, tris)
        if t is not None:
            return s, t
    return None


def check_path(stock, tool, table, a: int, b: int, k: np.ndarray, pose, res) -> None:
    """The probe ``tool``'s rows a..b-1 (samples: row j spans poses sum(k[:j-a]) … sum(k[:j-a+1]);
    ``pose.tip`` (p, 3) and ``pose.axis`` (p, 3) in the stock's frame): the findings into
    ``res.findings``; no material is removed."""
    r = tool.diameter / 2.0
    axis = np.asarray(pose.axis, float)
    axis = axis / np.linalg.norm(axis, axis=1)[:, None]
    centres = np.asarray(pose.tip, float) + r * axis
    ends = np.r_[0, np.cumsum(k)]
    start = None                                        # where a stopped probe really is
    for i, j in enumerate(range(a, b)):
        c = centres[ends[i]:ends[i + 1] + 1].copy()
        if start is not None:
            c[0], start = start, None
        measuring = table.kind[j] == PROBE
        hit = first_contact(stock, c, r if measuring else r - EPS)
        src = table.source(j)
        if measuring:
            if hit is None:
                if getattr(table.commands[int(table.command[j])], "required", True):
                    res.findings.append(error("probe_no_contact", "the probe meets no material on its "
                                              "measuring path", src, end=[round(x, 4) for x in c[-1]]))
                continue
            s, t = hit
            if s == 0 and t == 0.0:
                res.findings.append(error("probe_collision", "the probe already touches the part where "
                                          "its measuring move starts", src))
                continue
            start = c[s] + t * (c[s + 1] - c[s])
        elif hit is not None:
            s, t = hit
            at = c[s] + t * (c[s + 1] - c[s]) - r * axis[min(ends[i] + s, len(axis) - 1)]
            res.findings.append(error("probe_collision", "the probe runs into the part outside a "
                                      f"measuring move, at ({at[0]:.3f}, {at[1]:.3f}, {at[2]:.3f}) mm",
                                      src, at=[round(x, 4) for x in at]))


def probe_rows(table, library) -> np.ndarray:
    """(n,) bool: the rows whose tool is a touch probe (library type ``probe``)."""
    tool = np.asarray(table.tool)
    out = np.zeros(len(tool), bool)
    if library is not None:
        for i, name in enumerate(table.tools):
            if getattr(library.lookup(name), "kind", None) == "probe":
                out |= tool == i
    return out


def unchecked(table, library, simulated: bool) -> list[Finding]:
    """One ``probe_unchecked`` warning at the first measuring move of a tool that is not a
    probe (its moves are cut like feeds) when the stock is cut."""
    if not simulated or len(table) == 0:
        return []
    rows = np.flatnonzero((np.asarray(table.kind) == PROBE) & ~probe_rows(table, library))
    if len(rows) == 0:
        return []
    return [warning("probe_unchecked", f"{len(rows)} measuring move(s) with a tool that is not a probe "
                    "(library type \"probe\"): they are cut like feeds to the end of their measuring "
                    "path, no contact is checked", table.source(int(rows[0])), moves=len(rows))]
