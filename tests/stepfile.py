"""A STEP AP214 file of an axis-aligned box, written entity by entity (for the design loader's
tests: vmach only reads STEP, through trimesh and cascadio)."""

from __future__ import annotations

import itertools


def box_step(lo, hi) -> str:
    """The text of a STEP file holding the box from corner lo to corner hi (mm)."""
    ents: list[str] = []

    def add(s: str) -> str:
        ents.append(s)
        return f"#{len(ents)}"

    span = list(zip(lo, hi, strict=True))               # (lo, hi) per axis

    def at(corner) -> tuple[float, float, float]:
        return tuple(span[a][corner[a]] for a in range(3))

    point, vertex = {}, {}
    for c in itertools.product((0, 1), repeat=3):
        point[c] = add("CARTESIAN_POINT('',({:.6f},{:.6f},{:.6f}))".format(*at(c)))
        vertex[c] = add(f"VERTEX_POINT('',{point[c]})")
    edges: dict = {}

    def edge(a, b) -> tuple[str, bool]:
        key = tuple(sorted((a, b)))
        if key not in edges:
            d = [q - p for p, q in zip(at(key[0]), at(key[1]), strict=True)]
            n = sum(v * v for v in d) ** 0.5
            dr = add("DIRECTION('',({:.6f},{:.6f},{:.6f}))".format(*[v / n for v in d]))
            vec = add(f"VECTOR('',{dr},{n:.6f})")
            line = add(f"LINE('',{point[key[0]]},{vec})")
            edges[key] = add(f"EDGE_CURVE('',{vertex[key[0]]},{vertex[key[1]]},{line},.T.)")
        return edges[key], (a, b) == key

    faces = []
    for axis in range(3):
        for side in (0, 1):
            u, v = [a for a in range(3) if a != axis]
            corners = []
            for cu, cv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                c = [0, 0, 0]
                c[axis], c[u], c[v] = side, cu, cv
                corners.append(tuple(c))
            if (side == 1) != ((u + 1) % 3 == v):        # counter-clockwise seen from outside
                corners = corners[::-1]
            oriented = []
            for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
                e, same = edge(a, b)
                oriented.append(add(f"ORIENTED_EDGE('',*,*,{e},{'.T.' if same else '.F.'})"))
            loop = add(f"EDGE_LOOP('',({','.join(oriented)}))")
            bound = add(f"FACE_OUTER_BOUND('',{loop},.T.)")
            origin = add("CARTESIAN_POINT('',({:.6f},{:.6f},{:.6f}))".format(*at(corners[0])))
            normal = [0.0, 0.0, 0.0]
            normal[axis] = 1.0 if side else -1.0
            ref = [0.0, 0.0, 0.0]
            ref[u] = 1.0
            nd = add("DIRECTION('',({},{},{}))".format(*normal))
            rd = add("DIRECTION('',({},{},{}))".format(*ref))
            place = add(f"AXIS2_PLACEMENT_3D('',{origin},{nd},{rd})")
            plane = add(f"PLANE('',{place})")
            faces.append(add(f"ADVANCED_FACE('',({bound}),{plane},.T.)"))
    shell = add(f"CLOSED_SHELL('',({','.join(faces)}))")
    brep = add(f"MANIFOLD_SOLID_BREP('box',{shell})")
    origin = add("CARTESIAN_POINT('',(0.,0.,0.))")
    place = add(f"AXIS2_PLACEMENT_3D('',{origin},$,$)")
    mm = add("( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) )")
    rad = add("( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) )")
    sr = add("( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() )")
    unc = add(f"UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),{mm},'distance_accuracy_value','')")
    ctx = add(f"( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT(({unc})) "
              f"GLOBAL_UNIT_ASSIGNED_CONTEXT(({mm},{rad},{sr})) REPRESENTATION_CONTEXT('',''))")
    rep = add(f"ADVANCED_BREP_SHAPE_REPRESENTATION('',({place},{brep}),{ctx})")
    app = add("APPLICATION_CONTEXT('automotive design')")
    pctx = add(f"PRODUCT_CONTEXT('',{app},'mechanical')")
    prod = add(f"PRODUCT('box','box','',({pctx}))")
    form = add(f"PRODUCT_DEFINITION_FORMATION('','',{prod})")
    dctx = add(f"PRODUCT_DEFINITION_CONTEXT('part definition',{app},'design')")
    pdef = add(f"PRODUCT_DEFINITION('design','',{form},{dctx})")
    shape = add(f"PRODUCT_DEFINITION_SHAPE('','',{pdef})")
    add(f"SHAPE_DEFINITION_REPRESENTATION({shape},{rep})")
    body = "\n".join(f"#{i}={e};" for i, e in enumerate(ents, start=1))
    return ("ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('box'),'2;1');\n"
            "FILE_NAME('box.step','2026-01-01T00:00:00',(''),(''),'','','');\n"
            "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n"
            + body + "\nENDSEC;\nEND-ISO-10303-21;\n")
