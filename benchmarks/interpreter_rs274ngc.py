"""Speed of the RS274/NGC interpreter on a program expanding to 40,000 moves.

Two forms of the same toolpath: a flat file of 40,000 G1 blocks, and a short program whose
``while`` loop computes them. On the same file in the same run, vmach is timed

- ``vmach run``: the canonical commands (``interpreters.rs274ngc.run``, what ``vmach run``
  and the checks use);
- ``vmach trace``: the rs274 trace (``FORMATS["rs274"]``, what ``vmach run --format rs274``
  prints), which does not build canonical commands;
- ``trace+cmds``: both in one run (``rs274_trace(..., commands=True)``);

and, when LinuxCNC's ``rs274`` is installed, ``rs274 -g FILE`` (its own HOME, output to
/dev/null). Figures are CPU seconds (user + system), best of ``--repeat`` runs.

Fairness: every column interprets the same file from its text. vmach runs in this process,
so Python's start-up and imports (about 0.1 s for the interpreter package, 0.3 s for the
``vmach`` command) are not counted and its trace stays in memory; ``rs274`` runs as a
subprocess, so its process start (about 0.02 s) is counted and its trace is written (to
/dev/null). The figures compare interpreting, not whole commands.

    python benchmarks/interpreter_rs274ngc.py [--moves 40000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from interpreters.rs274ngc import FORMATS, rs274_trace, run  # noqa: E402


def flat_program(moves: int) -> str:
    lines = ["G21 G90 G17 F500"]
    for i in range(moves):
        lines.append(f"G1 X{i % 100 + 0.5:g} Y{(i // 100) % 100} Z-1")
    lines.append("M2")
    return "\n".join(lines) + "\n"


def loop_program(moves: int) -> str:
    return f"""G21 G90 G17 F500
#1 = 0
o100 while [#1 LT {moves}]
G1 X[#1 MOD 100 + 0.5] Y[FIX[#1/100] MOD 100] Z-1
#1 = [#1 + 1]
o100 endwhile
M2
"""


def best(fn, repeat: int) -> float:
    """Least CPU time (user + system, this process and its children) over ``repeat`` runs:
    on a shared machine CPU time is steadier than wall time."""
    times = []
    for _ in range(repeat):
        t = _cpu()
        fn()
        times.append(_cpu() - t)
    return min(times)


def _cpu() -> float:
    me = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def time_rs274(path: Path, repeat: int) -> float:
    home = tempfile.mkdtemp(prefix="rs274-home-")
    env = {**os.environ, "HOME": home}

    def once():
        with open(os.devnull, "w") as sink:
            subprocess.run(["rs274", "-g", path.name], cwd=path.parent, env=env,
                           stdout=sink, stderr=subprocess.DEVNULL, check=False)

    try:
        return best(once, repeat)
    finally:
        shutil.rmtree(home, ignore_errors=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--moves", type=int, default=40_000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    have_rs274 = shutil.which("rs274") is not None
    print(f"{args.moves} moves, best of {args.repeat}")
    print(f"{'program':<8} {'vmach run':>10} {'vmach trace':>12} {'trace+cmds':>11} {'rs274 -g':>10}  moves")
    with tempfile.TemporaryDirectory() as tmp:
        for name, text in (("flat", flat_program(args.moves)), ("loop", loop_program(args.moves))):
            path = Path(tmp) / f"{name}.ngc"
            path.write_text(text, encoding="utf-8")
            result = run(path)
            assert result.completed, result.findings
            n = sum(1 for c in result.commands if c.kind == "feed")
            t_run = best(lambda p=path: run(p), args.repeat)
            t_trace = best(lambda p=path: FORMATS["rs274"](p, None, None, {}), args.repeat)
            t_both = best(lambda p=path: rs274_trace(p, commands=True), args.repeat)
            t_ref = f"{time_rs274(path, args.repeat):9.3f}s" if have_rs274 else "   (absent)"
            print(f"{name:<8} {t_run:9.3f}s {t_trace:11.3f}s {t_both:10.3f}s {t_ref:>10}  {n}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
