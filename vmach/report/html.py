"""``report.html``: the verify report as one self-contained page (no network reference: it opens
offline from a CI artifact).

It shows whatever ``report.json`` carries — the summary, stages that did not run (``skipped``)
and partial runs, every finding in a sortable, filterable table (kind, severity, file:line, the
source line, the numbers), every picture (embedded as PNG data), the whole JSON — and an
interactive 3-D view of the cut part coloured by deviation, with the tool path and the
findings' places (three.js, bundled from ``vendor/``; ``docs/report.md`` says why).
"""

from __future__ import annotations

import base64
import html
import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from vmach.findings import SEVERITIES
from vmach.output import atomic_writer

_HERE = Path(__file__).resolve().parent
ASSETS = _HERE / "assets"
VENDOR = _HERE / "vendor"

#: the keys of a finding that have their own column
_COLUMNS = ("severity", "kind", "file", "line", "column", "message", "move_index")


def _e(x: Any) -> str:
    return html.escape("" if x is None else str(x), quote=True)


def _script_json(data: Any) -> str:
    """JSON safe inside a <script> element."""
    return json.dumps(data, ensure_ascii=False).replace("</", "<\\/")


def _data_url(path: Path, mime: str) -> str:
    return f"data:{mime};base64,{base64.b64encode(path.read_bytes()).decode('ascii')}"


def verdict(data: dict) -> tuple[str, str]:
    """(css class, word): FAIL with an error; INCOMPLETE when the program did not finish or a
    stage was skipped; else PASS."""
    if (data.get("summary") or {}).get("errors"):
        return "fail", "FAIL"
    if (data.get("program") or {}).get("completed") is False or data.get("partial") or data.get("skipped"):
        return "partial", "INCOMPLETE"
    return "pass", "PASS"


def _skipped(items: Any) -> list[str]:
    """The skipped stages, whatever shape ``report.json`` gives them: a mapping stage -> reason,
    or a list of strings or of objects (``stage``/``name`` and ``reason``)."""
    if not items:
        return []
    if isinstance(items, dict):
        return [f"{k}: {v if isinstance(v, str) else json.dumps(v)}" for k, v in items.items()]
    out = []
    for it in items if isinstance(items, list) else [items]:
        if isinstance(it, dict):
            name = it.get("stage") or it.get("name") or ""
            rest = {k: v for k, v in it.items() if k not in ("stage", "name")}
            reason = rest.pop("reason", "")
            extra = f" ({json.dumps(rest, ensure_ascii=False)})" if rest else ""
            out.append(f"{name}: {reason}{extra}".strip(": "))
        else:
            out.append(str(it))
    return out


def _summary(data: dict) -> str:
    prog = data.get("program") or {}
    rows: list[tuple[str, Any]] = [
        ("program", prog.get("path")),
        ("completed", {True: "yes", False: "no — stopped early", None: "not run"}[prog.get("completed")]),
        ("blocks / moves", f"{prog.get('blocks')} / {prog.get('moves')}"),
        ("machine", (data.get("machine") or {}).get("name")),
        ("tools", data.get("tools")),
        ("stock", data.get("stock")),
    ]
    s = data.get("summary") or {}
    rows.append(("findings", f"{s.get('errors', 0)} error(s), {s.get('warnings', 0)} warning(s), "
                             f"{s.get('infos', 0)} info"))
    if data.get("cycle_time_s") is not None:
        rows.append(("cycle time", f"{data['cycle_time_s']:.1f} s"))
    sim = data.get("simulation")
    if sim:
        b = sim.get("error_bounds_mm", {})
        bounds = ", ".join(f"{k} {v:g} mm" for k, v in b.items())
        rows.append(("stock simulation", f"{sim.get('accuracy')} accuracy, {sim.get('cutters')} cutters; "
                     f"error {bounds}"))
    p = data.get("profile")
    if p:
        dev = p.get("max_abs_deviation_mm")           # None: no station on the part (a finding says so)
        band = [round(t * 1000, 1) for t in p.get("tolerance_mm") or [] if t is not None]
        verdict = "PASS" if p.get("pass") else ("n/a" if p.get("pass") is None else "FAIL")
        rows.append(("profile", f"{p.get('type')} d1={p.get('d1')}: max |deviation| "
                     f"{'n/a' if dev is None else f'{dev * 1000:.1f} µm'}, band {band} µm: {verdict}"))
    t = data.get("timings_s") or {}
    if "total" in t:
        rows.append(("run time", f"{t['total']:.2f} s (" + ", ".join(
            f"{k} {v:.2f}" for k, v in t.items() if k != "total") + ")"))
    return "<dl class='summary'>" + "".join(f"<dt>{_e(k)}</dt><dd>{_e(v)}</dd>" for k, v in rows) + "</dl>"


def _numbers(f: dict) -> str:
    parts = []
    for k, v in f.items():
        if k in _COLUMNS:
            continue
        if isinstance(v, float):
            v = f"{v + 0.0:.6g}"                      # + 0.0: no "-0"
        elif isinstance(v, list) and all(isinstance(x, float | int) for x in v):
            v = "[" + ", ".join(f"{x + 0.0:.6g}" for x in v) + "]"
        elif isinstance(v, list | dict):
            v = json.dumps(v, ensure_ascii=False)
        parts.append(f"{k}={v}")
    return "<br>".join(_e(p) for p in parts)


def _findings(findings: Sequence[dict], sources: Sequence[str | None]) -> str:
    kinds = sorted({f.get("kind", "") for f in findings})
    head = (
        "<div class='filters'><input id='filter-text' type='search' placeholder='filter…'>"
        "<select id='filter-severity'><option value=''>every severity</option>"
        + "".join(f"<option>{s}</option>" for s in SEVERITIES)
        + "</select><select id='filter-kind'><option value=''>every kind</option>"
        + "".join(f"<option>{_e(k)}</option>" for k in kinds)
        + "</select><span id='filter-count'></span></div>"
    )
    rows = []
    for i, f in enumerate(findings):
        src = sources[i] if i < len(sources) else None
        file, line = f.get("file") or "", f.get("line")
        where = f"{Path(file).name}:{line}" if file and line else file
        sev = f.get("severity", "")
        rank = SEVERITIES.index(sev) if sev in SEVERITIES else len(SEVERITIES)
        rows.append(
            f"<tr data-index='{i}' data-severity='{_e(sev)}' data-kind='{_e(f.get('kind'))}'>"
            f"<td class='sev-{_e(sev)}' data-sort='{rank}'>{_e(sev)}</td>"
            f"<td><code>{_e(f.get('kind'))}</code></td>"
            f"<td data-sort='{_e(file)}:{int(line or 0):09d}' title='{_e(file)}'>{_e(where)}</td>"
            f"<td class='src'><code>{_e(src)}</code></td><td>{_e(f.get('message'))}</td>"
            f"<td>{_numbers(f)}</td></tr>"
        )
    table = (
        "<table id='findings' class='findings'><thead><tr><th>severity</th><th>kind</th>"
        "<th>file:line</th><th>source line</th><th>message</th><th>numbers</th></tr></thead>"
        f"<tbody>{''.join(rows)}</tbody></table>"
    )
    return head + table if findings else "<p>No findings.</p>"


def _pictures(images: dict, out_dir: Path) -> str:
    figs = []
    for name, fname in images.items():
        p = out_dir / fname
        if p.is_file() and p.suffix.lower() == ".png":
            figs.append(f"<figure><img alt='{_e(name)}' src='{_data_url(p, 'image/png')}'>"
                        f"<figcaption>{_e(name)} ({_e(fname)})</figcaption></figure>")
    return f"<div class='gallery'>{''.join(figs)}</div>" if figs else "<p>No pictures in this run.</p>"


def _viewer(scene: dict) -> str:
    band = scene.get("band")
    legend = ["<span style='background:#d62728'></span>rapid <span style='background:#2ca02c'></span>feed"]
    if band:
        against = "the design" if band.get("what") == "design" else "the profile"
        legend.append(
            f"deviation from {against}: "
            f"<span style='background:#9e9e9e'></span>in band {band['lo_um']:+.1f}…{band['hi_um']:+.1f} µm "
            "<span style='background:#b30418'></span>material outside "
            "<span style='background:#05308f'></span>gouged "
            "<span style='background:#f5f5f5;border:1px solid #bbb'></span>not measured")
    toggles = "".join(
        f"<label><input type='checkbox' data-layer='{k}' checked> {k}</label> "
        for k in ("part", "feed", "rapid", "places"))
    imports = {
        "three": _data_url(VENDOR / "three.module.min.js", "text/javascript"),
        "three/addons/OrbitControls.js": _data_url(VENDOR / "OrbitControls.js", "text/javascript"),
    }
    return (
        f"<div class='controls'>{toggles}<button id='view-home' type='button'>reset view</button> "
        "drag to turn, wheel to zoom, right-drag to pan; click a label or a table row</div>"
        f"<div id='viewer'><canvas></canvas><div class='legend'>{'<br>'.join(legend)}</div></div>"
        f"<script type='application/json' id='scene-data'>{_script_json(scene)}</script>"
        f"<script type='importmap'>{_script_json({'imports': imports})}</script>"
        f"<script type='module'>{(ASSETS / 'viewer.js').read_text(encoding='utf-8')}</script>"
    )


def render_html(
    data: dict, out_dir: Path, sources: Sequence[str | None] = (), scene: dict | None = None
) -> str:
    """The page for ``data`` (report.json's content) with the pictures of ``out_dir``;
    ``sources``: the source line of each finding (in ``data['findings']``'s order)."""
    prog = Path((data.get("program") or {}).get("path") or "program").name
    cls, word = verdict(data)
    banners = []
    program = data.get("program") or {}
    if program.get("completed") is False or data.get("partial"):
        stop = program.get("stopped_at")
        where = (f"stopped at {_e(stop.get('file'))}:{_e(stop.get('line'))}" if isinstance(stop, dict)
                 else "see the findings for where it stopped")
        banners.append(f"The program did not run to its end ({where}): every figure below covers only "
                       "the part that ran.")
    skipped = _skipped(data.get("skipped"))
    if skipped:
        items = "".join(f"<li>{_e(s)}</li>" for s in skipped)
        banners.append(f"Not checked in this run: <ul>{items}</ul>")
    findings = data.get("findings") or []
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        "<meta name='viewport' content='width=device-width, initial-scale=1'>",
        f"<title>vmach verify: {_e(prog)}</title>",
        f"<style>{(ASSETS / 'report.css').read_text(encoding='utf-8')}</style></head><body>",
        f"<h1>vmach verify: {_e(prog)} <span class='verdict {cls}'>{word}</span></h1>",
        *(f"<div class='banner'>{b}</div>" for b in banners),
        _summary(data),
        f"<h2>Findings ({len(findings)})</h2>",
        _findings(findings, sources),
    ]
    if scene:
        parts += ["<section id='view3d'><h2>3-D view: cut part, tool path and findings "
                  "<a href='#view' title='the view alone, full window (reload)'>⤢</a></h2>",
                  _viewer(scene), "</section>"]
    parts += [
        "<h2>Pictures</h2>", _pictures(data.get("images") or {}, out_dir),
        "<h2>report.json</h2><details><summary>the whole report as JSON</summary><pre>",
        _e(json.dumps(data, indent=2, ensure_ascii=False)), "</pre></details>",
        f"<footer><p>vmach {_e(data.get('vmach'))}</p></footer>",
        f"<script>{(ASSETS / 'table.js').read_text(encoding='utf-8')}</script>",
        "</body></html>",
    ]
    return "\n".join(parts)


def write_html(path: Path, data: dict, sources: Sequence[str | None] = (), scene: dict | None = None) -> Path:
    """Write ``report.html`` (whole or not at all) beside the pictures it embeds."""
    text = render_html(data, path.parent, sources, scene)
    with atomic_writer(path) as fh:
        fh.write(text)
    return path


def write_report_html(report, data: dict, out_dir: Path) -> Path:
    """``report.html`` of a verify Report (``data``: its report.json) in ``out_dir``: the
    findings' source lines and the 3-D scene taken from the Report."""
    from vmach.findings import sort_key
    from vmach.report.scene import viewer_scene

    found = sorted(report.findings, key=sort_key)      # report.json's order
    sources = [f.source.text if f.source is not None else None for f in found]
    return write_html(Path(out_dir) / "report.html", data, sources, viewer_scene(report))
