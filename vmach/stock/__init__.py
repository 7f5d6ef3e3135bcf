"""Stock removal: blank from a spec, tool paths swept and subtracted with manifold3d.

Public API::

    from vmach.stock import Stock, parse_stock
    stock = Stock.from_spec("cylinder:d=60,l=100")
    stock.cut(tool, tips, axes)            # poses in the work frame, (n, 3) each
    stock.solid / stock.section(z) / stock.export("part.stl")

``vmach.stock.engine`` is the only module of the project that imports manifold3d.
"""

from vmach.stock.spec import parse_stock
from vmach.stock.stock import CutStats, Stock

__all__ = ["CutStats", "Stock", "parse_stock"]
