"""`vmach --version` and `vmach check` import only what they need; `vmach machines` lists the
bundled models from their own metadata (issue 31: start fast, getting started)."""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
import tomllib

from catalog import ROOT

from vmach.bundled import MODELS_DIR
from vmach.cli import COMMANDS, HELPS, build_parser, main

HEAVY = ("numpy", "scipy", "trimesh", "manifold3d", "pyvista", "vtk", "shapely")


def imported_after(args: list[str]) -> set[str]:
    """The top-level modules a fresh interpreter has imported after running ``vmach args``."""
    code = (
        "import sys\nfrom vmach.cli import main\n"
        "try:\n    main(sys.argv[1:])\nexcept SystemExit:\n    pass\n"
        "print(' '.join(sorted({m.split('.')[0] for m in sys.modules})))\n"
    )
    out = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, cwd=ROOT,
                         check=True).stdout
    return set(out.split("\n")[-2].split())


def test_version_and_help_import_no_heavy_library():
    for args in (["--version"], ["--help"], ["machines"]):
        mods = imported_after(args)
        assert not mods & set(HEAVY), (args, sorted(mods & set(HEAVY)))
        assert "vmach" in mods


def test_check_imports_no_heavy_library():
    """check reads only the model's [control] (vmach.machine loads its kinematics lazily)."""
    mods = imported_after(["check", str(ROOT / "fixtures/polygon_shaft/POLY50.MPF")])
    assert not mods & set(HEAVY), sorted(mods & set(HEAVY))
    assert "interpreters" in mods


def test_the_listed_helps_are_the_commands_own():
    for name, modname in COMMANDS.items():
        assert HELPS[name] == importlib.import_module(modname).HELP, name


def test_a_command_parses_with_only_its_own_module_loaded():
    parser, modules = build_parser("profile")
    assert list(modules) == ["profile"]
    assert parser.parse_args(["profile", "P3G", "50"]).kind == "P3G"
    _, every = build_parser()
    assert set(every) == set(COMMANDS)


def test_machines_lists_every_bundled_model_from_its_metadata(capsys):
    assert main(["machines", "--format", "json"]) == 0
    listed = json.loads(capsys.readouterr().out)["models"]
    files = sorted(MODELS_DIR.glob("*.toml"))
    assert [m["name"] for m in listed] == [p.stem for p in files] and len(files) >= 4
    for m, p in zip(listed, files, strict=True):
        raw = tomllib.loads(p.read_text(encoding="utf-8"))
        assert m["description"] == raw.get("description", "")
        assert m["axes"] == [a["name"] for a in raw.get("axes", [])]
    assert main(["machines"]) == 0
    lines = capsys.readouterr().out.splitlines()
    for p in files:      # one line per model, starting with the name --machine takes
        assert sum(line.split()[:1] == [p.stem] for line in lines) == 1
    turnmill = next(m for m in listed if m["name"] == "turnmill")
    assert turnmill["dialect"] == "sinumerik" and "C1" in turnmill["axes"]
