"""``vmach batch`` on Dask with tiny cases: a local cluster, resume, and the same batch on a
separately started ``dask scheduler`` + ``dask worker`` on localhost giving the same summary."""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from vmach.cli import main

pytest.importorskip("distributed")

PROGRAMS = {
    "GOOD.MPF": "N10 G0 X40 Z10\nN20 G1 X30 F200\nN30 M30\n",
    "BAD.MPF": "N10 G0 X40 Z10\nN20 G999 X30\nN30 M30\n",          # an unknown G code: a finding
}


def make_jobs(root: Path) -> list[str]:
    for name, text in PROGRAMS.items():
        (root / name).write_text(text)
    odd = root / "odd"                               # its setup names no machine that exists
    odd.mkdir()
    (odd / "vmach.toml").write_text('machine = "no_such_machine"\n')
    (odd / "ODD.MPF").write_text(PROGRAMS["GOOD.MPF"])
    (root / "vmach.toml").write_text('machine = "turnmill"\n')
    return [str(root / "GOOD.MPF"), str(root / "BAD.MPF"), str(odd / "ODD.MPF")]


def summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow
def test_batch_local_resume_and_separate_cluster(tmp_path, capsys):
    jobs = make_jobs(tmp_path)
    local = tmp_path / "local"
    code = main(["batch", *jobs, "--out", str(local), "--workers", "1", "--no-images"])
    assert code == 1                                   # two cases fail; the batch itself ran
    s = summary(local)
    verdicts = {r["name"]: r["verdict"] for r in s["results"]}
    # GOOD: no stock nor tools, so the stock's checks are not run: said as warnings
    assert verdicts == {"GOOD": "warnings", "BAD": "fail", "ODD": "error"}
    good = next(r for r in s["results"] if r["name"] == "GOOD")
    assert good["errors"] == 0 and good["warnings"] >= 1
    bad = next(r for r in s["results"] if r["name"] == "BAD")
    assert bad["worst"]["line"] == 2 and bad["worst"]["severity"] == "error"
    assert (local / "GOOD" / "report.json").is_file() and (local / "index.html").is_file()
    err = capsys.readouterr().err
    assert "3/3 done" in err and "2 failed" in err

    # resumed: nothing runs again (no cluster is started) and the summary is the same
    assert main(["batch", *jobs, "--out", str(local), "--workers", "1", "--no-images", "--quiet"]) == 1
    timings = json.loads((local / "timings.json").read_text())
    assert timings["resumed"] == 3 and "workers" not in timings
    assert summary(local) == s

    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    procs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                               "--port", str(port), "--no-dashboard"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        time.sleep(2)
        procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address,
                                       "--nworkers", "2", "--nthreads", "1", "--no-dashboard"],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        remote = tmp_path / "remote"
        assert main(["batch", *jobs, "--out", str(remote), "--scheduler", address, "--no-images",
                     "--quiet"]) == 1
        assert json.loads((remote / "timings.json").read_text())["workers"] >= 1
        assert summary(remote) == s                    # the same verdicts, findings, numbers
        assert (remote / "GOOD" / "report.html").is_file()
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()



def test_a_changed_case_is_not_taken_from_before(tmp_path):
    from vmach.batch.execute import done_before
    from vmach.batch.family import file_cases

    jobs = make_jobs(tmp_path)
    case = file_cases([Path(jobs[0])])[0]
    d = tmp_path / "out" / case.name
    d.mkdir(parents=True)
    (d / "report.json").write_text("{}")
    (d / "case.json").write_text(json.dumps({"key": case.key(), "verdict": "pass"}))
    assert done_before(case, d) is not None
    Path(jobs[0]).write_text(PROGRAMS["GOOD.MPF"].replace("X30", "X32"))
    assert done_before(case, d) is None
    Path(jobs[0]).write_text(PROGRAMS["GOOD.MPF"])
    (d / "report.json").unlink()                       # a pass without its report is not complete
    assert done_before(case, d) is None
