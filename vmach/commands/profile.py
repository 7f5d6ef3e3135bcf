"""``vmach profile P3G 50``: sizes and nominal curve of a DIN 32711 / DIN 32712 polygon."""

from __future__ import annotations

import argparse
import json

from vmach.checks.polygon import p3g_sizes, parse_profile

HELP = "print the sizes of a DIN 32711 P3G / DIN 32712 P4C profile (and draw it with --png)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("kind", help="P3G or P4C (or a full spec such as P3G:50, P4C:35x30/5)")
    p.add_argument("size", nargs="?", help="P3G: d1 (a DIN 32711 size, or d1/e1); P4C: d1xd2[/e]")
    p.add_argument("--png", metavar="FILE", help="write the nominal curve as a PNG")
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.add_argument("--list", action="store_true", help="list the P3G size table")
    g = p.add_argument_group("design", "write the nominal shaft end as a mesh, for verify --design")
    g.add_argument("--design-stl", metavar="FILE",
                   help="write the nominal part (.stl, .3mf or .ply): the profile from Z = 0 to "
                   "Z = -LENGTH in the workpiece frame")
    g.add_argument("--length", type=float, help="polygon length along Z, mm (needed with --design-stl)")
    g.add_argument("--chamfer", metavar="ANGLExLEN", help="lead-in chamfer at Z = 0, e.g. 15x3 (degrees "
                   "from the axis x axial length, mm)")
    g.add_argument("--shoulder", metavar="D:L", help="the shoulder behind the polygon: the "
                   "cylinder's diameter and length, mm, e.g. 60:60")
    g.add_argument("--phase", type=float, default=0.0,
                   help="turn of the profile about Z, degrees (the polygon-shaft programs: 30)")


def run(args: argparse.Namespace) -> int:
    if args.list:
        for d1, e1 in p3g_sizes().items():
            print(f"P3G {d1:>5g}  e1 {e1:5.2f}  d2 {d1 + 2 * e1:7.2f}  d3 {d1 - 2 * e1:7.2f}")
        return 0
    spec = args.kind if args.size is None else f"{args.kind}:{args.size}"
    prof = parse_profile(spec)
    data = {
        "type": prof.kind,
        "name": prof.name,
        "d1": prof.d1,
        "e1": prof.e,
        "d2": round(prof.d2, 6),
        "d3": round(prof.d3, 6),
        "area_mm2": round(prof.area, 4),
    }
    if prof.kind == "P4C":  # designation d1 x d2 / e: d2 is the width across the flats
        data.update(d2=prof.d2_flats, d_m=prof.d)
        del data["d3"]
    if args.png is not None:
        from vmach.report.render import profile_png

        curves, labels = _drawing(prof, data)
        standard = "DIN 32711" if prof.kind == "P3G" else "DIN 32712"
        profile_png(args.png, curves, title=f"{standard} {prof.name}", labels=labels, scale=True)
        data["png"] = args.png
    if args.design_stl is not None:
        data["design"] = _write_design(prof, args)
    if args.format == "json":
        print(json.dumps(data, indent=2))
    else:
        label = {
            "d1": "d1 (nominal)",
            "e1": "e1 (eccentricity)",
            "d2": "d2 (circumscribed)",
            "d3": "d3 (inscribed)",
            "area_mm2": "area",
            "d_m": "d_m (mean)",
        }
        if prof.kind == "P4C":
            label.update({"d1": "d1 (outer circle)", "d2": "d2 (across flats)", "e1": "e"})
        print(prof.name)
        for key in ("d1", "e1", "d2", "d3", "d_m", "area_mm2"):
            if key in data:
                unit = "mm²" if key == "area_mm2" else "mm"
                print(f"  {label[key]:<20s} {data[key]:10.4f} {unit}")
        if args.png is not None:
            print(f"  curve written to {args.png}")
        if args.design_stl is not None:
            d = data["design"]
            print(f"  nominal part written to {d['path']} ({d['triangles']} triangles, "
                  f"{d['volume_mm3']:.1f} mm³)")
    return 0


def _write_design(prof, args) -> dict:
    """Write the nominal shaft end of ``prof`` (:mod:`vmach.checks.nominal`) whole or not at all."""
    import trimesh

    from vmach.checks.nominal import ShaftDesign, parse_pair, shaft_mesh
    from vmach.errors import InputError
    from vmach.output import atomic_writer, writable_file

    path = writable_file(args.design_stl)
    ext = path.suffix.lower()
    if ext not in (".stl", ".3mf", ".ply"):
        raise InputError(f"{path}: the design is written as .stl, .3mf or .ply", kind="export_format")
    if args.length is None:
        raise InputError("--design-stl needs --length (the polygon's length along Z, mm)", kind="usage")
    design = ShaftDesign(
        length=args.length,
        chamfer=parse_pair(args.chamfer, "--chamfer") if args.chamfer else None,
        shoulder=parse_pair(args.shoulder, "--shoulder") if args.shoulder else None,
        phase_deg=args.phase,
    )
    v, f = shaft_mesh(prof, design)
    mesh = trimesh.Trimesh(v, f, process=False)
    blob = mesh.export(file_type=ext[1:])
    with atomic_writer(path, "wb") as fh:
        fh.write(blob if isinstance(blob, bytes) else blob.encode())
    return {"path": str(path), "triangles": int(len(f)), "volume_mm3": round(float(mesh.volume), 3),
            "length": design.length, "chamfer": design.chamfer, "shoulder": design.shoulder,
            "phase_deg": design.phase_deg}


#: colours of the drawing: the profile, its circumscribed and inscribed circles
D2_COLOUR, D3_COLOUR = "steelblue", "darkorange"


def _drawing(prof, data: dict) -> tuple[list, list]:
    """The curves and labels of ``profile --png``: the nominal profile (black) with the
    circles of its sizes — P3G: d2 circumscribed, d3 inscribed; P4C: d1 outer circle, d2
    across the flats — each labelled with its diameter (mm)."""
    import numpy as np

    if prof.kind == "P4C":
        circles = [("d1", data["d1"], D2_COLOUR), ("d2", data["d2"], D3_COLOUR)]
    else:
        circles = [("d2", data["d2"], D2_COLOUR), ("d3", data["d3"], D3_COLOUR)]
    t = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    curves = [(prof.curve(1440), "black")]
    labels = []
    for n, (name, d, colour) in enumerate(circles):
        curves.append((np.column_stack([d / 2 * np.cos(t), d / 2 * np.sin(t)]), colour))
        a = np.radians(-60 - 35 * n)                         # labels apart, off the profile's lobes
        labels.append((np.array([d / 2 * np.cos(a), d / 2 * np.sin(a)]), f"{name} = {d:g}", colour))
    return curves, labels
