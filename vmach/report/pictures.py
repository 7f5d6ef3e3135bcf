"""What the pictures show, computed with numpy; ``render`` (pyvista) only draws it.

Pictures of a verify run (``make_pictures``):

- ``toolpath.png`` — the tool tip's path in the workpiece frame, rapids red and feeds green;
- ``x_of_c.png`` — X and Y of the program over one revolution of the rotary axis (the plots the
  thesis used to find the path);
- ``part_deviation.png`` — the cut part coloured by its signed deviation from the nominal
  profile (mm), where the profile is checked;
- ``collision_<n>.png`` — a close-up of each collision: tool, holder and stock at that moment.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from vmach.motion.table import TRAVERSE, MoveTable
from vmach.output import make_dir
from vmach.report.paths import toolpath_segments

# -- meshes of primitives (numpy) ---------------------------------------------------------------


def cylinder_mesh(radius: float, z0: float, z1: float, segments: int = 48) -> tuple[np.ndarray, np.ndarray]:
    """Closed cylinder on the local z axis: vertices (2s + 2, 3), faces (4s, 3)."""
    th = np.linspace(0, 2 * math.pi, segments, endpoint=False)
    ring = np.column_stack([radius * np.cos(th), radius * np.sin(th)])
    v = np.vstack(
        [
            np.column_stack([ring, np.full(segments, z0)]),
            np.column_stack([ring, np.full(segments, z1)]),
            [[0, 0, z0], [0, 0, z1]],
        ]
    )
    i = np.arange(segments)
    j = (i + 1) % segments
    c0, c1 = 2 * segments, 2 * segments + 1
    faces = np.vstack(
        [
            np.column_stack([i, j, j + segments]),
            np.column_stack([i, j + segments, i + segments]),
            np.column_stack([np.full(segments, c0), j, i]),
            np.column_stack([np.full(segments, c1), i + segments, j + segments]),
        ]
    )
    return v, faces


def box_mesh(size) -> tuple[np.ndarray, np.ndarray]:
    """Closed box centred on the origin, edge lengths ``size`` (3,)."""
    h = np.asarray(size, float) / 2
    v = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float) * h
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    faces = np.array([f for a, b, c, d in quads for f in ((a, b, c), (a, c, d))])
    return v, faces


def transformed(v: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """Vertices (n, 3) moved by a (4, 4) or (3, 4) transform."""
    m = np.asarray(matrix, float)
    return v @ m[:3, :3].T + m[:3, 3]


# -- data of the pictures -------------------------------------------------------------------


def one_revolution(table: MoveTable, axis: str) -> np.ndarray | None:
    """Rows of the longest stretch of feed moves turning ``axis`` one way, cut to one revolution."""
    if axis not in table.axes or len(table) == 0:
        return None
    c = table.axes.index(axis)
    dc = table.end[:, c] - table.start[:, c]
    feed = table.kind != TRAVERSE
    good = feed & (dc > 0)
    best, run = (0, 0), None
    for i, g in enumerate(np.r_[good, False]):
        if g and run is None:
            run = i
        elif not g and run is not None:
            if i - run > best[1] - best[0]:
                best = (run, i)
            run = None
    if best[1] - best[0] < 3:
        return None
    rows = np.arange(*best)
    travel = table.end[rows, c] - table.start[rows[0], c]
    return rows[travel <= 360.0 + 1e-9]


def make_pictures(report, out_dir: Path) -> dict[str, str]:
    """Render every picture of a verify report into ``out_dir``; returns name -> file name."""
    from vmach.report import render

    make_dir(out_dir)
    table, model = report.table, report.model
    images: dict[str, str] = {}
    part = report.part
    outline = part.mesh("part") if part is not None else None
    region = None
    if part is not None:
        b = np.asarray(part.initial_bounds, float)
        pad = 0.5 * float(np.max(b[1] - b[0]))
        region = np.stack([b[0] - pad, b[1] + pad])
    seg, kinds = toolpath_segments(table, model)          # every move, however far it goes
    markers = _markers(report)
    if len(seg):
        focus = region
        if focus is not None and markers:                     # the findings' places in the frame
            at = np.array([m[0] for m in markers])
            focus = np.stack([np.minimum(focus[0], at.min(axis=0)), np.maximum(focus[1], at.max(axis=0))])
        name = Path(report.program).name
        render.toolpath_png(
            out_dir / "toolpath.png",
            seg,
            kinds,
            outline,
            title=f"{name}: tool path (rapid red, feed green), findings at their lines",
            markers=markers,
            focus=focus,
        )
        images["toolpath"] = "toolpath.png"
        pts = seg.reshape(-1, 3)
        if focus is not None and not np.all((pts >= focus[0] - 1e-6) & (pts <= focus[1] + 1e-6)):
            render.toolpath_png(       # the moves that leave the close view, seen whole
                out_dir / "toolpath_all.png",
                seg,
                kinds,
                outline,
                title=f"{name}: the whole tool path, every move (rapid red, feed green)",
                markers=markers,
            )
            images["toolpath_all"] = "toolpath_all.png"
    rot = [a for a, r in zip(table.axes, table.rotary, strict=True) if r]
    if rot:
        rows = one_revolution(table, rot[0])
        if rows is not None and len(rows):
            c = table.axes.index(rot[0])
            cc = np.mod(table.end[rows, c], 360.0)
            order = np.argsort(cc)
            series = []
            for axis, colour in (("X", "b"), ("Y", "r")):
                if axis in table.axes:
                    series.append((cc[order], table.end[rows, table.axes.index(axis)][order], axis, colour))
            render.chart_png(
                out_dir / "x_of_c.png",
                series,
                f"{rot[0]} [deg]",
                "mm",
                title=f"X and Y over one revolution of {rot[0]} (lines "
                f"{int(table.line[rows[0]])}..{int(table.line[rows[-1]])})",
            )
            images["x_of_c"] = "x_of_c.png"
    if part is not None and report.profile is not None and report.profile_spec is not None:
        from vmach.report.scene import NOT_MEASURED, band_span, colour_bar, part_deviation, round_ticks

        v, f, dev, (lo, hi) = part_deviation(report)
        z = [s["z"] for s in report.profile["stations"]]
        span = band_span(lo, hi, dev)
        colours, rng = colour_bar(lo, hi, span)
        keep = np.all(v[f][:, :, 2] > min(z) - 10.0, axis=1)  # the profiled end, not the whole bar
        render.part_deviation_png(
            out_dir / "part_deviation.png", v, f[keep], dev * 1000.0, (rng[0] * 1000, rng[1] * 1000),
            title=f"{report.profile_spec} radial deviation: grey in the band "
            f"{lo * 1000:+.1f}..{hi * 1000:+.1f} um, red above, blue below, white not measured",
            colours=colours, ticks=[t * 1000 for t in round_ticks(lo, hi, rng)], unit="µm",
            nan_colour=NOT_MEASURED.tolist(),
        )
        images["part_deviation"] = "part_deviation.png"
    if getattr(report, "design", None) is not None:
        from vmach.checks.design_findings import design_picture

        images.update(design_picture(report.design, out_dir))
    images.update(collision_pictures(report, out_dir))
    return images


def _markers(report, most: int = 40) -> list[tuple[np.ndarray, str, str]]:
    """The findings' places for the tool-path picture, (at (3,) mm, label, colour): one per
    (line, kind), errors first, at most ``most``."""
    from vmach.report.scene import SEVERITY_COLOURS, finding_places

    seen, out = set(), []
    places = sorted(finding_places(report), key=lambda p: (p.severity != "error", p.line or 0))
    for p in places:
        if (p.line, p.kind) in seen or len(out) >= most:
            continue
        seen.add((p.line, p.kind))
        out.append((p.at, p.label, SEVERITY_COLOURS.get(p.severity, "black")))
    return out


COLLISION_KINDS = ("rapid_into_stock", "holder_collision", "fixture_collision")


def collision_pictures(report, out_dir: Path, most: int = 8) -> dict[str, str]:
    """A close-up per collision finding (first ``most``): the tool with shank and holder at the
    move's end, the stock as it was then (when the stock stage kept it), fixtures."""
    from vmach.checks.collisions import tool_cylinders
    from vmach.report import render

    table, model = report.table, report.model
    lib = report.library
    snaps = getattr(report.sim, "snapshots", {}) if report.sim is not None else {}
    out: dict[str, str] = {}
    found = [
        f
        for f in sorted(report.findings, key=lambda f: f.line or 0)
        if f.kind in COLLISION_KINDS and f.move_index is not None
    ]
    for n, f in enumerate(found[:most], 1):
        row = int(f.move_index)
        name = table.tools[int(table.tool[row])] if table.tool[row] >= 0 else None
        tool = lib.lookup(name) if (lib is not None and name is not None) else None
        q = table.columns(model.axes, model.home, table.end[row : row + 1])
        t2w = model.tool2work(q)[0]
        meshes = []
        legend: list[tuple[str, str]] = []
        bodies: dict[str, list] = {"tool": [], "holder": [], "other": []}   # solids of the overlap
        if tool is not None:
            colours = {"cutter": "gold", "shank": "silver", "holder": "sienna"}
            for c in tool_cylinders(tool):
                v, fc = cylinder_mesh(c.radius, c.z0, c.z1)
                meshes.append((transformed(v, t2w), fc, colours[c.part], 1.0))
                legend.append((f"tool {name}: {c.part}", colours[c.part]))
                solid = (c, t2w)
                bodies["tool"].append(solid)
                if c.part != "cutter":
                    bodies["holder"].append(solid)
        snap = snaps[row].mesh() if row in snaps else None
        if snap is None and report.part is not None:
            snap = report.part.mesh("part")
        if snap is not None:
            meshes.append((snap[0], snap[1], "lightsteelblue", 0.6))
            legend.append(("stock after the move" if row in snaps else "stock (finished part)",
                           "lightsteelblue"))
            if f.kind != "fixture_collision":
                bodies["other"].append(snap)
        if f.kind == "fixture_collision":
            frames = model.link2base(q)
            w2b = np.linalg.inv(frames["work"][0])
            for g in model.spec.geometry:
                if g.shape not in ("box", "cylinder"):
                    continue
                v, fc = (
                    box_mesh(g.size)
                    if g.shape == "box"
                    else cylinder_mesh(g.radius, -g.length / 2, g.length / 2)
                )
                m = w2b @ frames[g.link][0] @ g.origin.matrix
                hit = g.name == f.data.get("obstacle")
                meshes.append((transformed(v, m), fc, "tomato" if hit else "wheat", 0.8))
                if hit:
                    legend.append((f"{g.name} (struck)", "tomato"))
                    bodies["other"].append((g, m))
            if any(c == "wheat" for _, _, c, _ in meshes):
                legend.append(("other fixtures", "wheat"))
        # the overlap: holder and shank in the stock (the cutter is meant to be there), or the
        # whole tool in the struck fixture; the move itself as a thick line
        overlap = _overlap(bodies["tool" if f.kind == "fixture_collision" else "holder"], bodies["other"])
        if overlap is not None:
            meshes.append((overlap[0], overlap[1], "magenta", 1.0))
            legend.append(("intersection", "magenta"))
        path = _move_path(table, model, row)
        rapid = f.kind == "rapid_into_stock"
        legend.append(("the rapid move (tip)" if rapid else "the move (tip)",
                       "red" if rapid else "darkgreen"))
        legend.append(("contact point" if "at_mm" in f.data else "end of the move", "red"))
        at = np.asarray(f.data.get("at_mm", t2w[:3, 3]), float)
        radius = 40.0 if tool is None else max(25.0, 2.5 * tool.diameter)
        fname = f"collision_{n}.png"
        render.scene_png(
            out_dir / fname,
            meshes,
            (at, radius),
            title=f"{f.kind} at {Path(f.source.path).name}:{f.line}",
            marker=at,
            legend=legend,
            lines=[(path, "red" if rapid else "darkgreen")],
        )
        out[f"collision_{n}"] = fname
    return out


def _move_path(table: MoveTable, model, row: int, step_deg: float = 2.0) -> np.ndarray:
    """The tool tip's path over one move in the work frame, segments (s, 2, 3) mm: a move that
    turns a rotary axis is the curve the tip really follows (sampled every ``step_deg``)."""
    a, b = table.start[row], table.end[row]
    turn = float(np.max(np.abs(b - a)[table.rotary])) if table.rotary.any() else 0.0
    t = np.linspace(0.0, 1.0, max(1, math.ceil(turn / step_deg)) + 1)
    tips = model.fk(table.columns(model.axes, model.home, a + t[:, None] * (b - a))).tip
    return np.stack([tips[:-1], tips[1:]], axis=1)


def _overlap(tool: list, others: list) -> tuple[np.ndarray, np.ndarray] | None:
    """The volume where the tool's parts (``(Cylinder, tool2work (4, 4))``) overlap the other
    bodies — meshes (vertices, faces) mm, or a fixture's ``(Geometry, to-work (4, 4))`` — as a
    mesh; None when they do not (or a body is not a closed solid)."""
    if not tool or not others:
        return None
    from vmach.stock import engine
    try:
        parts = [engine.transform(engine.cylinder(c.radius, c.z0, c.z1, 48), m) for c, m in tool]
        solids = []
        for a, b in others:
            if isinstance(a, np.ndarray):
                solids.append(engine.from_arrays(a, b))
            elif a.shape == "box":
                h = np.asarray(a.size, float) / 2
                solids.append(engine.transform(engine.box(-h, h), b))
            else:
                solids.append(engine.transform(engine.cylinder(a.radius, -a.length / 2, a.length / 2, 48), b))
        other = engine.union(solids)
        cut = engine.intersect(engine.union(parts), other)
        if engine.is_empty(cut):
            return None
        return engine.to_mesh(cut)
    except (engine.StockError, ValueError, RuntimeError):
        return None
