"""Stock-removal figures: the polygon-shaft program, scaling, and a naive manifold3d baseline.

    python benchmarks/stock.py [--program FILE] [--quick]

Program: the published listing split as issue 2 describes (../shared/reference) when present,
else the project's own fixtures/polygon_shaft/POLY50.MPF. Each case runs in a child process so
that its peak memory (ru_maxrss) is its own. Printed per case: moves, cutters, sweep and boolean
seconds, total, peak memory, and for the program the P3G-50 deviation between z = -35 and -5.

Scaling: a synthetic finishing helix (face at X = h(C), C +1.713 deg per move, Z -0.01 per move,
the D25 cutter) of 1k, 4k and 16k moves on a Ø60 blank. Naive baseline (issue 4): one convex
hull of the tool at the two ends of every move, all subtracted in one batch boolean (it also
overcuts rotary moves by about R sin(delta/2), so its deviation is printed too).
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
REFERENCE = ROOT.parent / "shared" / "reference" / "polygon_shaft_thesis.mpf"
TOOLS = ROOT / "fixtures" / "tools" / "polygon_shaft.toml"


def _program_table(program: str | None):
    from interpreters import sinumerik
    from vmach.machine import load_model
    from vmach.motion.table import build

    model = load_model("turnmill")
    if program:
        path = Path(program)
    elif REFERENCE.is_file():
        from catalog import split_reference

        path = split_reference(Path(tempfile.mkdtemp()), REFERENCE)
    else:
        path = ROOT / "fixtures" / "polygon_shaft" / "POLY50.MPF"
    result = sinumerik.run(str(path), model.control)
    return model, build(result.commands, model.control), path


def _helix(n: int):
    from vmach.checks.polygon import p3g

    c = np.arange(n + 1) * 1.713
    h = p3g(50.0).h(np.radians(c - 30.0))
    a = np.radians(c)
    tips = np.column_stack([h * np.cos(a), h * np.sin(a), 12.5 - 0.01 * np.arange(n + 1)])
    axes = np.column_stack([np.cos(a), np.sin(a), np.zeros_like(a)])
    return tips, axes


def _naive(stock_solid, tool, tips, axes):
    from vmach.stock import engine
    from vmach.tooling import frames, place, tool_solid

    ts = tool_solid(tool)
    fr = frames(tips, axes)
    t0 = time.perf_counter()
    pts = place(ts.pieces[0], fr)
    hulls = [engine.hull(np.concatenate([pts[i], pts[i + 1]])) for i in range(len(fr) - 1)]
    sweep = time.perf_counter() - t0
    t0 = time.perf_counter()
    part = engine.subtract(stock_solid, hulls)
    engine.check(part)
    return part, sweep, time.perf_counter() - t0, len(hulls)


def _deviation(section):
    from vmach.checks.polygon import p3g
    from vmach.checks.profile import check_profile, stations

    r = check_profile(section, p3g(50.0), stations("-35:-5", 7), fit="g6")
    return r.max, r.min


def case(kind: str, n: int, program: str | None, conn) -> None:
    from vmach.stock import Stock, engine
    from vmach.stock.simulate import simulate
    from vmach.tooling import load_tools

    lib = load_tools(TOOLS)
    out: dict = {"case": kind, "n": n}
    t_all = time.perf_counter()
    if kind in ("program", "program-naive"):
        model, table, path = _program_table(program)
        out["program"] = path.name
        out["moves"] = len(table)
        if kind == "program":
            stock = Stock.from_spec("cylinder:d=60,l=100")
            sim = simulate(table, model, lib, stock)
            part = stock.solid
            out.update(cutters=stock.stats.cutters, sweep=stock.stats.sweep_seconds + sim.kinematics_seconds,
                       boolean=stock.stats.boolean_seconds, bound=sim.bound_mm)
            out["dev"] = _deviation(stock.section)
        else:  # one hull per move (ends only), one batch
            from vmach.stock.spec import parse_stock

            solid = parse_stock("cylinder:d=60,l=100")
            q0 = table.columns(model.axes, model.home, table.start)
            q1 = table.columns(model.axes, model.home, table.end)
            parts = []
            tools = np.asarray(table.tool)
            all_hulls = []
            t0 = time.perf_counter()
            for ti, name in enumerate(table.tools):
                rows = np.nonzero(tools == ti)[0]
                tool = lib.lookup(name)
                from vmach.tooling import frames, place, tool_solid

                ts = tool_solid(tool)
                a, b = model.fk(q0[rows]), model.fk(q1[rows])
                pa = place(ts.pieces[0], frames(a.tip, a.axis))
                pb = place(ts.pieces[0], frames(b.tip, b.axis))
                all_hulls += [engine.hull(np.concatenate([pa[i], pb[i]])) for i in range(len(rows))]
            hulls_sweep = time.perf_counter() - t0
            t0 = time.perf_counter()
            part = engine.subtract(solid, all_hulls)
            engine.check(part)
            parts.append(part)
            out.update(cutters=len(all_hulls), sweep=hulls_sweep, boolean=time.perf_counter() - t0)
            out["dev"] = _deviation(lambda z: engine.slice_polygons(part, z))
    else:
        tips, axes = _helix(n)
        tool = lib.lookup("GLOD D25")
        out["moves"] = n
        if kind == "helix":
            stock = Stock.from_spec("cylinder:d=60,l=100")
            stock.cut(tool, tips, axes)
            engine.check(stock.solid)
            out.update(cutters=stock.stats.cutters, sweep=stock.stats.sweep_seconds,
                       boolean=stock.stats.boolean_seconds)
        else:
            from vmach.stock.spec import parse_stock

            _, sw, bo, k = _naive(parse_stock("cylinder:d=60,l=100"), tool, tips, axes)
            out.update(cutters=k, sweep=sw, boolean=bo)
    out["total"] = time.perf_counter() - t_all
    out["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    conn.send(out)
    conn.close()


def run_case(kind: str, n: int = 0, program: str | None = None) -> dict:
    ctx = mp.get_context("fork")
    a, b = ctx.Pipe()
    p = ctx.Process(target=case, args=(kind, n, program, b))
    p.start()
    out = a.recv()
    p.join()
    return out


def line(r: dict) -> str:
    dev = ""
    if "dev" in r:
        dev = f"  deviation max {r['dev'][0]:+.4f} min {r['dev'][1]:+.4f} mm"
    if "bound" in r:
        dev += f"  (sampling bound {r['bound']:.4f} mm)"
    return (f"{r['case']:<14s} {r['moves']:>6d} moves {r['cutters']:>6d} cutters  sweep "
            f"{r['sweep']:6.2f} s  boolean {r['boolean']:7.2f} s  total {r['total']:7.2f} s  "
            f"peak {r['peak_mb']:6.0f} MB{dev}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--program", help="NC program (default: the split reference, else POLY50.MPF)")
    ap.add_argument("--quick", action="store_true", help="scaling at 1k and 4k only, no naive program")
    args = ap.parse_args(argv)
    print("vmach stock removal benchmark (2-core machine figures in docs/stock.md)")
    print(line(run_case("program", program=args.program)), flush=True)
    if not args.quick:
        print(line(run_case("program-naive", program=args.program)), flush=True)
    sizes = (1000, 4000) if args.quick else (1000, 4000, 16000)
    for n in sizes:
        print(line(run_case("helix", n)), flush=True)
    for n in sizes[:2]:
        print(line(run_case("helix-naive", n)), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
