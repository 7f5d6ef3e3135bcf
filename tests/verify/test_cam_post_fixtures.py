"""The CAM-post fixtures (fixtures/sinumerik_posts: programs written in the styles of Siemens
NX, hyperMILL, Mastercam, PowerMill, Fusion 360, ESPRIT, Edgecam, SolidCAM and CATIA posts
for the 840D, and a turning post) through the command line: ``check`` finds no error, ``run``
ends at the program's end on the machine its vmach.toml names, and four of them verify on
their machines with every tool, limit and stock check, without an error (#32)."""

from __future__ import annotations

import json

import pytest
from catalog import FIXTURES

from vmach.cli import main

POSTS = FIXTURES / "sinumerik_posts"
PROGRAMS = sorted(p.name for p in POSTS.glob("*.MPF"))


def test_every_post_style_is_a_fixture():
    assert len(PROGRAMS) >= 11


@pytest.mark.parametrize("name", PROGRAMS)
def test_check_finds_no_error(name, tmp_path, capsys):
    assert main(["check", str(POSTS / name), "--format", "json"]) == 0
    out = [json.loads(line) for line in capsys.readouterr().out.splitlines() if line.startswith("{")]
    assert [f for f in out if f.get("severity") == "error"] == []


@pytest.mark.parametrize("name", PROGRAMS)
def test_run_reaches_the_end(name, tmp_path, capsys):
    trace = tmp_path / "trace.jsonl"
    assert main(["run", str(POSTS / name), "--format", "json", "-o", str(trace)]) == 0
    last = json.loads(trace.read_text().splitlines()[-1])
    assert last["kind"] == "program_end"


@pytest.mark.parametrize("name, moves", [("FUSION3X.MPF", 60), ("NX5AX.MPF", 40), ("LATHE.MPF", 30),
                                         ("ESPRIT.MPF", 300)])
def test_verify_is_clean(name, moves, tmp_path):
    code = main(["verify", str(POSTS / name), "--out", str(tmp_path / "o"), "--no-images", "--quiet"])
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    errors = [(f["kind"], f["line"]) for f in report["findings"] if f["severity"] == "error"]
    assert (code, errors) == (0, [])
    assert report["program"]["completed"] and report["program"]["moves"] >= moves
    assert not report["partial"] and report["skipped"] == {}
