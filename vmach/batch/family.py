"""Cases of a batch: one parametric program over a size table, or many programs as they are.

A **parametric program** is an ordinary program (it verifies alone, as written) whose R
assignments ``N.. R56=50`` are rewritten per case: each case gets its own directory holding the
rewritten program, copies of the files it calls or names (subprograms, the tool library) and a
``vmach.toml`` with the case's stock and profile — so a case is self-contained, can be verified
again by hand (``vmach verify CASE/POLY.MPF``) and a remote worker needs nothing else.

The P3G family (DIN 32711, ``vmach/checks/data/din32711.csv``) sizes the polygon-shaft program
by rules stated in :func:`p3g_parameters` (docs/batch.md), reproducing the fixture's POLY14,
POLY50 and POLY100 where they apply. The P4C family (DIN 32712) sizes the four-lobe program
(fixtures/polygon_shaft/POLY4C.MPF) by :func:`p4c_parameters`; vmach holds no DIN 32712 size
table, so its sizes are given as designations ``d1xd2`` or ``d1xd2/e``.
"""

from __future__ import annotations

import hashlib
import math
import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from vmach.errors import InputError
from vmach.output import atomic_writer, make_dir

#: families a parametric program can be run over (name -> the profile kind it makes)
FAMILIES = ("P3G", "P4C")

#: polygon length R62 by d1: POLY14, POLY50 and POLY100 of the fixture, interpolated between
LENGTH_D1 = (14.0, 50.0, 100.0)
LENGTH_MM = (12.0, 40.0, 60.0)

#: the cutters' sizes the polygon-shaft program relies on (fixtures/polygon_shaft/tools.toml)
INSERT_DEPTH = 5.5      # mm, largest depth of cut of the D40 face mill's inserts
DEPTH_MARGIN = 0.5      # mm: the first pass stays this far inside the inserts' depth (at P3G-75 a
                        # first facing pass 5.5 mm deep ran the shank 0.5 mm³ into the corners)
FIN_RADII = (12.5, 16.0)  # mm, GLOD D25 and GLOD D32: the smaller one whose face holds 3*e1


@dataclass(frozen=True)
class Case:
    """One verification of a batch.

    name : directory name of the case under the batch's output (``P3G_050``, ``PLATE``).
    program : the program to verify (the parametric program for a family case).
    params : R number -> value written into the case's copy of the program (empty: as it is).
    setup : vmach.toml keys of the case (stock, profile, profile_z ...), beside the ones the
        program's own vmach.toml gives (empty: the program's own).
    label : what the summary's first column shows (``d1 = 50``, the file name).
    """

    name: str
    program: Path
    params: dict[int, float] = field(default_factory=dict)
    setup: dict[str, str] = field(default_factory=dict)
    label: str = ""

    def key(self) -> str:
        """A digest of what the case verifies (program text, its parameters and setup): a
        resumed batch redoes a case whose inputs changed."""
        h = hashlib.sha256(self.program.read_bytes())
        h.update(repr(sorted(self.params.items())).encode())
        h.update(repr(sorted(self.setup.items())).encode())
        return h.hexdigest()[:16]


def p3g_table() -> list[tuple[float, float]]:
    """The DIN 32711 P3G sizes (d1, e1), mm, ascending."""
    from vmach.checks.polygon import p3g_sizes

    return sorted(p3g_sizes().items())


def p3g_parameters(d1: float, e1: float, fit: str = "g6") -> tuple[dict[int, float], dict[str, str]]:
    """The polygon-shaft program's R parameters and the case's setup for one P3G size.

    Rules (mm): d2 = d1 + 2 e1; polygon length R62 interpolated over POLY14/50/100 (12, 40,
    60); blank: the even diameter at least 1 mm over d2, R62 + 60 long; finishing cutter
    radius R64 the smallest of 12.5 / 16 whose face holds the contact's 3 e1 swing (the
    program's own TOO_SMALL test, 3 e1 < R64 - 0.5); roughing passes R66 (at least 3) and
    facing passes R68 (at least 2) so that the first pass cuts at most 5 mm (the inserts' 5.5
    less a 0.5 mm margin) into the blank at the profile's smallest radius; flank offset R59 the
    middle of the g6 band on d1 (a quarter of the sum of its diameter deviations); profile
    check from 2 mm (short polygons) or 5 mm above the shoulder to 4 mm (the 3 mm chamfer) or
    5 mm below the end.
    """
    from vmach.checks.iso286 import limits

    d2 = round(d1 + 2 * e1, 4)
    length = float(round(np.interp(d1, LENGTH_D1, LENGTH_MM)))
    blank_d = 2 * math.ceil((d2 + 1.0) / 2)
    r64 = next((r for r in FIN_RADII if 3 * e1 < r - 0.5), None)
    if r64 is None:
        raise InputError(f"P3G d1={d1:g}: 3*e1 = {3 * e1:g} mm exceeds every finishing cutter's face",
                         kind="family")
    # passes that keep the first one's depth into the blank (at the profile's smallest radius
    # d1/2 - e1, XS = that + passes - 1 + 0.15) within the inserts less DEPTH_MARGIN
    needed = math.ceil(blank_d / 2 - d1 / 2 + e1 + 0.85 - (INSERT_DEPTH - DEPTH_MARGIN) - 1e-9)
    rough = max(3, needed)
    facing = max(2, needed)
    lim = limits(fit, d1)
    r59 = round((lim.lower + lim.upper) / 4, 6)
    params = {56: d1, 57: e1, 58: d2, 62: length, 63: 0.0, 64: r64, 65: 0.01, 66: float(rough),
              67: 20.0, 69: 20.0, 68: float(facing), 59: r59}
    short = length < 30
    z = f"{-(length - (2 if short else 5)):g}:{-4 if short else -5}"
    setup = {"stock": f"cylinder:d={blank_d:g},l={length + 60:g}", "profile": f"P3G:{d1:g}",
             "profile_z": z}
    return params, setup


def p4c_parameters(d1: float, d2: float, e: float,
                   fit: str = "g6") -> tuple[dict[int, float], dict[str, str]]:
    """The four-lobe program's R parameters and the case's setup for one P4C size ``d1xd2/e``.

    Rules (mm), as for P3G where they carry over: polygon length R62 interpolated over d1 as
    for P3G; blank: the bar turned to d1 in the middle of its g6 band (its circle truncates the
    corners, so it is part of the profile), R62 + 60 long; finishing cutter radius R64 the
    smaller of 12.5 / 16 whose face covers the flank's chord, sqrt(d1²/4 − d2²/4), with 0.5 to
    spare (the program's TOO_SMALL test); roughing passes R66 (at least 3) so that the first
    cuts at most 5 mm into the bar; flank offset R59 the middle of the g6 band on d1; profile
    stations where the finishing cutter's round face spans the flank's whole chord (the program
    does not face the shoulder, so the flank's ends next to it are left to the roughing cutter).
    """
    from vmach.checks.iso286 import limits

    chord = math.sqrt(max(d1 * d1 / 4 - d2 * d2 / 4, 0.0))
    r64 = next((r for r in FIN_RADII if chord < r - 0.5), None)
    if r64 is None:
        raise InputError(f"P4C {d1:g}x{d2:g}: the flank's chord {chord:.3g} mm either side exceeds every "
                         "finishing cutter's face", kind="family")
    length = float(round(np.interp(d1, LENGTH_D1, LENGTH_MM)))
    needed = math.ceil(d1 / 2 - d2 / 2 + 0.85 - (INSERT_DEPTH - DEPTH_MARGIN) - 1e-9)
    lim = limits(fit, d1)
    r59 = round((lim.lower + lim.upper) / 4, 6)
    params = {56: d1, 57: e, 58: d2, 62: length, 63: 0.0, 64: r64, 65: 0.01, 66: float(max(3, needed)),
              67: 20.0, 59: r59}
    # the profile is checked where the finishing face spans the whole flank: at least m mm from
    # the shaft's end and the shoulder, m the depth of the round face's chord at the flank's width
    m = max(4, math.ceil(r64 - math.sqrt(r64 * r64 - chord * chord)) + 1)
    z = f"{-(length - m):g}:{-m}"
    setup = {"stock": f"cylinder:d={d1 + 2 * r59:g},l={length + 60:g}", "profile": f"P4C:{d1:g}x{d2:g}/{e:g}",
             "profile_z": z}
    return params, setup


def p4c_cases(program: Path, sizes: str) -> list[Case]:
    """The P4C cases of ``program``: ``sizes`` a comma list of designations d1xd2[/e]."""
    from vmach.checks.polygon import parse_profile

    if sizes.strip().lower() == "all":
        raise InputError("--family P4C --sizes all: vmach holds no DIN 32712 size table; give the sizes "
                         "as designations, e.g. --sizes 35x30,40x34/5.5", kind="usage")
    cases = []
    for tok in sizes.split(","):
        try:
            poly = parse_profile(f"P4C:{tok.strip()}")
        except InputError as exc:
            raise InputError(f"--sizes {tok.strip()}: {exc.message}", kind="usage") from None
        d2 = float(poly.d2_flats or 0.0)
        params, setup = p4c_parameters(poly.d1, d2, poly.e)
        name = f"P4C_{poly.d1:g}x{d2:g}".replace(".", "_")
        cases.append(Case(name, program, params, setup, f"{poly.d1:g}x{d2:g}/{poly.e:g}"))
    return cases


def family_cases(program: Path, family: str, sizes: str) -> list[Case]:
    """The cases of ``program`` over ``family``'s sizes: ``all`` or a comma list of d1 (P3G),
    a comma list of designations d1xd2[/e] (P4C)."""
    fam = family.upper()
    if fam == "P4C":
        return p4c_cases(program, sizes)
    if fam not in FAMILIES:
        raise InputError(f"--family {family}: one of {', '.join(FAMILIES)}", kind="usage")
    table = p3g_table()
    if sizes.strip().lower() != "all":
        wanted = []
        for tok in sizes.split(","):
            try:
                wanted.append(float(tok))
            except ValueError:
                raise InputError(f"--sizes {sizes}: d1 values separated by commas, or all",
                                 kind="usage") from None
        known = dict(table)
        missing = [w for w in wanted if w not in known]
        if missing:
            raise InputError(f"--sizes: {', '.join(f'{m:g}' for m in missing)} not in the DIN 32711 "
                             f"table ({', '.join(f'{d:g}' for d, _ in table)})", kind="usage")
        table = [(w, known[w]) for w in wanted]
    cases = []
    for d1, e1 in table:
        params, setup = p3g_parameters(d1, e1)
        cases.append(Case(f"{fam}_{d1:05.1f}".replace(".0", "").replace(".", "_"), program, params, setup,
                          f"d1 = {d1:g}"))
    return cases


def file_cases(programs: list[Path]) -> list[Case]:
    """One case per program, verified as it is (names made unique by a number)."""
    seen: dict[str, int] = {}
    cases = []
    for p in programs:
        if not p.is_file():
            raise InputError(f"{p}: no such file", kind="unreadable")
        base = re.sub(r"[^A-Za-z0-9_.-]", "_", p.stem)
        seen[base] = seen.get(base, 0) + 1
        name = base if seen[base] == 1 else f"{base}_{seen[base]}"
        cases.append(Case(name, p, label=p.name))
    return cases


_ASSIGN = re.compile(r"^(\s*(?:N\d+\s+)?R(\d+)\s*=\s*)([-+]?[\d.]+)", re.IGNORECASE)


def rewritten(text: str, params: dict[int, float]) -> str:
    """``text`` with the value of each ``R<n>=<number>`` assignment that starts a line (after
    its block number) replaced by ``params[n]``; every parameter must be assigned somewhere."""
    found: set[int] = set()
    out = []
    for line in text.splitlines(keepends=True):
        m = _ASSIGN.match(line)
        if m and int(m.group(2)) in params:
            n = int(m.group(2))
            found.add(n)
            line = f"{m.group(1)}{params[n]:.6g}{line[m.end():]}"
        out.append(line)
    missing = sorted(set(params) - found)
    if missing:
        raise InputError(f"the parametric program assigns no {', '.join(f'R{n}' for n in missing)} "
                         "(a line 'N.. R<n>=<value>')", kind="family")
    return "".join(out)


def materialise(case: Case, case_dir: Path) -> Path:
    """Write the case's program into ``case_dir`` (with the other files of its directory it
    may call — subprograms, the tool library its vmach.toml names — and a vmach.toml holding
    the case's setup over the program's own); return the program to verify there."""
    if not case.params and not case.setup:
        return case.program
    make_dir(case_dir)
    src = case.program.parent
    for f in src.iterdir():
        if f.is_file() and f.suffix.lower() == ".spf":
            shutil.copyfile(f, case_dir / f.name)
    toml = _setup_text(src, case.setup, case_dir)
    with atomic_writer(case_dir / "vmach.toml") as fh:
        fh.write(toml)
    target = case_dir / case.program.name
    with atomic_writer(target) as fh:
        fh.write(rewritten(case.program.read_text(encoding="utf-8"), case.params))
    return target


def _setup_text(src: Path, setup: dict[str, str], case_dir: Path) -> str:
    """The case's vmach.toml: machine and tools of the program's own (the tool library copied
    beside the case), the case's keys over the rest."""
    import tomllib

    own: dict = {}
    if (src / "vmach.toml").is_file():
        own = tomllib.loads((src / "vmach.toml").read_text(encoding="utf-8"))
    own.pop("programs", None)
    if isinstance(own.get("tools"), str):
        lib = (src / own["tools"]).resolve()
        if lib.is_file():
            shutil.copyfile(lib, case_dir / "tools.toml")
            own["tools"] = "tools.toml"
    own.update(setup)
    lines = ["# written by vmach batch: this case's setup (docs/batch.md)\n"]
    for k, v in own.items():
        if isinstance(v, str):
            lines.append(f'{k} = "{v}"\n')
        elif isinstance(v, bool):
            lines.append(f"{k} = {'true' if v else 'false'}\n")
        elif isinstance(v, int | float):
            lines.append(f"{k} = {v!r}\n")
    return "".join(lines)
