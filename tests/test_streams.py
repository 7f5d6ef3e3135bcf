"""stdout carries a command's result, stderr what is not the result (issue 31): check, verify and
postcheck print their findings and summary on stdout; run prints the trace on stdout and its
findings on stderr (as LinuxCNC's rs274 does); a closed pipe ends a command quietly."""

from __future__ import annotations

import subprocess
import sys

from catalog import FIXTURES, POLY50

from vmach.cli import main


def _prog(tmp_path, text: str, name: str = "P.MPF"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_check_prints_findings_and_summary_on_stdout(tmp_path, capsys):
    p = _prog(tmp_path, "N10 G0 X0\nN20 GOTOF NOWHERE\nN30 M30\n")
    assert main(["check", str(p)]) == 1
    cap = capsys.readouterr()
    assert cap.err == ""
    lines = cap.out.splitlines()
    assert lines[0].startswith(f"{p}:2:") and "error[undefined_label]" in lines[0]
    assert lines[-1] == f"{p}: 1 error(s), 0 warning(s)"


def test_verify_prints_findings_and_summary_on_stdout(tmp_path, capsys):
    p = _prog(tmp_path, 'N10 T="EM10" D1\nN20 G0 X10\nN30 M30\n')
    assert main(["verify", str(p), "--machine", "s5d", "--no-images", "--out", str(tmp_path / "o")]) == 1
    cap = capsys.readouterr()
    # stderr holds only the progress log (one line a phase, not a tty); the findings are on stdout
    assert all(line.startswith("vmach verify: ") for line in cap.err.splitlines())
    assert "error[" not in cap.err
    assert "error[unknown_tool]" in cap.out and f"report: {tmp_path / 'o' / 'report.json'}" in cap.out


def test_postcheck_prints_findings_on_stdout(capsys):
    fix = FIXTURES / "postcheck"
    assert main(["postcheck", str(fix / "s5d_chamfer_typo.mpf"), "--cl", str(fix / "s5d_chamfer.cl")]) == 1
    cap = capsys.readouterr()
    assert cap.err == ""
    assert "error[" in cap.out


def test_run_prints_the_trace_on_stdout_and_findings_on_stderr(tmp_path, capsys):
    p = _prog(tmp_path, "N10 G0 X1\nN20 R1=R2/0\nN30 M30\n")
    assert main(["run", str(p)]) == 1
    cap = capsys.readouterr()
    assert "traverse" in cap.out and "error[" not in cap.out
    assert f"{p}:2:5: error[division_by_zero]" in cap.err


def _first_line_then_close(args):
    proc = subprocess.Popen([sys.executable, "-m", "vmach.cli", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    first = proc.stdout.readline()
    proc.stdout.close()
    err = proc.stderr.read().decode()
    proc.stderr.close()
    return first, err, proc.wait(timeout=300)


def test_a_closed_pipe_ends_quietly():
    """``vmach run POLY50.MPF | head -1``: the reader goes away after one line of thousands."""
    for args in (["run", str(POLY50)], ["run", str(POLY50), "--format", "json"]):
        first, err, code = _first_line_then_close(args)
        assert first.strip()
        assert err == "" and code == 0, (code, err)


def test_a_closed_pipe_keeps_the_exit_code_and_the_findings_on_stderr(tmp_path):
    """``vmach check BAD | head -1`` still fails: a closed pipe is no clean pass."""
    many = _prog(tmp_path, "".join(f"N{i} GOTOF NOPE{i}\n" for i in range(1, 20001)) + "M30\n")
    first, err, code = _first_line_then_close(["check", str(many)])
    assert "error[undefined_label]" in first.decode() and err == "" and code == 1
    loop = _prog(tmp_path, "R1=0\nLBL: R1=R1+1\nG1 X=R1 F100\nGOTOB LBL\nM30\n", "LOOP.MPF")
    first, err, code = _first_line_then_close(["run", str(loop), "--max-blocks", "100000"])
    assert first.strip() and code == 1
    assert err.startswith(f"{loop}:") and "error[block_limit]" in err and "Traceback" not in err
