"""Start-up of the command line: wall time of ``vmach --version``, ``vmach --help``,
``vmach machines`` and ``vmach check`` on the POLY50 fixture, for this tree and for an older
commit (default: the one before the command modules were imported lazily), measured in the
same run, interleaved; then the import cost of each heavy library on its own.

    python benchmarks/startup.py [--before REV] [--runs N]

Each figure is the best of N fresh interpreters (``python -c`` with the tree first on
``sys.path``, so that the editable install's own tree does not answer for the old one).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

COMMANDS = {
    "vmach --version": ["--version"],
    "vmach --help": ["--help"],
    "vmach machines": ["machines"],
    "vmach check POLY50.MPF": ["check", str(ROOT / "fixtures/polygon_shaft/POLY50.MPF")],
}
LIBRARIES = ("numpy", "scipy", "shapely", "trimesh", "manifold3d", "pyvista", "vtk", "PIL", "tqdm")

RUN = (
    "import sys; sys.path.insert(0, {tree!r}); from vmach.cli import main\n"
    "try:\n    main({args!r})\nexcept SystemExit:\n    pass\n"
)


def _seconds(code: str) -> float:
    t = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   cwd=ROOT, check=False)
    return time.perf_counter() - t


def _before(rev: str | None) -> str:
    """The commit to compare with: ``rev``, or the parent of the first commit that made the
    command modules lazy (``HELPS`` in vmach/cli.py)."""
    if rev:
        return rev
    first = subprocess.run(["git", "log", "--format=%H", "-S", "HELPS: dict", "--", "vmach/cli.py"],
                           cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    return f"{first[-1]}^" if first else "HEAD"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", help="older commit to compare with")
    ap.add_argument("--runs", type=int, default=7)
    args = ap.parse_args()
    rev = _before(args.before)
    with tempfile.TemporaryDirectory() as tmp:
        old = Path(tmp) / "old"
        old.mkdir()
        archive = subprocess.run(["git", "archive", rev, "vmach", "interpreters", "models"], cwd=ROOT,
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(old)], input=archive, check=True)
        commit = subprocess.run(["git", "rev-parse", "--short", rev], cwd=ROOT, capture_output=True,
                                text=True, check=True).stdout.strip()
        trees = {"before": str(old), "now": str(ROOT)}
        missing_before = [c for c, argv in COMMANDS.items()
                          if not (old / "vmach" / "commands" / f"{argv[0]}.py").is_file()
                          and not argv[0].startswith("-")]
        best = {(c, t): float("inf") for c in COMMANDS for t in trees}
        for _ in range(args.runs):          # interleaved: the machine's load falls on both alike
            for c, argv in COMMANDS.items():
                for t, tree in trees.items():
                    best[c, t] = min(best[c, t], _seconds(RUN.format(tree=tree, args=argv)))
    print(f"start-up, best of {args.runs} fresh interpreters (python {sys.version.split()[0]})")
    print(f"{'command':<26} {'before (' + commit + ')':>16} {'now':>10} {'ratio':>7}")
    for c in COMMANDS:
        b, n = best[c, "before"], best[c, "now"]
        print(f"{c:<26} {b:>14.3f} s {n:>8.3f} s {n / b:>7.2f}")
    for c in missing_before:
        print(f"  ({c}: no such command before; its figure there is the usage error's)")
    bare = min(_seconds("pass") for _ in range(args.runs))
    print(f"\nimport cost of each library alone, best of {args.runs} "
          f"(bare interpreter {bare:.3f} s subtracted)")
    for lib in LIBRARIES:
        t = min(_seconds(f"import {lib}") for _ in range(args.runs)) - bare
        print(f"  {lib:<12} {t:7.3f} s")


if __name__ == "__main__":
    main()
