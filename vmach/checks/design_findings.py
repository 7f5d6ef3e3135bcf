"""``verify --design``: the comparison of the cut part with its design as findings, the
report's ``design`` object and the per-vertex deviation for pictures and the HTML report.

    plan = plan_design("part.stl", "+0.05/-0.02", "0,0,0")        # read before the simulation
    outcome = check_design(plan, part_solid, table, model, library, blank_bounds, out_dir)
    outcome.findings            # design_gouge / design_excess (errors), design_placement
    outcome.to_json()           # report.json "design"

Each region beyond the band is one finding, numbered (``region``) in the order gouges then
excess, deepest first; its source is the row whose tool touches the region's deepest point
(else the row touching most of it) and ``lines`` lists every line whose tool touches it
(:mod:`vmach.checks.provenance`). ``DIR/design_deviation.npz`` holds the part's mesh with the
deviation and the region number of every vertex (docs/report.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from vmach.checks.design import Band, Comparison, compare, load_design, parse_band, parse_offset
from vmach.checks.provenance import touching_rows
from vmach.findings import Finding

#: mm a design may reach beyond the blank before its placement is doubted
PLACEMENT_SLACK = 0.1
ARRAYS = "design_deviation.npz"
#: mm: a gouge's maker holds a point of the design's surface inside its tool (the simulated
#: tool's polygon may lie this far inside the true one); excess lies at most this far from the
#: surface the tool left
INSIDE, AT_SURFACE = 0.01, 0.05


@dataclass(frozen=True)
class DesignPlan:
    """A design read and placed: path, mesh (vertices (n, 3) mm, faces (m, 3)), band, offset."""

    path: str
    vertices: np.ndarray
    faces: np.ndarray
    band: Band
    offset: np.ndarray


def plan_design(path: str, tolerance: str | None, offset: str | None) -> DesignPlan:
    """Read and check everything ``--design`` asks for (InputError on a bad file or option)."""
    band = parse_band(tolerance) if tolerance else Band()
    move = parse_offset(offset)
    v, f = load_design(path, move)
    return DesignPlan(str(path), v, f, band, move)


@dataclass
class DesignOutcome:
    plan: DesignPlan
    comparison: Comparison
    findings: list[Finding] = field(default_factory=list)
    arrays: str | None = None        # file name of the per-vertex arrays in the output directory

    def to_json(self) -> dict[str, Any]:
        c = self.comparison
        dev = c.deviation
        inside = (dev >= c.band.lo) & (dev <= c.band.hi)
        return {
            "path": self.plan.path,
            "offset_mm": [float(x) for x in self.plan.offset],
            "tolerance_mm": [c.band.lo, c.band.hi],
            "vertices": int(len(dev)),
            "max_excess_mm": round(max(0.0, float(dev.max())), 5) if len(dev) else None,
            "max_gouge_mm": round(max(0.0, float(-dev.min())), 5) if len(dev) else None,
            "within_band": round(float(inside.mean()), 5) if len(dev) else None,
            "gouges": sum(r.kind == "gouge" for r in c.regions),
            "excess": sum(r.kind == "excess" for r in c.regions),
            "deviation_file": self.arrays,
            "seconds": round(c.seconds, 3),
        }


def check_design(plan: DesignPlan, part, table, model, library, blank_bounds, out: Path | None = None
                 ) -> DesignOutcome:
    """Compare the part (a solid of :mod:`vmach.stock.engine`) with the planned design; name
    the lines behind each region; write the per-vertex arrays into ``out`` when given."""
    comp = compare(part, (plan.vertices, plan.faces), plan.band)
    outcome = DesignOutcome(plan, comp)
    lo_d, hi_d = plan.vertices.min(axis=0), plan.vertices.max(axis=0)
    blank = np.asarray(blank_bounds, dtype=float)
    beyond = float(max((blank[0] - lo_d).max(), (hi_d - blank[1]).max()))
    if beyond > PLACEMENT_SLACK:
        outcome.findings.append(Finding(
            "design_placement", "warning",
            f"the design reaches {beyond:.3f} mm beyond the blank: is it placed in the workpiece "
            "frame? (--design-offset X,Y,Z moves it)", data={"beyond_mm": round(beyond, 4)}))
    touches = touching_rows(table, model, library, [r.points for r in comp.regions],
                            slack=[INSIDE if r.kind == "gouge" else AT_SURFACE for r in comp.regions])
    for number, (region, touch) in enumerate(zip(comp.regions, touches, strict=True), start=1):
        outcome.findings.append(_finding(number, region, touch, table, plan.band))
    if out is not None:
        outcome.arrays = save_arrays(comp, Path(out))
    return outcome


def _finding(number: int, region, touch, table, band: Band) -> Finding:
    lines: dict[tuple[str, int], int] = {}
    for row in touch.rows:
        src = table.source(int(row))
        key = (src.path, int(src.line))
        lines[key] = lines.get(key, 0) + 1
    named = [{"file": f, "line": ln, "moves": m}
             for (f, ln), m in sorted(lines.items(), key=lambda x: x[0][1])]
    limit = -band.lo if region.kind == "gouge" else band.hi
    what = ("material removed inside the design" if region.kind == "gouge"
            else "material left outside the design")
    c, (lo, hi) = region.centroid, region.bounds
    who = ", ".join(str(d["line"]) for d in named[:12]) + (" …" if len(named) > 12 else "")
    lines_word = "lines" if len(named) > 1 else "line"
    verb = "made" if region.kind == "gouge" else "stopped at"
    if not named:
        by = "; no tool of the program comes near it"
    elif touch.touching:
        by = f"; the tool of {lines_word} {who} {verb} it"
    else:
        by = (f"; no tool touches it, the nearest ({lines_word} {who}) passes "
              f"{float(touch.distance.min()):.2f} mm away")
    msg = (f"#{number}: {what}, {region.depth:.3f} mm deep (band {limit:g} mm) over "
           f"{region.area:.1f} mm², {region.volume:.3f} mm³, at ({c[0]:.2f}, {c[1]:.2f}, {c[2]:.2f}){by}")
    data = {
        "region": number,
        "volume_mm3": round(region.volume, 4),
        "depth_mm": round(region.depth, 5),
        "area_mm2": round(region.area, 3),
        "centroid_mm": [round(float(x), 4) for x in c],
        "bbox_mm": [[round(float(x), 4) for x in lo], [round(float(x), 4) for x in hi]],
        "deepest_mm": [round(float(x), 4) for x in region.deepest],
        "tolerance_mm": [band.lo, band.hi],
        "lines": named,
        "lines_touch": bool(touch.touching),
    }
    source = None if touch.first is None else table.source(int(touch.first))
    return Finding(f"design_{region.kind}", "error", msg, source, touch.first, data)


def save_arrays(comp: Comparison, out: Path) -> str:
    """Write ``out/design_deviation.npz``: ``vertices`` (n, 3) float mm, ``faces`` (m, 3)
    int, ``deviation`` (n,) float mm (> 0 excess), ``region`` (n,) int (0 within the band,
    else the finding's region number), ``tolerance`` (2,) float mm. Returns the file name."""
    import io

    from vmach.output import atomic_writer, make_dir

    make_dir(out)
    buf = io.BytesIO()
    np.savez_compressed(buf, vertices=comp.vertices, faces=comp.faces, deviation=comp.deviation,
                        region=comp.region_of_vertex(), tolerance=np.array([comp.band.lo, comp.band.hi]))
    with atomic_writer(out / ARRAYS, "wb") as fh:
        fh.write(buf.getvalue())
    return ARRAYS


def design_picture(outcome: DesignOutcome, out_dir: Path) -> dict[str, str]:
    """``design_deviation.png``: the part coloured by its deviation from the design, regions
    labelled by their numbers (:func:`vmach.report.render.design_deviation_png`)."""
    from vmach.report import render

    c = outcome.comparison
    labels = [(r.deepest, f"#{i} {r.kind} {r.depth:.3f}") for i, r in enumerate(c.regions, start=1)]
    render.design_deviation_png(out_dir / "design_deviation.png", c.vertices, c.faces, c.deviation,
                                (c.band.lo, c.band.hi), labels,
                                title=f"{Path(outcome.plan.path).name}: deviation from the design [mm]")
    return {"design_deviation": "design_deviation.png"}
