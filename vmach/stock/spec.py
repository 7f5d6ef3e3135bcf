"""Stock from a spec string (``--stock``).

- ``cylinder:d=60,l=100`` — a cylinder on the Z axis, end face at Z = 0, material toward −Z
  (the lathe convention of the turn-mill); optional ``z=`` moves the end face.
- ``box:x=80,y=60,z=40`` — a box centred on the Z axis in X and Y, top face at Z = 0, material
  toward −Z; or by corners ``box:xmin=..,xmax=..,ymin=..,ymax=..,zmin=..,zmax=..``.
- ``mesh:path.stl`` — any closed mesh trimesh reads (``.stl``, ``.ply``, ``.obj``, ``.3mf``...),
  in work coordinates as it is; a convex one is taken as its convex hull when that has fewer
  triangles and the mesh lies within ``tol.blank_hull`` (1e-4 mm) of it
  (:func:`vmach.stock.hull.as_hull`).

Round stock is a polygon straddling the true circle within ``tol.blank_chord``.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from vmach.errors import InputError
from vmach.stock import engine
from vmach.stock.hull import as_hull
from vmach.tol import tol
from vmach.tooling.solid import segments_for, straddle_radius

_NUM = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")


def _params(kind: str, text: str, allowed: set[str]) -> dict[str, float]:
    out: dict[str, float] = {}
    for item in filter(None, (s.strip() for s in text.split(","))):
        key, eq, val = item.partition("=")
        key = key.strip().lower()
        if not eq or key not in allowed:
            raise InputError(
                f"stock {kind}: bad parameter {item!r}; expected {', '.join(sorted(allowed))}",
                kind="stock_spec",
            )
        if key in out:
            raise InputError(f"stock {kind}: {key} given twice", kind="stock_spec")
        if not _NUM.match(val.strip()):
            raise InputError(f"stock {kind}: {key}={val!r} is not a number", kind="stock_spec")
        out[key] = float(val)
    return out


def parse_stock(spec: str, base: str | Path | None = None, notes: list | None = None) -> engine.Solid:
    """The stock solid of a spec string; bad specs raise :class:`InputError`, so does a
    stock larger than ``tol.max_size`` in any direction. ``notes`` (a list) receives
    ``(message, data)`` for what was made of the spec (a mesh blank cut as its hull)."""
    solid = _parse(spec, base, notes)
    size = np.ptp(engine.bounds(solid), axis=0).max()
    if not size <= tol.max_size:
        raise InputError(f"stock {spec!r}: {size:g} mm across, larger than any machine "
                         f"({tol.max_size:g} mm)", kind="stock_spec")
    return solid


def _parse(spec: str, base: str | Path | None, notes: list | None = None) -> engine.Solid:
    kind, sep, rest = spec.partition(":")
    kind = kind.strip().lower()
    if not sep:
        raise InputError(f"stock {spec!r}: expected cylinder:..., box:... or mesh:FILE",
                         kind="stock_spec")
    if kind == "cylinder":
        p = _params(kind, rest, {"d", "l", "z"})
        for k in ("d", "l"):
            if k not in p:
                raise InputError(f"stock cylinder: missing {k}=", kind="stock_spec")
            if not p[k] >= tol.min_size:
                raise InputError(f"stock cylinder: {k} must be at least {tol.min_size:g} mm",
                                 kind="stock_spec")
            if p[k] > tol.max_size:
                raise InputError(f"stock cylinder: {k}={p[k]:g} mm is larger than any machine "
                                 f"({tol.max_size:g} mm)", kind="stock_spec")
        r = p["d"] / 2.0
        n = segments_for(r, tol.blank_chord)
        top = p.get("z", 0.0)
        return engine.cylinder(straddle_radius(r, n), top - p["l"], top, n)
    if kind == "box":
        p = _params(kind, rest, {"x", "y", "z", "xmin", "xmax", "ymin", "ymax", "zmin", "zmax"})
        if {"x", "y", "z"} <= p.keys() and len(p) == 3:
            lo = (-p["x"] / 2, -p["y"] / 2, -p["z"])
            hi = (p["x"] / 2, p["y"] / 2, 0.0)
        elif len(p) == 6 and all(k in p for k in ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")):
            lo = (p["xmin"], p["ymin"], p["zmin"])
            hi = (p["xmax"], p["ymax"], p["zmax"])
        else:
            raise InputError("stock box: give x=,y=,z= or all of xmin..zmax", kind="stock_spec")
        if not all(math.isfinite(v) for v in (*lo, *hi)):
            raise InputError("stock box: sizes must be finite", kind="stock_spec")
        if not all(h - lo_ >= tol.min_size for lo_, h in zip(lo, hi, strict=True)):
            raise InputError(f"stock box: sizes must be at least {tol.min_size:g} mm", kind="stock_spec")
        return engine.box(lo, hi)
    if kind == "mesh":
        path = Path(rest.strip())
        if base is not None and not path.is_absolute():
            path = Path(base) / path
        return load_mesh(path, notes)
    raise InputError(f"stock {spec!r}: unknown kind {kind!r} (cylinder, box, mesh)",
                     kind="stock_spec")


def load_mesh(path: str | Path, notes: list | None = None) -> engine.Solid:
    """A closed mesh file as a solid (trimesh reads it); a convex one as its hull when that
    has fewer triangles (:func:`vmach.stock.hull.as_hull`; said in ``notes``)."""
    import trimesh

    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such mesh file", kind="unreadable")
    try:
        mesh = trimesh.load(p, force="mesh", process=True)
    except Exception as exc:  # trimesh raises many types for bad files
        raise InputError(f"{p}: cannot read mesh: {exc}", kind="unreadable") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise InputError(f"{p}: no triangles in the file", kind="stock_mesh")
    mesh.merge_vertices()
    try:
        solid = engine.from_mesh(np.asarray(mesh.vertices), np.asarray(mesh.faces), str(p))
    except engine.StockError as exc:
        raise InputError(str(exc), kind="stock_mesh") from None
    cut = as_hull(solid, tol.blank_hull)
    if cut is not solid and notes is not None:
        n, m = engine.num_triangles(solid), engine.num_triangles(cut)
        notes.append((f"{p}: a convex blank of {n} triangles, cut as its convex hull ({m} triangles; "
                      f"every triangle of the mesh within {tol.blank_hull:g} mm of it)",
                      {"triangles": n, "hull_triangles": m, "within_mm": tol.blank_hull}))
    return cut
