"""report.html in a real browser (issue 31): headless Chromium (Debian's ``chromium``; .ci/run
installs it) opens the page from disk with the network off, draws the 3-D view (its
screenshot is not blank: the part's grey and the path's red and green are there) and lists in
its table exactly the findings of report.json.

Skips when chromium is absent; with CI=true it fails instead.
"""

from __future__ import annotations

import html
import json
import os
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from catalog import FIXTURES

from vmach.cli import main

#: a slot milled with EM10, then a rapid straight through the blank (rapid_into_stock at
#: line 11), on the desktop five-axis mill
CRASH = """; a slot, then a rapid through the blank
N10 G17 G90 G54 G40
N20 T="EM10" D1
N30 S3000 M3
N40 G0 X-45 Y0 Z5
N50 G1 Z-3 F300
N60 X20 F600
N70 G0 Z5
N80 G0 X-45 Y10
N90 G0 Z-2
N100 G0 X20
N110 G0 Z50
N120 M30
"""

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run",
         # WebGL on the CPU (SwiftShader): --disable-gpu leaves no other way to draw
         "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]


def chromium() -> str:
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        msg = "chromium not installed (apt-get install chromium; .ci/run does)"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(msg)
        pytest.skip(msg)
    return exe


def browse(exe: str, url: str, profile: Path, *what: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [exe, *FLAGS, f"--user-data-dir={profile}", "--window-size=1000,800",
         "--virtual-time-budget=20000", *what, url],
        capture_output=True, text=True, timeout=240,
    )


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("crash")
    shutil.copy(FIXTURES / "milling" / "tools.toml", d / "tools.toml")
    (d / "vmach.toml").write_text('machine = "s5d"\ntools = "tools.toml"\nstock = "box:x=70,y=50,z=10"\n')
    (d / "CRASH.MPF").write_text(CRASH)
    assert main(["verify", str(d / "CRASH.MPF"), "--out", str(d / "out"), "--quiet"]) == 1
    return d / "out"


class _Rows(HTMLParser):
    """The findings table's rows: (kind, severity, file:line) of each."""

    def __init__(self):
        super().__init__()
        self.rows: list[dict] = []
        self.viewer: dict = {}
        self._cell: list[str] | None = None
        self._in_table = False

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "table" and a.get("id") == "findings":
            self._in_table = True
        elif tag == "tr" and self._in_table and "data-kind" in a:
            self.rows.append({"kind": a["data-kind"], "severity": a["data-severity"], "cells": []})
        elif tag == "td" and self._in_table and self.rows:
            self._cell = []
        elif a.get("id") == "viewer":
            self.viewer = a

    def handle_endtag(self, tag):
        if tag == "td" and self._cell is not None:
            self.rows[-1]["cells"].append("".join(self._cell).strip())
            self._cell = None
        elif tag == "table":
            self._in_table = False

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def test_the_page_needs_no_network(report):
    page = (report / "report.html").read_text(encoding="utf-8")
    assert not re.search(r"""(src|href)\s*=\s*['"]?(https?:)?//""", page)
    assert not re.search(r"""import[^'"]*['"]https?:""", page)
    assert "<img" in page and "data:image/png;base64," in page      # the pictures, embedded


def test_chromium_draws_the_3d_view_and_lists_every_finding(report, tmp_path):
    exe = chromium()
    data = json.loads((report / "report.json").read_text())
    assert any(f["kind"] == "rapid_into_stock" and f["line"] == 11 for f in data["findings"])
    url = (report / "report.html").as_uri()

    dom = browse(exe, url, tmp_path / "p1", "--dump-dom")
    assert dom.returncode == 0, dom.stderr[-2000:]
    parsed = _Rows()
    parsed.feed(dom.stdout)
    got = [(r["kind"], r["severity"], r["cells"][2]) for r in parsed.rows]
    want = [(f["kind"], f["severity"], f"{Path(f['file']).name}:{f['line']}") for f in data["findings"]]
    assert got == want
    rapid = next(r for r in parsed.rows if r["kind"] == "rapid_into_stock")
    assert rapid["cells"][3] == "N100 G0 X20"           # the source line
    # the viewer ran and read back its own picture: triangles drawn, pixels inked
    assert int(parsed.viewer.get("data-drawn", 0)) > 12
    assert int(parsed.viewer.get("data-inked", 0)) > 50

    shot = tmp_path / "view.png"
    res = browse(exe, url + "#view", tmp_path / "p2", f"--screenshot={shot}")
    assert res.returncode == 0 and shot.is_file(), res.stderr[-2000:]
    from PIL import Image

    img = np.asarray(Image.open(shot).convert("RGB")).astype(int)
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    inked = (img < 235).any(axis=2).mean()
    grey = ((abs(r - g) < 8) & (abs(g - b) < 8) & (r > 60) & (r < 225)).mean()
    red = ((r > 150) & (g < 90) & (b < 90)).sum()
    green = ((g > 110) & (r < 110) & (b < 110)).sum()
    assert inked > 0.03, inked           # not a blank page
    assert grey > 0.01, grey             # the part (in-band grey and shading)
    assert red > 20 and green > 20, (red, green)   # rapids and feeds


#: appended to a copy of the page: drives the table as a reader would and writes what it saw
PROBE = """<script>
(function () {
  const t = document.getElementById('findings');
  const shown = () => Array.from(t.tBodies[0].rows).filter(r => !r.hidden).map(r => r.dataset.kind);
  const out = {};
  const kind = document.getElementById('filter-kind');
  kind.value = 'near_miss'; kind.dispatchEvent(new Event('input'));
  out.kind = shown();
  kind.value = ''; kind.dispatchEvent(new Event('input'));
  const text = document.getElementById('filter-text');
  text.value = 'N100'; text.dispatchEvent(new Event('input'));
  out.text = shown();
  text.value = ''; text.dispatchEvent(new Event('input'));
  const head = t.tHead.rows[0].cells;
  head[0].click();
  out.severity_asc = shown();
  head[0].click();
  out.severity_desc = shown();
  document.body.dataset.probe = JSON.stringify(out);
})();
</script>"""


def test_the_table_sorts_and_filters_in_chromium(report, tmp_path):
    exe = chromium()
    data = json.loads((report / "report.json").read_text())
    page = (report / "report.html").read_text(encoding="utf-8").replace("</body>", PROBE + "</body>")
    probe = report / "probe.html"
    probe.write_text(page, encoding="utf-8")
    dom = browse(exe, probe.as_uri(), tmp_path / "p3", "--dump-dom")
    assert dom.returncode == 0, dom.stderr[-2000:]
    seen = json.loads(html.unescape(re.search(r'data-probe="([^"]*)"', dom.stdout).group(1)))
    kinds = [f["kind"] for f in data["findings"]]
    assert seen["kind"] == [k for k in kinds if k == "near_miss"] and seen["kind"]
    assert seen["text"] == ["rapid_into_stock"]                  # the row whose source line is N100
    rank = {"error": 0, "warning": 1, "info": 2}
    sev = {f["kind"]: rank[f["severity"]] for f in data["findings"]}
    assert [sev[k] for k in seen["severity_asc"]] == sorted(sev[k] for k in kinds)
    assert [sev[k] for k in seen["severity_desc"]] == sorted((sev[k] for k in kinds), reverse=True)
