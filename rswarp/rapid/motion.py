"""What the interpreter hands the program layer, and what it asks of it. Out: a flat list of
``Motion`` records, one per move or wait, each with its data in SI and where it came from (file,
line, routine, call chain). In: a ``Robot``, the little the interpreter must know of the
kinematics to run CRobT, CJointT, CalcJointT and CalcRobT; ``NoRobot`` where there is none."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, Sequence

from ..errors import Diagnostic
from . import data as rd

KINDS = ("joint", "linear", "circular", "absolute", "wait")


@dataclass(frozen=True)
class Motion:
    """One move or wait. ``kind``: joint (MoveJ and its kin), linear (MoveL, TriggL, ArcL, SearchL,
    ...), circular (MoveC, ...; ``targets`` the circle point, then the end), absolute (MoveAbsJ)
    or wait (``seconds`` at rest). ``conf``: whether the configuration is checked (ConfJ/ConfL).
    ``accel`` and ``ramp`` (AccSet), ``override`` and ``vmax`` (VelSet, m/s) scale the timing;
    ``duration`` is a move's ``\\T``. ``cycle`` counts the passes of the task's main loop. ``load``:
    the payload GripLoad connected (in the flange's frame, tool0), which lowers the accelerations;
    the tool's own load is ``tool.load``."""

    kind: str
    instruction: str
    file: str
    line: int
    routine: str
    chain: tuple[str, ...] = ()
    targets: tuple = ()
    names: tuple[str, ...] = ()
    speed: rd.Speed | None = None
    zone: rd.Zone | None = None
    tool: rd.Tool | None = None
    wobj: rd.WorkObject | None = None
    conf: bool = True
    accel: float = 1.0
    ramp: float = 1.0
    override: float = 1.0
    vmax: float | None = None
    duration: float | None = None
    seconds: float = 0.0
    cycle: int = 0
    declared: tuple[str, ...] = ()  # per target, "file:line" of the data it is or is built from ("" inline)
    load: rd.Load | None = None  # GripLoad's payload in the flange's frame (a moves.HeldLoad: its source); None: none
    sync: str | None = None  # MultiMove: the syncident of a SyncMoveOn, SyncMoveOff or WaitSyncTask (a wait of 0 s)
    sync_kind: str = ""  # "on", "off" or "wait" for those
    sync_id: float | None = None  # a move's \\ID: its place among the tasks' synchronized moves

    @property
    def held_loads(self) -> tuple:
        """(the tool's load where the robot holds the tool, else None; GripLoad's payload or None):
        what the robot carries on this move besides ``--payload``."""
        tool = self.tool
        return (tool.load if tool is not None and tool.robhold else None), self.load


class Robot(Protocol):
    """The kinematics a running task asks about, in SI (joint values in rad or m, the robot's
    active axes in order)."""

    def revolute(self) -> tuple[bool, ...]:
        """Whether each active axis turns (degrees in RAPID) or slides (mm)."""

    def joints_after(self, motions: Sequence[Motion]) -> tuple[float, ...]:
        """The joint values where these motions leave the robot (CRobT, CJointT)."""

    def seconds_after(self, motions: Sequence[Motion]) -> float:
        """How long these motions take (the clocks: ClkRead)."""

    def extax_after(self, motions: Sequence[Motion]) -> tuple[float | None, ...]:
        """The six logical external axes (eax_a .. eax_f, mm or degrees; None: none) where these
        motions leave them (CRobT, CJointT)."""

    def pose(self, joints: Sequence[float], tool: rd.Tool, wobj: rd.WorkObject,
             extax: Sequence[float | None] = ()) -> tuple[rd.Pose, tuple]:
        """The TCP pose in the work object at ``joints`` (and the external axes at ``extax``, where
        they are now where not given), and the configuration data there (CalcRobT)."""

    def solve(self, target: rd.RobTarget, tool: rd.Tool, wobj: rd.WorkObject) -> tuple:
        """(joints that put the TCP on ``target`` with its confdata, None) or (None, why none do)
        (CalcJointT)."""


class NoRobot:
    """A task run without a robot: the robot-state functions are errors, said at their line."""

    def revolute(self) -> tuple[bool, ...]:
        return (True,) * 6

    def joints_after(self, motions):
        raise LookupError("it needs a robot model")

    def seconds_after(self, motions):
        raise LookupError("it needs a robot model")

    def extax_after(self, motions):
        return (None,) * 6

    def pose(self, joints, tool, wobj, extax=()):
        raise LookupError("it needs a robot model")

    def solve(self, target, tool, wobj):
        raise LookupError("it needs a robot model")


@dataclass(frozen=True)
class Cycle:
    """The task's main loop: where it is, and the motions each pass began at."""

    file: str
    line: int
    starts: tuple[int, ...]  # the index of each pass's first motion, then the end
    endless: bool = True


@dataclass(frozen=True)
class Run:
    """A task run: its motions, the warnings of what was assumed or skipped, and its cycles."""

    motions: tuple[Motion, ...]
    warnings: tuple[Diagnostic, ...] = ()
    cycle: Cycle | None = None
    files: tuple[str, ...] = ()
    routine: str = "main"
    statements: int = 0
    notes: tuple[str, ...] = field(default=())
    stopped: Diagnostic | None = None  # where the run stopped for a live input no --input gave
    needs_input: dict | None = None  # that input: name, source, file, line, read_file, read_line
    error: Diagnostic | None = None  # the run-time error the task stopped at (division by zero, ...)
    error_chain: tuple[str, ...] = ()  # the calls that led to it, outermost first
    assumed: tuple = ()  # check.Assumed: the stand-ins --assume-missing took for names declared nowhere
