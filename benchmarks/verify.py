"""End-to-end `vmach verify` figures: wall time per stage and peak memory, for the reference
polygon-shaft program split as intended (../shared/reference) — or our fixture POLY50 when the
reference is absent — on models/turnmill.toml with the fixture tools, a Ø60 blank and the P3G-50
profile check between z = -35 and -5.

    python benchmarks/verify.py [--program FILE] [--no-images] [--accuracy fine]
                                [--mesh-blank TRIANGLES]

``--mesh-blank N`` reads the same Ø60 × 100 blank from an STL of about N triangles (a finely
tessellated cylinder, as a scanned or CAD-exported blank would be) instead of the
``cylinder:`` spec.

Each run happens in a child process so that its peak resident memory (ru_maxrss) is its own.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import resource
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from vmach.tol import ACCURACY  # noqa: E402

SETUP = """machine = "turnmill"
tools = "{tools}"
stock = "cylinder:d=60,l=100"
profile = "P3G:50"
profile_z = "-35:-5"
"""


def _program(directory: Path, given: str | None) -> Path:
    from catalog import POLYGON_TOOLS, REFERENCE, split_reference

    if given:
        return Path(given)
    if REFERENCE.is_file():
        main = split_reference(directory, REFERENCE)
        (directory / "vmach.toml").write_text(SETUP.format(tools=POLYGON_TOOLS))
        return main
    return ROOT / "fixtures" / "polygon_shaft" / "POLY50.MPF"


def _mesh_blank(directory: Path, triangles: int) -> str:
    """A ``mesh:`` stock spec: the Ø60 × 100 blank (end face at z = 0) as an STL of about
    ``triangles`` triangles."""
    import trimesh

    blank = trimesh.creation.cylinder(radius=30.0, height=100.0, sections=max(8, triangles // 4))
    blank.apply_translation([0.0, 0.0, -50.0])
    path = directory / "blank.stl"
    blank.export(path)
    return f"mesh:{path}"


def _child(program: str, out: str, images: bool, accuracy: str | None, stock: str | None, queue) -> None:
    from vmach.verify import VerifyOptions, verify

    t = time.perf_counter()
    report = verify(program, VerifyOptions(out=Path(out), images=images, accuracy=accuracy, stock=stock))
    wall = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    queue.put(
        (
            wall,
            peak,
            dict(report.timings),
            len(report.table),
            report.errors,
            report.profile,
            report.cycle["total_s"] if report.cycle else None,
        )
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--program")
    ap.add_argument("--no-images", action="store_true")
    ap.add_argument("--accuracy", choices=tuple(ACCURACY), help="as vmach verify --accuracy")
    ap.add_argument("--mesh-blank", type=int, metavar="TRIANGLES",
                    help="the blank as an STL of about this many triangles")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        program = _program(Path(tmp), args.program)
        stock = _mesh_blank(Path(tmp), args.mesh_blank) if args.mesh_blank else None
        q: mp.Queue = mp.get_context("spawn").Queue()
        p = mp.get_context("spawn").Process(
            target=_child, args=(str(program), tmp + "/out", not args.no_images, args.accuracy, stock, q)
        )
        p.start()
        wall, peak, timings, moves, errors, profile, cycle = q.get()
        p.join()
    print(
        f"vmach verify {program.name} ({args.accuracy or 'standard'} accuracy"
        f"{f', blank of {args.mesh_blank} triangles' if args.mesh_blank else ''}): {moves} moves, "
        f"{errors} error(s), wall {wall:.1f} s, "
        f"peak memory {peak:.0f} MB"
    )
    for stage, seconds in timings.items():
        print(f"  {stage:<12s} {seconds:8.2f} s")
    if profile:
        print(
            f"  profile {profile['type']}-{profile['d1']:g}: "
            f"max |dev| {profile['max_abs_deviation_mm']:.4f} mm, "
            f"band {profile['tolerance_mm']}, pass={profile['pass']}"
        )
    if cycle:
        print(f"  cycle time {cycle:.1f} s ({int(cycle // 60)} min {cycle % 60:.0f} s)")


if __name__ == "__main__":
    main()
