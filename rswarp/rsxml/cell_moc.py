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
  SINGLE's base frame), where its ``frame`` is not given.

Axes one side drives and the other does not are warnings."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ..errors import Diagnostic, RsxmlError
from .moc import MocConfig, read_moc
from .model import Limit


def moc_path(folder: Path, value, fail) -> Path:
    """The MOC.cfg a ``backup`` value names: a backup folder (its SYSPAR/MOC.cfg) or the file."""
    if not isinstance(value, str) or not value.strip():
        fail("backup: give the backup's folder (it holds SYSPAR/MOC.cfg) or its MOC.cfg, as a path relative to "
             "the cell file")
    path = folder / value.strip().replace("\\", "/")
    if path.is_dir():
        for sub in ("SYSPAR", "syspar", "Syspar"):
            if (path / sub / "MOC.cfg").is_file():
                return path / sub / "MOC.cfg"
        fail(f"backup: '{value}' holds no SYSPAR/MOC.cfg")
    if not path.is_file():
        fail(f"backup: no such file or folder '{value}' (looked for {path})")
    return path


class MocApplied:
    """A cell as read, with its MOC.cfg's settings applied; ``said`` the notes and warnings."""

    def __init__(self, cell, moc: MocConfig, line: int, given: dict):
        self.cell, self.moc, self.line, self.given = cell, moc, line, given
        self.said: list[Diagnostic] = []

    def note(self, message: str, severity: str = "note") -> None:
        self.said.append(Diagnostic(self.cell.path, self.line, f"{Path(self.moc.path).name}: {message}", severity))

    def apply(self):
        """The cell with the bounds, the carrier and the frames the MOC sets."""
        externals = tuple(self._bounds(e) for e in self.cell.externals)
        self._unmapped(externals)
        cell = replace(self.cell, externals=externals)
        cell = self._robot(cell)
        return cell

    def _bounds(self, e):
        """Unit ``e`` with the MOC's bounds on each joint whose logical axis the MOC has."""
        found = self.moc.external_axes
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
        for axis, j in self.moc.external_axes.items():
            if axis not in mine:
                self.note(f"the controller drives {axis} ({j.unit}'s joint {j.name}); no unit of the cell does",
                          "warning")

    def _robot(self, cell):
        """The robot's carrier and base frame as the MOC's first robot has them, where not given."""
        robots = self.moc.robots
        if not robots:
            return cell
        bf = robots[0].base_frame
        robot = cell.robot
        if bf.moved_by:
            carrier = self._unit_of(cell, bf.moved_by)
            if carrier is None:
                self.note(f"{robots[0].name}'s base is moved by {bf.moved_by}, whose axes drive no unit of the cell",
                          "warning")
            elif robot.on is None:
                robot = replace(robot, on=carrier)
                self.note(f"{robots[0].name}'s base is moved by {bf.moved_by}: the robot stands on '{carrier}'")
            elif robot.on != carrier:
                self.note(f"{robots[0].name}'s base is moved by {bf.moved_by} ('{carrier}' in the cell), not "
                          f"'{robot.on}' as [robot] on says", "warning")
        if not self.given.get(("robot", "frame")):
            robot = replace(robot, frame=bf.matrix())
            self.note(f"the robot's frame is {robots[0].name}'s base frame: {bf.words()}")
        externals = tuple(self._unit_frame(e) for e in cell.externals)
        return replace(cell, robot=robot, externals=externals)

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
                if j is not None and j.axis == e.axes[0]:
                    self.note(f"the frame of '{e.name}' is {u.name}'s single {s.name}'s base frame: "
                              f"{s.base_frame.words()}")
                    return replace(e, frame=s.base_frame.matrix())
        return e


def apply_backup(cell, folder: Path, value, line: int, given: dict, fail):
    """(the cell with its backup's MOC.cfg applied, the notes and warnings it said)."""
    path = moc_path(folder, value, fail)
    done = MocApplied(cell, read_moc(path), line, given)
    return done.apply(), done.said
