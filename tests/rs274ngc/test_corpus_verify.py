"""#37: every LinuxCNC example program of ``../shared/corpus/rs274ngc`` runs end to end in
``vmach verify`` on a fitting model (the lathe programs on ``lathe``, one with an A axis on
``mill5ac``, the others on ``s5d``),
with LinuxCNC's sim tool tables; the three that LinuxCNC's own ``rs274`` stops with these
tables stop in verify at the same line with the same kind (the corpus runner's ``rs274:``
column shows the real interpreter's outcome)."""

from __future__ import annotations

import shutil

import pytest
from catalog import ROOT, shared_or_skip

from vmach.verify import VerifyOptions, verify

CORPUS = ROOT.parent / "shared" / "corpus"
LATHE = {"linuxcnc_g76.ngc", "linuxcnc_lathe_g70_71_demo.ngc", "linuxcnc_lathe_g7x_face_boring.ngc",
         "linuxcnc_lathe_g7x_quadrants.ngc", "linuxcnc_lathe_pawn.ngc", "linuxcnc_lathecomp.ngc",
         "linuxcnc_threading.ngc"}
#: programs that turn an A axis: the table-table A/C mill (s5d turns B and C)
A_AXIS = {"linuxcnc_daisy.ngc"}
#: where rs274 2.9 itself stops these programs with the corpus's tool tables: (kind, line)
RS274_STOPS = {"linuxcnc_cone.ngc": ("bad_character", 34), "linuxcnc_g76.ngc": ("comp_entry_short", 26),
               "linuxcnc_mmount.ngc": ("tool_not_found", 200)}
#: the corpus's main programs (touchoff.ngc is the subroutine linuxcnc_x-trim.ngc calls)
MAINS = sorted(p.name for p in CORPUS.joinpath("rs274ngc").glob("linuxcnc_*.ngc")) if CORPUS.is_dir() else []


def test_the_corpus_holds_the_linuxcnc_examples():
    shared_or_skip(CORPUS / "README.md", "the development corpus")
    assert len(MAINS) == 31


@pytest.mark.slow
@pytest.mark.parametrize("name", MAINS)
def test_linuxcnc_example_runs_end_to_end_in_verify(name, tmp_path):
    src = shared_or_skip(CORPUS / "rs274ngc" / name, "LinuxCNC example")
    for f in (src, CORPUS / "rs274ngc" / "touchoff.ngc"):
        shutil.copyfile(f, tmp_path / f.name)
    lathe = name in LATHE
    table = tmp_path / "tools.tbl"
    shutil.copyfile(CORPUS / "tools" / ("lathe.tbl" if lathe else "sim.tbl"), table)
    tools = ROOT / "fixtures" / "tools" / "turning.toml" if lathe else CORPUS / "tools" / "generic_mill.toml"
    machine = "lathe" if lathe else "mill5ac" if name in A_AXIS else "s5d"
    rep = verify(tmp_path / name, VerifyOptions(machine=machine, tools=str(tools),
                                                default_tool="flat:d=6", images=False,
                                                dialect_options={"tool_table": str(table)}))
    if name in RS274_STOPS:
        first = next(f for f in rep.findings if f.is_error)
        assert (first.kind, first.source.line) == RS274_STOPS[name]
        return
    errors = [f.render() for f in rep.findings if f.is_error]
    assert rep.result is not None and rep.result.completed, errors[:5]
    assert rep.table is not None and rep.stopped_at is None
