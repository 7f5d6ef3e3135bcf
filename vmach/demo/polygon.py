"""``vmach demo polygon-shaft``: the P3G polygon-shaft program of the fixture, made for one size
(or the whole DIN 32711 family run as a batch first), verified, and shown: an animation of the
cut, X and Y over C1, the profile against its band, and a page ``demo.html`` with all of it."""

from __future__ import annotations

import html
import json
import math
from pathlib import Path

import numpy as np

from vmach.errors import InputError
from vmach.output import atomic_writer, make_dir

_HERE = Path(__file__).resolve().parent


def default_program() -> Path:
    """The parametric program of the polygon-shaft fixture: the installed package's copy
    (``vmach/examples/polygon_shaft/POLY.MPF``, see setup.py) or the checkout's
    ``fixtures/polygon_shaft/POLY.MPF``."""
    for p in (_HERE.parent / "examples" / "polygon_shaft" / "POLY.MPF",
              _HERE.parent.parent / "fixtures" / "polygon_shaft" / "POLY.MPF"):
        if p.is_file():
            return p
    raise InputError("the polygon-shaft program is missing from this installation (vmach/examples/"
                     "polygon_shaft/POLY.MPF): reinstall vmach, or give --program", kind="usage")


def profile_band_png(report, path: Path) -> bool:
    """The flank's radial deviation over the angle at the middle profile station, µm, with the
    band's two limits; False when there is no profile to show."""
    from vmach.checks.polygon import parse_profile
    from vmach.checks.profile import axis_contour, densify
    from vmach.report import render

    prof = report.profile
    if prof is None or report.part is None or not prof.get("stations"):
        return False
    st = [s for s in prof["stations"] if s.get("found", True)]
    if not st:
        return False
    z = float(st[len(st) // 2]["z"])
    c = axis_contour(report.part.section(z))
    if c is None:
        return False
    pts = densify(c)
    d = parse_profile(report.profile_spec).signed_distance(pts, math.radians(prof["phase_deg"])) * 1000
    ang = np.degrees(np.arctan2(pts[:, 1], pts[:, 0])) % 360
    order = np.argsort(ang)
    lo, hi = (t * 1000 for t in prof["tolerance_mm"])
    ends = np.array([0.0, 360.0])
    series = [(ang[order], d[order], "deviation", "b"), (ends, np.full(2, hi), "band upper", "r"),
              (ends, np.full(2, lo), "band lower", "r")]
    render.chart_png(path, series, "angle [deg]", "radial deviation [um]",
                     title=f"{report.profile_spec} at z = {z:g} mm: the flank against its {prof['fit']} band")
    return True


def run_demo(out: Path, size: float, program: Path | None = None, frames: int = 48,
             frame_size: tuple[int, int] = (800, 600)) -> dict[str, str]:
    """Verify ``program`` (the fixture's parametric POLY.MPF) at P3G ``size`` into
    ``out/<case>``, animate its cut and write ``out/demo.html``; returns what was written."""
    from vmach.batch.family import family_cases, materialise
    from vmach.demo.animation import cut_frames, write_animation
    from vmach.report.html import write_report_html
    from vmach.report.pictures import make_pictures
    from vmach.verify import VerifyOptions, verify

    prog = program or default_program()
    case = family_cases(prog, "P3G", f"{size:g}")[0]
    case_dir = out / case.name
    target = materialise(case, case_dir)
    report = verify(target, VerifyOptions(images=False, out=case_dir))
    make_dir(out)
    written: dict[str, str] = {}
    images = make_pictures(report, case_dir)
    report.images = images
    data = report.to_json()
    with atomic_writer(case_dir / "report.json") as fh:
        json.dump(data, fh, indent=2, ensure_ascii=False)
        fh.write("\n")
    write_report_html(report, data, case_dir)
    written["report"] = f"{case.name}/report.html"
    if "x_of_c" in images:
        written["x_of_c"] = f"{case.name}/{images['x_of_c']}"
    if profile_band_png(report, case_dir / "profile_band.png"):
        written["profile_band"] = f"{case.name}/profile_band.png"
    anim = write_animation(list(cut_frames(report, frames, frame_size)), out, stem=f"cut_{case.name}")
    written.update(anim)
    verdict = "errors" if report.errors else "no errors"
    prof = report.profile
    line = (f"{report.profile_spec}: max |deviation| {prof['max_abs_deviation_mm'] * 1000:.1f} µm, "
            f"{'PASS' if prof['pass'] else 'FAIL'}" if prof else "profile not checked")
    written["summary"] = f"{case.label}: {verdict}; {line}"
    with atomic_writer(out / "demo.html") as fh:
        fh.write(_page(case.label, written, (out / "index.html").is_file()))
    written["page"] = "demo.html"
    return written


def _page(label: str, w: dict[str, str], family: bool) -> str:
    e = html.escape
    imgs = "".join(f"<figure><img src='{e(w[k])}' alt='{k}'><figcaption>{e(t)}</figcaption></figure>"
                   for k, t in (("gif", "the cut"), ("x_of_c", "X and Y over C1"),
                                ("profile_band", "the profile against its band")) if k in w)
    link = f"<p><a href='{e(w['report'])}'>the verify report</a>"
    link += " · <a href='index.html'>the whole family</a></p>" if family else "</p>"
    return ("<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>P3G polygon shaft</title>"
            "<style>body{font-family:sans-serif;margin:1.5em}img{max-width:100%}</style></head><body>"
            f"<h1>DIN 32711 P3G polygon shaft, {e(label)}</h1><p>{e(w['summary'])}</p>{link}{imgs}"
            f"<p><a href='{e(w['mp4'])}'>the cut as MP4</a></p></body></html>\n")
