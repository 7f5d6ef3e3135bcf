"""Travel, rate and reach findings, computed vectorised from arrays of axis values.

Nothing is clipped: a value beyond a limit stays what the program asked for and gives an error
finding with the numbers (stable kinds ``axis_limit``, ``rate_limit``, ``unreachable``).

Every function takes optional ``sources`` (one :class:`SourceRef` or None per row) and
``move_index`` (one int per row; default the row number) so a finding points at its block and
its move-table row.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from vmach.findings import Finding
from vmach.source import SourceRef

#: values within this much of a limit are inside (mm or degrees; relative for rates).
EPS = 1e-9


def limit_mask(values: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """(n, k) bool — True where ``values`` (n, k) lie outside ``limits`` (k, 2); NaN = no limit."""
    v = np.atleast_2d(np.asarray(values, float))
    lo, hi = limits[:, 0], limits[:, 1]
    with np.errstate(invalid="ignore"):
        return (v < lo - EPS) | (v > hi + EPS)


def _src(sources, i):
    return None if sources is None else sources[i]


def _mi(move_index, i):
    return int(i) if move_index is None else int(move_index[i])


def _unit(model, name):
    if name in model.axes and model.rotary[model.axes.index(name)]:
        return "°", "°/min"
    return "mm", "mm/min"


def axis_limit_findings(
    model,
    q: np.ndarray,
    *,
    sources: Sequence[SourceRef | None] | None = None,
    move_index: Sequence[int] | None = None,
) -> list[Finding]:
    """``axis_limit`` for every row and axis of q (n, k) beyond travel, and — on hybrids —
    ``unreachable`` for poses no drive assembly reaches plus ``axis_limit`` for drives."""
    q = np.atleast_2d(np.asarray(q, float))
    out: list[Finding] = []
    names = list(model.axes)
    values, limits = q, model.limits
    if model.drives:
        drives, ok = model.drive_values(q)
        for i in np.flatnonzero(~ok):
            out.append(
                Finding(
                    "unreachable",
                    "error",
                    "the parallel mechanism cannot reach this pose (a strut has no real solution)",
                    _src(sources, i),
                    _mi(move_index, i),
                    {"axes": {a: float(q[i, j]) for j, a in enumerate(names)}},
                )
            )
        values = np.concatenate([q, np.stack([drives[d] for d in model.drives], axis=1)], axis=1)
        limits = np.concatenate([limits, model.drive_limits])
        names += list(model.drives)
    rows, cols = np.nonzero(limit_mask(values, limits))
    for i, j in zip(rows, cols, strict=True):
        v, lo, hi = float(values[i, j]), float(limits[j, 0]), float(limits[j, 1])
        u = _unit(model, names[j])[0]
        side = f"above the maximum {hi:g}" if v > hi else f"below the minimum {lo:g}"
        out.append(
            Finding(
                "axis_limit",
                "error",
                f"{names[j]} = {v:.4f} {u} is {side} {u}",
                _src(sources, i),
                _mi(move_index, i),
                {"axis": names[j], "value": v, "min": lo, "max": hi},
            )
        )
    return out


def rate_findings(
    model,
    start: np.ndarray,
    end: np.ndarray,
    seconds: np.ndarray,
    *,
    sources: Sequence[SourceRef | None] | None = None,
    move_index: Sequence[int] | None = None,
) -> list[Finding]:
    """``rate_limit`` for every move and axis whose mean rate exceeds the model's ``max_rate``.

    start, end : (n, k) float, mm / degrees (rotary values unwrapped, as the canonical stream
    gives them). seconds : (n,) float, duration of each move. On hybrids the drives' mean rates
    (between the drive values at start and end) are checked too.
    """
    a = np.atleast_2d(np.asarray(start, float))
    b = np.atleast_2d(np.asarray(end, float))
    t = np.broadcast_to(np.asarray(seconds, float), a.shape[:1])
    names = list(model.axes)
    delta, rates = np.abs(b - a), model.max_rates
    if model.drives:
        da, _ = model.drive_values(a)
        db, _ = model.drive_values(b)
        dd = np.stack([np.abs(db[d] - da[d]) for d in model.drives], axis=1)
        delta = np.concatenate([delta, dd], axis=1)
        rates = np.concatenate([rates, model.drive_rates])
        names += list(model.drives)
    with np.errstate(divide="ignore", invalid="ignore"):
        per_min = np.where(delta > 0, delta / t[:, None] * 60.0, 0.0)
        bad = per_min > rates * (1 + EPS)
    out: list[Finding] = []
    for i, j in zip(*np.nonzero(bad), strict=True):
        u = _unit(model, names[j])[1]
        out.append(
            Finding(
                "rate_limit",
                "error",
                f"{names[j]} moves at {per_min[i, j]:.1f} {u}, above its maximum {rates[j]:g} {u}",
                _src(sources, i),
                _mi(move_index, i),
                {
                    "axis": names[j],
                    "rate": float(per_min[i, j]),
                    "max_rate": float(rates[j]),
                    "seconds": float(t[i]),
                },
            )
        )
    return out


def unreachable_findings(
    ok: np.ndarray,
    *,
    sources: Sequence[SourceRef | None] | None = None,
    move_index: Sequence[int] | None = None,
    data=None,
) -> list[Finding]:
    """``unreachable`` for each False of an IK ``ok`` mask (n,)."""
    return [
        Finding(
            "unreachable",
            "error",
            "no axis values reach this tool pose",
            _src(sources, i),
            _mi(move_index, i),
            {} if data is None else data[i],
        )
        for i in np.flatnonzero(~np.asarray(ok, bool))
    ]
