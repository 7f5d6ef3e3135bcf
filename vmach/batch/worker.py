"""What a Dask worker runs for one case: ``vmach verify`` into the case's directory.

A plain function of strings and a dict (picklable, importable by name on any worker that has
vmach installed); it never raises for the case's own trouble: an unreadable program, a
program error or a crash is the case's result (``verdict`` ``error`` or ``crashed``).
"""

from __future__ import annotations

import contextlib
import io
import json
import time
import traceback
from pathlib import Path

#: verdicts, best first (the summary sorts and colours by them)
VERDICTS = ("pass", "warnings", "fail", "error", "crashed")


def verify_case(program: str, out: str, options: dict) -> dict:
    """Verify ``program`` into the directory ``out``; the case's result (see :func:`result_of`).

    options: ``images`` (bool), ``machine``, ``accuracy``, ``extra`` (a list of further
    ``vmach verify`` arguments)."""
    import argparse

    from vmach.commands import verify as command
    from vmach.errors import VmachError

    t0 = time.perf_counter()
    argv = [program, "--out", out, "--quiet", "--format", "json"]
    if not options.get("images", True):
        argv.append("--no-images")
    for key in ("machine", "accuracy"):
        if options.get(key):
            argv += [f"--{key}", str(options[key])]
    argv += list(options.get("extra", ()))
    parser = argparse.ArgumentParser(prog="vmach verify")
    command.add_arguments(parser)
    sink = io.StringIO()
    try:
        args = parser.parse_args(argv)
        with contextlib.redirect_stdout(sink):
            command.run(args)
        res = result_of(Path(out))
    except VmachError as exc:
        res = {"verdict": "error", "diagnostics": [f.render() for f in exc.findings()]}
    except SystemExit as exc:          # argparse's own usage errors
        res = {"verdict": "error", "diagnostics": [f"usage error (exit {exc.code})"]}
    except Exception as exc:  # noqa: BLE001 - a crash is this case's result, not the batch's
        res = {"verdict": "crashed", "diagnostics": [f"{type(exc).__name__}: {exc}"],
               "traceback": traceback.format_exc(limit=8)}
    res["seconds"] = round(time.perf_counter() - t0, 3)
    return res


def result_of(out: Path) -> dict:
    """The summary row of the report in ``out``: verdict, counts, worst finding, cycle time,
    profile deviation, what could not be checked, the thumbnail. Paths are the case
    directory's own names, so the row is the same wherever the batch ran."""
    data = json.loads((out / "report.json").read_text(encoding="utf-8"))
    s = data["summary"]
    findings = data.get("findings") or []
    order = {"error": 0, "warning": 1, "info": 2}
    worst = min(findings, key=lambda f: (order.get(f.get("severity"), 3), f.get("line") or 0), default=None)
    prof = data.get("profile")
    if s["errors"] or (prof is not None and not prof.get("pass")):
        verdict = "fail"
    elif s["warnings"]:
        verdict = "warnings"
    else:
        verdict = "pass"
    images = data.get("images") or {}
    thumb = next((images[k] for k in ("part_deviation", "toolpath") if k in images), None)
    return {
        "verdict": verdict,
        "errors": s["errors"],
        "warnings": s["warnings"],
        "partial": bool(data.get("partial")),
        "skipped": data.get("skipped") or {},
        "worst": None if worst is None else {
            "severity": worst.get("severity"), "kind": worst.get("kind"),
            "file": Path(str(worst.get("file") or "")).name, "line": worst.get("line"),
            "message": worst.get("message")},
        "kinds": sorted({f.get("kind") for f in findings}),
        "cycle_time_s": data.get("cycle_time_s"),
        "profile": None if prof is None else {
            "type": prof.get("type"), "d1": prof.get("d1"),
            "max_abs_deviation_mm": prof.get("max_abs_deviation_mm"),
            "tolerance_mm": prof.get("tolerance_mm"), "pass": prof.get("pass")},
        "thumbnail": thumb,
    }
