"""The import graph has no cycles — every import counts: at module level, inside a function
(a lazy import), under ``if TYPE_CHECKING`` and in a package's ``__getattr__``.

A cycle means two modules each need the other, so neither can be read (or changed) alone.
``CHECKED`` lists the top-level packages whose graph is checked: the core and the dialects. (The
dialects' steps name the running interpreter and the block parser by protocols,
``interpreters/sinumerik/running.py``; an RS274/NGC file is loaded by ``rs274ngc/program.py``,
which both the interpreter and its subroutine lookup use.)
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: top-level packages whose import graph must be acyclic
CHECKED = ("vmach", "interpreters")


def _name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules(tops: tuple[str, ...]) -> dict[str, Path]:
    """Module name -> file, for every module under the ``tops`` directories of the repo."""
    return {_name(p): p for top in tops for p in sorted((ROOT / top).rglob("*.py"))}


def _owner(name: str, known: dict[str, Path]) -> str | None:
    """The module of ``known`` that importing ``name`` runs: itself, or the package that holds
    it (``a.b.func`` -> ``a.b``); None for a module outside them (a library)."""
    while name and name not in known:
        name = name.rpartition(".")[0]
    return name or None


def imports(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """The modules of ``known`` that module ``name`` (its file ``path``) imports anywhere in
    its body. ``from p import x`` imports module ``p.x`` when there is one, else ``p``;
    relative imports are resolved against the module's package."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out.update(t for a in node.names if (t := _owner(a.name, known)))
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + ([base] if base else []))
            for a in node.names:
                full = f"{base}.{a.name}"
                t = full if full in known else _owner(base, known)
                if t:
                    out.add(t)
    out.discard(name)
    return out


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (each a set of modules that
    import one another round a loop), sorted; iterative Tarjan."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))
    return sorted(out)


def graph_of(tops: tuple[str, ...]) -> dict[str, set[str]]:
    known = modules(tops)
    return {name: imports(name, path, known) for name, path in known.items()}


def test_cycles_are_found():
    """The finder itself: a loop through a lazy import and a relative one is one cycle; a
    module beside it that only imports into the loop is not part of it."""
    g = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert cycles(g) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_imports_read_lazy_relative_and_type_checking(tmp_path, monkeypatch):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("def __getattr__(n):\n    from pkg.a import A\n    return A\n")
    (pkg / "a.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .b import B\n")
    (pkg / "b.py").write_text("def f():\n    import pkg.a\n    from pkg import c\n")
    (pkg / "c.py").write_text("import numpy\n")
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    g = graph_of(("pkg",))
    assert g == {"pkg": {"pkg.a"}, "pkg.a": {"pkg.b"}, "pkg.b": {"pkg.a", "pkg.c"}, "pkg.c": set()}
    assert cycles(g) == [["pkg.a", "pkg.b"]]


def test_no_import_cycles():
    assert cycles(graph_of(CHECKED)) == []
