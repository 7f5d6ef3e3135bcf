"""Tool and holder against the machine's fixed collision geometry (chuck, jaws, headstock ...).

The tool is a stack of cylinders along its axis from the tip: cutting part, shank, holder
(:func:`tool_cylinders`). Each move is sampled densely enough that no surface point of the tool
travels more than ``step`` mm between samples (rotary motion included); at every sample the
tool's surface points are tested against every obstacle analytically (boxes and cylinders in
their own frames). A box test on bounding boxes first skips samples far from every obstacle.

Error bound: a collision deeper than ``step`` mm along the path, or with an obstacle feature
larger than the surface-point spacing ``step``, cannot be missed; shallower grazes may be.

Findings: ``fixture_collision`` (error) where the tool enters an obstacle, ``near_miss``
(warning) where a rapid passes closer than ``clearance`` without touching,
``machine_collision`` (error) where geometry carried with the tool (the turret) enters geometry
that is not (chuck, headstock). One finding per (kind, obstacle, block); ``data`` holds the
depth or distance in mm and the obstacle's name.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vmach.errors import ProgramError
from vmach.findings import Finding
from vmach.motion.table import TRAVERSE, MoveTable
from vmach.tol import tol


@dataclass(frozen=True)
class Cylinder:
    """A part of the tool: axis from ``z0`` to ``z1`` mm above the tip, ``radius`` mm."""

    part: str
    z0: float
    z1: float
    radius: float


def tool_cylinders(tool) -> list[Cylinder]:
    """Cutting part, shank and holder of a :class:`vmach.tooling.model.Tool`, stacked from the tip."""
    return [Cylinder(*part) for part in tool.stack()]


def sphere_cover(parts: list[Cylinder]) -> tuple[np.ndarray, np.ndarray]:
    """Balls that hold the cylinders: each cut along its axis into pieces no longer than its
    radius (or than 1 mm, for a needle-thin part), one ball around each piece. Returns centres
    (k, 4) homogeneous, tool frame, and radii (k,) mm. A point farther than d from every ball's
    surface is farther than d from the cylinders (and from their surface points)."""
    centres, radii = [], []
    for c in parts:
        length = c.z1 - c.z0
        n = max(1, math.ceil(length / max(c.radius, 1.0)))
        half = length / (2 * n)
        for i in range(n):
            centres.append([0.0, 0.0, c.z0 + (2 * i + 1) * half, 1.0])
            radii.append(math.hypot(c.radius, half))
    return np.array(centres), np.array(radii)


def surface_points(parts: list[Cylinder], step: float) -> tuple[np.ndarray, np.ndarray]:
    """Points on the cylinders' mantles and end discs, spaced at most ``step`` mm.

    Returns (p, 4) homogeneous points in the tool frame (z = tool axis) and (p,) part index.
    """
    pts, idx = [], []
    for k, c in enumerate(parts):
        n_theta = max(8, math.ceil(2 * math.pi * c.radius / step))
        th = np.linspace(0, 2 * math.pi, n_theta, endpoint=False)
        zs = np.linspace(c.z0, c.z1, max(2, math.ceil((c.z1 - c.z0) / step) + 1))
        ring = np.stack([c.radius * np.cos(th), c.radius * np.sin(th)], axis=1)
        mantle = np.concatenate([np.column_stack([ring, np.full(n_theta, z)]) for z in zs])
        radii = np.arange(step, c.radius, step)
        disc = [np.zeros((1, 2))] + [
            np.stack([r * np.cos(t), r * np.sin(t)], axis=1)
            for r in radii
            for t in [np.linspace(0, 2 * math.pi, max(6, math.ceil(2 * math.pi * r / step)), endpoint=False)]
        ]
        disc_xy = np.concatenate(disc)
        caps = np.concatenate([np.column_stack([disc_xy, np.full(len(disc_xy), z)]) for z in (c.z0, c.z1)])
        p = np.concatenate([mantle, caps])
        pts.append(p)
        idx.append(np.full(len(p), k))
    p = np.concatenate(pts)
    return np.column_stack([p, np.ones(len(p))]), np.concatenate(idx)


def signed_distance(points: np.ndarray, geom) -> np.ndarray:
    """Signed distance (mm; < 0 inside) of (..., 3) points given in the obstacle's own frame."""
    if geom.shape == "box":
        h = np.asarray(geom.size, float) / 2
        q = np.abs(points) - h
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=-1)
        inside = np.minimum(q.max(axis=-1), 0.0)
        return outside + inside
    r, h = float(geom.radius), float(geom.length) / 2
    d_r = np.hypot(points[..., 0], points[..., 1]) - r
    d_z = np.abs(points[..., 2]) - h
    outside = np.hypot(np.maximum(d_r, 0.0), np.maximum(d_z, 0.0))
    inside = np.minimum(np.maximum(d_r, d_z), 0.0)
    return outside + inside


def _bounds(geom) -> np.ndarray:
    """(8, 4) corners of the obstacle's bounding box in its own frame."""
    if geom.shape == "box":
        h = np.asarray(geom.size, float) / 2
    else:
        h = np.array([geom.radius, geom.radius, geom.length / 2], float)
    c = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float) * h
    return np.column_stack([c, np.ones(8)])


def primitive_points(geom, step: float) -> np.ndarray:
    """(p, 4) homogeneous points on the surface of a box or cylinder, in its own frame, spaced
    at most ``step`` mm."""
    if geom.shape == "cylinder":
        pts, _ = surface_points([Cylinder(geom.name, -geom.length / 2, geom.length / 2, geom.radius)], step)
        return pts
    h = np.asarray(geom.size, float) / 2
    out = []
    for axis in range(3):
        u, v = [i for i in range(3) if i != axis]
        gu = np.linspace(-h[u], h[u], max(2, math.ceil(2 * h[u] / step) + 1))
        gv = np.linspace(-h[v], h[v], max(2, math.ceil(2 * h[v] / step) + 1))
        uu, vv = np.meshgrid(gu, gv)
        for side in (-1.0, 1.0):
            p = np.zeros((uu.size, 3))
            p[:, u], p[:, v], p[:, axis] = uu.ravel(), vv.ravel(), side * h[axis]
            out.append(p)
    p = np.concatenate(out)
    return np.column_stack([p, np.ones(len(p))])


def rigid_inverse(m: np.ndarray) -> np.ndarray:
    """Inverses (..., 4, 4) of rigid transforms (rotation | translation, mm): [Rᵀ | −Rᵀ·t],
    without a general matrix inverse (the check's frames are rigid: a chain of rotations and
    translations)."""
    out = np.zeros_like(m)
    rt = np.swapaxes(m[..., :3, :3], -1, -2)
    out[..., :3, :3] = rt
    out[..., :3, 3] = -np.einsum("...ij,...j->...i", rt, m[..., :3, 3])
    out[..., 3, 3] = 1.0
    return out


def sample_moves(
    table: MoveTable, rows: np.ndarray, reach: float, step: float
) -> tuple[np.ndarray, np.ndarray]:
    """Axis values along the given rows, no tool point moving more than ``step`` mm between two.

    reach : distance of the farthest tool point from any rotary axis (mm), to turn degrees
        into travel. Returns q (s, k) and the row each sample belongs to (s,).
    """
    a, b = table.start[rows], table.end[rows]
    d = b - a
    lin = np.linalg.norm(d[:, ~table.rotary], axis=1) if (~table.rotary).any() else np.zeros(len(rows))
    rot = np.abs(d[:, table.rotary]).sum(axis=1) * math.radians(1) * reach if table.rotary.any() else 0.0
    n = np.maximum(1, np.ceil((lin + rot) / step))
    if not n.sum() <= tol.max_samples:
        worst = int(np.argmax(np.nan_to_num(n, nan=np.inf)))
        raise ProgramError("resource_limit", f"checking collisions along the move needs {n[worst]:.3g} "
                           f"samples of {step:g} mm (vmach's limit: {tol.max_samples} in all)",
                           table.source(int(rows[worst])))
    n = n.astype(int)
    owner = np.repeat(np.arange(len(rows)), n + 1)
    t = np.concatenate([np.linspace(0.0, 1.0, k + 1) for k in n])
    q = a[owner] + t[:, None] * d[owner]
    return q, rows[owner]


def fixture_collisions(
    model,
    table: MoveTable,
    tools: dict[int, list[Cylinder]],
    clearance: float = tol.near_miss,
    step: float = 2.0,
) -> list[Finding]:
    """``fixture_collision`` and ``near_miss`` findings for every move with a known tool.

    tools : row tool index (``table.tool``) -> the tool's cylinders.
    """
    geoms = [g for g in model.spec.geometry if g.shape in ("box", "cylinder")]
    if not geoms or len(table) == 0:
        return []
    out: dict[tuple, Finding] = {}

    for tool_ix, parts in tools.items():
        rows = np.flatnonzero(table.tool == tool_ix)
        if len(rows) == 0:
            continue
        pts, part_of = surface_points(parts, step)
        ball_c, ball_r = sphere_cover(parts)
        top = max(c.z1 for c in parts)
        reach = 600.0 + top
        q_table, owner = sample_moves(table, rows, reach, step)
        q = table.columns(model.axes, model.home, q_table)
        frames = model.link2base(q)
        tool2base = frames["tool"]
        tool_lo = np.array([-max(c.radius for c in parts)] * 2 + [0.0])
        tool_hi = np.array([max(c.radius for c in parts)] * 2 + [top])
        tool_box = np.array(
            [
                [x, y, z, 1.0]
                for x in (tool_lo[0], tool_hi[0])
                for y in (tool_lo[1], tool_hi[1])
                for z in (tool_lo[2], tool_hi[2])
            ]
        )
        tb = np.einsum("sij,pj->spi", tool2base, tool_box)[..., :3]
        t_min, t_max = tb.min(axis=1), tb.max(axis=1)
        rapid = table.kind[owner] == TRAVERSE
        for g in geoms:
            g2base = frames[g.link] @ g.origin.matrix
            rel = rigid_inverse(tool2base) @ g2base
            if np.abs(rel - rel[:1]).max() < 1e-9:
                continue  # carried with the tool (turret, tool carrier): never hit by it
            ob = np.einsum("sij,pj->spi", g2base, _bounds(g))[..., :3]
            o_min, o_max = ob.min(axis=1) - clearance, ob.max(axis=1) + clearance
            near = np.flatnonzero(np.all((t_min <= o_max) & (t_max >= o_min), axis=1))
            # samples whose balls all lie farther than the clearance need no point-by-point look
            local = rigid_inverse(g2base[near]) @ tool2base[near]                 # (n, 4, 4)
            gap = signed_distance(np.einsum("sij,kj->ski", local[:, :3], ball_c), g) - ball_r
            close = gap.min(axis=1, initial=np.inf) <= clearance
            for s, tool2g in zip(near[close], local[close], strict=True):
                p = (pts @ tool2g.T)[:, :3]
                dist = signed_distance(p, g)
                dmin = float(dist.min())
                row = int(owner[s])
                if dmin < 0:
                    kind, sev = "fixture_collision", "error"
                    part = parts[int(part_of[int(np.argmin(dist))])].part
                    msg = f"the tool's {part} enters {g.name} by {-dmin:.2f} mm"
                    data = {"obstacle": g.name, "part": part, "depth_mm": round(-dmin, 4)}
                elif dmin < clearance and rapid[s]:
                    kind, sev = "near_miss", "warning"
                    msg = f"rapid passes {dmin:.2f} mm from {g.name} (clearance {clearance} mm)"
                    data = {"obstacle": g.name, "distance_mm": round(dmin, 4), "clearance_mm": clearance}
                else:
                    continue
                key = (kind, g.name, int(table.command[row]))
                prev = out.get(key)
                worse = (
                    prev is None
                    or (kind == "fixture_collision" and data["depth_mm"] > prev.data["depth_mm"])
                    or (kind == "near_miss" and data["distance_mm"] < prev.data["distance_mm"])
                )
                if worse:
                    out[key] = Finding(kind, sev, msg, table.source(row), row, data)
    found = list(out.values())
    hit = {(f.data["obstacle"], f.move_index) for f in found if f.kind == "fixture_collision"}
    return [
        f for f in found if f.kind == "fixture_collision" or (f.data["obstacle"], f.move_index) not in hit
    ]


def machine_collisions(model, table: MoveTable, step: float = 5.0) -> list[Finding]:
    """``machine_collision`` where geometry carried with the tool meets geometry that is not,
    at samples of every move (no tool point travels more than ``step`` mm between samples)."""
    geoms = [g for g in model.spec.geometry if g.shape in ("box", "cylinder")]
    if len(geoms) < 2 or len(table) == 0:
        return []
    q_table, owner = sample_moves(table, np.arange(len(table)), 800.0, step)
    q = table.columns(model.axes, model.home, q_table)
    frames = model.link2base(q)
    tool2base = frames["tool"]
    placed = {g.name: frames[g.link] @ g.origin.matrix for g in geoms}
    carried = []
    for g in geoms:
        rel = rigid_inverse(tool2base) @ placed[g.name]
        carried.append(bool(np.abs(rel - rel[:1]).max() < 1e-9))
    movers = [g for g, c in zip(geoms, carried, strict=True) if c]
    fixed = [g for g, c in zip(geoms, carried, strict=True) if not c]
    out: dict[tuple, Finding] = {}
    for a in movers:
        pts = primitive_points(a, step)
        a_box = np.einsum("sij,pj->spi", placed[a.name], _bounds(a))[..., :3]
        for b in fixed:
            b_box = np.einsum("sij,pj->spi", placed[b.name], _bounds(b))[..., :3]
            near = np.all(
                (a_box.min(axis=1) <= b_box.max(axis=1)) & (a_box.max(axis=1) >= b_box.min(axis=1)), axis=1
            )
            for s in np.flatnonzero(near):
                local = rigid_inverse(placed[b.name][s]) @ placed[a.name][s]
                dmin = float(signed_distance((pts @ local.T)[:, :3], b).min())
                if dmin >= 0:
                    continue
                row = int(owner[s])
                key = (a.name, b.name, int(table.command[row]))
                if key not in out or -dmin > out[key].data["depth_mm"]:
                    out[key] = Finding(
                        "machine_collision",
                        "error",
                        f"{a.name} enters {b.name} by {-dmin:.2f} mm",
                        table.source(row),
                        row,
                        {"part": a.name, "obstacle": b.name, "depth_mm": round(-dmin, 4)},
                    )
    return list(out.values())
