"""Simulation error of stock removal on the polygon-shaft program: the part simulated at the
default tolerances against a converged reference simulated at much finer ones, region by region.

    python benchmarks/stock_error.py [--cache DIR] [--shared DIR] [--program FILE]
                                     [--reference FILE.npz] [--fine-chord MM] [--fine-angle DEG]
                                     [--fine-step MM] [--samples N] [--seed N] [--threshold MM]
                                     [--attribute]

Both parts are cut from the same blank (``cylinder:d=60,l=100``, polygonised to
``tol.blank_chord``), so the blank's own polygon cancels out. The default part is what
``simulate`` makes with its defaults (tools to ``tol.tool_chord``, fan cutters, rotary moves
sampled every ``tol.sweep_angle`` / ``tol.sweep_step``); the reference uses tools to
``--fine-chord``, no fan cutters (placed poses only: they never overcut) and rotary moves sampled
every ``--fine-angle`` / ``--fine-step``. Each simulation runs in a child process; its mesh
(double precision) and figures are kept in ``--cache`` (default: <tempdir>/vmach-stock-error),
keyed by the settings, the program and the code version (HEAD and a hash of ``git diff HEAD --
vmach``), so reruns only measure. ``--reference FILE`` takes the reference mesh from a file this
script wrote (e.g. one made from another commit) instead.

Measured (all lengths mm, volumes mm³): the signed distance d of points of the default part's
surface from the reference surface — area-weighted samples (the untouched blank surface at a
tenth of the density) plus every vertex — and, the other way, of points of the reference
surface from the default surface. Sign, both ways: d > 0 where the default part has material
the reference lacks (the simulation left material), d < 0 where it lacks material the
reference keeps (a gouge). Distances are exact nearest-triangle distances: the triangles are
covered by points 0.1 mm apart, candidates come from a k-d tree of those points and a
candidate set is accepted only when no triangle outside it can be closer; a brute-force self-check on a
subset confirms it. Per region of the part: points, max d, min d, RMS and the 99.9th
percentile of |d|; where |d| exceeds ``--threshold``, where those points are. Also the volumes
of (default − reference) and (reference − default), and as a check of the sign the integral of
d over each surface (to first order the volume difference). ``--attribute`` also simulates the
default with one setting at a time taken from the reference (fans off; tool chord; sweep angle
and step) and tabulates each variant's max/min per region: which setting makes which error.

The reference's own error (measured at 34a6b62 against a still finer one, tool chord 0.0005 mm,
0.25°, 0.125 mm, 608 s): at most 0.003 mm, 99.9 % of points within 0.0018 mm.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import multiprocessing as mp
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))

import stock as bench  # noqa: E402  (benchmarks/stock.py: program and tool library)

from vmach.tol import ACCURACY  # noqa: E402

SPEC = "cylinder:d=60,l=100"
FINE_CHORD = 0.001   # mm, tool polygons
FINE_ANGLE = 0.5     # deg, rotary sampling
FINE_STEP = 0.25     # mm, rotary sampling
SPACING = 0.1        # mm, spacing of the cover points of a surface (Surface, cover)
EPS_TIE = 1e-9       # mm, candidate triangles this close to the nearest count as tied (sign)
UNTOUCHED_WEIGHT = 0.1


# --------------------------------------------------------------------------------------------
# simulation (child process) and cache

CODE = ("vmach", "interpreters", "models", "fixtures", "tests/catalog.py")   # what a simulation runs


def _code_version() -> tuple[str, str]:
    """(label, key) of the code a simulation runs: HEAD, and the git trees of ``CODE`` with a hash
    of their uncommitted changes and untracked files (so a commit elsewhere keeps the cache)."""
    try:
        def git(*cmd: str) -> bytes:
            return subprocess.run(["git", "-C", str(ROOT), *cmd], capture_output=True, check=True).stdout

        head = git("rev-parse", "--short=12", "HEAD").decode().strip()
        trees = git("rev-parse", *(f"HEAD:{c}" for c in CODE)).decode().split()
        diff = git("diff", "HEAD", "--", *CODE)
        # files not yet committed count too (their contents, by name)
        for name in sorted(git("ls-files", "--others", "--exclude-standard", "--", *CODE).decode().split()):
            diff += name.encode() + (ROOT / name).read_bytes()
    except (OSError, subprocess.CalledProcessError):
        return "no git", "nogit"
    dirty = "" if not diff else "-dirty" + hashlib.sha1(diff).hexdigest()[:8]
    return head + dirty, ",".join(trees) + dirty


def _program_source(program: str | None) -> Path:
    if program:
        return Path(program)
    if bench.REFERENCE.is_file():
        return bench.REFERENCE
    return bench.ROOT / "fixtures" / "polygon_shaft" / "POLY50.MPF"


def _simulate_child(settings: dict, program: str | None, out_file: str, conn) -> None:
    from vmach.stock import Stock, engine
    from vmach.stock.simulate import simulate
    from vmach.tol import tol
    from vmach.tooling import load_tools

    lib = load_tools(bench.TOOLS)
    model, table, path = bench._program_table(program)
    t0 = time.perf_counter()
    stock = Stock.from_spec(SPEC, chord=settings["chord"], fans=settings["fans"],
                            cusp=settings.get("cusp", tol.sweep_cusp), arcs=settings.get("arcs", False))
    sim = simulate(table, model, lib, stock, angle=settings["angle"], step=settings["step"])
    part = stock.solid
    engine.check(part)
    wall = time.perf_counter() - t0
    v, f = engine.to_mesh(part, double=True)
    meta = dict(settings, blank_chord=tol.blank_chord, spec=SPEC, program=path.name, moves=len(table),
                wall=wall, triangles=engine.num_triangles(part), volume=engine.volume(part),
                cutters=stock.stats.cutters, fans_made=stock.stats.fans, samples=sim.samples,
                bound=sim.bound_mm, fan_overcut=stock.stats.fan_overcut_mm,
                peak_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                vmach=str(Path(sys.modules["vmach"].__file__).parent))
    np.savez(out_file, v=v, f=f, meta=json.dumps(meta))
    conn.send(meta)
    conn.close()


def part_mesh(settings: dict, program: str | None, cache: Path, label: str) -> tuple:
    """(vertices, faces, meta) of the part simulated with ``settings``, from the cache or made in
    a child process (fork) and cached."""
    from vmach.tol import tol

    src = _program_source(program)
    key = json.dumps([SPEC, tol.blank_chord, settings, hashlib.sha1(src.read_bytes()).hexdigest(),
                      str(program or ""), _code_version()[1]], sort_keys=True)
    name = f"{label}-{hashlib.sha1(key.encode()).hexdigest()[:16]}.npz"
    file = cache / name
    if not file.is_file():
        print(f"  simulating the {label} part ({settings}) ...", flush=True)
        ctx = mp.get_context("fork")
        a, b = ctx.Pipe()
        tmp = cache / (name + ".part.npz")
        p = ctx.Process(target=_simulate_child, args=(settings, program, str(tmp), b))
        p.start()
        b.close()
        try:
            a.recv()
        except EOFError:
            p.join()
            raise SystemExit(f"the {label} simulation failed (exit code {p.exitcode})") from None
        p.join()
        tmp.replace(file)
    return load_part(file) + (file,)


def load_part(file: Path) -> tuple:
    with np.load(file) as d:
        return d["v"], d["f"], json.loads(str(d["meta"]))


# --------------------------------------------------------------------------------------------
# geometry

def triangle_normals(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals (m, 3) and areas (m,) of triangles t (m, 3, 3)."""
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    a = np.linalg.norm(n, axis=1)
    return n / np.where(a > 0, a, 1.0)[:, None], a / 2


def closest_on_triangles(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Closest points of triangles (a, b, c) to points p, all (..., 3) (Ericson, Real-Time
    Collision Detection 5.1.5, vectorised)."""
    def dot(u, v):
        return np.einsum("...i,...i->...", u, v)

    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = dot(ab, ap), dot(ac, ap)
    bp = p - b
    d3, d4 = dot(ab, bp), dot(ac, bp)
    cp = p - c
    d5, d6 = dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        den = va + vb + vc
        q = a + ab * (vb / den)[..., None] + ac * (vc / den)[..., None]       # inside the face
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        m = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)                       # edge BC
        q = np.where(m[..., None], b + (c - b) * w[..., None], q)
        w = d2 / (d2 - d6)
        m = (vb <= 0) & (d2 >= 0) & (d6 <= 0)                                 # edge AC
        q = np.where(m[..., None], a + ac * w[..., None], q)
        m = (d6 >= 0) & (d5 <= d6)                                            # vertex C
        q = np.where(m[..., None], c, q)
        v = d1 / (d1 - d3)
        m = (vc <= 0) & (d1 >= 0) & (d3 <= 0)                                 # edge AB
        q = np.where(m[..., None], a + ab * v[..., None], q)
        m = (d3 >= 0) & (d4 <= d3)                                            # vertex B
        q = np.where(m[..., None], b, q)
        m = (d1 <= 0) & (d2 <= 0)                                             # vertex A
        q = np.where(m[..., None], a, q)
    return q


def cover(t: np.ndarray, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """Points on triangles t (m, 3, 3) such that every point of a triangle is within
    ``1.12 * spacing`` of one of its own points, and the triangle of each point.

    Rows parallel to the longest edge ab, at most ``spacing`` apart from ab to the apex c, each
    with points at most ``spacing`` apart. Every point of the triangle lies between two rows
    and (ab being longest, the angles at a and b are acute) projects onto the longer of the
    two, within spacing / 2 of one of its points: sqrt(1 + 1/4) * spacing at most. A sliver
    gets points along its length only, not a square grid over its bounding box."""
    e = np.linalg.norm(t - np.roll(t, -1, axis=1), axis=2)      # edge i: vertex i -> i + 1
    idx = (e.argmax(axis=1)[:, None] + np.arange(3)) % 3
    t = np.take_along_axis(t, idx[:, :, None], axis=1)           # longest edge 0 -> 1
    a, b, c = t[:, 0], t[:, 1], t[:, 2]
    length = np.linalg.norm(b - a, axis=1)
    height = np.linalg.norm(np.cross(b - a, c - a), axis=1) / np.maximum(length, 1e-300)
    rows = np.maximum(1, np.ceil(height / spacing)).astype(np.int64)
    tri = np.repeat(np.arange(len(t)), rows + 1)                 # one entry per row
    frac = (np.arange(len(tri)) - np.repeat(np.cumsum(rows + 1) - (rows + 1), rows + 1)) / rows[tri]
    count = np.ceil(length[tri] * (1 - frac) / spacing).astype(np.int64) + 1
    row = np.repeat(np.arange(len(tri)), count)
    step = np.arange(len(row)) - np.repeat(np.cumsum(count) - count, count)
    u = np.where(count[row] > 1, step / np.maximum(count[row] - 1, 1), 0.0)[:, None]
    f = frac[row][:, None]
    t_row = tri[row]
    start = a[t_row] + (c[t_row] - a[t_row]) * f
    end = b[t_row] + (c[t_row] - b[t_row]) * f
    return start + (end - start) * u, t_row


class Surface:
    """A closed triangle mesh to measure signed distances from (exact nearest triangle).

    Candidates for a point are the triangles of its k nearest cover points (:func:`cover`). A
    triangle none of whose cover points is among them is at least (distance of the k-th) −
    ``reach`` away; when that exceeds the nearest distance found, the answer is exact. Points
    where it does not are retried with more candidates, then with a ball query."""

    def __init__(self, v: np.ndarray, f: np.ndarray, spacing: float = SPACING):
        self.tris = v[f]
        self.normals, self.areas = triangle_normals(self.tris)
        keep = np.nonzero(self.areas > 1e-12)[0]   # no area: neighbours hold all its points
        pts, which = cover(self.tris[keep], spacing)
        self.sample_tri = keep[which]
        self.reach = float(np.sqrt(1.25) * spacing) + 1e-9
        self.tree = cKDTree(pts)

    def _best(self, p: np.ndarray, cand: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Nearest distance, its sign and triangle of points p (n, 3) over candidate triangles
        cand (n, k)."""
        t = self.tris[cand]
        q = closest_on_triangles(p[:, None], t[:, :, 0], t[:, :, 1], t[:, :, 2])
        dv = p[:, None] - q
        dist = np.linalg.norm(dv, axis=2)
        dmin = dist.min(axis=1)
        s = np.einsum("nki,nki->nk", dv, self.normals[cand])
        # among (near-)tied candidates the one whose normal sees the point most squarely: at a
        # convex edge both faces give s > 0, at a concave one both s < 0
        score = np.where(dist <= dmin[:, None] + EPS_TIE, np.abs(s), -1.0)
        j = score.argmax(axis=1)
        rows = np.arange(len(p))
        return dmin, np.sign(s[rows, j]), cand[rows, j]

    def signed_distance(self, p: np.ndarray, k: int = 32, pairs: int = 400_000):
        """Signed distances (n,) of points p (n, 3), + outside, the nearest triangles (n,) and
        how many points needed the wider searches."""
        out = np.empty(len(p))
        tri = np.empty(len(p), dtype=np.int64)
        best = np.full(len(p), np.inf)
        todo = np.arange(len(p))
        wider = []
        n_samples = self.tree.n
        for kk in (min(k, n_samples), min(16 * k, n_samples)):
            wider.append(len(todo))
            left = []
            for s0 in range(0, len(todo), max(1, pairs // kk)):
                block = todo[s0 : s0 + max(1, pairs // kk)]
                dk, idx = self.tree.query(p[block], k=kk, workers=-1)
                dk, idx = dk.reshape(len(block), -1), idx.reshape(len(block), -1)
                d, sg, t = self._best(p[block], self.sample_tri[idx])
                exact = (dk[:, -1] - self.reach > d) | (kk == n_samples)
                out[block[exact]], tri[block[exact]] = (sg * d)[exact], t[exact]
                best[block] = d
                left.append(block[~exact])
            todo = np.concatenate(left)
            if not len(todo):
                break
        wider.append(len(todo))
        for i in todo:
            cand = np.unique(self.sample_tri[self.tree.query_ball_point(p[i], best[i] + self.reach)])
            d, sg, t = self._best(p[i : i + 1], cand[None])
            out[i], tri[i] = sg[0] * d[0], t[0]
        return out, tri, wider[1:]

    def brute_force(self, p: np.ndarray, chunk: int = 100_000) -> np.ndarray:
        """Unsigned distances of points p to every triangle of the mesh (the self-check)."""
        out = np.full(len(p), np.inf)
        t = self.tris
        for i, pi in enumerate(p):
            for s0 in range(0, len(t), chunk):
                tc = t[s0 : s0 + chunk]
                q = closest_on_triangles(pi[None], tc[:, 0], tc[:, 1], tc[:, 2])
                out[i] = min(out[i], float(np.linalg.norm(pi - q, axis=1).min()))
        return out


def untouched(t: np.ndarray) -> np.ndarray:
    """Triangles (m, 3, 3) on the blank's own surface: its Ø60 side or its back face."""
    r = np.hypot(t[..., 0], t[..., 1])
    return np.all(r > 29.99, axis=1) | np.all(t[..., 2] < -99.999, axis=1)


def surface_points(v: np.ndarray, f: np.ndarray, n: int, rng) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Area-weighted random points on the mesh (the untouched blank surface at
    ``UNTOUCHED_WEIGHT`` of the density) and every vertex; the surface normal at each (a
    vertex takes the normal of its largest triangle), and the area each stands for (mm²; 0
    for the vertices), so that sum(weight * g) estimates the integral of g over the surface."""
    t = v[f]
    normals, areas = triangle_normals(t)
    factor = np.where(untouched(t), UNTOUCHED_WEIGHT, 1.0)
    w = areas * factor
    pick = rng.choice(len(f), size=n, p=w / w.sum())
    r1, r2 = rng.random(n), rng.random(n)
    s = np.sqrt(r1)
    pts = (t[pick, 0] * (1 - s)[:, None] + t[pick, 1] * (s * (1 - r2))[:, None]
           + t[pick, 2] * (s * r2)[:, None])
    order = np.argsort(areas)                               # larger triangles written last win
    vn = np.zeros((len(v), 3))
    for corner in range(3):
        vn[f[order, corner]] = normals[order]
    used = np.unique(f)
    weight = np.r_[w.sum() / n / factor[pick], np.zeros(len(used))]
    return np.concatenate([pts, v[used]]), np.concatenate([normals[pick], vn[used]]), weight


# --------------------------------------------------------------------------------------------
# regions

REGIONS = [
    ("end face", "z > -0.05 and nz > 0.99"),
    ("chamfer", "z > -3.5 and 0.05 <= nz <= 0.99"),
    ("flank z -35..-5", "-35 <= z <= -5, r < 28, |nz| < 0.05 (the profile-checked stations)"),
    ("flank rest", "-40.5 < z < -35 or -5 < z, r < 28, |nz| < 0.05"),
    ("shoulder", "-41 < z < -39 and nz > 0.95"),
    ("blank untouched", "r > 29.9 and |nz| < 0.05, or z < -99.95 and nz < -0.99"),
    ("other", "none of the above"),
]


def regions(p: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Region index (into REGIONS) of surface points p with normals n; first rule that holds."""
    z, nz = p[:, 2], n[:, 2]
    r = np.hypot(p[:, 0], p[:, 1])
    side = (r < 28) & (np.abs(nz) < 0.05)
    rules = [
        (z > -0.05) & (nz > 0.99),
        (z > -3.5) & (nz >= 0.05) & (nz <= 0.99),
        side & (z >= -35) & (z <= -5),
        side & (z > -40.5),
        (z > -41) & (z < -39) & (nz > 0.95),
        ((r > 29.9) & (np.abs(nz) < 0.05)) | ((z < -99.95) & (nz < -0.99)),
    ]
    out = np.full(len(p), len(REGIONS) - 1)
    for i in reversed(range(len(rules))):
        out[rules[i]] = i
    return out


def table(title: str, d: np.ndarray, reg: np.ndarray) -> None:
    print(f"\n{title}")
    print(f"  {'region':<18s} {'points':>8s} {'max +d':>9s} {'min d':>9s} {'RMS':>9s} {'p99.9 |d|':>9s}")
    for i, (name, _) in enumerate(REGIONS):
        x = d[reg == i]
        if not len(x):
            print(f"  {name:<18s} {0:8d}")
            continue
        print(f"  {name:<18s} {len(x):8d} {x.max():+9.5f} {x.min():+9.5f} {np.sqrt(np.mean(x * x)):9.5f} "
              f"{np.quantile(np.abs(x), 0.999):9.5f}")
    print(f"  {'all':<18s} {len(d):8d} {d.max():+9.5f} {d.min():+9.5f} {np.sqrt(np.mean(d * d)):9.5f} "
          f"{np.quantile(np.abs(d), 0.999):9.5f}")


def where_large(title: str, p: np.ndarray, d: np.ndarray, reg: np.ndarray, threshold: float) -> None:
    """Where |d| > threshold: per region and sign, count, z and r range, angles (5° bins)."""
    big = np.abs(d) > threshold
    print(f"\n{title}: points with |d| > {threshold} mm: {int(big.sum())}")
    for i, (name, _) in enumerate(REGIONS):
        for sgn, word in ((1, "material left"), (-1, "gouge")):
            m = big & (reg == i) & (np.sign(d) == sgn)
            if not m.any():
                continue
            q = p[m]
            r = np.hypot(q[:, 0], q[:, 1])
            ang = np.degrees(np.arctan2(q[:, 1], q[:, 0])) % 360
            bins = np.unique(np.floor(ang / 5) * 5).astype(int)
            spans = _spans(bins, 5)
            worst = np.argmax(np.abs(d[m]))
            print(f"  {name:<16s} {word:<13s} {int(m.sum()):7d} pts  z {q[:, 2].min():8.3f}.."
                  f"{q[:, 2].max():8.3f}  r {r.min():6.3f}..{r.max():6.3f}  angle {spans}  worst "
                  f"{d[m][worst]:+.5f} at (z {q[worst, 2]:.3f}, r {r[worst]:.3f}, {ang[worst]:.1f} deg)")


def _spans(bins: np.ndarray, width: int) -> str:
    """5°-bins as ranges, e.g. '0-10,120-125 deg'."""
    if not len(bins):
        return "-"
    out, lo, prev = [], bins[0], bins[0]
    for b in bins[1:]:
        if b != prev + width:
            out.append((lo, prev + width))
            lo = b
        prev = b
    out.append((lo, prev + width))
    if len(out) > 1 and out[0][0] == 0 and out[-1][1] == 360:
        out[0] = (out[-1][0] - 360, out[0][1])
        out.pop()
    text = ",".join(f"{a}-{b}" for a, b in out)
    return (text if len(text) < 60 else text[:57] + "...") + " deg"


# --------------------------------------------------------------------------------------------

def attribute(args, default: dict, fine: dict, ref: Surface, base: tuple, rng) -> None:
    """Which setting makes which error: the default with one setting changed to the
    reference's, each measured (default surface vs reference, 1/4 of the samples)."""
    variants = [("default", default, base),
                ("fans off", dict(default, fans=False), None),
                (f"chord {fine['chord']:g}", dict(default, chord=fine["chord"]), None),
                (f"sweep {fine['angle']:g}/{fine['step']:g}", dict(default, angle=fine["angle"],
                                                                  step=fine["step"]), None)]
    cols = []
    for label, settings, measured in variants:
        if measured is None:
            v, f, m, _ = part_mesh(settings, args.program, args.cache, "variant")
            p, n, _ = surface_points(v, f, args.samples // 4, rng)
            d = ref.signed_distance(p)[0]
            measured = (p, n, d)
            label += f" ({m['wall']:.0f} s)"
        cols.append((label, regions(measured[0], measured[1]), measured[2]))
    print("\nattribution: the default part with one setting taken from the reference, against the "
          "reference (default surface; max +d / min d per region)")
    print(f"  {'region':<18s}" + "".join(f" {label:>19s}" for label, _, _ in cols))
    for i, (name, _) in enumerate(REGIONS):
        cells = []
        for _, reg, d in cols:
            x = d[reg == i]
            cells.append(f"{x.max():+.4f}/{x.min():+.4f}" if len(x) else "-")
        print(f"  {name:<18s}" + "".join(f" {c:>19s}" for c in cells))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cache", type=Path, default=Path(tempfile.gettempdir()) / "vmach-stock-error",
                    help="directory for the simulated meshes (default: %(default)s)")
    ap.add_argument("--shared", type=Path,
                    default=Path(os.environ.get("VMACH_SHARED", ROOT.parent / "shared")),
                    help="the shared directory holding reference/ (default: $VMACH_SHARED or ../shared)")
    ap.add_argument("--program", help="NC program (default: the split reference, else POLY50.MPF)")
    ap.add_argument("--reference", type=Path, help="reference mesh (.npz written by this script)")
    ap.add_argument("--fine-chord", type=float, default=FINE_CHORD, help="reference tool chord, mm")
    ap.add_argument("--fine-angle", type=float, default=FINE_ANGLE, help="reference sweep angle, deg")
    ap.add_argument("--fine-step", type=float, default=FINE_STEP, help="reference sweep step, mm")
    ap.add_argument("--accuracy", choices=tuple(ACCURACY), default="standard",
                    help="the default part's preset (vmach verify --accuracy)")
    ap.add_argument("--samples", type=int, default=400_000, help="random points per surface")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--threshold", type=float, default=0.005, help="|d| reported by location, mm")
    ap.add_argument("--attribute", action="store_true",
                    help="also simulate the default with one setting at a time taken from the reference "
                         "(fans off; tool chord; sweep angle and step) and measure each against it")
    args = ap.parse_args(argv)

    from vmach.stock import engine
    from vmach.tol import tol

    bench.REFERENCE = args.shared / "reference" / "polygon_shaft_thesis.mpf"
    args.cache.mkdir(parents=True, exist_ok=True)
    print("vmach stock removal error: default tolerances against a fine reference (mm, mm³)")
    print(f"code {ROOT} ({_code_version()[0]}), program {_program_source(args.program)}, cache {args.cache}")

    default = {"chord": tol.tool_chord, "fans": True, "angle": tol.sweep_angle, "step": tol.sweep_step}
    if args.accuracy != "standard":     # (the standard settings keep their cache key)
        acc = ACCURACY[args.accuracy]
        default.update(chord=acc.tool_chord, cusp=acc.sweep_cusp)
        if acc.rim_arcs:
            default.update(arcs=True)
    fine = {"chord": args.fine_chord, "fans": False, "angle": args.fine_angle, "step": args.fine_step}
    vd, fd, md, file_d = part_mesh(default, args.program, args.cache, "default")
    if args.reference:
        vr, fr, mr = load_part(args.reference)
        file_r = args.reference
    else:
        vr, fr, mr, file_r = part_mesh(fine, args.program, args.cache, "reference")
    for label, m, file in (("default", md, file_d), ("reference", mr, file_r)):
        fan = f", {m['fans_made']} fans (overcut <= {m['fan_overcut']:.4f})" if m["fans"] else ""
        cusp = m.get("cusp", tol.sweep_cusp)
        print(f"  {label:<9s}: tool chord {m['chord']:g} mm, side cusps {cusp:g} mm, "
              f"sweep angle {m['angle']:g} deg, step "
              f"{m['step']:g} mm, fans {'on' if m['fans'] else 'off'}; blank {m['spec']} to chord "
              f"{m['blank_chord']:g} mm; {m['program']} {m['moves']} moves")
        print(f"  {'':<9s}  wall {m['wall']:.1f} s, {m['triangles']} triangles, {m['cutters']} cutters, "
              f"{m['samples']} poses{fan}, sampling bound {m['bound']:.5f} mm, volume {m['volume']:.3f}, "
              f"peak {m['peak_mb']:.0f} MB")
        print(f"  {'':<9s}  {file}")
    if md["blank_chord"] != mr["blank_chord"] or md["spec"] != mr["spec"]:
        print("  WARNING: the two parts were cut from different blanks")

    t0 = time.perf_counter()
    a = engine.from_mesh(vd, fd, "default part", double=True)
    b = engine.from_mesh(vr, fr, "reference part", double=True)
    extra, missing = engine.volume(engine.subtract(a, [b])), engine.volume(engine.subtract(b, [a]))
    print(f"\nvolumes: default {engine.volume(a):.4f}, reference {engine.volume(b):.4f}; "
          f"default - reference {extra:.5f} (material left), reference - default {missing:.5f} (gouged)")

    rng = np.random.default_rng(args.seed)
    ref, dflt = Surface(vr, fr), Surface(vd, fd)
    print("\nregions (z: work frame, end face at 0, material toward -z; r from the Z axis; nz: the "
          "surface normal's z; first rule that holds):")
    for name, rule in REGIONS:
        print(f"  {name:<18s} {rule}")
    pd, nd, wd = surface_points(vd, fd, args.samples, rng)
    pr, nr, wr = surface_points(vr, fr, args.samples, rng)
    d_fwd, _, wide_f = ref.signed_distance(pd)
    d_rev, _, wide_r = dflt.signed_distance(pr)
    d_rev = -d_rev        # a reference point outside the default part: the default lacks material
    reg_d, reg_r = regions(pd, nd), regions(pr, nr)
    print(f"\npoints: {args.samples} area-weighted per surface (the untouched blank at "
          f"{UNTOUCHED_WEIGHT:g} of the density) + vertices ({len(pd)} and {len(pr)}); cover points "
          f"{SPACING} mm apart (default {dflt.tree.n}, reference {ref.tree.n}); points needing the "
          f"wider searches: {wide_f} and {wide_r}")
    table("default part's surface vs the reference surface (d > 0: material left, d < 0: gouge)",
          d_fwd, reg_d)
    table("reference surface vs the default part's surface (same sign: d > 0 material left, "
          "d < 0 gouge)", d_rev, reg_r)
    where_large("default surface", pd, d_fwd, reg_d, args.threshold)
    where_large("reference surface", pr, d_rev, reg_r, args.threshold)
    print(f"\nsign check: integral of d over the default surface {np.sum(wd * d_fwd):+.3f}, over the "
          f"reference surface {np.sum(wr * d_rev):+.3f} (volume default - reference: {extra - missing:+.3f})")
    if args.attribute:
        attribute(args, default, fine, ref, (pd, nd, d_fwd), rng)

    # self-check: brute force over every triangle at random points and the largest |d|
    pick = np.r_[rng.choice(len(pd), 150, replace=False), np.argsort(-np.abs(d_fwd))[:50]]
    err_f = np.abs(ref.brute_force(pd[pick]) - np.abs(d_fwd[pick])).max()
    pick_r = np.r_[rng.choice(len(pr), 150, replace=False), np.argsort(-np.abs(d_rev))[:50]]
    err_r = np.abs(dflt.brute_force(pr[pick_r]) - np.abs(d_rev[pick_r])).max()
    print(f"\nself-check against brute force (200 points each way): largest difference "
          f"{max(err_f, err_r):.2e} mm")
    print(f"measurement {time.perf_counter() - t0:.1f} s")
    return 0 if max(err_f, err_r) < 1e-6 else 1


if __name__ == "__main__":
    raise SystemExit(main())
