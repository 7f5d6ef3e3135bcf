"""What the 3-D views show, computed with numpy: where each finding happened, the deviation
map's colours, and the scene of ``report.html``'s interactive view. ``render`` (pyvista) and
``html`` (three.js in the page) only draw it.

Colours of the deviation map (radial deviation from the nominal profile, µm): grey inside the
tolerance band; above the band (material left outside) from light to dark red, below it (the
part gouged) from light to dark blue, each reaching its darkest ``span`` beyond the band's edge;
near white where nothing is measured (outside the profiled length).
"""

from __future__ import annotations

import base64
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vmach.findings import Finding, sort_key

IN_BAND = np.array([0.62, 0.62, 0.62])        # grey: within the tolerance band
NOT_MEASURED = np.array([0.96, 0.96, 0.96])   # near white: outside the profiled length
ABOVE = (np.array([0.98, 0.75, 0.68]), np.array([0.70, 0.02, 0.09]))   # light -> dark red
BELOW = (np.array([0.70, 0.80, 0.98]), np.array([0.02, 0.19, 0.58]))   # light -> dark blue
SEVERITY_COLOURS = {"error": "#d62728", "warning": "#ff7f0e", "info": "#1f77b4"}


@dataclass(frozen=True)
class Place:
    """Where a finding happened in the workpiece frame.

    at : (3,) float, mm. index : the finding's position in ``report.json``'s ``findings``.
    """

    at: np.ndarray
    index: int
    kind: str
    severity: str
    line: int | None

    @property
    def label(self) -> str:
        return f"L{self.line}" if self.line is not None else self.kind


def finding_places(report) -> list[Place]:
    """The place of every finding that has one: the contact point a collision check gives
    (``at_mm``) or the deepest point of a design region (``deepest_mm``), else the tool tip at
    the end of the finding's move. Findings in the order of ``report.json``."""
    table, model = report.table, report.model
    found = sorted(report.findings, key=sort_key)
    rows = [i for i, f in enumerate(found)
            if f.move_index is not None or "at_mm" in f.data or "deepest_mm" in f.data]
    if not rows or table is None or model is None or len(table) == 0:
        return []
    moves = [int(found[i].move_index) for i in rows if found[i].move_index is not None]
    tips = {}
    if moves:
        q = table.columns(model.axes, model.home, table.end[moves])
        tips = dict(zip(moves, np.asarray(model.fk(q).tip, float), strict=True))
    out = []
    for i in rows:
        f: Finding = found[i]
        at = f.data.get("at_mm", f.data.get("deepest_mm"))
        if at is None:
            at = tips.get(int(f.move_index))
        at = np.asarray(at, float).reshape(-1)
        if at.shape == (3,) and np.all(np.isfinite(at)):
            out.append(Place(at, i, f.kind, f.severity, f.line))
    return out


def band_span(lo: float, hi: float, deviation: np.ndarray) -> float:
    """How far beyond the band (mm) the colours reach their darkest: the worst deviation
    outside the band, but at least the band's width (a part just outside still reads red)."""
    d = np.asarray(deviation, float)
    d = d[np.isfinite(d)]
    worst = float(max(np.max(d - hi, initial=0.0), np.max(lo - d, initial=0.0))) if len(d) else 0.0
    return max(hi - lo, worst, 1e-6)


def deviation_rgb(deviation: np.ndarray, lo: float, hi: float, span: float) -> np.ndarray:
    """Colours (n, 3) float in 0..1 of deviations (n,) mm against the band [lo, hi] mm."""
    d = np.asarray(deviation, float)
    out = np.tile(IN_BAND, (len(d), 1))
    out[~np.isfinite(d)] = NOT_MEASURED
    for sel, t, (light, dark) in (
        (np.isfinite(d) & (d > hi), (d - hi) / span, ABOVE),
        (np.isfinite(d) & (d < lo), (lo - d) / span, BELOW),
    ):
        s = np.clip(t[sel], 0.0, 1.0)[:, None]
        out[sel] = light + s * (dark - light)
    return out


def colour_bar(lo: float, hi: float, span: float, n: int = 256) -> tuple[np.ndarray, tuple[float, float]]:
    """The colour bar of the map: colours (n, 3) over the range (lo - span, hi + span) mm."""
    rng = (lo - span, hi + span)
    return deviation_rgb(np.linspace(*rng, n), lo, hi, span), rng


def round_ticks(lo: float, hi: float, rng: tuple[float, float]) -> list[float]:
    """Ticks of the colour bar, mm: the band's limits and round values beyond them (µm)."""
    width_um = (rng[1] - rng[0]) * 1000
    step = 10 ** math.floor(math.log10(max(width_um / 4, 1e-3)))
    step *= min((m for m in (1, 2, 5, 10) if width_um / (m * step) <= 6), default=10)
    ticks = {round(lo, 6), round(hi, 6)}
    k = math.ceil(rng[0] * 1000 / step)
    while k * step <= rng[1] * 1000 + 1e-9:
        t = k * step / 1000
        if min(abs(t - lo), abs(t - hi)) > 0.3 * step / 1000:   # not crowding a band label
            ticks.add(round(t, 6))
        k += 1
    return sorted(ticks)


def scale_length(extent: float) -> float:
    """A round scale-bar length (1, 2 or 5 × 10^k mm) about a quarter of ``extent`` mm."""
    target = max(extent / 4, 1e-3)
    k = 10 ** math.floor(math.log10(target))
    return max(m * k for m in (1, 2, 5) if m * k <= target)


def part_deviation(report) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, tuple[float, float] | None]:
    """The cut part: vertices (n, 3) mm, faces (m, 3), deviation (n,) mm (NaN outside the
    profiled length; None without a profile check) and the band (lo, hi) mm."""
    v, f = report.part.mesh("part")
    if report.profile is None or report.profile_spec is None:
        return v, f, None, None
    from vmach.checks.polygon import parse_profile
    from vmach.report.paths import deviation_per_vertex

    prof = parse_profile(report.profile_spec)
    z = [s["z"] for s in report.profile["stations"]]
    dev = deviation_per_vertex(v, prof, report.profile["phase_deg"], min(z), max(z))
    lo, hi = report.profile["tolerance_mm"]
    return v, f, dev, (float(lo), float(hi))


def _coloured_part(report) -> tuple[np.ndarray, np.ndarray, np.ndarray | None,
                                    tuple[float, float] | None, str | None]:
    """The part the 3-D view shows and what colours it: the comparison with the design when
    ``--design`` ran (signed distance to the design over the whole part, its band), else the
    profile check's radial deviation (:func:`part_deviation`), else nothing. The last item
    says which: ``"design"``, ``"profile"`` or None."""
    outcome = getattr(report, "design", None)
    comparison = getattr(outcome, "comparison", None)
    if comparison is not None:
        band = comparison.band
        return (comparison.vertices, comparison.faces, comparison.deviation,
                (float(band.lo), float(band.hi)), "design")
    v, f, dev, band = part_deviation(report)
    return v, f, dev, band, (None if dev is None else "profile")


def _b64(a: np.ndarray, dtype) -> str:
    return base64.b64encode(np.ascontiguousarray(a, dtype=dtype).tobytes()).decode("ascii")


def viewer_scene(report) -> dict | None:
    """The data of report.html's 3-D view, JSON-ready (arrays as little-endian base64):
    ``part`` (positions float32 (n*3), colours uint8 (n*3), indices uint32 (m*3)) when there is
    a cut part, ``path`` (segment end points float32 (s*2*3), kinds uint8 (s,): 0 rapid, 1 feed),
    ``places`` (findings: at, index, kind, severity, label), ``band`` and ``scale_mm``."""
    from vmach.report.paths import toolpath_segments

    table, model = report.table, report.model
    if table is None or model is None:
        return None
    scene: dict = {"places": [], "band": None}
    pts = []
    if report.part is not None:
        v, f, dev, band, what = _coloured_part(report)
        if dev is None:
            rgb = np.tile(IN_BAND, (len(v), 1))
        else:
            span = band_span(*band, dev)
            rgb = deviation_rgb(dev, *band, span)
            scene["band"] = {"lo_um": band[0] * 1000, "hi_um": band[1] * 1000, "span_um": span * 1000,
                             "what": what}
        scene["part"] = {
            "positions": _b64(v, "<f4"),
            "colours": _b64(np.round(rgb * 255), "u1"),
            "indices": _b64(f, "<u4"),
            "triangles": int(len(f)),
        }
        pts.append(v)
    if len(table):
        seg, kinds = toolpath_segments(table, model)
        scene["path"] = {"points": _b64(seg, "<f4"), "kinds": _b64(kinds, "u1"), "segments": int(len(seg))}
        pts.append(seg.reshape(-1, 3))
    for p in finding_places(report):
        scene["places"].append({"at": [round(float(x), 4) for x in p.at], "index": p.index,
                                "kind": p.kind, "severity": p.severity, "label": p.label})
    if not pts:
        return None
    allp = pts[0]                       # the part when there is one: the view frames it
    scene["scale_mm"] = scale_length(float(np.max(np.ptp(allp, axis=0))))
    scene["program"] = Path(report.program).name
    return scene
