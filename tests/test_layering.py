"""The architecture's boundaries, enforced (architecture.md, "Style by example" 12)."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

INTERPRETER_MAY_IMPORT = {
    "vmach.files",
    "vmach.canon",
    "vmach.source",
    "vmach.errors",
    "vmach.findings",
    "vmach.tol",
}
HEAVY_OWNERS = {
    "manifold3d": {"vmach/stock/engine.py"},
    "pyvista": {"vmach/report/render.py"},
    "vtk": {"vmach/report/render.py"},
    "igl": {"vmach/checks/distance.py"},
}


def _imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.extend(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module in ("vmach", "interpreters"):  # "from vmach import canon"
                names.extend(f"{node.module}.{a.name}" for a in node.names)
            else:
                names.append(node.module)
    return names


def _files(top: str) -> list[Path]:
    return sorted((ROOT / top).rglob("*.py"))


def test_interpreters_depend_only_on_the_canonical_contract():
    bad = []
    for f in _files("interpreters"):
        for name in _imports(f):
            if name.startswith("vmach") and name not in INTERPRETER_MAY_IMPORT:
                bad.append(f"{f.relative_to(ROOT)} imports {name}")
            if name.split(".")[0] in {"numpy", "trimesh", "manifold3d", "pyvista", "vtk"}:
                bad.append(f"{f.relative_to(ROOT)} imports {name}")
    assert bad == []


def test_core_never_imports_a_dialects_internals():
    bad = []
    for f in _files("vmach"):
        for name in _imports(f):
            if name.startswith("interpreters."):
                bad.append(f"{f.relative_to(ROOT)} imports {name}")
    assert bad == []


def test_heavy_libraries_sit_behind_one_module_each():
    bad = []
    for top in ("vmach", "interpreters"):
        for f in _files(top):
            rel = str(f.relative_to(ROOT))
            for name in _imports(f):
                lib = name.split(".")[0]
                if lib in HEAVY_OWNERS and rel not in HEAVY_OWNERS[lib]:
                    bad.append(f"{rel} imports {name}")
    assert bad == []


def test_modules_stay_small():
    big = [
        f"{f.relative_to(ROOT)}: {n} lines"
        for top in ("vmach", "interpreters")
        for f in _files(top)
        if (n := len(f.read_text(encoding="utf-8").splitlines())) > 800
    ]
    assert big == []
