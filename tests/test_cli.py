"""The command line: exit codes, formats, diagnostics, nothing half-written."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest
from catalog import POLY50, ROOT

from vmach.cli import main


def prog(tmp_path, text, name="P.MPF"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


def test_check_clean_program_exits_0(tmp_path, capsys):
    assert main(["check", prog(tmp_path, "G0 X1\nM30\n")]) == 0


def test_check_reports_in_compiler_format_and_exits_1(tmp_path, capsys):
    p = prog(tmp_path, "N10 G0 X1\nN20 GOTOF NIRGENDS\nN30 M30\n")
    assert main(["check", p]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[0] == f"{p}:2:11: error[undefined_label]: GOTOF NIRGENDS: label NIRGENDS does not exist"
    assert out[1] == "    N20 GOTOF NIRGENDS"
    assert out[2] == "              ^"


def test_check_json(tmp_path, capsys):
    p = prog(tmp_path, "N20 G0 X1\nN10 G0 X2\nM30\n")
    assert main(["check", p, "--format", "json"]) == 0  # warnings only
    data = json.loads(capsys.readouterr().out)
    assert data == [
        {
            "severity": "warning",
            "kind": "block_number_order",
            "file": p,
            "line": 2,
            "column": 1,
            "message": data[0]["message"],
            "previous": 20,
            "number": 10,
        }
    ]


def test_check_with_machine_by_name(tmp_path, capsys):
    p = prog(tmp_path, "C_AXIS_ON\nG0 C1=10\nM30\n")
    assert main(["check", p]) == 1
    assert main(["check", p, "--machine", "turnmill"]) == 0
    assert main(["check", p, "--machine", "no_such_machine"]) == 2
    assert "not found" in capsys.readouterr().err


def test_run_text_and_json_lines(tmp_path, capsys):
    p = prog(tmp_path, "G0 X1 Y2\nG1 Z-1 F100\nM30\n")
    assert main(["run", p, "--format", "json"]) == 0
    rows = [json.loads(x) for x in capsys.readouterr().out.splitlines()]
    assert rows[0] == {
        "kind": "traverse",
        "file": p,
        "line": 1,
        "axes": {"X": 1.0, "Y": 2.0, "Z": 0.0},
        "feed": None,
    }
    assert rows[1]["kind"] == "feed" and rows[1]["feed"] == 100.0 and rows[1]["axes"]["Z"] == -1.0
    assert rows[-1] == {"kind": "program_end", "file": p, "line": 3, "code": "M30"}
    assert main(["run", p]) == 0
    assert "traverse" in capsys.readouterr().out


def test_run_output_file_is_written_only_on_success(tmp_path, capsys):
    good = prog(tmp_path, "G0 X1\nM30\n", "GOOD.MPF")
    bad = prog(tmp_path, "G0 X1\nR1=1/0\nM30\n", "BAD.MPF")
    out = tmp_path / "trace.txt"
    assert main(["run", bad, "-o", str(out)]) == 1
    assert not out.exists() and list(tmp_path.glob(".trace*")) == []
    err = capsys.readouterr().err
    assert f"{bad}:2:1: error[division_by_zero]" in err
    assert main(["run", good, "-o", str(out)]) == 0
    assert "traverse" in out.read_text()
    # found by fuzzing: -o naming a directory raised IsADirectoryError after the run
    assert main(["run", good, "-o", str(tmp_path)]) == 2
    assert "error[unwritable]" in capsys.readouterr().err
    assert list(tmp_path.glob(".*")) == []


def test_runtime_limit_and_usage_errors(tmp_path, capsys):
    loop = prog(tmp_path, "LL: G0 X=R1\nR1=R1+1\nGOTOB LL\n")
    assert main(["run", loop, "--max-blocks", "500"]) == 1
    assert "error[block_limit]" in capsys.readouterr().err
    assert main(["run", str(tmp_path / "missing.mpf")]) == 2
    assert main(["run", prog(tmp_path, "x", "P.TXT")]) == 2
    assert main(["run", loop, "--format", "yaml"]) == 2
    with pytest.raises(SystemExit) as exc:
        main(["run"])
    assert exc.value.code == 2


def test_unreadable_model_is_a_clear_error(tmp_path, capsys):
    model = tmp_path / "m.toml"
    model.write_text("[control\nx=1\n")
    assert main(["check", prog(tmp_path, "M30\n"), "--machine", str(model)]) == 2
    err = capsys.readouterr().err
    assert "error[model_syntax]" in err and "Traceback" not in err


def test_setup_file_beside_the_program_selects_the_machine(capsys):
    assert main(["check", str(POLY50)]) == 0  # fixtures/polygon_shaft/vmach.toml names turnmill


def test_console_script_runs_without_traceback(tmp_path):
    p = prog(tmp_path, "G0 X1\nG1 X=SQRT(-1) F1\nM30\n")
    r = subprocess.run(
        [sys.executable, "-m", "vmach", "run", p], capture_output=True, text=True, cwd=ROOT, timeout=60
    )
    assert r.returncode == 1
    assert "error[domain_error]" in r.stderr and "Traceback" not in r.stderr


def test_run_on_a_hybrid_adds_drive_values_and_flags_unreachable_poses(tmp_path, capsys):
    from vmach.machine import load_model

    p = prog(tmp_path, "G0 X0 Y0 Z0 B0 C0\nG1 X10 Y5 Z-5 B30 C45 F100\nG1 Z-500\nM30\n")
    assert main(["run", p, "--machine", "h5d", "--format", "json"]) == 1
    cap = capsys.readouterr()
    rows = [json.loads(x) for x in cap.out.splitlines()]
    model = load_model("h5d")
    values, ok = model.drive_values([[10, 5, -5, 30, 45]])
    assert ok[0] and rows[1]["drives"] == {k: pytest.approx(float(v[0])) for k, v in values.items()}
    assert set(rows[2]["drives"].values()) == {None}
    assert f"{p}:3:1: error[unreachable]" in cap.err


def test_option_values_that_start_with_a_minus_sign_are_values(tmp_path, capsys):
    """README's `--profile-z -35:-5` (and `ik --tip -1,2,3`) used to be usage errors:
    argparse took the value for an option."""
    from vmach.cli import build_parser, negative_values_joined

    parser, _ = build_parser()
    args = parser.parse_args(negative_values_joined(
        ["verify", "P.MPF", "--profile-z", "-35:-5", "--clearance", "-.5", "--out", "-1"]))
    assert (args.profile_z, args.clearance, args.out) == ("-35:-5", -0.5, "-1")
    args = parser.parse_args(negative_values_joined(["ik", "s5d", "--tip", "-1,2,3", "--axis", "-0,0,1"]))
    assert (args.tip, args.axis) == ("-1,2,3", "-0,0,1")
    # end to end: the range reaches its check (an unknown fit class then stops the run early)
    p = prog(tmp_path, 'T="GLOD D40"\nM30\n')
    tools = str(ROOT / "fixtures/polygon_shaft/tools.toml")
    code = main(["verify", p, "--machine", "turnmill", "--tools", tools,
                 "--stock", "cylinder:d=60,l=50", "--profile", "P3G:50", "--profile-z", "-35:-5",
                 "--fit", "zz9", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and "error[fit]" in err and "usage" not in err
    assert main(["ik", "turnmill", "--tip", "30,0,-3", "--axis", "-1,0,0"]) in (0, 1)
    assert "error[usage]" not in capsys.readouterr().err


def test_a_bad_profile_check_stops_verify_before_the_simulation(tmp_path, capsys, monkeypatch):
    """A typo in --fit, --stations or --profile-z used to surface only after the whole stock
    simulation (20 s on the reference program), and after --export had written its files."""
    import vmach.stock.simulate as simulate_module

    def boom(*a, **k):
        raise AssertionError("the simulation ran")

    monkeypatch.setattr(simulate_module, "simulate", boom)
    p = prog(tmp_path, 'T="GLOD D40"\nM30\n')
    base = ["verify", p, "--machine", "turnmill", "--tools", str(ROOT / "fixtures/polygon_shaft/tools.toml"),
            "--stock", "cylinder:d=60,l=50", "--profile", "P3G:50", "--export", str(tmp_path / "part.stl"),
            "--out", str(tmp_path / "o"), "--no-images"]
    for extra, kind in ((["--profile-z=-35:-5", "--fit", "zz9"], "fit"),
                        (["--profile-z=-35:-5", "--stations", "0"], "profile_spec"),
                        (["--profile-z=nan:-5"], "profile_spec"),
                        ([], "usage")):
        assert main(base + extra) == 2
        assert f"error[{kind}]" in capsys.readouterr().err
    assert not (tmp_path / "part.stl").exists() and not (tmp_path / "o").exists()


def test_an_out_directory_that_cannot_be_made_is_an_error_before_any_work(tmp_path, capsys):
    """Found by fuzzing: `--out` naming a file, or a place no directory can be made, raised
    FileExistsError / FileNotFoundError tracebacks after the whole run."""
    from vmach.output import writable_dir

    p = prog(tmp_path, "M30\n")
    afile = tmp_path / "afile"
    afile.write_text("x")
    for out in (afile, afile / "sub", "/proc/vmach-no-such/x"):
        assert main(["verify", p, "--machine", "turnmill", "--out", str(out), "--no-images"]) == 2
        assert "error[unwritable]" in capsys.readouterr().err
    assert afile.read_text() == "x"
    assert writable_dir(tmp_path / "new" / "deeper") == tmp_path / "new" / "deeper"
    assert not (tmp_path / "new").exists()                       # checking creates nothing


@pytest.mark.parametrize("setup, line", [
    ("programs = 5\n", 1), ("machine = 5\n", 1), ('machine = "turnmill"\n[programs.P]\nstock = 3\n', 3),
    ("[zero_offsets.G54]\nX = \"abc\"\n", 2), ("[zero_offsets.G54]\nX = nan\n", 2),
    ("[zero_offsets]\nG54 = 5\n", 2),
    ('accuracy = ["fine"]\n', 1), ('machine = "turnmill"\n[programs.P]\nmachine = "nope"\n', 3)])
def test_a_setup_file_value_of_the_wrong_type_is_an_error_at_its_line(tmp_path, capsys, setup, line):
    """Found by fuzzing: each of these raised TypeError/AttributeError/ValueError tracebacks."""
    (tmp_path / "vmach.toml").write_text(setup)
    assert main(["check", prog(tmp_path, "G0 X1\nM30\n")]) == 2
    err = capsys.readouterr().err
    assert f"vmach.toml:{line}:1: error[" in err and "Traceback" not in err


def test_ik_on_a_model_without_axes_and_export_without_a_stock_are_usage_errors(tmp_path, capsys):
    """Found by fuzzing: ik on a chain-less model raised a reshape ValueError; --export was
    silently ignored when nothing was simulated; a bad second --export target was found only
    after the first had been written."""
    model = tmp_path / "nochain.toml"
    model.write_text('[work]\nlink = "base"\n[tool]\nlink = "base"\n')
    assert main(["ik", str(model), "--tip", "1,2,3", "--axis", "0,0,1"]) == 2
    assert "error[usage]" in capsys.readouterr().err
    p = prog(tmp_path, 'T="GLOD D40"\nM30\n')
    first = tmp_path / "first.stl"
    assert main(["verify", p, "--machine", "turnmill", "--no-images", "--out", str(tmp_path / "o"),
                 "--export", str(first)]) == 2
    assert "error[usage]" in capsys.readouterr().err
    tools = str(ROOT / "fixtures/polygon_shaft/tools.toml")
    assert main(["verify", p, "--machine", "turnmill", "--tools", tools, "--stock", "cylinder:d=60,l=50",
                 "--no-images", "--out", str(tmp_path / "o"), "--export", str(first),
                 "--export", str(tmp_path / "second.xyz")]) == 2
    assert "error[export_format]" in capsys.readouterr().err
    assert not first.exists() and not (tmp_path / "o").exists()


def test_an_endless_cycle_time_is_null_in_the_report_not_a_crash(tmp_path, capsys):
    """Found by fuzzing: two dwells of 1e308 s summed to inf; the summary's int(inf // 60)
    raised, and report.json held `Infinity` (not JSON)."""
    p = prog(tmp_path, "G4 F=1EX308\nG4 F=1EX308\nM30\n")
    out = tmp_path / "o"
    assert main(["verify", p, "--machine", "turnmill", "--no-images", "--out", str(out)]) == 0
    data = json.loads((out / "report.json").read_text(), parse_constant=lambda c: pytest.fail(c))
    assert data["cycle_time_s"] is None


def test_a_program_whose_extension_does_not_say_is_read_in_the_machines_dialect(tmp_path, capsys):
    # R parameters and a label jump are Sinumerik; the turn-mill model declares that dialect
    prog = tmp_path / "part.nc"
    prog.write_text("R1=2\nLL: G1 X=R1 F100\nR1=R1-1\nIF R1>0 GOTOB LL\nM30\n")
    assert main(["check", str(prog), "--machine", "turnmill"]) == 0
    # without a machine, .nc is RS274/NGC, which has no R parameters
    assert main(["check", str(prog)]) == 1
    capsys.readouterr()
    # an extension only one dialect uses wins over the machine's; --dialect over both
    ngc = tmp_path / "part.ngc"
    ngc.write_text("#1=2\nG1 X#1 F100\nM2\n")
    assert main(["check", str(ngc), "--machine", "turnmill"]) == 0
    assert main(["check", str(prog), "--machine", "s5d", "--dialect", "sinumerik"]) == 0


def test_an_export_may_go_into_the_out_directory_verify_makes(tmp_path, capsys):
    """`--out o --export o/part.stl` failed (the directory o did not exist yet) although verify
    makes o itself; an export's directory now follows --out's rule: one that exists or can be
    made, made only when the file is written. A parent that is a file is still an error before
    any work, and nothing is made."""
    import trimesh

    p = prog(tmp_path, 'T="GLOD D40"\nM30\n')
    tools = str(ROOT / "fixtures/polygon_shaft/tools.toml")
    base = ["verify", p, "--machine", "turnmill", "--tools", tools, "--stock", "cylinder:d=60,l=50",
            "--no-images", "--out", str(tmp_path / "o")]
    part = tmp_path / "o" / "deeper" / "part.ply"
    assert main(base + ["--export", str(part)]) == 0
    mesh = trimesh.load(part, force="mesh")
    assert mesh.is_watertight and abs(mesh.volume - math.pi * 30**2 * 50) < 0.01 * math.pi * 30**2 * 50
    afile = tmp_path / "afile"
    afile.write_text("x")
    assert main(base + ["--out", str(tmp_path / "o2"), "--export", str(afile / "part.stl")]) == 2
    assert "error[unwritable]" in capsys.readouterr().err
    assert afile.read_text() == "x" and not (tmp_path / "o2").exists()


def test_files_written_whole_get_the_usual_permissions(tmp_path):
    """report.json came out 0600 (mkstemp's mode) beside 0644 pictures: a CI artifact or a
    shared directory could not read it. A new file gets 0666 less the umask; a file written
    over keeps its mode."""
    import os
    import stat

    from vmach.output import atomic_writer

    old = os.umask(0o022)
    try:
        with atomic_writer(tmp_path / "new.json") as fh:
            fh.write("{}")
        assert stat.S_IMODE((tmp_path / "new.json").stat().st_mode) == 0o644
        os.umask(0o077)
        with atomic_writer(tmp_path / "private.json") as fh:
            fh.write("{}")
        assert stat.S_IMODE((tmp_path / "private.json").stat().st_mode) == 0o600
        (tmp_path / "new.json").chmod(0o640)
        with atomic_writer(tmp_path / "new.json") as fh:
            fh.write("[]")
        assert stat.S_IMODE((tmp_path / "new.json").stat().st_mode) == 0o640
        assert (tmp_path / "new.json").read_text() == "[]"
    finally:
        os.umask(old)


def test_a_write_that_fails_half_way_leaves_nothing_and_is_an_error(tmp_path):
    """A full disk while writing (OSError from the writer) is error[unwritable], with neither
    the target nor the temporary file left; a picture is written the same way, so a PNG is
    never half there (it was written straight to its name by VTK)."""
    import errno

    from vmach.errors import InputError
    from vmach.output import atomic_writer

    target = tmp_path / "report.json"
    with pytest.raises(InputError) as err:
        with atomic_writer(target) as fh:
            fh.write("{" * 1000)
            raise OSError(errno.ENOSPC, "No space left on device")
    assert err.value.kind == "unwritable" and "No space left" in str(err.value)
    assert list(tmp_path.iterdir()) == []


def test_run_and_verify_compensate_with_the_tool_librarys_radius(tmp_path, capsys):
    """G41 takes the radius of the active D offset from the tool library (--tools, or the
    setup file's): GLOD D40's D1 is 20 mm. Without a library G41 is error[no_tool_radius]."""
    import json

    tools = str(ROOT / "fixtures/polygon_shaft/tools.toml")
    p = prog(tmp_path, 'T="GLOD D40" D1\nG17 G0 X-50 Y-50 Z5\nG1 F500 G41 X0 Y0\nY40\nG40 X-50 Y60\nM30\n')
    assert main(["run", p, "--format", "json", "--tools", tools]) == 0
    feeds = [json.loads(x) for x in capsys.readouterr().out.splitlines()]
    feeds = [c for c in feeds if c["kind"] == "feed"]
    assert [(c["axes"]["X"], c["axes"]["Y"], c["line"]) for c in feeds] == [
        (-20.0, 0.0, 3), (-20.0, 40.0, 4), (-50.0, 60.0, 5)]
    assert main(["run", p]) == 1
    err = capsys.readouterr().err
    assert "P.MPF:3:" in err and "error[no_tool_radius]" in err and "--tools" in err
    (tmp_path / "tools.toml").write_bytes(Path(tools).read_bytes())   # a library beside the program
    (tmp_path / "vmach.toml").write_text('tools = "tools.toml"\n')
    assert main(["run", p]) == 0
    capsys.readouterr()
    assert main(["verify", p, "--machine", "turnmill", "--out", str(tmp_path / "o"), "--no-images"]) in (0, 1)
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert not [f for f in report["findings"] if f["kind"] == "no_tool_radius"]
