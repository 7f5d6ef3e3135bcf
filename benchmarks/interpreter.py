"""Interpreter speed: blocks/s for the polygon-shaft program and a 40,000-iteration WHILE loop,
with the PyPI package nc-gcode-interpreter timed on the same work in the same run when it is
importable. Prints a table; no assertion (figures go to README's Performance section).

    python benchmarks/interpreter.py [--repeat 5]

nc-gcode-interpreter cannot parse R parameters (``R1=0``), arithmetic functions (``SIN``),
labels with GOTO, or ``C1=ACP(...)``; it gets a copy of each program with R parameters renamed
to DEF variables. Where the copy still holds words it rejects, the table says so instead of a
time: those programs have no equivalent in its language.
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from interpreters import sinumerik  # noqa: E402
from vmach.canon import MOTIONS, RunOptions  # noqa: E402
from vmach.machine.control import load_control  # noqa: E402

WHILE_LOOP = """DEF INT CNT=0
WHILE CNT<40000
G1 X=CNT*0.01 Y=CNT F100
CNT=CNT+1
ENDWHILE
M30
"""


def best_of(fn, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def polygon_program(directory: Path) -> tuple[Path, str]:
    from catalog import REFERENCE, split_reference

    if REFERENCE.is_file():
        return split_reference(directory, REFERENCE), "reference listing, split (L_POLY)"
    return ROOT / "fixtures" / "polygon_shaft" / "POLY50.MPF", "fixture POLY50 (reference absent)"


def for_ncgi(text: str) -> str:
    """The copy nc-gcode-interpreter gets: R parameters as DEF REAL variables, spindle-2 words as
    plain S/M words, ACP(...) as a plain value, maker's cycles and SETMS dropped."""
    text = re.sub(r"\bS2=", "S", text)
    text = re.sub(r"\bM2=(\d)", r"M\1", text)
    text = re.sub(r"\bSETMS\(\d\)", "", text)
    text = re.sub(r"\bC_AXIS_OF+\b|\bC_AXIS_ON\b|\bG971\b", "", text)
    text = re.sub(r"=ACP\(([^()]*)\)", r"=\1", text)
    text = re.sub(r"=\((-?[\d.]+)\)", r"=\1", text)
    used = sorted({int(m) for m in re.findall(r"\bR(\d+)\b", text)})
    body = re.sub(r"\bR(\d+)\b", r"RP\1", text)
    decl = f"DEF REAL {', '.join(f'RP{i}' for i in used)}\n" if used else ""
    return decl + body


def run_ncgi(text: str, repeat: int) -> tuple[float | None, str]:
    try:
        import nc_gcode_interpreter as ncgi
    except ImportError:
        return None, "not installed"
    try:
        ncgi.nc_to_dataframe(text, iteration_limit=10**8, extra_axes=["C1"])
    except Exception as exc:  # the package raises ValueError with a parse dump
        msg = str(exc)
        m = re.search(r'line: \\"([^"\\]*)', msg) or re.search(r'block: \\"([^"\\]*)', msg)
        return None, f"rejects the program ({'at: ' + m.group(1) if m else msg[:60]})"
    t = best_of(lambda: ncgi.nc_to_dataframe(text, iteration_limit=10**8, extra_axes=["C1"]), repeat)
    return t, "ok"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    turn = load_control(ROOT / "models" / "turnmill.toml")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        loop = d / "LOOP.MPF"
        loop.write_text(WHILE_LOOP)
        poly, label = polygon_program(d)
        cases = [("WHILE loop, 40,000 iterations", loop, None, WHILE_LOOP),
                 (f"polygon shaft ({label})", poly, turn, None)]
        for name, path, control, ncgi_text in cases:
            kwargs = {"control": control} if control else {}
            result = sinumerik.run(path, options=RunOptions(), **kwargs)
            assert result.completed, [f.render() for f in result.findings]
            t = best_of(lambda p=path, k=kwargs: sinumerik.run(p, options=RunOptions(), **k), args.repeat)
            moves = sum(isinstance(c, MOTIONS) for c in result.commands)
            if ncgi_text is None:
                files = sorted(path.parent.glob("*.[MS]PF"))
                ncgi_text = "\n".join(f.read_text(encoding="utf-8") for f in files)
            nt, note = run_ncgi(for_ncgi(ncgi_text), args.repeat)
            rows.append((name, result.blocks, moves, t, nt, note))
    print(f"{'program':<46} {'blocks':>8} {'moves':>7} {'vmach s':>8} {'blocks/s':>10} "
          f"{'nc-gcode-interp. s':>19}  note")
    for name, blocks, moves, t, nt, note in rows:
        other = f"{nt:19.3f}" if nt is not None else f"{'n/a':>19}"
        print(f"{name:<46} {blocks:8d} {moves:7d} {t:8.3f} {blocks / t:10,.0f} {other}  {note}")
    print(f"(best of {args.repeat}; vmach = parse + check structure + run to canonical commands)")


if __name__ == "__main__":
    main()
