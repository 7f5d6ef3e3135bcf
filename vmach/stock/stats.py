"""What a :class:`vmach.stock.Stock` counted and measured while it cut (``stock.stats``)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class CutStats:
    """Counters of a stock's life (seconds, counts).

    cutters : cutters made; culled : cutters that miss the stock; covered : placed poses left
    out because a translation hull contains them; fans : fan cutters (:mod:`vmach.stock.fan`)
    and fan_poses : the poses they cover; fan_overcut_mm : the largest bridge of a fan's hull
    over the floor its tool's side sweeps, measured (mm), where no other pose of the path cuts
    anyway; fan_covered_mm : the largest such bridge where other poses of the path do (a
    helix's other turns; :func:`vmach.stock.fan_measure.covered`); cusp_poses : placed poses added
    between samples against the cusps of a curved side (:mod:`vmach.stock.cusps`), and
    cusp_fins : those cut as their fin only (:func:`vmach.stock.cusps.fin_widths`); inner_fins :
    placed poses between two placed rotary steps cut as their fin (:mod:`vmach.stock.strategies.fins`);
    foot_steps : steps parted against the feet of a flat face's rim (:mod:`vmach.stock.feet`); columns :
    column cutters (:mod:`vmach.stock.column`) and column_cells : the turns' cells they hold;
    column_overcut_mm : the deepest a column's face chain lies below one of its turns' own, or
    its hull bridges a floor beyond what the path cuts anyway (mm; also in fan_overcut_mm);
    axial_runs : translation runs along the tool's axis cut as the tool at their inner pose
    (:func:`vmach.stock.strategies.runs.claim_axial`);

    sweep_seconds : making cutters; boolean_seconds : batch booleans (in the worker process
    too, where they overlap the sweep); wait_seconds : waiting for the worker.
    """

    paths: int = 0
    poses: int = 0
    cutters: int = 0
    culled: int = 0
    covered: int = 0
    fans: int = 0
    fan_poses: int = 0
    fan_overcut_mm: float = 0.0
    fan_covered_mm: float = 0.0
    cusp_poses: int = 0
    cusp_fins: int = 0
    inner_fins: int = 0
    foot_steps: int = 0
    columns: int = 0
    column_cells: int = 0
    axial_runs: int = 0
    column_overcut_mm: float = 0.0
    batches: int = 0
    sweep_seconds: float = 0.0
    boolean_seconds: float = 0.0
    wait_seconds: float = 0.0
