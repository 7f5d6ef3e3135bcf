"""A batch's summary: ``summary.json`` (the same wherever and on how many workers the batch
ran: no times, no absolute paths) and ``index.html``, a table of the cases with a link to each
case's report.html; ``timings.json`` holds what differs from run to run."""

from __future__ import annotations

import html
import json
from pathlib import Path

from vmach.batch.worker import VERDICTS
from vmach.output import atomic_writer

COLOURS = {"pass": "#2e7d32", "warnings": "#b26a00", "fail": "#c62828", "error": "#c62828",
           "crashed": "#6a1b9a"}


def summary_data(batch: dict, records: list[dict]) -> dict:
    """The summary: the batch's description, counts by verdict, one row per case."""
    counts = {v: sum(r["verdict"] == v for r in records) for v in VERDICTS}
    rows = []
    for r in records:
        row = {k: v for k, v in r.items() if k not in ("key", "seconds")}
        row["report"] = f"{r['name']}/report.html" if r["verdict"] in ("pass", "warnings", "fail") else None
        rows.append(row)
    return {"batch": batch, "cases": len(records), "verdicts": counts, "results": rows}


def write_summary(out: Path, batch: dict, records: list[dict], timings: dict) -> dict:
    data = summary_data(batch, records)
    with atomic_writer(out / "summary.json") as fh:
        json.dump(data, fh, indent=2, ensure_ascii=False)
        fh.write("\n")
    with atomic_writer(out / "timings.json") as fh:
        json.dump(timings, fh, indent=2)
        fh.write("\n")
    with atomic_writer(out / "index.html") as fh:
        fh.write(index_html(data, timings))
    return data


def _e(x) -> str:
    return html.escape("" if x is None else str(x), quote=True)


def _row(r: dict, seconds) -> str:
    worst = r.get("worst")
    if worst:
        w = f"{_e(worst['severity'])} {_e(worst['kind'])} at {_e(worst['file'])}:{_e(worst['line'])}"
        w = f"<span title='{_e(worst['message'])}'>{w}</span>"
    else:
        w = "; ".join(_e(d) for d in r.get("diagnostics", [])) or "none"
    prof = r.get("profile")
    dev = (f"{prof['max_abs_deviation_mm'] * 1000:.1f} µm {'PASS' if prof['pass'] else 'FAIL'}"
           if prof and prof.get("max_abs_deviation_mm") is not None else "not checked")
    ct = r.get("cycle_time_s")
    ct = f"{ct / 60:.1f} min" if isinstance(ct, int | float) else "-"
    thumb = (f"<img src='{_e(r['name'])}/{_e(r['thumbnail'])}' alt='' loading='lazy'>"
             if r.get("thumbnail") else "")
    link = f"<a href='{_e(r['report'])}'>report</a>" if r.get("report") else "-"
    sec = f"{seconds:.1f} s" if isinstance(seconds, int | float) else "-"
    colour = COLOURS.get(r["verdict"], "black")
    return (f"<tr><td>{_e(r.get('label') or r['name'])}</td>"
            f"<td style='color:{colour};font-weight:bold'>{_e(r['verdict'])}</td>"
            f"<td>{w}</td><td>{ct}</td><td>{dev}</td><td>{thumb}</td><td>{link}</td><td>{sec}</td></tr>")


def index_html(data: dict, timings: dict) -> str:
    """The batch's page: counts by verdict and the table of cases."""
    secs = timings.get("cases", {})
    counts = ", ".join(f"{n} {v}" for v, n in data["verdicts"].items() if n)
    rows = "\n".join(_row(r, secs.get(r["name"])) for r in data["results"])
    title = _e(data["batch"].get("title", "vmach batch"))
    return (
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
        f"<title>{title}</title><style>"
        "body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse}"
        "td,th{border:1px solid #ccc;padding:4px 8px;text-align:left;vertical-align:middle}"
        "img{height:72px}</style></head><body>"
        f"<h1>{title}</h1><p>{data['cases']} case(s): {_e(counts)}</p>"
        "<table><thead><tr><th>case</th><th>verdict</th><th>worst finding</th><th>cycle time</th>"
        "<th>profile deviation</th><th>picture</th><th>report</th><th>verify time</th></tr></thead>"
        f"<tbody>\n{rows}\n</tbody></table></body></html>\n"
    )
