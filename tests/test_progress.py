"""Progress of `vmach verify` (issue 31): a line per phase with its time when stderr is not a
terminal (CI logs), bars on a terminal, nothing with --quiet; stdout keeps the report alone."""

from __future__ import annotations

import io
import re
import shutil

from catalog import FIXTURES

from vmach.cli import main
from vmach.progress import Progress

SLOT = 'N10 G17 G90 G54\nN20 T="EM10" D1\nN30 S3000 M3\nN40 G0 X-45 Y0 Z5\nN50 G1 Z-3 F300\nN60 X20 F600\n' \
       "N70 G0 Z50\nN80 M30\n"


def _program(tmp_path):
    shutil.copy(FIXTURES / "milling" / "tools.toml", tmp_path / "tools.toml")
    setup = 'machine = "s5d"\ntools = "tools.toml"\nstock = "box:x=70,y=50,z=10"\n'
    (tmp_path / "vmach.toml").write_text(setup)
    (tmp_path / "SLOT.MPF").write_text(SLOT)
    return str(tmp_path / "SLOT.MPF")


def test_a_log_line_per_phase_when_not_a_terminal_and_silence_when_quiet(tmp_path, capsys):
    prog = _program(tmp_path)
    assert main(["verify", prog, "--out", str(tmp_path / "o"), "--no-images"]) == 0
    cap = capsys.readouterr()
    lines = [ln for ln in cap.err.splitlines() if ln.startswith("vmach verify: ")]
    phases = [re.match(r"vmach verify: (\w+)(?: \(continued\))? (\d+\.\d\d) s$", ln) for ln in lines[:-1]]
    assert all(phases), lines
    names = [m.group(1) for m in phases]
    for phase in ("setup", "interpret", "stock", "collisions", "report"):
        assert phase in names, names
    assert names.index("interpret") < names.index("stock") < names.index("report")
    assert re.fullmatch(r"vmach verify: done in \d+\.\d\d s", lines[-1])
    assert "vmach verify:" not in cap.out                  # stdout: the summary only
    assert main(["verify", prog, "--out", str(tmp_path / "o"), "--no-images", "--quiet"]) == 0
    assert "vmach verify:" not in capsys.readouterr().err


def test_a_stopped_run_says_where_it_stopped(tmp_path, capsys):
    prog = _program(tmp_path)
    (tmp_path / "vmach.toml").write_text('machine = "s5d"\ntools = "no_such.toml"\n')
    assert main(["verify", prog, "--out", str(tmp_path / "o"), "--no-images"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err[-1] != "" and any(ln == "vmach verify: stopped in setup" for ln in err)


class _Tty(io.StringIO):
    def isatty(self):
        return True


def test_bars_on_a_terminal():
    tty = _Tty()
    p = Progress.for_stream("verify", False, ("interpret", "stock"), tty)
    assert p.mode == "bar"
    for name in ("interpret", "stock"):
        p.start(name)
        p.done(name, 0.5)
    p.close()
    text = tty.getvalue()
    assert "\r" in text and "vmach verify: interpret" in text and "vmach verify: stock" in text
    assert "2/2" in text
    assert Progress.for_stream("verify", True, (), _Tty()).mode == "off"
    assert Progress.for_stream("verify", False, (), io.StringIO()).mode == "log"
