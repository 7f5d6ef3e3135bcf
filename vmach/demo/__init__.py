"""The instructor's demo: the polygon-shaft family verified and one size's cut animated
(:mod:`vmach.demo.animation`, :mod:`vmach.demo.polygon`)."""
