"""A RobotStudio backup's motion configuration (``SYSPAR/MOC.cfg``): what the controller says
about where its robots stand and which axes it drives. Read: each mechanical unit
(MECHANICAL_UNIT: the ROBOT and SINGLE units it uses), each robot's and single's base frame
(metres and a quaternion) and what moves it (``-base_frame_moved_by``, a mechanical unit), each
joint's logical axis (1-6 the robot's axes, 7-12 the external axes eax_a..eax_f), whether it
rotates (TRANSMISSION ``-rotating_move``) and its bounds (ARM, rad or m). Everything else in the
file (servo, supervision, drive data) is skipped. ``notes`` say in plain words what the file
set, so a cell built on a backup can tell its user where each figure came from.

A line that is no ``-key value``, a number that is none, a reference to an instance the file
lacks: a ``file:line`` error, as for RSXML."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import Diagnostic, RsxmlError
from ..transforms import quat_matrix
from .cfg import CfgInstance, read_cfg
from .parse import number

SECTIONS = ("MECHANICAL_UNIT", "ROBOT", "SINGLE", "JOINT", "ARM", "TRANSMISSION")
EXTERNAL_AXES = ("eax_a", "eax_b", "eax_c", "eax_d", "eax_e", "eax_f")  # logical axes 7..12
ROBOT_JOINTS = 7  # -use_joint_0 .. -use_joint_6 (a seven-axis robot's last)
UNIT_SINGLES = 6  # -use_single_0 .. -use_single_5


@dataclass(frozen=True)
class BaseFrame:
    """A base frame as MOC.cfg gives it: position (m) and orientation (w, x, y, z, normalized) in
    the world, or on the mechanical unit ``moved_by`` names; ``line`` where its instance starts."""

    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quaternion: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    moved_by: str | None = None
    line: int = 0

    def matrix(self) -> np.ndarray:
        """The frame as a 4x4 transform (metres)."""
        m = np.eye(4)
        m[:3, :3] = quat_matrix(self.quaternion)
        m[:3, 3] = self.position
        return m

    def words(self) -> str:
        """``[x, y, z] m, q [w, x, y, z]``, then what moves it."""
        moved = f"moved by {self.moved_by}" if self.moved_by else "fixed in the world"
        return f"[{_nums(self.position)}] m, q [{_nums(self.quaternion)}], {moved}"


@dataclass(frozen=True)
class MocJoint:
    """A JOINT: its logical axis (1..12), the mechanical unit it belongs to (None: no unit uses
    it), whether it rotates (None: no TRANSMISSION says), its ARM bounds (rad, or m for a linear
    joint; None where not given) and the ARM and TRANSMISSION instances it names."""

    name: str
    logical_axis: int
    unit: str | None
    rotating: bool | None
    lower: float | None
    upper: float | None
    arm: str | None
    transmission: str | None
    line: int

    @property
    def axis(self) -> str:
        """RAPID's name of the axis: ``rax_1`` .. ``rax_6`` (a robot's), ``eax_a`` .. ``eax_f``."""
        return f"rax_{self.logical_axis}" if self.logical_axis <= 6 else EXTERNAL_AXES[self.logical_axis - 7]

    def words(self) -> str:
        """``linear, -0.1 .. 3.85 m`` or ``rotating, -1.5708 .. 1.5708 rad (-90 .. 90 deg)``."""
        kind = {True: "rotating", False: "linear", None: "rotating or linear (no TRANSMISSION says)"}[self.rotating]
        if self.lower is None and self.upper is None:
            return f"{kind}, no bounds given"
        lo, hi = (f"{v:g}" if v is not None else "?" for v in (self.lower, self.upper))
        if self.rotating is False:
            return f"{kind}, {lo} .. {hi} m"
        deg = " .. ".join(f"{math.degrees(v):.5g}" if v is not None else "?" for v in (self.lower, self.upper))
        return f"{kind}, {lo} .. {hi} rad ({deg} deg)"


@dataclass(frozen=True)
class MocRobot:
    """A ROBOT: its type (``-use_robot_type``), base frame and joints (axis 1 first)."""

    name: str
    robot_type: str | None
    base_frame: BaseFrame
    joints: tuple[str, ...]
    line: int


@dataclass(frozen=True)
class MocSingle:
    """A SINGLE (one external axis): its type, base frame and joint."""

    name: str
    single_type: str | None
    base_frame: BaseFrame
    joint: str | None
    line: int


@dataclass(frozen=True)
class MocUnit:
    """A MECHANICAL_UNIT: the robot and singles it uses, and their joints in that order."""

    name: str
    robot: MocRobot | None
    singles: tuple[MocSingle, ...]
    joints: tuple[MocJoint, ...]
    line: int


@dataclass(frozen=True)
class MocConfig:
    """What a MOC.cfg sets: its mechanical units (file order), every joint it defines (file
    order), and ``notes``, one line of plain words per thing set."""

    path: str
    units: tuple[MocUnit, ...]
    joints: tuple[MocJoint, ...]
    notes: tuple[str, ...]

    def unit(self, name: str) -> MocUnit:
        """The mechanical unit ``name`` (case ignored); KeyError where there is none."""
        for u in self.units:
            if u.name.lower() == name.lower():
                return u
        raise KeyError(name)

    @property
    def robots(self) -> tuple[MocRobot, ...]:
        return tuple(u.robot for u in self.units if u.robot is not None)

    @property
    def external_axes(self) -> dict[str, MocJoint]:
        """The joints on logical axes 7..12 by RAPID name (``eax_a`` ..), in axis order."""
        found = {j.axis: j for j in self.joints if j.logical_axis >= 7 and j.unit is not None}
        return {a: found[a] for a in EXTERNAL_AXES if a in found}


def read_moc(path) -> MocConfig:
    """A backup's ``SYSPAR/MOC.cfg``, read; an ``RsxmlError`` at the line of the first problem."""
    path = str(path)
    by_section: dict[str, dict[str, CfgInstance]] = {s: {} for s in SECTIONS}
    for inst in read_cfg(path, domain="MOC"):
        if inst.section in by_section:
            _add(path, by_section[inst.section], inst)
    cfg = _Reader(path, by_section)
    units = [cfg.unit(inst) for inst in by_section["MECHANICAL_UNIT"].values()]
    owner = {j: u.name for u in units for j in u.joints}
    joints = tuple(cfg.joint(inst, owner.get(inst.name.lower())) for inst in by_section["JOINT"].values())
    by_name = {j.name.lower(): j for j in joints}
    units = tuple(MocUnit(u.name, u.robot, u.singles, tuple(by_name[j] for j in u.joints), u.line) for u in units)
    return MocConfig(path, units, joints, _notes(units, joints))


def _add(path: str, table: dict[str, CfgInstance], inst: CfgInstance) -> None:
    name = inst.name
    if not name:
        raise RsxmlError(Diagnostic(path, inst.line, f"a {inst.section} instance without -name"))
    if name.lower() in table:
        first = table[name.lower()].line
        raise RsxmlError(Diagnostic(path, inst.line, f"{inst.section} '{name}' is defined twice (first at line "
                                                     f"{first})"))
    table[name.lower()] = inst


def _moved_key(inst: CfgInstance) -> str:
    return "base_frame_moved_by" if inst.flag("base_frame_moved_by") else "base_frame_coordinated"


@dataclass(frozen=True)
class _Unit:
    name: str
    robot: MocRobot | None
    singles: tuple[MocSingle, ...]
    joints: tuple[str, ...]  # lower-case joint names
    line: int


class _Reader:
    """The instances of the sections read, by lower-case name, and how each becomes a record;
    every reference followed must name an instance the file has."""

    def __init__(self, path: str, by_section: dict[str, dict[str, CfgInstance]]):
        self.path, self.by = path, by_section

    def fail(self, inst: CfgInstance, key: str, message: str):
        raise RsxmlError(Diagnostic(self.path, inst.line_of(key), f"{inst.section} '{inst.name}': {message}"))

    def ref(self, inst: CfgInstance, key: str, section: str) -> CfgInstance | None:
        """The instance of ``section`` that ``inst``'s ``key`` names; None where it names none."""
        target = inst.text(key)
        if not target:  # absent, or "" as the controller writes a reference left unset
            return None
        found = self.by[section].get(target.lower())
        if found is None:
            self.fail(inst, key, f"-{key} '{target}' names no {section} instance")
        return found

    def number(self, inst: CfgInstance, key: str, default: float | None) -> float | None:
        if not inst.flag(key):
            return default
        text = inst.text(key)
        if text is None:
            self.fail(inst, key, f"-{key} needs a number")
        try:
            return number(text)
        except ValueError as exc:
            self.fail(inst, key, f"-{key}: {exc}")

    def frame(self, inst: CfgInstance) -> BaseFrame:
        xyz = tuple(self.number(inst, f"base_frame_pos_{a}", 0.0) for a in "xyz")
        q = np.array([self.number(inst, f"base_frame_orient_u{k}", 1.0 if k == 0 else 0.0) for k in range(4)])
        norm = float(np.linalg.norm(q))
        if not norm > 1e-9 or abs(norm - 1.0) > 1e-3:
            self.fail(inst, "base_frame_orient_u0", f"the base frame's quaternion [{_nums(q)}] (u0..u3; u0 is 1 where "
                                                    f"omitted) has length {norm:.6g}, not 1")
        key = _moved_key(inst)
        moved = inst.text(key) or None  # absent, or "" as the controller writes a reference left unset
        if moved is not None and moved.lower() not in self.by["MECHANICAL_UNIT"]:
            self.fail(inst, key, f"-{key} '{moved}' names no MECHANICAL_UNIT")
        return BaseFrame(xyz, tuple(float(v) for v in q / norm), moved, inst.line)

    def unit(self, inst: CfgInstance) -> _Unit:
        robot_inst = self.ref(inst, "use_robot", "ROBOT")
        robot = None if robot_inst is None else self.robot(robot_inst)
        singles = tuple(self.single(s) for k in range(UNIT_SINGLES)
                        if (s := self.ref(inst, f"use_single_{k}", "SINGLE")) is not None)
        joints = (*(robot.joints if robot else ()), *(s.joint for s in singles if s.joint))
        return _Unit(inst.name, robot, singles, tuple(j.lower() for j in joints), inst.line)

    def robot(self, inst: CfgInstance) -> MocRobot:
        joints = tuple(j.name for k in range(ROBOT_JOINTS) if (j := self.ref(inst, f"use_joint_{k}", "JOINT")))
        return MocRobot(inst.name, inst.text("use_robot_type"), self.frame(inst), joints, inst.line)

    def single(self, inst: CfgInstance) -> MocSingle:
        joint = self.ref(inst, "use_joint", "JOINT")
        return MocSingle(inst.name, inst.text("use_single_type"), self.frame(inst),
                         None if joint is None else joint.name, inst.line)

    def joint(self, inst: CfgInstance, unit: str | None) -> MocJoint:
        axis = self.number(inst, "logical_axis", None)
        if axis is None or axis != int(axis) or not 1 <= axis <= 12:
            self.fail(inst, "logical_axis", "-logical_axis must be a whole number 1..12 (7..12: eax_a..eax_f), not "
                                            f"{inst.text('logical_axis') or 'absent'}")
        arm = self.ref(inst, "use_arm", "ARM")
        trans = self.ref(inst, "use_transmission", "TRANSMISSION")
        lower = None if arm is None else self.number(arm, "lower_joint_bound", None)
        upper = None if arm is None else self.number(arm, "upper_joint_bound", None)
        if lower is not None and upper is not None and lower > upper:
            self.fail(arm, "lower_joint_bound", f"-lower_joint_bound {lower:g} is above -upper_joint_bound {upper:g}")
        return MocJoint(inst.name, int(axis), unit, None if trans is None else trans.flag("rotating_move"), lower,
                        upper, None if arm is None else arm.name, None if trans is None else trans.name, inst.line)


def _notes(units: tuple[MocUnit, ...], joints: tuple[MocJoint, ...]) -> tuple[str, ...]:
    """One line per base frame and per joint, in plain words: what the file set."""
    out = []
    for u in units:
        if u.robot is not None:
            kind = f" (robot type {u.robot.robot_type})" if u.robot.robot_type else ""
            out.append(f"{u.robot.name}'s base frame {u.robot.base_frame.words()}{kind}")
        for s in u.singles:
            out.append(f"{u.name}'s single {s.name}: base frame {s.base_frame.words()}")
        for j in u.joints:
            what = f"{u.name}'s joint {j.name}" if j.logical_axis >= 7 else f"{u.name} axis {j.logical_axis} ({j.name})"
            out.append(f"{j.axis}: {what}, {j.words()}")
    out.extend(f"JOINT {j.name} (logical axis {j.logical_axis}) belongs to no mechanical unit"
               for j in joints if j.unit is None)
    return tuple(out)


def _nums(values) -> str:
    return ", ".join(f"{v:.6g}" for v in values)
