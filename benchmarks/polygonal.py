"""Polygonal turning against milling: the four shape families and a hexagon's flank flatness
(#34, domain §6), measured on parts vmach cuts.

    python benchmarks/polygonal.py [--images DIR]

1. The four shape families: the bundled flywheels (fixtures/tools/polygon.toml, cutting
   radius R = 25 mm) coupled at tool:work k cut Ø32 bar at X; for each part's section at
   z = −12: the number of flats, each flank's bulge (signed: + convex, − concave) and
   flatness over the middle 80 % between its corners (:mod:`vmach.checks.flats`), and the
   wall time of the cut and its section.
2. The hexagon SW 24 (24 mm across the flats), once polygon-turned (three inserts, 2:1, as
   fixtures/polygon_turning/HEXAGON.MPF) and once milled — a Ø16 end mill's side along the six
   flanks in X–Y interpolation — each flank measured the same way; the turned flank's bulge
   against the sagitta of the relative tip curve (an ellipse of semi-axes X and X + 2R: radius
   of curvature ρ = (X + 2R)² / X at the flat's middle, sagitta L² / 8ρ over the chord L).
3. The turned hexagon's flatness against the cutting radius R (the same SW 24).

With ``--converge``: 4. each shape's section against one made with a 100 times smaller sag
(the stated accuracy of the strategy; slow: the fine sections unite ten times the hulls).

With ``--images DIR``: a picture of each shape's section (docs/polygonal-turning.md), and a
chart of the turned and milled flanks' deviation from their chords.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from vmach.checks.flats import dense, flanks, radius_profile  # noqa: E402
from vmach.stock import Stock, engine  # noqa: E402
from vmach.stock.strategies import polygonal  # noqa: E402
from vmach.stock.strategies.polygonal import Coupling  # noqa: E402
from vmach.tooling import load_tools  # noqa: E402
from vmach.tooling.flywheel import FlywheelTool  # noqa: E402
from vmach.tooling.model import Tool  # noqa: E402

LIB = ROOT / "fixtures" / "tools" / "polygon.toml"
Z = -12.0
FAMILIES = [("square", "FLY2", 2, 11.0), ("hexagon", "FLY3", 2, 12.0), ("arcs", "FLY3", 1, 10.0),
            ("concave", "FLY2", 3, 12.0)]


def turned(tool, k: float, x: float, bar: float = 32.0) -> tuple[np.ndarray, float]:
    """The section at Z of a bar polygon-turned at X = x (radius), and the wall seconds."""
    stock = Stock.from_spec(f"cylinder:d={bar},l=40")
    t0 = time.perf_counter()
    stock.polygon(tool, Coupling(k), np.array([[x, 0.0, 2.0], [x, 0.0, -25.0]]))
    sec = stock.section(Z)
    return max(sec, key=len), time.perf_counter() - t0


def milled_hexagon(across: float = 24.0, cutter: float = 16.0, bar: float = 32.0) -> np.ndarray:
    """The section at Z of a hexagon milled with an end mill's side along its flanks (X–Y)."""
    stock = Stock.from_spec(f"cylinder:d={bar},l=40")
    tool = Tool(name="EM16", kind="flat", diameter=cutter, cutting_length=30.0)
    r = (across / 2.0 + cutter / 2.0) / math.cos(math.pi / 6)          # the offset hexagon's corners
    ang = np.radians(30.0 + 60.0 * np.arange(7))
    tips = np.column_stack([r * np.cos(ang), r * np.sin(ang), np.full(7, -25.0)])
    stock.cut(tool, tips, np.tile([0.0, 0.0, 1.0], (7, 1)))
    return max(stock.section(Z), key=len)


def deviation(contour: np.ndarray, flank) -> tuple[np.ndarray, np.ndarray]:
    """(s, d): points of the flank's middle 80 %: position along the chord and signed distance
    from it (mm, + outward)."""
    mid = math.radians(flank.angle)
    half = math.atan2(flank.width / 2.0, flank.radius)
    pts = dense(contour, 0.05)
    th = np.arctan2(pts[:, 1], pts[:, 0])
    rel = (th - mid + math.pi) % (2 * math.pi) - math.pi
    pts = pts[np.abs(rel) <= half]
    u = np.array([-math.sin(mid), math.cos(mid)])
    n = np.array([math.cos(mid), math.sin(mid)])
    s = pts @ u
    order = np.argsort(s)
    s, d = s[order], (pts @ n)[order]
    ends = np.interp([s[0], s[-1]], s, d)
    return s, d - np.interp(s, [s[0], s[-1]], ends)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--images", type=Path, help="write the pictures into this directory")
    ap.add_argument("--converge", action="store_true", help="measure the sections against 100x finer ones")
    args = ap.parse_args()
    lib = load_tools(LIB)
    shapes = {}
    print("1. shape families (Ø32 bar, flywheels R = 25 mm; bulge + convex, − concave; mm)")
    print(f"{'shape':<9} {'tool':<5} {'k':>3} {'X':>6} {'flats':>5} {'bulge':>9} {'flatness':>9} "
          f"{'wall s':>6}")
    for name, tname, k, x in FAMILIES:
        sec, cpu = turned(lib.lookup(tname), k, x)
        fl = flanks(sec)
        shapes[name] = (sec, fl, k, tname)
        print(f"{name:<9} {tname:<5} {k:>3} {x:>6.1f} {len(fl):>5} {np.mean([f.bulge for f in fl]):>9.4f} "
              f"{max(f.flatness for f in fl):>9.4f} {cpu:>6.2f}")

    print("\n2. hexagon SW 24: polygonal turning (FLY3, 2:1) against milling (Ø16 end mill, X-Y)")
    tsec, tfl, _, _ = shapes["hexagon"]
    msec = milled_hexagon()
    mfl = flanks(msec)
    x, r_cut = 12.0, lib.lookup("FLY3").radius
    rho = (x + 2.0 * r_cut) ** 2 / x
    chord = float(np.mean([f.width for f in tfl]))
    print(f"turned : flats {len(tfl)}, flatness {max(f.flatness for f in tfl):.4f} mm "
          f"(bulge {np.mean([f.bulge for f in tfl]):+.4f}, over {chord:.2f} mm of each flank)")
    print(f"         the tip's curve: ellipse, radius of curvature (X + 2R)^2 / X = {rho:.1f} mm at the flat;"
          f" sagitta L^2 / 8 rho = {chord ** 2 / (8 * rho):.4f} mm")
    print(f"milled : flats {len(mfl)}, flatness {max(f.flatness for f in mfl):.6f} mm "
          f"(the cutter's side translated: a straight line, to the simulation's tolerance)")
    print("thesis (measured): polygonal turning 0.124 mm; milling 0.005-0.013 mm")

    print("\n3. turned hexagon SW 24: flatness against the cutting radius R (Ø28 bar)")
    print(f"{'R':>6} {'flatness':>9} {'L^2/8rho':>9}")
    for radius in (12.5, 16.0, 20.0, 25.0, 32.0, 40.0):
        tool = FlywheelTool("FW", inserts=3, radius=radius, shape="T", inscribed=min(8.0, radius / 2),
                            nose_radius=0.2, width=10.0)
        fl = flanks(turned(tool, 2, x, bar=28.0)[0])
        length = float(np.mean([f.width for f in fl]))
        sagitta = length ** 2 * x / (8 * (x + 2 * radius) ** 2)
        print(f"{radius:>6.1f} {max(f.flatness for f in fl):>9.4f} {sagitta:>9.4f}")

    if args.converge:
        print("\n4. sections against 100x finer ones (sag 1e-5 mm): radial difference, mm (+: material left)")
        for name, tname, k, x in FAMILIES:
            tool = lib.lookup(tname)
            r = []
            for sag in (polygonal.SAG, polygonal.SAG / 100.0):
                hulls = polygonal.section(tool, Coupling(k), complex(x + tool.radius, 0.0), None, 17.0, sag)
                part = engine.subtract(engine.cylinder(16.0, -30.0, 0.0, 2048),
                                       [engine.extruded(hulls, -31.0, 1.0, 17.0)])
                r.append(radius_profile(max(engine.slice_polygons(part, Z), key=len), 72000)[1])
            d = r[0] - r[1]
            print(f"{name:<9} {d.min():+.5f} .. {d.max():+.5f}")

    if args.images:
        from vmach.report import render

        args.images.mkdir(parents=True, exist_ok=True)
        circle = 16.0 * np.column_stack([np.cos(np.linspace(0, 2 * np.pi, 721)[:-1]),
                                         np.sin(np.linspace(0, 2 * np.pi, 721)[:-1])])
        for name, (sec, fl, k, tname) in shapes.items():
            title = (f"{name}: {tname} ({lib.lookup(tname).inserts} inserts), tool:work {k}:1 - "
                     f"{len(fl)} flats, bulge {np.mean([f.bulge for f in fl]):+.3f} mm")
            out = render.profile_png(args.images / f"polygon_{name}.png",
                                     [(circle, "gray"), (sec, "steelblue")], title=title, size=(700, 700),
                                     scale=True)
            print(out)
        st, dt = deviation(tsec, tfl[0])
        sm, dm = deviation(msec, mfl[0])
        out = render.chart_png(args.images / "polygon_hexagon_flank.png",
                               [(st, dt, "polygonal turning", "tab:blue"),
                                (sm, dm, "milling (X-Y)", "tab:orange")],
                               "along the flank (mm)", "from the chord (mm)",
                               title="Hexagon SW 24: a flank's deviation from its chord")
        print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
