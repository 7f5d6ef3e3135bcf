"""``vmach verify``: the whole pipeline for one program, as a function that returns a Report.

    text -> blocks -> interpreter -> canonical commands -> move table -> kinematics
         -> stock removal / collisions / limits / profile -> findings -> report (JSON, PNG)

Each stage is timed; each stage that fails on bad input raises a VmachError (clear diagnostic,
no traceback), and a program error stops the pipeline after the interpreter's findings are in.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

import interpreters
from vmach import __version__, coverage
from vmach.canon import RunOptions, RunResult
from vmach.checks import probing
from vmach.checks.process import spindle_off_cuts, turning_rows, unknown_tools, zero_feeds
from vmach.errors import InputError
from vmach.files import input_file
from vmach.findings import Finding, sort_key
from vmach.machine.oriented import needs_resolving
from vmach.machine.oriented import resolve as resolve_orientation
from vmach.motion import MoveTable, build
from vmach.setup import Setup, read_setup, resolve_model, setting, with_offsets
from vmach.tol import ACCURACY, tol


@dataclass
class VerifyOptions:
    """What the user asked for; None means: from the setup file beside the program."""

    machine: str | None = None
    tools: str | None = None
    stock: str | None = None
    profile: str | None = None
    profile_z: str | None = None
    profile_stations: int = 7
    fit: str = "g6"
    out: Path | None = None
    images: bool = True
    max_blocks: int = tol.max_blocks
    quiet: bool = True
    export: tuple[str, ...] = ()
    clearance: float = 1.0  # near-miss distance for rapids, mm
    accuracy: str | None = None  # stock simulation preset (vmach.tol.ACCURACY); None: setup, else standard
    dialect: str | None = None  # None: by the extension, or the machine's (interpreters.dialect_for)
    design: str | None = None  # the part's design (.stl/.3mf/.ply/.step), compared with the cut part
    design_tolerance: str | None = None  # "+0.05/-0.02" mm (vmach.checks.design.parse_band)
    design_offset: str | None = None  # "X,Y,Z" mm: the design moved in the workpiece frame
    default_tool: str | None = None  # stand-in for tools the library lacks (vmach.tooling.default)
    progress: Any = None  # vmach.progress.Progress told of each phase (None: nothing shown)
    #: a dialect's own settings (RunOptions.dialect_options: LinuxCNC tool table, INI, .var)
    dialect_options: dict = field(default_factory=dict)


@dataclass
class Report:
    program: str
    setup: Setup
    result: RunResult | None = None
    table: MoveTable | None = None
    model: Any = None
    machine_path: Path | None = None
    tools_path: Path | None = None
    stock_spec: str | None = None
    findings: list[Finding] = field(default_factory=list)
    profile: dict | None = None
    cycle: dict | None = None
    images: dict[str, str] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    part: Any = None  # the simulated stock (vmach.stock.Stock) when there was one
    timing: Any = None  # vmach.motion.timing.Timing
    sim: Any = None  # vmach.stock.simulate.SimResult
    library: Any = None  # vmach.tooling.ToolLibrary
    profile_spec: str | None = None
    accuracy: str = "standard"  # the stock simulation's preset (vmach.tol.ACCURACY)
    design: Any = None  # vmach.checks.design_findings.DesignOutcome with --design
    skipped: dict[str, str] = field(default_factory=dict)  # stage -> why it did not run (coverage)
    stopped_at: Any = None  # SourceRef of the error that stopped an unfinished run (coverage)

    @property
    def errors(self) -> int:
        return sum(f.severity == "error" for f in self.findings)

    def simulation(self) -> dict[str, Any] | None:
        """What the stock simulation did and the error it allows (mm), or None without one.
        ``error_bounds_mm``: the flat-face scallop of the sampled rotary steps (the P3G flanks'
        bound), the most a fan or column cutter removes beyond the true sweep (measured on
        every one),
        the tool polygon in directions its turn does not make exact, the estimated cusps of
        curved sides between placed poses, the blank's polygon (docs/stock.md)."""
        if self.sim is None or self.part is None:
            return None
        from vmach.tol import tol

        st = self.part.stats
        return {
            "accuracy": self.accuracy,
            "partial": self.stopped_at is not None,
            "rim_arcs": bool(self.part.arcs),
            "moves": int(self.sim.moves),
            "poses": int(self.sim.samples),
            "cutters": int(st.cutters),
            "fan_cutters": int(st.fans),
            "column_cutters": int(st.columns),
            "cusp_poses": int(st.cusp_poses),
            "cusp_fins": int(st.cusp_fins),
            "max_rotary_step_deg": round(float(self.sim.max_step_deg), 4),
            "error_bounds_mm": {
                "face_scallop": round(float(self.sim.bound_mm), 5),
                "fan_overcut": round(float(st.fan_overcut_mm), 5),
                "tool_polygon": float(self.part.chord),
                "side_cusps": float(self.part.cusp),
                "blank_polygon": float(tol.blank_chord),
            },
        }

    def to_json(self) -> dict[str, Any]:
        findings = sorted(self.findings, key=sort_key)
        res = self.result
        cycle = None if self.stopped_at is not None else self.cycle    # never for an unfinished run
        return {
            "vmach": __version__,
            "program": {
                "path": self.program,
                "completed": None if res is None else res.completed,
                "blocks": None if res is None else res.blocks,
                "moves": None if self.table is None else len(self.table),
                "stopped_at": None if self.stopped_at is None
                else {"file": self.stopped_at.path, "line": self.stopped_at.line},
            },
            "partial": self.stopped_at is not None,
            "skipped": dict(self.skipped),
            "machine": None
            if self.machine_path is None
            else {
                "path": str(self.machine_path),
                "name": getattr(self.model, "name", self.machine_path.stem),
                "axes": list(self.table.axes) if self.table is not None else None,
            },
            "tools": None if self.tools_path is None else str(self.tools_path),
            "stock": self.stock_spec,
            "summary": {
                "errors": self.errors,
                "warnings": sum(f.severity == "warning" for f in self.findings),
                "infos": sum(f.severity == "info" for f in self.findings),
            },
            "findings": [_finding_json(f) for f in findings],
            "simulation": self.simulation(),
            "profile": self.profile,
            "design": None if self.design is None else self.design.to_json(),
            "cycle_time_s": None if cycle is None else cycle["total_s"],
            "cycle_time": cycle,
            "images": dict(self.images),
            "timings_s": {k: round(v, 4) for k, v in self.timings.items()},
        }


def _finding_json(f: Finding) -> dict[str, Any]:
    d = f.to_json()
    d.setdefault("move_index", f.move_index)
    for k, v in list(d.items()):
        if isinstance(v, np.generic):
            d[k] = v.item()
    return d


class _Clock:
    def __init__(self, report: Report, progress=None):
        self.report = report
        self.progress = progress

    def __call__(self, name: str):
        report, progress = self.report, self.progress

        class _T:
            def __enter__(self):
                if progress is not None:
                    progress.start(name)
                self.t = time.perf_counter()

            def __exit__(self, *exc):
                dt = time.perf_counter() - self.t
                report.timings[name] = report.timings.get(name, 0.0) + dt
                if progress is not None and exc[0] is None:
                    progress.done(name, dt)
                return False

        return _T()


def _collisions(report: Report, clock, model, table, library, options: VerifyOptions) -> None:
    """The machine's own collisions and the tools' with the fixtures (they do not read the
    stock)."""
    with clock("collisions"):
        from vmach.checks.collisions import fixture_collisions, machine_collisions, tool_cylinders

        report.findings.extend(machine_collisions(model, table))
        if library is not None:
            cyl = {
                i: tool_cylinders(t)
                for i, name in enumerate(table.tools)
                if (t := library.lookup(name)) is not None
            }
            report.findings.extend(fixture_collisions(model, table, cyl, clearance=options.clearance))


def verify(program: str | Path, options: VerifyOptions) -> Report:
    """Run every stage on ``program``; return the Report (findings, profile, timings ...)."""
    path = Path(program)
    input_file(path, str(program))  # a directory, a device or a pipe is named as such
    setup = read_setup(path)
    report = Report(str(program), setup)
    clock = _Clock(report, options.progress)
    t0 = time.perf_counter()

    with clock("setup"):
        from vmach.machine import load_model

        report.machine_path = resolve_model(options.machine) if options.machine else setup.machine
        if report.machine_path is None:
            raise InputError(
                f"{program}: which machine? give --machine (or a vmach.toml beside the program)", kind="usage"
            )
        model = load_model(report.machine_path, setup.parameters or None)   # vmach.toml [parameters]
        report.model = model
        control = with_offsets(model.control, setup)
        tools_path = Path(options.tools) if options.tools else setup.tools
        report.tools_path = tools_path
        library = None
        if tools_path is not None:
            from vmach.tooling.library import load_tools

            library = load_tools(tools_path)
        default_spec = options.default_tool or setup.default_tool
        if default_spec:
            from vmach.tooling.default import WithDefault, parse_default_tool

            with setting(setup, "default_tool", options.default_tool):
                library = WithDefault(library, parse_default_tool(
                    default_spec, "--default-tool" if options.default_tool else "default_tool"))
        report.library = library
        report.stock_spec = options.stock or setup.stock
        # the stock is read now: a malformed spec fails before anything runs, with or without tools
        with setting(setup, "stock", options.stock):
            blank = _blank(report.stock_spec, report.findings) if report.stock_spec else None
        report.accuracy = options.accuracy or setup.accuracy or "standard"
        if report.accuracy not in ACCURACY:
            with setting(setup, "accuracy", options.accuracy):
                raise InputError(f"{report.accuracy!r} is not one of {', '.join(ACCURACY)}", kind="usage")
        if options.export:
            from vmach.stock.stock import export_target

            for target in options.export:      # a bad target fails now, not after the simulation
                export_target(target)
        report.profile_spec = options.profile or setup.profile
        # the profile, its stations and fit are read now: a typo fails before the simulation
        with setting(setup, "profile", options.profile), setting(setup, "profile_z", options.profile_z):
            profile_plan = (_profile_plan(report.profile_spec, options.profile_z or setup.profile_z, options)
                            if report.profile_spec else None)
        if options.design:                # the design is read now too (vmach.checks.design_findings)
            from vmach.checks.design_findings import plan_design

            design_plan = plan_design(options.design, options.design_tolerance, options.design_offset)

    with clock("interpret"):
        dialect = interpreters.dialect_for(path, options.dialect, control.dialect)
        static = dialect.check(str(program), control)     # verify reports all that check does
        result = dialect.run(str(program), control, RunOptions(
            max_blocks=options.max_blocks, tool_radius=library.radius if library is not None else None,
            tool_data=library.data if library is not None else None,
            dialect_options=options.dialect_options))
        report.result = result
        report.findings.extend(coverage.merged(static, result.findings))
        report.stopped_at = coverage.stop_place(result)
        stopped = coverage.runaway(result)               # at a limit: nothing after this is checked
        commands = [] if stopped is not None else result.commands

    with clock("move_table"):
        if needs_resolving(commands):          # TRAORI: tip and vector → axis values (the model's IK)
            commands, found = resolve_orientation(commands, model)
            report.findings.extend(found)
            result.commands = commands
        table = build(commands, control)
        report.table = table

    with clock("checks"):
        report.findings.extend(unknown_tools(commands, library))
        report.findings.extend(zero_feeds(table))
        report.findings.extend(_limit_findings(model, table))

    with clock("cycle_time"):
        from vmach.motion.timing import cycle_time

        timing = cycle_time(table, model)
        report.cycle = timing.to_json()
        report.timing = timing
        report.findings.extend(_rate_findings(model, table))

    if report.stock_spec is None:
        from vmach.blank import stock_from_program

        declared = stock_from_program(commands)
        if declared is not None:
            report.stock_spec, notes = declared
            report.findings.extend(Finding("workpiece", "info", n) for n in notes)
    spec = report.stock_spec
    if spec and blank is None:
        blank = _blank(spec, report.findings)
    simulated = bool(spec) and library is not None and stopped is None    # the stock is cut
    with clock("checks"):
        from vmach.checks.envelope import in_envelope

        report.findings.extend(coverage.toolless_feeds(table, simulated))
        report.findings.extend(probing.unchecked(table, library, simulated))
        report.findings.extend(spindle_off_cuts(table, model.tool_spindle, None if blank is None else partial(
            in_envelope, table, model, library, _bounds(blank)), turning=turning_rows(table, library),
            probe=probing.probe_rows(table, library)))
    coverage.say_skipped(report, spec, library, profile_plan is not None, stopped, bool(options.design))
    if (options.export or options.design) and not simulated and stopped is None:
        which = "export" if options.export else "design"
        raise InputError(f"--{which} needs a simulated stock: give {'--tools' if spec else '--stock'} "
                         "(or name it in vmach.toml)", kind="usage")
    if simulated:
        with clock("stock"):
            from vmach.stock import Stock, engine
            from vmach.stock.simulate import simulate

            if options.images and options.out is not None:
                from vmach.report.render import preload

                # VTK's import overlaps the stock's booleans (started after this thread's own
                # imports, so that the two threads do not import the same modules at once)
                preload()

            acc = ACCURACY[report.accuracy]
            stock = Stock(blank, progress=not options.quiet, **acc.stock)
            sim = simulate(table, model, library, stock, checks=True, clearance=options.clearance)
        # the collision checks do not read the stock: they run while its worker process, if
        # it took the batches, subtracts the last of them
        _collisions(report, clock, model, table, library, options)
        with clock("stock"):
            engine.check(stock.solid)      # the last queued cutters subtracted: the stock's work
            stock.close()                  # its worker process, if any, ends here
            report.part = stock
            report.sim = sim
            # tools missing from the library are already `unknown_tool` errors
            report.findings.extend(_group_by_block(f for f in sim.findings if f.kind != "stock_tool_unknown"))
            for target in options.export:
                which = "removed" if Path(target).stem.endswith("removed") else "part"
                stock.export(target, which=which)
        if profile_plan is not None and report.stopped_at is None:
            with clock("profile"):
                report.findings.extend(_profile(report, stock, report.profile_spec, profile_plan, options))
        if options.design and report.stopped_at is not None:
            coverage.skip(report, "design", "the program did not run to its end: its part is not the "
                          "finished one", report.stopped_at)
        elif options.design:
            with clock("design"):
                from vmach.checks.design_findings import check_design

                report.design = check_design(design_plan, stock.solid, table, model, library,
                                             stock.initial_bounds, options.out)
                report.findings.extend(report.design.findings)

    if not simulated:
        _collisions(report, clock, model, table, library, options)

    if options.images and options.out is not None:
        with clock("pictures"):
            from vmach.report.pictures import make_pictures

            report.images = make_pictures(report, Path(options.out))

    report.timings["total"] = time.perf_counter() - t0
    return report


def _bounds(solid) -> np.ndarray:
    from vmach.stock import engine

    return engine.bounds(solid)


def _blank(spec: str, findings: list[Finding]):
    """The stock solid of ``spec`` (InputError for a malformed one); a convex mesh blank cut as
    its hull is a ``blank_hull`` info in ``findings``."""
    from vmach.stock.spec import parse_stock

    notes: list = []
    solid = parse_stock(spec, notes=notes)
    findings.extend(Finding("blank_hull", "info", m, data=d) for m, d in notes)
    return solid


def _limit_findings(model, table: MoveTable) -> list[Finding]:
    from vmach.machine import axis_limit_findings

    if len(table) == 0:
        return []
    q = table.columns(model.axes, model.home)
    sources = [table.source(i) for i in range(len(table))]
    found = axis_limit_findings(model, q, sources=sources, move_index=list(range(len(table))))
    # a move that leaves an axis where an earlier move put it is not reported again
    moved = table.start != table.end
    keep = []
    for f in found:
        axis = f.data.get("axis")
        if f.move_index is not None and axis in table.axes:
            row = f.move_index
            if row > 0 and not moved[row, table.axes.index(axis)]:
                continue
        keep.append(f)
    return _first_per_line(keep)


def _profile_plan(spec: str, z_range: str | None, options: VerifyOptions):
    """(profile, Z stations (n,) mm) of a profile check, every part of it validated: the
    profile spec, the Z range, the station count and the fit class (InputError)."""
    from vmach.checks.iso286 import limits
    from vmach.checks.polygon import parse_profile
    from vmach.checks.profile import stations

    profile = parse_profile(spec)
    if not z_range:
        raise InputError(
            f"--profile {spec}: give the Z range to check with --profile-z (e.g. -35:-5)", kind="usage"
        )
    zs = stations(z_range, options.profile_stations)
    limits(options.fit, profile.d1)
    return profile, zs


def _profile(report: Report, stock, spec: str, plan, options: VerifyOptions) -> list[Finding]:
    """Check the cut part against a DIN profile (``plan``: :func:`_profile_plan`);
    ``profile_out_of_tolerance`` when it misses."""
    from vmach.checks.profile import check_profile

    profile, zs = plan
    res = check_profile(stock.section, profile, zs, fit=options.fit)
    report.profile = res.to_json()
    if res.passed:
        return []
    lo, hi = res.tolerance
    worst = max((s for s in res.stations if s.found), key=lambda s: max(s.max - hi, lo - s.min), default=None)
    missing = [s.z for s in res.stations if not s.found]
    if worst is None:                              # e.g. a --profile-z range beside the part
        z_range = options.profile_z or report.setup.profile_z
        given = f"--profile-z {z_range}" if options.profile_z else f"profile_z = {z_range!r}"
        msg = (f"no material around the axis at z = {missing} ({given}): the {spec} profile is "
               "not there")
        place = None if options.profile_z else report.setup.places.get("profile_z")
        return [Finding("profile_out_of_tolerance", "error", msg, place, None,
                        {"missing_z": missing, "z_range": z_range})]
    else:
        msg = (
            f"{spec} profile out of tolerance ({options.fit}: {lo * 1000:+.1f}…{hi * 1000:+.1f} µm on the "
            f"flank): deviation {worst.min * 1000:+.1f}…{worst.max * 1000:+.1f} µm at z = {worst.z:g} mm"
        )
        data = {
            "z": worst.z,
            "max_deviation_mm": worst.max,
            "min_deviation_mm": worst.min,
            "tolerance_mm": [lo, hi],
            "missing_z": missing,
        }
    return [Finding("profile_out_of_tolerance", "error", msg, None, None, data)]


def _rate_findings(model, table: MoveTable) -> list[Finding]:
    """``rate_limit`` where the programmed feed would drive an axis faster than the model allows
    (the control would slow down; the program asks for more than the machine can give)."""
    from vmach.machine import rate_findings
    from vmach.motion.timing import programmed_seconds

    t = programmed_seconds(table)
    rows = np.flatnonzero(np.isfinite(t) & (t > 0))
    if len(rows) == 0:
        return []
    a = table.columns(model.axes, model.home, table.start[rows])
    b = table.columns(model.axes, model.home, table.end[rows])
    found = rate_findings(
        model, a, b, t[rows], sources=[table.source(int(r)) for r in rows], move_index=rows.tolist()
    )
    # the control does not alarm: it slows the path so the axis keeps its limit (the cycle time
    # counts that); the program asks for more than the machine gives, which is worth a warning
    slowed = [
        Finding(
            f.kind,
            "warning",
            f.message + "; the control slows the path to the axis's limit",
            f.source,
            f.move_index,
            f.data,
        )
        for f in found
    ]
    return _first_per_line(slowed)


def _group_by_block(findings) -> list[Finding]:
    """One finding per (kind, block, part): the first move, with the number of moves and the
    total and largest volume (a G0 inside a loop is one defect, not hundreds)."""
    groups: dict[tuple, list[Finding]] = {}
    for f in findings:
        key = (f.kind, f.source.path if f.source else None, f.line, f.data.get("part"))
        groups.setdefault(key, []).append(f)
    out = []
    for fs in groups.values():
        f = fs[0]
        if len(fs) == 1:
            out.append(f)
            continue
        data = {**f.data, "occurrences": len(fs), "last_move_index": fs[-1].move_index}
        extra = ""
        if "volume_mm3" in f.data:
            vols = [x.data["volume_mm3"] for x in fs]
            data.update(volume_mm3=round(sum(vols), 4), max_volume_mm3=max(vols))
            extra = f"; {sum(vols):.3f} mm³ in all"
        if "distance_mm" in f.data:
            data["distance_mm"] = min(x.data["distance_mm"] for x in fs)
            extra = f"; closest {data['distance_mm']:.3f} mm"
        msg = f"{f.message} (and {len(fs) - 1} more times{extra})"
        out.append(Finding(f.kind, f.severity, msg, f.source, f.move_index, data))
    return out


def _first_per_line(findings: list[Finding]) -> list[Finding]:
    """One finding per (kind, file, line, axis): a block in a loop is reported once."""
    seen: dict[tuple, Finding] = {}
    counts: dict[tuple, int] = {}
    for f in findings:
        key = (f.kind, f.source.path if f.source else None, f.line, f.data.get("axis"))
        counts[key] = counts.get(key, 0) + 1
        seen.setdefault(key, f)
    out = []
    for key, f in seen.items():
        if counts[key] > 1:
            f = Finding(
                f.kind,
                f.severity,
                f.message + f" (and {counts[key] - 1} more times)",
                f.source,
                f.move_index,
                {**f.data, "occurrences": counts[key]},
            )
        out.append(f)
    return out
