"""Stock-removal figures: the polygon-shaft program, scaling, the pipeline before issue 4's speed
work, and a naive manifold3d baseline.

    python benchmarks/stock.py [--program FILE] [--quick] [--repeat N] [--accuracy fine]

Program: the published listing split as issue 2 describes (../shared/reference) when present,
else the project's own fixtures/polygon_shaft/POLY50.MPF. Each case runs in a child process so
that its peak memory (ru_maxrss) is its own. Printed per case: moves, cutters, sweep (cutters
and kinematics) and boolean seconds (with the stock's worker process, which takes the batches
once 512 cutters were queued, its boolean time, overlapping the sweep, and how long the
main process waited for it), total wall time, peak memory (the worker's separately), and for the program the
P3G-50 deviation between z = -35 and -5 with the sampling bound.

Cases
- ``program``: ``simulate`` with the defaults (fan cutters for rotary runs of flat-faced tools,
  column cutters for the same sector of consecutive turns of a helix,
  cutters trimmed to the stock within their Z range, placed poses inside translation hulls left
  out, spread batches, tools to ``tol.tool_chord``).
- ``program-checked``: the same with ``checks=True`` (what ``vmach verify`` runs).
- ``program-before``: the pipeline as it was before issue 4's speed work (no trimming, no fans,
  batches in queue order, tools to 0.002 mm) — measured in the same run, so on the same load.
- ``program-naive``: one convex hull of the tool at the two ends of every move, one batch
  (it also overcuts rotary moves by about R sin(delta/2)).
- ``helix N``: a synthetic finishing helix (face at X = h(C), the tool centred on the contact
  point Y = h'(C), C +1.713 deg per move, Z -0.01 per move, the D25 cutter) of N moves on a Ø60
  blank; ``helix-naive N`` one hull per move.

Figures on a loaded 2-core machine vary by tens of percent: ``--repeat`` runs each case N
times and prints the fastest, and every run's total (docs/stock.md says which). How fast the
machine is on the day: ``machine`` lines, first and last, time a fixed workload that runs no
vmach code — 256 placed Ø25 cylinders subtracted from a Ø60 cylinder in four checked batch
booleans (manifold3d, both cores), and a numpy loop of small array operations like the sweep's
(one core) — fastest of three; the program's figures scale with them from day to day.
"""

from __future__ import annotations

import argparse
import math
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

from vmach.tol import ACCURACY  # noqa: E402

REFERENCE = ROOT.parent / "shared" / "reference" / "polygon_shaft_thesis.mpf"
TOOLS = ROOT / "fixtures" / "polygon_shaft" / "tools.toml"
BEFORE = {"trim": False, "spread": 1, "chord": 0.002}   # the pipeline before the speed work
NAIVE_CHORD = 0.002
PRESET: dict = {}   # --accuracy: the program cases' Stock(chord=..., cusp=...) (vmach.tol.ACCURACY)


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
    poly = p3g(50.0)
    h = poly.h(np.radians(c - 30.0))
    y = poly.dh(np.radians(c - 30.0))          # the tool centred on the contact point, Y = h'(C)
    a = np.radians(c)
    tips = np.column_stack([h * np.cos(a) - y * np.sin(a), h * np.sin(a) + y * np.cos(a),
                            12.5 - 0.01 * np.arange(n + 1)])
    axes = np.column_stack([np.cos(a), np.sin(a), np.zeros_like(a)])
    return tips, axes


def _deviation(section):
    from vmach.checks.polygon import p3g
    from vmach.checks.profile import check_profile, stations

    r = check_profile(section, p3g(50.0), stations("-35:-5", 7), fit="g6")
    return r.max, r.min


def _naive_hulls(tool, tips_a, axes_a, tips_b, axes_b):
    from vmach.stock import engine
    from vmach.tooling import frames, place, tool_solid

    ts = tool_solid(tool, NAIVE_CHORD)
    pa = place(ts.pieces[0], frames(tips_a, axes_a))
    pb = place(ts.pieces[0], frames(tips_b, axes_b))
    return [engine.hull(np.concatenate([pa[i], pb[i]])) for i in range(len(pa))]


def case(kind: str, n: int, program: str | None, conn) -> None:
    from vmach.stock import Stock, engine
    from vmach.stock.simulate import simulate
    from vmach.stock.spec import parse_stock
    from vmach.tooling import load_tools

    lib = load_tools(TOOLS)
    out: dict = {"case": kind, "n": n}
    t_all = time.perf_counter()
    if kind.startswith("program"):
        model, table, path = _program_table(program)
        out["program"] = path.name
        out["moves"] = len(table)
        t_all = time.perf_counter()          # the interpreter is not part of the figure
        if kind != "program-naive":
            stock = Stock.from_spec("cylinder:d=60,l=100", **(BEFORE if kind == "program-before" else PRESET))
            sim = simulate(table, model, lib, stock, checks=kind == "program-checked")
            part = stock.solid
            engine.check(part)
            stock.close()
            out.update(cutters=stock.stats.cutters, sweep=stock.stats.sweep_seconds + sim.kinematics_seconds,
                       boolean=stock.stats.boolean_seconds, wait=stock.stats.wait_seconds, bound=sim.bound_mm,
                       fans=stock.stats.fans, fan_overcut=stock.stats.fan_overcut_mm,
                       fan_covered=stock.stats.fan_covered_mm, cusp_poses=stock.stats.cusp_poses,
                       columns=stock.stats.columns, column_cells=stock.stats.column_cells,
                       findings=len(sim.findings), triangles=engine.num_triangles(part),
                       volume=engine.volume(part))
            out["total"] = time.perf_counter() - t_all
            out["dev"] = _deviation(stock.section)
        else:  # one hull per move (ends only), one batch
            q0 = table.columns(model.axes, model.home, table.start)
            q1 = table.columns(model.axes, model.home, table.end)
            tools = np.asarray(table.tool)
            hulls = []
            t0 = time.perf_counter()
            for ti, name in enumerate(table.tools):
                rows = np.nonzero(tools == ti)[0]
                a, b = model.fk(q0[rows]), model.fk(q1[rows])
                hulls += _naive_hulls(lib.lookup(name), a.tip, a.axis, b.tip, b.axis)
            sweep = time.perf_counter() - t0
            t0 = time.perf_counter()
            part = engine.subtract(parse_stock("cylinder:d=60,l=100"), hulls)
            engine.check(part)
            out.update(cutters=len(hulls), sweep=sweep, boolean=time.perf_counter() - t0)
            out["total"] = time.perf_counter() - t_all
            out["dev"] = _deviation(lambda z: engine.slice_polygons(part, z))
    else:
        tips, axes = _helix(n)
        tool = lib.lookup("GLOD D25")
        out["moves"] = n
        if kind in ("helix", "helix-before"):
            stock = Stock.from_spec("cylinder:d=60,l=100", **(BEFORE if kind == "helix-before" else {}))
            stock.cut(tool, tips, axes)
            engine.check(stock.solid)
            out["volume"] = engine.volume(stock.solid)
            stock.close()
            out.update(cutters=stock.stats.cutters, sweep=stock.stats.sweep_seconds,
                       boolean=stock.stats.boolean_seconds, wait=stock.stats.wait_seconds,
                       fans=stock.stats.fans, fan_overcut=stock.stats.fan_overcut_mm,
                       fan_covered=stock.stats.fan_covered_mm,
                       columns=stock.stats.columns, column_cells=stock.stats.column_cells)
        else:
            t0 = time.perf_counter()
            hulls = _naive_hulls(tool, tips[:-1], axes[:-1], tips[1:], axes[1:])
            sweep = time.perf_counter() - t0
            t0 = time.perf_counter()
            engine.check(engine.subtract(parse_stock("cylinder:d=60,l=100"), hulls))
            out.update(cutters=len(hulls), sweep=sweep, boolean=time.perf_counter() - t0)
        out["total"] = time.perf_counter() - t_all
    out["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    # the stock's worker process, if one took the batches (ended by stock.close())
    out["worker_mb"] = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    conn.send(out)
    conn.close()


def _in_child(target, *args):
    """What ``target(*args, conn)`` sends on ``conn``, run in a forked child process (so that
    its peak memory is its own, and manifold3d's thread pool starts in it: TBB's pool does
    not survive a fork)."""
    ctx = mp.get_context("fork")
    a, b = ctx.Pipe()
    p = ctx.Process(target=target, args=(*args, b))
    p.start()
    out = a.recv()
    p.join()
    return out


def run_case(kind: str, n: int = 0, program: str | None = None, repeat: int = 1) -> dict:
    """Run a case in a child process ``repeat`` times; the fastest run, with every run's
    total time (``totals``)."""
    best = None
    totals = []
    for _ in range(max(1, repeat)):
        out = _in_child(case, kind, n, program)
        totals.append(out["total"])
        if best is None or out["total"] < best["total"]:
            best = out
    best["totals"] = totals
    return best


def line(r: dict) -> str:
    dev = ""
    if "dev" in r:
        dev = f"  deviation max {r['dev'][0]:+.4f} min {r['dev'][1]:+.4f} mm"
    if "bound" in r:
        dev += f"  (sampling bound {r['bound']:.4f} mm)"
    if r.get("fans"):
        dev += f"  [{r['fans']} fans, side-floor overcut <= {r['fan_overcut']:.4f} mm"
        if r.get("fan_covered"):
            dev += f"; bridges up to {r['fan_covered']:.4f} mm where the path's other turns cut anyway"
        dev += "]"
    if r.get("columns"):
        dev += f"  [{r['columns']} column cutters holding {r['column_cells']} turns' sectors]"
    if r.get("cusp_poses"):
        dev += f"  [{r['cusp_poses']} poses added against cusps]"
    if len(r.get("totals", ())) > 1:
        dev += f"  (runs: {', '.join(f'{t:.2f}' for t in r['totals'])} s)"
    worker = ""
    if r.get("worker_mb"):
        worker = f" + worker {r['worker_mb']:4.0f} MB (waited {r.get('wait', 0.0):.2f} s)"
    return (f"{r['case']:<16s} {r['moves']:>6d} moves {r['cutters']:>6d} cutters  sweep "
            f"{r['sweep']:6.2f} s  boolean {r['boolean']:7.2f} s  total {r['total']:7.2f} s  "
            f"peak {r['peak_mb']:6.0f} MB{worker}{dev}")


def machine_figure() -> str:
    """The ``machine`` line: seconds of a fixed manifold3d and numpy workload (no vmach code),
    fastest of three — in a child process like every case: manifold3d's thread pool (TBB)
    started in this process would not survive the fork of the cases that follow (they ran
    1.3–1.5 times slower when it had)."""
    return _in_child(_machine_child)


def _machine_child(conn) -> None:
    conn.send(_machine_line())
    conn.close()


def _machine_line() -> str:
    import manifold3d as m3d

    def booleans() -> float:
        t0 = time.perf_counter()
        stock = m3d.Manifold.cylinder(100.0, 30.0, 30.0, 192).translate((0.0, 0.0, -100.0))
        tool = m3d.Manifold.cylinder(30.0, 12.5, 12.5, 56)
        for b in range(4):
            batch = []
            for i in range(64):
                k = 64 * b + i
                c, zc = math.radians(1.713 * k), -5.0 - 0.06 * k
                # the tool's axis radial, its face 20 mm from the shaft's axis
                pose = tool.rotate((0.0, 90.0, 0.0)).translate((20.0, 3.0 * math.sin(3 * c), zc))
                batch.append(pose.rotate((0.0, 0.0, math.degrees(c))))
            stock = m3d.Manifold.batch_boolean([stock, *batch], m3d.OpType.Subtract)
            if stock.status() != m3d.Error.NoError:
                raise RuntimeError("calibration boolean failed")
        return time.perf_counter() - t0

    def arrays() -> float:
        rng = np.random.default_rng(1)
        pts = rng.normal(size=(64, 3))
        rot = rng.normal(size=(256, 3, 3))
        t0 = time.perf_counter()
        acc = 0.0
        for _ in range(200):
            placed = pts @ rot.transpose(0, 2, 1)                          # (256, 64, 3)
            lo, hi = placed.min(axis=1), placed.max(axis=1)
            n = np.cross(placed[:, 1:] - placed[:, :1], placed[:, 2:3] - placed[:, :1])
            acc += float(np.einsum("ijk,ijk->", n, n)) + float((hi - lo).sum())
            acc += float(np.nonzero(np.linalg.norm(placed, axis=2) > 1.5)[0].size)
        return time.perf_counter() - t0

    b = min(booleans() for _ in range(3))
    a = min(arrays() for _ in range(3))
    return f"machine          fixed workload: booleans {b:5.2f} s (2 cores)  arrays {a:5.2f} s (1 core)"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--program", help="NC program (default: the split reference, else POLY50.MPF)")
    ap.add_argument("--quick", action="store_true",
                    help="the program (plain and checked) and 1k/4k helices only: no before/naive cases")
    ap.add_argument("--repeat", type=int, default=1,
                    help="runs per case; the fastest is printed, and every run's total")
    ap.add_argument("--accuracy", default="standard", choices=tuple(ACCURACY),
                    help="the program cases' preset, as vmach verify --accuracy")
    args = ap.parse_args(argv)
    acc = ACCURACY[args.accuracy]
    PRESET.update(acc.stock)
    print(f"vmach stock removal benchmark ({args.accuracy} accuracy; 2-core figures in docs/stock.md)")
    print(machine_figure(), flush=True)
    kinds = ["program", "program-checked"] + ([] if args.quick else ["program-before", "program-naive"])
    for kind in kinds:
        once = kind in ("program-before", "program-naive")    # minutes each: run once
        print(line(run_case(kind, program=args.program, repeat=1 if once else args.repeat)), flush=True)
    sizes = (1000, 4000) if args.quick else (1000, 4000, 16000)
    for n in sizes:
        print(line(run_case("helix", n, repeat=args.repeat)), flush=True)
    if not args.quick:
        for n in sizes[:2]:
            print(line(run_case("helix-before", n, repeat=args.repeat)), flush=True)
        print(line(run_case("helix-naive", 1000, repeat=1)), flush=True)
    print(machine_figure(), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
