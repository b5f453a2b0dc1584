"""The cell's types, in one place: the robot placed, the external units, the tool, the environment
meshes and the cell that holds them (``cell.read_cell`` reads a cell file into them; a MultiMove
cell holds one ``Cell`` per robot in ``team``)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import Diagnostic, InputError
from ..transforms import matrix_euler_zyx
from .model import Mechanism

LOGICAL_AXES = ("eax_a", "eax_b", "eax_c", "eax_d", "eax_e", "eax_f")


def _identity() -> np.ndarray:
    return np.eye(4)


@dataclass(frozen=True)
class PlacedRobot:
    """The robot: its RSXML file and mechanism, its base's frame (4x4, m) in the world, or on the
    carrier ``on`` names (the external unit whose last joint's link carries it; None: the floor);
    its ``name`` in the cell (``ROB_2``) and the motion task it runs (``T_ROB2``; None: the first)."""

    rsxml: str
    mechanism: Mechanism = field(compare=False, repr=False)
    frame: np.ndarray = field(default_factory=_identity, compare=False, repr=False)
    on: str | None = None
    line: int = 0
    name: str = ""
    task: str | None = None


@dataclass(frozen=True)
class External:
    """An external unit (a track, a positioner): its name in the cell, its RSXML file and
    mechanism, its frame in the world (4x4, m), the logical axes driving its active joints and
    those joints' names, in joint order."""

    name: str
    rsxml: str
    mechanism: Mechanism = field(compare=False, repr=False)
    frame: np.ndarray = field(default_factory=_identity, compare=False, repr=False)
    axes: tuple[str, ...] = ()
    joints: tuple[str, ...] = ()
    line: int = 0
    flange: str | None = None  # the RSXML Flange what rides the unit is mounted on; None: it has none

    @property
    def mount(self):
        """The unit's ``Flange`` that what rides it is placed in (a track's mount, a positioner's
        face plate): the one the cell file names, else its only one; None where it has none."""
        flanges = self.mechanism.flanges
        return next((f for f in flanges if f.name == self.flange), flanges[0] if flanges else None)

    @property
    def carrier_link(self) -> str:
        """The link that carries what stands on this unit: its mounting flange's link; without a
        flange, the child of its last active joint (its base link where it has no joint)."""
        if self.mount is not None:
            return self.mount.link
        active = self.mechanism.active_joints
        return active[-1].child if active else self.mechanism.base_link


@dataclass(frozen=True)
class CellTool:
    """The tool on the flange, as ``--tool`` takes it: a mesh file or an RSXML Mechanism of type
    Tool (``mechanism``), mounted at ``mount`` (4x4, m) in the flange's frame."""

    path: str
    mount: np.ndarray = field(default_factory=_identity, compare=False, repr=False)
    mechanism: Mechanism | None = field(default=None, compare=False, repr=False)
    line: int = 0

    def spec(self, mech: Mechanism) -> str:
        """The ``--tool PATH@x,y,z,rx,ry,rz`` text for the robot ``mech`` (its length unit, degrees)."""
        xyz = self.mount[:3, 3] / mech.length_factor
        angles = np.degrees(matrix_euler_zyx(self.mount[:3, :3]))
        return f"{self.path}@" + ",".join(f"{v:.12g}" for v in (*xyz, *angles))


@dataclass(frozen=True)
class CellMesh:
    """An environment mesh: its name (the file's stem), path and pose in the world (4x4, m); or,
    ``on`` a unit (the work clamped on a positioner's face plate), in that unit's flange frame,
    moving with it."""

    name: str
    path: str
    pose: np.ndarray = field(default_factory=_identity, compare=False, repr=False)
    line: int = 0
    on: str | None = None


@dataclass(frozen=True)
class Cell:
    """A cell file read: the robot, the external units (file order), the tool, the environment
    meshes, and warnings (``file:line: warning: ...``)."""

    path: str
    robot: PlacedRobot
    externals: tuple[External, ...] = ()
    tool: CellTool | None = None
    environment: tuple[CellMesh, ...] = ()
    warnings: tuple[str, ...] = ()
    diagnostics: tuple[Diagnostic, ...] = ()  # the warnings as records (``rswarp check``'s)
    eio: str | None = None  # the backup's SYSPAR/EIO.cfg: the signals a task run on the cell knows
    team: tuple[Cell, ...] = ()  # MultiMove ([[robot]] tables): one cell per robot, each with its units

    @property
    def mapping(self) -> dict[str, tuple[str, str]]:
        """Each logical axis the cell uses -> (external unit, joint), in axis order."""
        found = {a: (e.name, j) for e in self.externals for a, j in zip(e.axes, e.joints)}
        return {a: found[a] for a in LOGICAL_AXES if a in found}

    def unit_of(self, axis: str) -> tuple[str, str]:
        """The (external unit, joint) that logical ``axis`` (``eax_a``, case ignored) drives; an
        InputError naming the axes the cell uses where it drives none."""
        found = self.mapping.get(axis.strip().lower())
        if found is None:
            used = ", ".join(self.mapping) or "none"
            raise InputError(f"{self.path}: {axis} drives no joint in this cell (its logical axes: {used})")
        return found

    def external(self, name: str) -> External:
        """The external unit ``name``; KeyError where the cell has none of that name."""
        for e in self.externals:
            if e.name == name:
                return e
        raise KeyError(name)

    @property
    def carrier(self) -> External | None:
        """The external unit the robot stands on; None on the floor."""
        return None if self.robot.on is None else self.external(self.robot.on)
