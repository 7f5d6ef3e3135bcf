"""Post-processor check (domain §2): CL poses against the moves of the post's G-code.

For every CL pose (tool tip r_T and axis a in the workpiece frame) the paired G-code move's axis
values q are put through the machine's forward kinematics; the pose is right when
``FK(q) = (r_T, a)``. On the table-table machine this is exactly the papers' check — the
programmed tool axis turned by C then B equals a0 = (0, 0, 1), and X, Y, Z equal the §2 formula
for the programmed B, C — because ``|FK(q).tip − r_T| = |(X, Y, Z) − formula(B, C)|``. The
report also gives the expected axis values (closed-form or numeric IK of the CL pose; at B = 0
the programmed C is kept since C is free there; modulo axes on the programmed turn).

Pairing: CL poses and G-code moves are walked in order. A pose takes the first move within
tolerance among the next ``window`` moves (moves skipped on the way — safety retracts, tool
change positions — are *unpaired moves*); if none is within tolerance it takes the next move,
and that pose is reported. CL poses left when the program's moves run out are ``missing_pose``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from vmach.canon import ArcFeed, Command, FeedMode, LinearFeed, Traverse
from vmach.findings import Finding
from vmach.machine.cl import ClData
from vmach.source import SourceRef

TOL_POSITION = 0.01  # mm
TOL_ANGLE = 0.01  # degrees
WINDOW = 8


@dataclass(frozen=True)
class Moves:
    """End points of a program's motion commands.

    q : (m, k) float, mm / degrees, model axis order. rapid : (m,) bool.
    feed : (m,) float, mm/min (NaN for rapids or feeds not per minute). sources : (m,) SourceRef.
    """

    q: np.ndarray
    rapid: np.ndarray
    feed: np.ndarray
    sources: tuple[SourceRef, ...]


def moves_from_commands(commands: Sequence[Command], axes: Sequence[str],
                        home: np.ndarray) -> Moves:
    """Motion end points of a canonical stream (axes a command omits keep their last value)."""
    q, rapid, feed, sources = [], [], [], []
    cur = np.array(home, float)
    mode = "per_minute"
    index = {a: i for i, a in enumerate(axes)}
    for c in commands:
        if isinstance(c, FeedMode):
            mode = c.mode
        if not isinstance(c, Traverse | LinearFeed | ArcFeed):
            continue
        cur = cur.copy()
        for name, v in c.axes.items():
            if name in index:
                cur[index[name]] = v
        q.append(cur)
        is_rapid = isinstance(c, Traverse)
        rapid.append(is_rapid)
        feed.append(np.nan if is_rapid or mode != "per_minute" else float(c.feed))
        sources.append(c.source)
    k = len(axes)
    return Moves(np.array(q, float).reshape(-1, k), np.array(rapid, bool),
                 np.array(feed, float), tuple(sources))


@dataclass(frozen=True)
class PostCheck:
    """Per-pose result, arrays over the n CL poses.

    move : (n,) int — paired move index, −1 if none. position : (n,) float, mm — tool-tip
    deviation. angle : (n,) float, degrees — tool-axis deviation (NaN if unpaired).
    expected, programmed : (n, k) float — IK of the CL pose / the G-code's axis values.
    unpaired : indices of program moves no pose took. findings : everything to report.
    """

    cl: ClData
    moves: Moves
    axes: tuple[str, ...]
    move: np.ndarray
    position: np.ndarray
    angle: np.ndarray
    expected: np.ndarray
    programmed: np.ndarray
    unpaired: tuple[int, ...]
    findings: tuple[Finding, ...]

    def pose_json(self, i: int) -> dict:
        j = int(self.move[i])
        nc = self.moves.sources[j] if j >= 0 else None

        def axes(row):
            return {a: float(round(v, 9)) for a, v in zip(self.axes, row, strict=True)}

        return {
            "cl_line": self.cl.sources[i].line,
            "nc_file": None if nc is None else nc.path,
            "nc_line": None if nc is None else nc.line,
            "position_mm": None if j < 0 else float(self.position[i]),
            "angle_deg": None if j < 0 else float(self.angle[i]),
            "expected": axes(self.expected[i]),
            "programmed": None if j < 0 else axes(self.programmed[i]),
        }


def _angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    cross = np.linalg.norm(np.cross(a, b), axis=-1)
    return np.degrees(np.arctan2(cross, np.einsum("...i,...i->...", a, b)))


def pair(cl: ClData, tip_m: np.ndarray, axis_m: np.ndarray, tol_position: float,
         tol_angle: float, window: int = WINDOW) -> np.ndarray:
    """Index of the move paired with each CL pose (−1 when the moves ran out)."""
    n, m = len(cl), tip_m.shape[0]
    out = np.full(n, -1)
    j = 0
    for i in range(n):
        if j >= m:
            break
        hi = min(m, j + window)
        dp = np.linalg.norm(tip_m[j:hi] - cl.tip[i], axis=1)
        da = _angle_deg(axis_m[j:hi], cl.axis[i])
        good = np.flatnonzero((dp <= tol_position) & (da <= tol_angle))
        c = j + (int(good[0]) if good.size else 0)
        out[i] = c
        j = c + 1
    return out


def postcheck(model, cl: ClData, moves: Moves, *, tol_position: float = TOL_POSITION,
              tol_angle: float = TOL_ANGLE, window: int = WINDOW) -> PostCheck:
    """Check the program's moves against the CL poses; see the module docstring."""
    pose_m = model.fk(moves.q) if len(moves.q) else None
    n, k = len(cl), len(model.axes)
    if pose_m is None:
        idx = np.full(n, -1)
    else:
        idx = pair(cl, pose_m.tip, pose_m.axis, tol_position, tol_angle, window)
    ok = idx >= 0
    position = np.full(n, np.nan)
    angle = np.full(n, np.nan)
    programmed = np.full((n, k), np.nan)
    if ok.any():
        position[ok] = np.linalg.norm(pose_m.tip[idx[ok]] - cl.tip[ok], axis=1)
        angle[ok] = _angle_deg(pose_m.axis[idx[ok]], cl.axis[ok])
        programmed[ok] = moves.q[idx[ok]]
    first = moves.q[idx[ok][0]] if ok.any() else model.home
    expected = np.full((n, k), np.nan)
    if n:
        sol = model.ik(cl.tip, cl.axis, previous=first)
        expected = sol.q.copy()
        if "C" in model.axes:
            c = model.axes.index("C")
            free = sol.singular & ok
            expected[free, c] = programmed[free, c]
        for t, spec in enumerate(model.control.axes):  # the turn nearest the programmed one
            if spec.modulo:
                turns = np.round((programmed[ok, t] - expected[ok, t]) / spec.modulo)
                expected[ok, t] += spec.modulo * turns
    findings = list(cl.findings)
    for i in np.flatnonzero(ok & ((position > tol_position) | (angle > tol_angle))):
        j = int(idx[i])
        delta = programmed[i] - expected[i]
        beyond = np.abs(delta) > np.where(model.rotary, tol_angle, tol_position)
        diff = {a: float(round(delta[t], 9)) for t, a in enumerate(model.axes) if beyond[t]}
        findings.append(Finding(
            "post_deviation", "error",
            f"the move misses the CL pose of {cl.path}:{cl.sources[i].line} by "
            f"{position[i]:.4f} mm and {angle[i]:.4f}°",
            moves.sources[j], j,
            {"cl_file": cl.path, "cl_line": cl.sources[i].line,
             "position_mm": float(position[i]), "angle_deg": float(angle[i]),
             "programmed_minus_expected": diff}))
    for i in np.flatnonzero(ok):
        j = int(idx[i])
        if bool(cl.rapid[i]) != bool(moves.rapid[j]):
            what = "rapid" if cl.rapid[i] else "feed"
            findings.append(Finding(
                "motion_kind", "warning",
                f"CL line {cl.sources[i].line} is a {what} move, the program's is not",
                moves.sources[j], j, {"cl_file": cl.path, "cl_line": cl.sources[i].line}))
        elif not cl.rapid[i] and np.isfinite(cl.feed[i]) and np.isfinite(moves.feed[j]) and \
                abs(cl.feed[i] - moves.feed[j]) > 1e-6 * max(1.0, cl.feed[i]):
            findings.append(Finding(
                "feed_mismatch", "warning",
                f"feed {moves.feed[j]:g} mm/min, CL line {cl.sources[i].line} says "
                f"{cl.feed[i]:g}", moves.sources[j], j,
                {"cl_file": cl.path, "cl_line": cl.sources[i].line,
                 "feed": float(moves.feed[j]), "cl_feed": float(cl.feed[i])}))
    for i in np.flatnonzero(~ok):
        findings.append(Finding("missing_pose", "error",
                                "the program ends before this CL pose", cl.sources[i], None,
                                {"cl_line": cl.sources[i].line}))
    taken = set(int(j) for j in idx[ok])
    unpaired = tuple(j for j in range(len(moves.q)) if j not in taken)
    return PostCheck(cl, moves, tuple(model.axes), idx, position, angle, expected, programmed,
                     unpaired, tuple(findings))
