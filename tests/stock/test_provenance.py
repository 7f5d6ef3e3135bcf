"""Every cutter names the program rows that made it (``Stock.provenance``,
``Stock.cutters_by_row``), and the planner speaks in typed jobs (vmach/stock/jobs.py)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from tests.stock.conftest import turnmill
from vmach.errors import InputError
from vmach.stock import Stock
from vmach.stock.jobs import ColumnJob, Cutter, Fan, Placed, Runs, span


def _path():
    """A radial face mill's path on a Ø60 blank with a row per segment: a plunge (row 10), a
    straight move along Z (row 11), a turn of C1 over 20° in 10 samples (row 12), a retract
    (row 13). Returns tips, axes, rows (one per pose; a step belongs to the row it ends in)."""
    x = [40.0, 26.0, 26.0] + [26.0] * 10 + [40.0]
    z = [-5.0, -5.0, -15.0] + [-15.0] * 10 + [-15.0]
    c = [0.0, 0.0, 0.0] + list(np.linspace(2.0, 20.0, 10)) + [20.0]
    rows = [10, 10, 11] + [12] * 10 + [13]
    tips, axes = turnmill(np.array(x), 0.0, np.array(z), np.array(c))
    return tips, axes, np.array(rows)


def test_every_cutter_names_rows_of_the_moves_that_made_it(face40):
    tips, axes, rows = _path()
    stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01)
    n = stock.cut(face40, tips, axes, rows=rows)
    prov = stock.provenance
    assert n > 0 and prov.shape == (n, 2)
    assert np.all(prov[:, 0] <= prov[:, 1])
    assert set(prov.ravel()) <= {10, 11, 12, 13}
    by = stock.cutters_by_row()
    assert sum(by.values()) == n
    assert by.get(12, 0) > 0          # the turn made cutters of its own (fans or placed poses)
    assert 11 in by                   # the straight move's hull


def test_a_path_cut_without_rows_names_none(face40):
    tips, axes, _ = _path()
    stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01)
    n = stock.cut(face40, tips, axes)
    assert n > 0 and np.all(stock.provenance == -1)
    assert stock.cutters_by_row() == {}


def test_rows_must_match_the_poses(face40):
    tips, axes, rows = _path()
    stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01)
    with pytest.raises(InputError) as exc:
        stock.cut(face40, tips, axes, rows=rows[:-1])
    assert exc.value.kind == "stock_input"


def test_the_planner_yields_typed_frozen_jobs_in_path_order(face40):
    tips, axes, rows = _path()
    stock = Stock.from_spec("cylinder:d=60,l=60", chord=0.01)
    kinds = set()
    for _, jobs in stock.planner.plan(face40, tips, axes, rows=rows):
        for job in jobs:
            assert isinstance(job, Placed | Runs | Fan | ColumnJob)
            with pytest.raises(dataclasses.FrozenInstanceError):
                job.rows = None
            kinds.add(type(job))
        made = stock.maker.make(stock.planner.tool_solid(face40), jobs)
        assert all(isinstance(c, Cutter) and c.box.shape == (2, 3) for c in made)
    assert {Placed, Runs} <= kinds


def test_a_step_belongs_to_the_row_it_ends_in():
    rows = np.array([10, 10, 11, 12, 12, 13])
    assert span(rows, 0, 2) == (10, 11)      # steps 0→1 (row 10) and 1→2 (row 11)
    assert span(rows, 2, 2) == (11, 11)      # a lone pose: its own row
    assert span(rows, 3, 5) == (12, 13)
    assert span(None, 0, 5) == (-1, -1)
