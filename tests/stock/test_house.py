"""The stock engine stays readable: no module of vmach/stock over 400 lines, no function over
60, no class over 300 (docstrings included), and every cutter strategy states its error bound."""

from __future__ import annotations

import ast
import inspect
import pkgutil
from pathlib import Path

import pytest

import vmach.stock.strategies as strategies
from vmach.errors import InputError
from vmach.stock.path import Bound
from vmach.stock.plan import TABLE, WITHOUT, Settings

STOCK = Path(__file__).resolve().parents[2] / "vmach" / "stock"


def _too_big() -> list[str]:
    out = []
    for path in sorted(STOCK.rglob("*.py")):
        src = path.read_text(encoding="utf-8")
        name = path.relative_to(STOCK.parent.parent)
        if (n := len(src.splitlines())) > 400:
            out.append(f"{name}: {n} lines")
        for node in ast.walk(ast.parse(src)):
            size = getattr(node, "end_lineno", 0) - getattr(node, "lineno", 0) + 1
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and size > 60:
                out.append(f"{name}: def {node.name}: {size} lines")
            if isinstance(node, ast.ClassDef) and size > 300:
                out.append(f"{name}: class {node.name}: {size} lines")
    return out


def test_modules_functions_and_classes_stay_small():
    assert _too_big() == []


def test_every_strategy_states_its_error_bound_and_claims():
    """Each module of strategies/ is one line of the planner's table, in the order the package
    states, with its NAME, its BOUND and the one door ``claim(path, free, view, cover)``;
    placed poses come last, and only fans (and a turning path's revolution, which straddles
    the blank's circle, and a polygonal-turning path's section, within its sag) may remove more
    than the true sweep."""
    names = [m.name for m in pkgutil.iter_modules(strategies.__path__)]
    assert [m.NAME for m in TABLE] == [m.__name__.rsplit(".", 1)[1] for m in TABLE]
    assert sorted(m.NAME for m in TABLE) == sorted(names)
    assert TABLE[-1].NAME == "placed"
    doc = strategies.__doc__
    assert [doc.index(f":mod:`.{m.NAME}`") for m in TABLE] == sorted(doc.index(f":mod:`.{m.NAME}`")
                                                                     for m in TABLE)
    for mod in TABLE:
        assert "Error bound" in (mod.__doc__ or ""), mod.NAME
        assert isinstance(mod.BOUND, Bound), mod.NAME
        assert list(inspect.signature(mod.claim).parameters) == ["path", "free", "view", "cover"], mod.NAME
    assert {m.NAME for m in TABLE if m.BOUND.over} == {"fans", "revolved", "polygonal"}


def test_a_strategy_is_switched_off_by_name_and_an_unknown_name_is_an_error(monkeypatch):
    """VMACH_STOCK_WITHOUT (benchmarks/stock_strategies.py) names strategies to leave out; a
    name it does not know is a usage error, not a measurement of something else."""
    monkeypatch.setenv(WITHOUT, "fins, cover")
    assert Settings().without == {"fins", "cover"} and not Settings().on("fins") and Settings().on("fans")
    monkeypatch.setenv(WITHOUT, "fins,runs")
    with pytest.raises(InputError) as e:
        Settings()
    assert e.value.kind == "usage"
