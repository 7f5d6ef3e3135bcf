"""Acceptance on the published polygon-shaft listing (../shared/reference), issue 2.

The listing is read at run time; nothing of it is copied into the project. Lines are located
in its text, and the expected moves come from an independent Python model of its loops.
"""

from __future__ import annotations

import math
import re

import pytest
from catalog import TURNMILL, reference_or_skip, split_reference

from interpreters import sinumerik
from vmach.canon import MOTIONS
from vmach.machine.control import load_control

TURN = load_control(TURNMILL)
D1, E1, STEP_FINE, STEP_ROUGH = 50.0, 1.8, 1.713, 15.323


def _line_of(lines: list[str], needle: str, start: int = 0) -> int:
    """First line (1-based, from ``start``) holding ``needle`` as whole words, outside comments."""
    pat = re.compile(r"(?<![\w])" + re.escape(needle) + r"(?![\w])")
    return next(i for i, ln in enumerate(lines) if i >= start and pat.search(ln.split(";")[0])) + 1


@pytest.fixture(scope="module")
def reference():
    return reference_or_skip()


def test_check_reports_every_static_defect_of_the_listing(reference):
    lines = reference.read_text(encoding="utf-8").splitlines()
    findings = sinumerik.check(reference, TURN)
    errors = sorted((f.kind, f.line) for f in findings if f.severity == "error")
    expected = sorted(
        [
            ("syntax", _line_of(lines, "GLODALU OBAVEZNO")),  # the stray text line without ';'
            ("proc_not_first", _line_of(lines, "PROC L_POLY")),  # parameters and PROC in one file
            # in the second edge round, a forward jump to the first round's label, which lies behind
            ("jump_direction", _line_of(lines, "GOTOF ENDDDZ", _line_of(lines, "DDZZ:"))),
            ("undefined_label", _line_of(lines, "GOTOF ENDEEEZZ")),  # label that does not exist
            ("unknown_cycle", next(i + 1 for i, ln in enumerate(lines) if ln.rstrip().endswith("C_AXIS_OF"))),
        ]
    )
    assert errors == expected  # and nothing else at error level
    warnings = [(f.kind, f.line) for f in findings if f.severity == "warning"]
    assert ("block_number_order", _line_of(lines, "N1610")) in warnings
    n1620 = _line_of(lines, "N1620")
    assert n1620 == _line_of(lines, "N1610") - 1  # N1620 stands before N1610 in the listing


def test_published_listing_stops_at_its_stray_line_as_the_control_would(reference):
    lines = reference.read_text(encoding="utf-8").splitlines()
    r = sinumerik.run(reference, TURN)
    assert not r.completed
    err = [f for f in r.findings if f.severity == "error"][-1]
    assert (err.kind, err.line) == ("syntax", _line_of(lines, "GLODALU OBAVEZNO"))


# ---- the listing split as intended ---------------------------------------------------------


def _walk(a: float, step: float) -> tuple[list[float], float]:
    """Angles a sector chain visits from ``a`` until it reaches 360, and the wrapped angle."""
    seen = []
    while a < 360.0 - 1e-9:
        seen.append(a)
        a += step
    return seen, a - 360.0


@pytest.fixture(scope="module")
def split_run(reference, tmp_path_factory):
    directory = tmp_path_factory.mktemp("split")
    main = split_reference(directory, reference)
    result = sinumerik.run(main, TURN)
    sub_lines = (directory / "L_POLY.SPF").read_text(encoding="utf-8").splitlines()
    return result, sub_lines


def _segments(result):
    """Motions grouped by the tool change that precedes them."""
    segs: list[list] = []
    for c in result.commands:
        if c.kind == "tool_change":
            segs.append([])
        elif isinstance(c, MOTIONS) and segs:
            segs[-1].append(c)
    return segs


def test_split_listing_runs_to_completion(split_run):
    result, _ = split_run
    assert result.completed, [f.render() for f in result.findings]
    assert [f for f in result.findings if f.severity == "error"] == []
    assert [c.tool for c in result.commands if c.kind == "tool_change"] == [
        "GLOD D40",
        "GLOD D40",
        "GLOD D16_15",
        "GLOD D25",
    ]


def test_finishing_moves_follow_the_polygon_formula_and_turn_forward(split_run):
    result, lines = split_run
    fine_start = _line_of(lines, "GLODPOLY:")
    fine = [
        m
        for m in _segments(result)[3]
        if m.kind == "feed" and m.source.line > fine_start and "C1=ACP(R85)" in m.source.text
    ]
    assert fine, "no finishing moves found"
    c1 = [m.axes["C1"] for m in fine]
    for m in fine:
        expected_x = D1 / 2 - E1 * math.sin(math.radians(3 * m.axes["C1"]))
        assert abs(m.axes["X"] - expected_x) < 1e-9
    steps = [b - a for a, b in zip(c1, c1[1:], strict=False)]
    assert max(abs(s - STEP_FINE) for s in steps) < 1e-9  # +1.713 each move, never unwinding


def test_move_counts_per_operation_match_the_loop_structure(split_run):
    result, lines = split_run
    rough, face, chamfer, fine = _segments(result)
    # roughing: R71 passes from 4 down to 1, R85 carries over between passes
    a, plunges = 0.0, 0
    for _ in range(4):
        seen, a = _walk(a, STEP_ROUGH)
        plunges += len(seen)
    per_plunge = [
        m
        for m in rough
        if "R71" in m.source.text
        or m.source.text.strip().endswith(("C1=ACP(R85)", "Z=-R63+R67+5", "Z=-R62+R67", "Z=30"))
    ]
    body = [
        m for m in per_plunge if _line_of(lines, "WHILE(R71>0)") < m.source.line < _line_of(lines, "ENDWHILE")
    ]
    assert len(body) == 7 * plunges
    # facing: two passes, two moves per point, plus the Z moves around each pass
    a, points = 0.0, 0
    for _ in range(2):
        seen, a = _walk(a, STEP_FINE)
        points += len(seen)
    loop = [
        m
        for m in face
        if _line_of(lines, "WHILE(R68>0)")
        < m.source.line
        < _line_of(lines, "ENDWHILE", _line_of(lines, "WHILE(R68>0)"))
    ]
    assert len(loop) == 2 * points + 2 * 2
    # chamfer: one revolution from 0
    seen, _ = _walk(0.0, STEP_FINE)
    assert len([m for m in chamfer if "C1=ACP(R85)" in m.source.text]) == len(seen)
    # finishing: R63 grows by 0.01 before each point and stops once it reaches R62 = 40
    r63, n_fine, a = 0.0, 0, 0.0
    while True:
        r63 += 0.01
        if r63 >= 40 or math.isclose(r63, 40, rel_tol=1e-12):
            break
        n_fine += 1
        a += STEP_FINE
        if a >= 360:
            a -= 360
    first, a = _walk(a, STEP_FINE)
    second, _ = _walk(a, STEP_FINE)
    edge_start = _line_of(lines, "ENDGLODPOLY:")
    fine_moves = [m for m in fine if "C1=ACP(R85)" in m.source.text and m.source.line < edge_start]
    edge_moves = [m for m in fine if "C1=ACP(R85)" in m.source.text and m.source.line > edge_start]
    assert len(fine_moves) == n_fine == 3999
    assert len(edge_moves) == len(first) + len(second)
    # the edge rounds sit at the final Z
    assert {m.axes["Z"] for m in edge_moves} == {-40 + 12.5}


def test_roughing_allowance_is_missing_in_two_sectors_as_published(split_run):
    """The listing forgets '+0.15' on the plunge in the 240-360 degree sectors: the trace shows it."""
    result, _ = split_run
    rough = _segments(result)[0]
    plunges = [
        m
        for m in rough
        if m.kind == "feed"
        and m.source.text.strip().startswith(("N1070", "N1230", "N430", "N590", "N750", "N910"))
    ]
    assert plunges
    for m in plunges:
        c = m.axes["C1"] % 360
        h = D1 / 2 - E1 * math.sin(math.radians(3 * m.axes["C1"]))
        allowance = m.axes["X"] - h
        frac = allowance - round(allowance)  # passes add whole millimetres
        expected = 0.0 if c >= 240 - 1e-9 else 0.15
        assert abs(frac - expected) < 1e-9, (c, allowance)
