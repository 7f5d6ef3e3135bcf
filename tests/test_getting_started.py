"""docs/getting-started.md is true: its files, written out as the page shows them, verify clean,
and its deliberate mistake gives the finding the page says, at its line."""

from __future__ import annotations

import json
import re

import pytest
from catalog import ROOT

from vmach.cli import main

DOC = ROOT / "docs" / "getting-started.md"


def files() -> dict[str, str]:
    """``{name: text}`` of every file the page shows as "`myjob/NAME`:" and a fenced block."""
    text = DOC.read_text(encoding="utf-8")
    return dict(re.findall(r"^`myjob/([\w.]+)`:\n\n```\w*\n(.*?)^```", text, re.M | re.S))


@pytest.fixture
def job(tmp_path):
    d = tmp_path / "myjob"
    d.mkdir()
    for name, text in files().items():
        (d / name).write_text(text, encoding="utf-8")
    return d


def test_the_page_shows_every_file_of_the_job():
    assert set(files()) == {"mill3.toml", "tools.toml", "vmach.toml", "POCKET.MPF"}


def test_the_job_verifies_clean_and_the_mistake_is_found_at_its_line(job, capsys):
    out = job.parent / "out"
    assert main(["verify", str(job / "POCKET.MPF"), "--out", str(out), "--quiet", "--no-images"]) == 0
    data = json.loads((out / "report.json").read_text())
    assert data["summary"] == {"errors": 0, "warnings": 0, "infos": 0}
    assert data["machine"]["name"] == "mill3_demo" and data["program"]["completed"] is True
    assert data["simulation"]["cutters"] > 0 and (out / "report.html").is_file()
    # the page's mistake: N50 as a rapid to 2 mm inside the block
    prog = job / "POCKET.MPF"
    text = prog.read_text()
    assert "N50 G0 X0 Y0 Z5" in text
    prog.write_text(text.replace("N50 G0 X0 Y0 Z5", "N50 G0 X0 Y0 Z-2"))
    assert main(["verify", str(prog), "--out", str(out), "--quiet", "--no-images"]) == 1
    found = json.loads((out / "report.json").read_text())["findings"]
    assert [(f["kind"], f["line"]) for f in found if f["severity"] == "error"] == [("rapid_into_stock", 6)]
    assert "POCKET.MPF:6:1: error[rapid_into_stock]" in capsys.readouterr().out


def test_the_model_is_listed_like_a_bundled_one(job, capsys):
    from vmach.commands.machines import describe

    d = describe(job / "mill3.toml")
    got = (d["name"], d["formula"], d["dialect"], d["axes"])
    assert got == ("mill3", "WYXVZT", "sinumerik", ["X", "Y", "Z"])
