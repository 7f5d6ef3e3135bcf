"""Values a machine model is made of (frozen dataclasses; no behaviour beyond small helpers).

Units everywhere: lengths in mm, angles in degrees, rates in units per minute (mm/min for
linear axes and drives, degrees/min for rotary axes). Vectors are tuples of floats.

Frames (pytransform3d naming, ``a2b`` maps coordinates in frame a to frame b):

- ``base`` — the machine frame; every chain starts there.
- ``link2base`` — pose of a link; a joint's child link is placed by
  ``child2parent = Tr(origin.xyz) · R(origin.rpy) · J(q)`` with ``J`` a translation
  ``axis · q`` (prismatic, mm) or a rotation ``Rot(axis, q)`` (revolute, degrees).
- ``work2base`` — the workpiece (program) frame, fixed to the work-mount link.
- ``tool2base`` — the tool frame: origin at the tool tip, z along the tool axis pointing from the
  tip toward the spindle (the CAM convention of ``GOTO/x,y,z,i,j,k``).
- ``tool2work = inv(work2base) @ tool2base`` — what forward kinematics returns.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from vmach.canon import ControlSpec

Vec3 = tuple[float, float, float]


def rpy_matrix(rpy_deg: Vec3) -> np.ndarray:
    """Fixed-axis roll-pitch-yaw (degrees) → (3, 3) rotation ``Rz(yaw) · Ry(pitch) · Rx(roll)``."""
    r, p, y = np.radians(rpy_deg)
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


@dataclass(frozen=True)
class Origin:
    """A fixed placement: translation ``xyz`` (mm) then rotation ``rpy`` (degrees)."""

    xyz: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)

    @property
    def rotation(self) -> np.ndarray:
        """(3, 3) float."""
        return rpy_matrix(self.rpy)

    @property
    def matrix(self) -> np.ndarray:
        """(4, 4) float homogeneous transform."""
        m = np.eye(4)
        m[:3, :3] = self.rotation
        m[:3, 3] = self.xyz
        return m


@dataclass(frozen=True)
class Joint:
    """A joint between ``parent`` and ``child`` links.

    type : ``"prismatic"`` (mm), ``"revolute"`` (degrees) or ``"fixed"``.
    axis : unit vector in the joint frame (after ``origin``).
    variable : the machine axis (``X``, ``C1``) whose value drives the joint; None if fixed.
    limits : (min, max) travel of the variable, mm or degrees; None if unlimited.
    max_rate : mm/min or degrees/min; None if not stated.
    max_accel : mm/s² or degrees/s² (note: per SECOND squared); None if not stated.
    """

    name: str
    type: str
    parent: str
    child: str
    axis: Vec3 = (0.0, 0.0, 1.0)
    origin: Origin = Origin()
    variable: str | None = None
    limits: tuple[float, float] | None = None
    max_rate: float | None = None
    max_accel: float | None = None


@dataclass(frozen=True)
class TimingSpec:
    """Machine times for the cycle-time estimate (a model's ``[timing]`` table), seconds.

    stated : False when the model has no ``[timing]`` table (every time below is then 0).
    tool_change_s : one tool change (turret index or changer), the programmed moves excluded.
    spindle_start_s, spindle_stop_s : run-up from standstill to speed, and to standstill.
    spindle_change_s : a speed or direction change of a running spindle.
    corner_overload : Sinumerik MD32310 MAX_ACCEL_OVL_FACTOR: at a G64 block transition an
        axis' velocity may jump by ``max_accel · (corner_overload − 1) · ipo_cycle_s``.
    ipo_cycle_s : interpolator cycle, s.
    cycles : ``{name: s}`` for machine cycles and functions (``C_AXIS_ON``, ``M10``).
    """

    stated: bool = False
    tool_change_s: float = 0.0
    spindle_start_s: float = 0.0
    spindle_stop_s: float = 0.0
    spindle_change_s: float = 0.0
    corner_overload: float = 1.2
    ipo_cycle_s: float = 0.004
    cycles: Mapping[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class Geometry:
    """A collision primitive attached to a link, in the link frame.

    shape : ``"box"`` (``size`` = full edge lengths x, y, z, centred on the origin),
        ``"cylinder"`` (``radius``, ``length`` along local z, centred on the origin),
        or ``"mesh"`` (``path``, resolved against the model file's folder).
    """

    name: str
    link: str
    shape: str
    origin: Origin = Origin()
    size: Vec3 | None = None
    radius: float | None = None
    length: float | None = None
    path: str | None = None


@dataclass(frozen=True)
class WorkMount:
    """The workpiece frame: ``work2link = origin``."""

    link: str
    origin: Origin = Origin()


@dataclass(frozen=True)
class ToolMount:
    """The tool: tip at ``origin.xyz`` of ``link``; tool axis ``direction`` (unit, link frame,
    from tip toward spindle); the spindle gauge point (``tool_mount`` frame) is ``length`` mm from
    the tip along ``direction``."""

    link: str
    origin: Origin = Origin()
    direction: Vec3 = (0.0, 0.0, 1.0)
    length: float = 0.0


@dataclass(frozen=True)
class Leg:
    """One drive of a parallel mechanism (domain §3), mechanism coordinates (m = 2 or 3).

    drive : actuator name (``p1``).
    guide_point, guide_dir : g_i (mm) and unit u_i of the guideway; slider at ``g + p·u``.
    length : strut length L_i, mm.
    attach : b_i, the strut's platform attachment relative to the platform point P, mm.
    root : +1 or -1, the root of ``p = u·d ± √((u·d)² − |d|² + L²)`` (working mode).
    """

    drive: str
    guide_point: tuple[float, ...]
    guide_dir: tuple[float, ...]
    length: float
    attach: tuple[float, ...]
    root: int = -1
    limits: tuple[float, float] | None = None
    max_rate: float | None = None


@dataclass(frozen=True)
class Parallel:
    """A parallel mechanism that produces the virtual serial axes ``virtual``.

    The platform point is ``P = origin + (values of the virtual axes)`` in mechanism
    coordinates (mm). ``assembly`` (+1/-1) picks the forward solution of the planar case: the
    side of the line from the first to the second strut centre on which P lies.
    """

    name: str
    virtual: tuple[str, ...]
    origin: tuple[float, ...]
    legs: tuple[Leg, ...]
    assembly: int = -1

    @property
    def drives(self) -> tuple[str, ...]:
        return tuple(leg.drive for leg in self.legs)


@dataclass(frozen=True)
class ModelSpec:
    """A whole machine model as loaded (every parameter reference resolved)."""

    name: str
    path: str
    control: ControlSpec
    axes: tuple[str, ...]
    links: tuple[str, ...]
    joints: tuple[Joint, ...]
    work: WorkMount
    tool: ToolMount
    geometry: tuple[Geometry, ...] = ()
    parallel: tuple[Parallel, ...] = ()
    parameters: Mapping[str, float | tuple[float, ...]] = field(default_factory=dict)
    ik: str = "numeric"
    positions: Mapping[str, Mapping[str, float]] = field(default_factory=dict)
    formula: str | None = None
    description: str = ""
    timing: TimingSpec = TimingSpec()
