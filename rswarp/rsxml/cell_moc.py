"""A cell file's ``backup``: the RobotStudio or controller backup whose ``SYSPAR/MOC.cfg`` says how
the controller has the cell set up (``rsxml.moc``). What it sets, each said in a note at the
``backup`` key's line:

- each external axis's bounds: the controller's (MOC's ARM bounds) replace the unit's RSXML limits
  for the joint the cell maps that logical axis to (an axis the MOC calls linear on a joint that
  turns, or the other way, is an error);
- what carries the robot (``base_frame_moved_by``): the unit of the cell that the moving
  mechanical unit's logical axes drive, where the cell's ``[robot] on`` is not given (a warning
  where it names another);
- the robot's base frame, where ``[robot] frame`` is not given; a single-axis unit's frame (its
  SINGLE's base frame), where its ``frame`` is not given;
- the backup's ``SYSPAR/EIO.cfg``, where it has one: the signals a task run on the cell knows
  (``Cell.eio``, read by ``rswarp.motion.plan``).

A MultiMove controller has several robots: ``[robot] unit`` says which is the cell's (its
mechanical unit, ``ROB_2``, or the motion task that moves it, ``T_ROB2``, where the backup's
``SYSPAR/SYS.cfg`` says), and the external axes are that robot's task's: its mechanical unit
group's in SYS.cfg; without SYS.cfg, those of no unit that carries another robot. Axes one side
drives and the other does not are warnings."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import Diagnostic, RsxmlError
from ..files import read_regular
from .cfg import decode_cfg, parse_cfg
from .moc import MocConfig, MocJoint, MocRobot, read_moc
from .model import Limit

GROUP_UNITS = 6  # -MechUnit_1 .. -MechUnit_6 of a SYS.cfg MECHANICAL_UNIT_GROUP


def moc_path(folder: Path, value, fail) -> Path:
    """The MOC.cfg a ``backup`` value names: a backup folder (its SYSPAR/MOC.cfg) or the file."""
    if not isinstance(value, str) or not value.strip():
        fail("backup: give the backup's folder (it holds SYSPAR/MOC.cfg) or its MOC.cfg, as a path relative to "
             "the cell file")
    path = folder / value.strip().replace("\\", "/")
    if path.is_dir():
        for sub in ("SYSPAR", "syspar", "Syspar"):
            moc = path / sub / "MOC.cfg"
            if moc.is_file():
                return moc
            if moc.exists():
                fail(f"backup: {moc} is {kind_of(moc)}, not a MOC.cfg file")
        fail(f"backup: '{value}' holds no SYSPAR/MOC.cfg")
    if path.exists() and not path.is_file():
        fail(f"backup: '{value}' is {kind_of(path)}, not a backup folder or a MOC.cfg file")
    if not path.is_file():
        fail(f"backup: no such file or folder '{value}' (looked for {path})")
    return path


def kind_of(path: Path) -> str:
    """What a path that is no regular file is, in words: a folder, a FIFO, a device, a socket."""
    import stat

    mode = path.stat().st_mode
    return "a folder" if stat.S_ISDIR(mode) else "a FIFO" if stat.S_ISFIFO(mode) else \
        "a device" if stat.S_ISBLK(mode) or stat.S_ISCHR(mode) else "a socket" if stat.S_ISSOCK(mode) else \
        "not a regular file"


def beside(moc: Path, name: str) -> Path | None:
    """The backup's other SYSPAR file ``name`` (``EIO.cfg``, ``SYS.cfg``) beside its MOC.cfg."""
    for spelt in (name, name.lower(), name.upper()):
        if (moc.parent / spelt).is_file():
            return moc.parent / spelt
    return None


@dataclass(frozen=True)
class MotionGroup:
    """A SYS.cfg MECHANICAL_UNIT_GROUP: its robot's and other mechanical units' names (lower case)
    and the motion tasks (CAB_TASKS) that use it."""

    name: str
    robot: str | None
    units: tuple[str, ...]
    tasks: tuple[str, ...]


def motion_groups(path: Path) -> tuple[MotionGroup, ...]:
    """The mechanical unit groups of a backup's SYS.cfg, read leniently (only two sections are
    read: a line that is no attribute elsewhere is skipped); an RsxmlError where it cannot be read."""
    try:
        data = read_regular(path)
    except OSError as exc:
        raise RsxmlError(Diagnostic(str(path), 0, f"cannot read: {exc.strerror or exc}")) from None
    entries = parse_cfg(decode_cfg(data, str(path)), str(path), strict=False)
    tasks: dict[str, list[str]] = {}
    for e in entries:
        group = e.text("usemechanicalunitgroup")
        if e.section == "CAB_TASKS" and e.name and group:
            tasks.setdefault(group.lower(), []).append(e.name)
    out = []
    for e in entries:
        if e.section == "MECHANICAL_UNIT_GROUP" and e.name:
            units = tuple(u.lower() for k in range(1, GROUP_UNITS + 1) if (u := e.text(f"mechunit_{k}")))
            robot = e.text("robot")
            out.append(MotionGroup(e.name, robot.lower() if robot else None, units,
                                   tuple(tasks.get(e.name.lower(), ()))))
    return tuple(out)


class MocApplied:
    """A cell as read, with its MOC.cfg's settings applied; ``said`` the notes and warnings.
    ``groups``: the backup's SYS.cfg mechanical unit groups (None: it has no SYS.cfg)."""

    def __init__(self, cell, moc: MocConfig, line: int, given: dict, groups: tuple[MotionGroup, ...] | None = None):
        self.cell, self.moc, self.line, self.given, self.groups = cell, moc, line, given, groups
        self.said: list[Diagnostic] = []
        self.robot = self._which()
        self.axes = self._task_axes()

    def note(self, message: str, severity: str = "note") -> None:
        self.said.append(Diagnostic(self.cell.path, self.line, f"{Path(self.moc.path).name}: {message}", severity))

    def fail(self, message: str, line: int | None = None):
        raise RsxmlError(Diagnostic(self.cell.path, self.line if line is None else line,
                                    f"{Path(self.moc.path).name}: {message}"))

    def apply(self):
        """The cell with the bounds, the carrier and the frames the MOC sets."""
        externals = tuple(self._bounds(e) for e in self.cell.externals)
        self._unmapped(externals)
        cell = replace(self.cell, externals=externals)
        cell = self._robot(cell)
        return cell

    # -- which robot, which axes (MultiMove: several robots, one task each) -------------------------
    def _unit_of_robot(self, robot: MocRobot) -> str:
        """The mechanical unit (lower case) that uses ``robot``."""
        return next((u.name.lower() for u in self.moc.units if u.robot is robot), robot.name.lower())

    def _which(self) -> MocRobot | None:
        """The MOC's robot the cell's robot is: the one ``[robot] unit`` names (its mechanical
        unit or ROBOT, or a motion task of SYS.cfg that moves it), else the only one."""
        robots = self.moc.robots
        name, line = self.given.get(("robot", "unit")) or (None, None)
        names = ", ".join(r.name for r in robots) or "none"
        tasks = [t for g in self.groups or () if g.robot for t in g.tasks]
        index = self.given.get(("robot", "index"))
        if name is None and index is not None and len(robots) > 1:  # the k-th [[robot]]: the k-th robot
            if index >= len(robots):
                self.fail(f"the cell has a [[robot]] {index + 1}, the controller {len(robots)} robots ({names})")
            return robots[index]
        if name is None:
            if len(robots) > 1:
                hint = f" (or its motion task: {', '.join(tasks)})" if tasks else ""
                self.fail(f"the controller has {len(robots)} robots ({names}: MultiMove): say which is the cell's, "
                          f"[robot] unit = \"{robots[0].name}\"{hint}")
            return robots[0] if robots else None
        key = name.strip().lower()
        for r in robots:
            if key in (r.name.lower(), self._unit_of_robot(r)):
                return r
        for g in self.groups or ():
            if g.robot and key in (t.lower() for t in g.tasks):
                found = next((r for r in robots if g.robot in (r.name.lower(), self._unit_of_robot(r))), None)
                if found is not None:
                    return found
        hint = f", and SYS.cfg the motion tasks {', '.join(tasks)}" if tasks else \
            "; a motion task is known by the backup's SYSPAR/SYS.cfg, which it lacks" if self.groups is None else ""
        self.fail(f"[robot] unit = '{name}' is no robot of the controller (its robots: {names}{hint})", line)

    def _task_axes(self) -> dict[str, MocJoint]:
        """The external axes of the chosen robot's task by logical axis: the joints of its
        mechanical unit group's units (SYS.cfg); without SYS.cfg, of every unit but those that
        carry another robot (one robot: every unit's). An axis two units still claim (one per
        task) is the carrier's where one of them carries the robot; else neither, with a warning."""
        joints = [j for j in self.moc.joints if j.logical_axis >= 7 and j.unit is not None]
        robots = self.moc.robots
        if self.robot is None or len(robots) < 2:
            return self.moc.external_axes
        mine = self._unit_of_robot(self.robot)
        group = next((g for g in self.groups or () if g.robot == mine), None)
        if group is not None:
            joints = [j for j in joints if j.unit.lower() in group.units]
        else:
            others = {r.base_frame.moved_by.lower() for r in robots if r is not self.robot and r.base_frame.moved_by}
            joints = [j for j in joints if j.unit.lower() not in others]
        carrier = (self.robot.base_frame.moved_by or "").lower()
        by_axis: dict[str, list[MocJoint]] = {}
        for j in joints:
            by_axis.setdefault(j.axis, []).append(j)
        out = {}
        for axis, found in by_axis.items():
            if len(found) > 1:
                found = [j for j in found if j.unit.lower() == carrier] or found
            if len(found) > 1:
                claims = " and ".join(f"{j.unit}'s joint {j.name}" for j in found)
                self.note(f"{axis} is {claims} (one per task); the backup has no SYS.cfg to say which is "
                          f"{self.robot.name}'s: neither is applied", "warning")
                continue
            out[axis] = found[0]
        return {a: out[a] for a in sorted(out)}

    def _bounds(self, e):
        """Unit ``e`` with the MOC's bounds on each joint whose logical axis the MOC has."""
        found = self.axes
        limits = {lim.joint: lim for lim in e.mechanism.limits}
        mech = e.mechanism
        for axis, name in zip(e.axes, e.joints):
            j = found.get(axis)
            if j is None:
                self.note(f"{axis} drives {e.name}'s {name} in the cell; the controller drives no {axis}", "warning")
                continue
            joint = mech.joint(name)
            if j.rotating is not None and j.rotating != joint.revolute:
                raise RsxmlError(Diagnostic(self.cell.path, self.line, f"{Path(self.moc.path).name}: {axis} is "
                                            f"{'rotating' if j.rotating else 'linear'} ({j.name}), but {e.name}'s "
                                            f"{name} {'turns' if joint.revolute else 'slides'}"))
            if j.lower is None or j.upper is None:
                continue
            old = limits.get(name)
            limits[name] = Limit(name, float(j.lower), float(j.upper))
            unit, f = ("deg", np.degrees(1.0)) if joint.revolute else ("mm", 1000.0)
            was = f"{old.min * f:g} .. {old.max * f:g} {unit}" if old is not None else "none"
            self.note(f"{axis} bounds {j.lower * f:g} .. {j.upper * f:g} {unit} ({j.unit}'s joint {j.name}) replace "
                      f"{e.name}'s {name} limits ({was})")
        return replace(e, mechanism=replace(mech, limits=tuple(limits.values()))) if mech.limits != tuple(
            limits.values()) else e

    def _unmapped(self, externals) -> None:
        mine = {a for e in externals for a in e.axes}
        for axis, j in self.axes.items():
            if axis not in mine:
                self.note(f"the controller drives {axis} ({j.unit}'s joint {j.name}); no unit of the cell does",
                          "warning")

    def _robot(self, cell):
        """The robot's carrier and base frame as its MOC robot has them, where not given."""
        if self.robot is None:
            return cell
        me = self.robot.name
        bf = self.robot.base_frame
        robot = cell.robot
        if len(self.moc.robots) > 1:
            self.note(f"the cell's robot is {me} (robot type {self.robot.robot_type or 'not given'}), one of the "
                      f"controller's {len(self.moc.robots)}")
        if bf.moved_by:
            carrier = self._unit_of(cell, bf.moved_by)
            if carrier is None:
                self.note(f"{me}'s base is moved by {bf.moved_by}, whose axes drive no unit of the cell", "warning")
            elif robot.on is None:
                robot = replace(robot, on=carrier)
                self.note(f"{me}'s base is moved by {bf.moved_by}: the robot stands on '{carrier}'")
            elif robot.on != carrier:
                self.note(f"{me}'s base is moved by {bf.moved_by} ('{carrier}' in the cell), not "
                          f"'{robot.on}' as [robot] on says", "warning")
        if not self.given.get(("robot", "frame")):
            robot = replace(robot, frame=self._on_flange(cell, robot.on, bf.matrix()))
            self.note(f"the robot's frame is {me}'s base frame: {bf.words()}")
        mine = self._unit_of_robot(self.robot)
        task = next((t for g in self.groups or () if g.robot == mine for t in g.tasks), None)
        robot = replace(robot, name=robot.name or me, task=robot.task or task)
        externals = tuple(self._unit_frame(e) for e in cell.externals)
        return replace(cell, robot=robot, externals=externals)

    @staticmethod
    def _on_flange(cell, on: str | None, frame: np.ndarray) -> np.ndarray:
        """A MOC base frame of a robot that a unit moves, given in the unit's own frame (at its base,
        moving with it), as the cell file places a carried robot: in the unit's mounting flange."""
        unit = next((e for e in cell.externals if e.name == on), None) if on else None
        if unit is None or unit.mount is None:
            return frame
        return np.linalg.inv(unit.mount.pose.matrix()) @ frame

    def _unit_of(self, cell, moc_unit: str) -> str | None:
        """The cell's unit driven by the logical axes of the MOC's mechanical unit ``moc_unit``."""
        try:
            axes = {j.axis for j in self.moc.unit(moc_unit).joints}
        except KeyError:
            return None
        for e in cell.externals:
            if axes and set(e.axes) == axes:
                return e.name
        return None

    def _unit_frame(self, e):
        """A single-axis unit's frame from its SINGLE's base frame, where the cell gives none (a
        unit of several axes has a base frame per axis, none of which is the unit's: a warning)."""
        if self.given.get(("external", e.name)):
            return e
        if len(e.axes) != 1:
            self.note(f"the frame of '{e.name}' is not set: its {len(e.axes)} axes each have their own base frame "
                      "in MOC.cfg, none the unit's; give its frame", "warning")
            return e
        for u in self.moc.units:
            for s in u.singles:
                j = next((j for j in u.joints if j.name == s.joint), None)
                if j is not None and j is self.axes.get(e.axes[0]):
                    self.note(f"the frame of '{e.name}' is {u.name}'s single {s.name}'s base frame: "
                              f"{s.base_frame.words()}")
                    return replace(e, frame=s.base_frame.matrix())
        return e


def apply_backup(cell, folder: Path, value, line: int, given: dict, fail):
    """(the cell with its backup's MOC.cfg applied and its EIO.cfg named, the notes and warnings
    it said). ``given``: what the cell file gives itself (``("robot", "frame")``: True; ``("robot",
    "unit")``: (the name, its line))."""
    path = moc_path(folder, value, fail)
    sys_cfg = beside(path, "SYS.cfg")
    done = MocApplied(cell, read_moc(path), line, given, motion_groups(sys_cfg) if sys_cfg else None)
    cell = done.apply()
    eio = beside(path, "EIO.cfg")
    if eio is not None:
        cell = replace(cell, eio=str(eio))
        done.said.append(Diagnostic(cell.path, line, f"{eio.name}: the controller's I/O configuration: the signals "
                                                     "it declares are known to a task run on the cell", "note"))
    return cell, done.said
