"""``vmach verify PROG``: interpretation, kinematics, cutting, checks, report."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from vmach import coverage
from vmach.commands.run import add_linuxcnc_arguments, linuxcnc_options
from vmach.errors import InputError
from vmach.motion.timing import format_seconds
from vmach.output import atomic_writer, make_dir, writable_dir
from vmach.progress import Progress
from vmach.tol import ACCURACY, tol
from vmach.verify import VerifyOptions, verify

#: the phases of a run, in order (for the progress bar's length)
PHASES = ("setup", "interpret", "move_table", "checks", "cycle_time", "stock", "collisions", "profile",
          "pictures", "report")

HELP = "verify a program on a machine: limits, collisions, stock, profile, cycle time, report"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("program", help="NC program (.mpf/.spf Sinumerik, .ngc RS274/NGC)")
    p.add_argument("--machine", help="machine model (path or name in models/)")
    p.add_argument("--dialect", help="override the dialect chosen by the extension or the machine")
    p.add_argument("--tools", help="tool library (TOML)")
    p.add_argument(
        "--default-tool",
        metavar="KIND:d=D[,l=L]",
        help="stand in for every tool the library lacks (or all, without one) with this cutter, e.g. "
        "flat:d=10 (flat, ball, drill); each is a default_tool warning, never assumed silently",
    )
    add_linuxcnc_arguments(p)
    p.add_argument("--stock", help="stock: cylinder:d=60,l=100 | box:x=..,y=..,z=.. | mesh:part.stl")
    p.add_argument("--profile", help="profile to check, e.g. P3G:50 (DIN 32711) or P4C:35x30")
    p.add_argument("--profile-z", help="Z range of the profile check, e.g. -35:-5")
    p.add_argument("--fit", default="g6", help="ISO 286 fit class of the shaft (default g6)")
    p.add_argument("--stations", type=int, default=7, help="Z stations of the profile check (default 7)")
    p.add_argument(
        "--export",
        action="append",
        default=[],
        help="write the cut part (or, for a name ending in 'removed', the removed volume) "
        "as .stl/.3mf/.ply; may be given twice",
    )
    p.add_argument("--out", help="directory for report.json and the pictures (default: out/<program>)")
    p.add_argument("--no-images", action="store_true", help="skip the PNG pictures")
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.add_argument(
        "--clearance",
        type=float,
        default=tol.near_miss,
        help=f"near-miss distance for rapids, mm (default {tol.near_miss})",
    )
    p.add_argument(
        "--accuracy",
        choices=tuple(ACCURACY),
        help="stock simulation: standard (tool polygons and side cusps to 0.01 mm) or fine (0.004 / "
        "0.0035 mm: about 0.005 mm everywhere, about 1.7 times the time; docs/stock.md); default: "
        "the vmach.toml's accuracy, else standard",
    )
    g = p.add_argument_group("design", "compare the cut part with its design (docs/report.md)")
    g.add_argument("--design", metavar="FILE",
                   help="the part's design as .stl/.3mf/.ply (.step with vmach[step]), in the "
                   "workpiece frame (the stock's and --export's): design_gouge / design_excess")
    g.add_argument("--design-tolerance", metavar="+UP/-DOWN",
                   help="band about the design's surface, mm (default +0.05/-0.02)")
    g.add_argument("--design-offset", metavar="X,Y,Z", help="move the design by this, mm")
    p.add_argument("--max-blocks", type=int, default=tol.max_blocks)
    p.add_argument("--quiet", action="store_true",
                   help="no progress (else: bars on a terminal, one line a phase with its time on stderr)")


def run(args: argparse.Namespace) -> int:
    if not 1 <= args.max_blocks <= tol.max_blocks_ceiling:   # a huge value must not switch it off
        raise InputError(f"--max-blocks must be 1 to {tol.max_blocks_ceiling:,}", kind="usage")
    if not args.clearance >= 0:
        raise InputError("--clearance must be a distance >= 0 mm", kind="usage")
    out = writable_dir(args.out if args.out else Path("out") / Path(args.program).stem)
    progress = Progress.for_stream("verify", args.quiet, PHASES)
    options = VerifyOptions(
        machine=args.machine,
        tools=args.tools,
        stock=args.stock,
        profile=args.profile,
        profile_z=args.profile_z,
        fit=args.fit,
        out=out,
        images=not args.no_images,
        max_blocks=args.max_blocks,
        quiet=args.quiet or not sys.stderr.isatty(),
        export=tuple(args.export),
        clearance=args.clearance,
        profile_stations=args.stations,
        accuracy=args.accuracy,
        dialect=args.dialect,
        design=args.design,
        design_tolerance=args.design_tolerance,
        design_offset=args.design_offset,
        default_tool=args.default_tool,
        progress=progress,
        dialect_options=linuxcnc_options(args),
    )
    try:
        report = verify(args.program, options)
    except BaseException:
        progress.close(finished=False)
        raise
    data = report.to_json()
    args.exit_code = 1 if report.errors else 0    # known before the output (a closed pipe keeps it)
    make_dir(out)
    stale_pictures_removed(out, data["images"])
    with atomic_writer(out / "report.json") as fh:
        json.dump(data, fh, indent=2, ensure_ascii=False)
        fh.write("\n")
    from vmach.report.html import write_report_html

    progress.start("report")
    t = time.perf_counter()
    write_report_html(report, data, out)       # report.html beside it: the same report, shown
    progress.done("report", time.perf_counter() - t)
    progress.close()
    if args.format == "json":
        json.dump(data, sys.stdout, indent=2, ensure_ascii=False)
        sys.stdout.write("\n")
    else:
        print(summary(report, out))
    return 1 if report.errors else 0


def stale_pictures_removed(out: Path, images: dict) -> None:
    """Remove the pictures an earlier report in ``out`` listed that this one does not (a run with
    --no-images, or fewer findings, must not leave an older picture beside the new report).
    Only files that report named are touched, and only inside ``out``."""
    old = out / "report.json"
    try:
        listed = json.loads(old.read_text(encoding="utf-8")).get("images") or {}
    except (OSError, ValueError, AttributeError):
        return
    keep = {str(v) for v in images.values()}
    for name in listed.values() if isinstance(listed, dict) else ():
        p = out / str(name)
        if str(name) in keep or p.resolve().parent != out.resolve() or not p.is_file():
            continue
        try:
            p.unlink()
        except OSError:
            pass


def summary(report, out: Path) -> str:
    lines = []
    for f in sorted(report.findings, key=lambda f: (f.severity != "error", f.line or 0)):
        lines.append(f.render())
    d = report.to_json()
    s = d["summary"]
    lines.append("")
    partial = " (partial)" if d["partial"] else ""
    lines.append(
        f"{report.program}: {d['program']['moves']} moves{partial}, {s['errors']} error(s), "
        f"{s['warnings']} warning(s)"
    )
    lines.extend(coverage.summary_lines(report))
    if d["cycle_time_s"] is not None:
        lines.append(f"cycle time {format_seconds(d['cycle_time_s'])}")
    if d["simulation"]:
        m = d["simulation"]
        b = m["error_bounds_mm"]
        known = [v for v in (b.get("fan_overcut"), b.get("tool_polygon"), b.get("side_cusps"))
                 if v is not None]
        lines.append(
            f"stock ({m['accuracy']} accuracy{', partial' if partial else ''}): "
            f"{m['cutters']} cutters ({m['fan_cutters']} fans); "
            "simulation error within "
            f"{_figure(b.get('face_scallop'), '.4f')} on flat faces, "
            f"{_figure(max(known, default=None), 'g')} on sides "
            "(report.json: simulation.error_bounds_mm)"
        )
    if d["profile"]:
        p = d["profile"]
        dev = p.get("max_abs_deviation_mm")            # None where no station found the part
        lines.append(
            f"profile {p['type']} d1={p['d1']}: max |deviation| "
            f"{_figure(dev, '.4f')}, "
            f"band {p['tolerance_mm']}: {'PASS' if p['pass'] else 'FAIL'}"
        )
    if d.get("design"):
        g = d["design"]
        lo, hi = g["tolerance_mm"]
        lines.append(f"design {g['path']}: deviation -{g['max_gouge_mm']:.4f}…+{g['max_excess_mm']:.4f} mm, "
                     f"band {lo:+g}/{hi:+g}: {g['gouges']} gouge(s), {g['excess']} excess region(s)")
    lines.append(f"report: {out / 'report.json'} ({out / 'report.html'})")
    return "\n".join(lines)


def _figure(value, spec: str) -> str:
    """A length of the summary in mm, or ``n/a`` where the report has none (never a crash on
    None)."""
    return "n/a" if value is None else f"{format(value, spec)} mm"
