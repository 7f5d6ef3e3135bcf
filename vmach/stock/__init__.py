"""Stock removal: blank from a spec, tool paths swept and subtracted with manifold3d.

Public API::

    from vmach.stock import Stock, parse_stock
    stock = Stock.from_spec("cylinder:d=60,l=100")
    stock.cut(tool, tips, axes)            # poses in the work frame, (n, 3) each
    stock.solid / stock.section(z) / stock.export("part.stl")
    stock.provenance                       # (cutters, 2): the program rows of each cutter

A path becomes a cut solid in three modules: :mod:`vmach.stock.plan` (the path into typed jobs,
by the cutter strategies of :mod:`vmach.stock.strategies`), :mod:`vmach.stock.make` (jobs into
trimmed cutters) and :mod:`vmach.stock.queue` (cutters subtracted in checked batches); see
docs/stock.md. ``vmach.stock.engine`` is the only module of the project that imports manifold3d.
"""


__all__ = ["CutStats", "Stock", "parse_stock"]


def __getattr__(name: str):
    """The public names, imported when first asked for: the boolean worker process
    (:mod:`vmach.stock.remote`) imports only :mod:`vmach.stock.engine` and its batches."""
    if name == "parse_stock":
        from vmach.stock.spec import parse_stock

        return parse_stock
    if name == "CutStats":
        from vmach.stock.stats import CutStats

        return CutStats
    if name == "Stock":
        from vmach.stock.stock import Stock

        return Stock
    raise AttributeError(f"module 'vmach.stock' has no attribute {name!r}")
