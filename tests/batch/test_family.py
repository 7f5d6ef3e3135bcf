"""The P3G and P4C families' cases: sizing rules against the fixture's hand-made sizes, the
per-case program and setup, a P4C size verified end to end, and clear usage errors."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

from vmach.batch.family import (
    INSERT_DEPTH,
    family_cases,
    materialise,
    p3g_parameters,
    p3g_table,
    p4c_parameters,
    rewritten,
)
from vmach.errors import InputError

FIX = Path(__file__).resolve().parents[2] / "fixtures" / "polygon_shaft"


def r_values(path: Path) -> dict[int, float]:
    out = {}
    for line in path.read_text().splitlines():
        m = re.match(r"N\d+\s+R(\d+)=([-\d.]+)", line)
        if m:
            out[int(m.group(1))] = float(m.group(2))
    return out


@pytest.mark.parametrize("size", [14, 50])
def test_rules_make_the_fixture_programs(size):
    """POLY14 and POLY50 were sized by hand from the drawing: the rules give their R values."""
    params, setup = p3g_parameters(*next(r for r in p3g_table() if r[0] == size))
    assert {k: params[k] for k in r_values(FIX / f"POLY{size}.MPF")} == r_values(FIX / f"POLY{size}.MPF")
    assert setup["profile"] == f"P3G:{size}"


def test_largest_size_takes_the_big_finishing_cutter():
    params, setup = p3g_parameters(100, 4.5)
    hand = r_values(FIX / "POLY100.MPF")
    assert params[64] == hand[64] == 16 and params[62] == hand[62] and params[59] == hand[59]
    assert params[66] == hand[66] == 6 and params[68] == hand[68] == 6   # on a Ø110 blank, not Ø112
    assert setup["profile_z"] == "-55:-5"


def test_every_size_roughs_within_the_inserts():
    """The first roughing pass never cuts deeper into the blank than the inserts' 5.5 mm, the
    blank is above d2, and the finishing cutter's face holds the contact's 3*e1 swing."""
    table = p3g_table()
    assert len(table) == 23
    for d1, e1 in table:
        p, setup = p3g_parameters(d1, e1)
        blank = float(re.search(r"d=([\d.]+)", setup["stock"]).group(1))
        assert blank >= p[58] + 1
        for passes in (p[66], p[68]):                       # roughing, facing
            first = d1 / 2 - e1 + (passes - 1) + 0.15           # the program's XS at SIN = 1
            assert blank / 2 - first <= INSERT_DEPTH - 0.5 + 1e-9
        assert 3 * e1 < p[64] - 0.5


def test_rewritten_program_and_case_directory(tmp_path):
    case = family_cases(FIX / "POLY.MPF", "P3G", "14")[0]
    prog = materialise(case, tmp_path / case.name)
    assert r_values(prog) == r_values(FIX / "POLY14.MPF") | {63: 0.0, 67: 20.0, 69: 20.0, 65: 0.01}
    assert (prog.parent / "P3G_SHAFT.SPF").read_bytes() == (FIX / "P3G_SHAFT.SPF").read_bytes()
    setup = tomllib.loads((prog.parent / "vmach.toml").read_text())
    assert setup["stock"] == case.setup["stock"] and setup["tools"] == "tools.toml"
    assert (prog.parent / "tools.toml").is_file() and "programs" not in setup
    with pytest.raises(InputError):
        rewritten("N10 R56=1\n", {56: 2.0, 57: 3.0})      # R57 assigned nowhere


def test_case_key_follows_its_inputs():
    a, b = family_cases(FIX / "POLY.MPF", "P3G", "14,16")
    assert a.key() != b.key() and a.key() == family_cases(FIX / "POLY.MPF", "P3G", "14")[0].key()


@pytest.mark.parametrize("family,sizes", [("P4C", "all"), ("P5X", "all"), ("P3G", "13"), ("P3G", "a")])
def test_bad_family_or_size_is_a_usage_error(family, sizes):
    with pytest.raises(InputError) as exc:
        family_cases(FIX / "POLY.MPF", family, sizes)
    assert exc.value.exit_code == 2


@pytest.mark.parametrize("argv", [["batch", "{fix}/POLY.MPF", "--family", "P4C"],
                                  ["batch", "{fix}/POLY.MPF", "{fix}/POLY50.MPF", "--family", "P3G"],
                                  ["batch", "{fix}/POLY.MPF", "--workers", "0"],
                                  ["demo", "polygon-shaft", "--size", "13"],
                                  ["demo", "polygon-shaft", "--frames", "1"]])
def test_commands_refuse_bad_usage_before_any_work(argv, tmp_path, capsys):
    from vmach.cli import main

    out = tmp_path / "out"
    assert main([a.format(fix=FIX) for a in argv] + ["--out", str(out)]) == 2
    assert "error[usage]" in capsys.readouterr().err and not out.exists()


def test_p4c_rules_make_the_fixture_program():
    """POLY4C (P4C 35x30/5) and its setup in vmach.toml were written by hand: the rules agree."""
    params, setup = p4c_parameters(35, 30, 5)
    hand = r_values(FIX / "POLY4C.MPF")
    assert {k: params[k] for k in hand} == hand
    own = tomllib.loads((FIX / "vmach.toml").read_text())["programs"]["POLY4C"]
    assert setup["profile"] == own["profile"] == "P4C:35x30/5"
    assert setup["stock"] == own["stock"] == "cylinder:d=34.983,l=88"
    assert setup["profile_z"] == own["profile_z"]


def test_p4c_cases_come_from_designations():
    a, b = family_cases(FIX / "POLY4C.MPF", "P4C", "35x30, 40x34/5.5")
    assert (a.name, a.label, a.params[57]) == ("P4C_35x30", "35x30/5", 5.0)   # e = d2/6 when not given
    assert (b.name, b.params[56], b.params[58], b.params[57]) == ("P4C_40x34", 40.0, 34.0, 5.5)
    assert b.setup["profile"] == "P4C:40x34/5.5"
    for bad in ("35", "30x35", "all"):
        with pytest.raises(InputError) as exc:
            family_cases(FIX / "POLY4C.MPF", "P4C", bad)
        assert exc.value.exit_code == 2
    with pytest.raises(InputError) as exc:              # a flank wider than every finishing face
        p4c_parameters(60, 40, 40 / 6)
    assert exc.value.kind == "family"


@pytest.mark.slow
def test_a_p4c_size_verifies_within_its_band(tmp_path):
    """P4C 16x14 made from the four-lobe program by the rules: the part's profile lies in the
    g6 band of d1 = 16 at every station (the bar's circle included), and no error."""
    import json

    from vmach.cli import main

    case = family_cases(FIX / "POLY4C.MPF", "P4C", "16x14")[0]
    prog = materialise(case, tmp_path / case.name)
    out = tmp_path / "out"
    code = main(["verify", str(prog), "--out", str(out), "--no-images", "--quiet"])
    report = json.loads((out / "report.json").read_text())
    assert code == 0 or all(f["severity"] != "error" for f in report["findings"])
    prof = report["profile"]
    assert prof["type"] == "P4C" and prof["pass"] is True, prof
    lo, hi = prof["tolerance_mm"]
    assert len(prof["stations"]) >= 2
    for st in prof["stations"]:
        assert st["found"] and lo <= st["min_deviation_mm"] and st["max_deviation_mm"] <= hi, st
