"""Batches of verifications on Dask: a parametric program over a size table (the DIN 32711
P3G family of the polygon shaft) or many programs, one report per case and a summary.

- :mod:`vmach.batch.family` — the cases, the P3G sizing rules, the per-case programs.
- :mod:`vmach.batch.worker` — one case on a worker (``vmach verify`` into its directory).
- :mod:`vmach.batch.execute` — the cluster (local or ``--scheduler``), resume, progress.
- :mod:`vmach.batch.summary` — summary.json, timings.json, index.html.
"""
