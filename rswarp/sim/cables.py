"""Cable runs: every cable of a mechanism in many environments at once, each environment's robot
following its own joint trajectory kinematically, and what a dress-pack designer asks of them
(``simulate_cables``): peak tension, the tightest bend, clearance and contact per link, whether
the cable is long enough, its twist, and its final shape.

Each run starts from the rest shape at the zero position (where the file gives the control
points): the robot moves to the trajectory's start in SETTLE_MOVE seconds and holds for
SETTLE_HOLD while the cable settles under more damping; results count from the trajectory's t = 0.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import InputError
from ..rsxml.model import Mechanism
from .cable import DENSITY, CableModel, CableState, CableStepper, cable_model, link_meshes
from .cable_results import CableResult, Tally
from .trajectory import Trajectory, assign, minimum_jerk

FRAME_RATE = 60.0  # frames per second: results are sampled per frame, substeps between
SUBSTEPS = 10  # per frame: 1.7 ms steps
SETTLE_MOVE, SETTLE_HOLD, SETTLE_DAMPING = 0.5, 0.5, 10.0  # s, s, 1/s
BEND_FACTOR = 10.0  # the least allowed bend radius, in diameters, unless given
MAX_ENVS = 1 << 16  # environments of one run: its state and per-frame results stay bounded
MAX_FRAMES = 1_000_000  # frames of one run (4.6 h at 60 fps)


@dataclass(frozen=True)
class CableOptions:
    """How a run is stepped and judged (SI)."""

    frame_rate: float = FRAME_RATE
    substeps: int = SUBSTEPS
    iterations: int = 2
    damping: float = 1.0  # 1/s: velocities decay as exp(-damping t)
    density: float = DENSITY
    bend_factor: float = BEND_FACTOR
    min_bend_radius: float | None = None  # m; default bend_factor x the diameter
    floor: float | None = 0.0  # z of the floor (m); None: no floor
    contact: bool = True  # against the link meshes
    record: int = -1  # the environment whose shapes are kept for playback (--usd); -1: none
    device: str = "cpu"
    threads: int | None = None


@dataclass(frozen=True)
class CableRun:
    """A run: its cables' results, the frame times, which trajectory each environment followed."""

    mechanism: str
    cables: tuple[CableResult, ...]
    times: np.ndarray
    trajectories: tuple[str, ...]
    assignment: tuple[int, ...]
    q: np.ndarray = field(repr=False)  # (frames, dof) the recorded environment's joints; empty without record
    options: CableOptions = CableOptions()
    warnings: tuple[str, ...] = ()

    @property
    def envs(self) -> int:
        return len(self.assignment)


def simulate_cables(mech: Mechanism, trajectories: list[Trajectory], envs: int, seconds: float | None = None,
                    options: CableOptions = CableOptions(),
                    progress: Callable[[int, int], None] | None = None, cluster=None) -> CableRun:
    """Every cable of ``mech`` in ``envs`` environments, environment e following
    ``trajectories[assign(...)[e]]`` for ``seconds`` (default: the longest trajectory). ``cluster``
    (a ``rswarp.Cluster`` or a Ray address) runs the environments as tasks on Ray; ``progress``
    then counts environments, not frames."""
    if not mech.cables:
        raise InputError(f"{mech.path or mech.name}: the mechanism has no Cable to simulate")
    if not trajectories:
        raise InputError("no trajectory to follow")
    if not 1 <= envs <= MAX_ENVS:
        raise InputError(f"--envs must be between 1 and {MAX_ENVS}, got {envs}")
    seconds = max(t.duration for t in trajectories) if seconds is None else float(seconds)
    frames = int(round(seconds * options.frame_rate))
    if not 1 <= frames <= MAX_FRAMES:
        raise InputError(f"{seconds:g} s at {options.frame_rate:g} frames per second is {frames} frames; "
                         f"a run takes 1 to {MAX_FRAMES}")
    meshes = link_meshes(mech) if options.contact else None
    who = assign(trajectories, envs)
    if cluster is not None:
        from .cable_tasks import on_cluster

        for c in mech.cables:  # a cable rswarp cannot model fails here, before anything is scheduled
            cable_model(mech, c, density=options.density)
        cables, recorded_q = on_cluster(mech, trajectories, who, frames, options, progress, cluster)
    else:
        runs, recorded_q = simulate(mech, trajectories, who, frames, options, meshes, progress)
        cables = tuple(r.result() for r in runs)
    times = np.arange(1, frames + 1) / options.frame_rate
    return CableRun(mech.name, cables, times, tuple(t.source for t in trajectories), tuple(who),
                    recorded_q, options, meshes.warnings if meshes else ())


def simulate(mech: Mechanism, trajectories: list[Trajectory], who: list[int], frames: int, options: CableOptions,
             meshes, progress: Callable[[int, int], None] | None = None, values: bool = False,
             stepper: Callable | None = None) -> tuple[list["_CableRun"], np.ndarray]:
    """The run of environments ``who`` (each its trajectory's index): its cables, settled and
    stepped ``frames`` frames, and the recorded environment's joints. ``values``: keep every
    environment's per-frame values (a task of a cluster run) instead of their spread."""
    make = stepper or (lambda model: make_stepper(mech, model, options, meshes))
    runs = [_CableRun(mech, c, len(who), frames, options, make, values) for c in mech.cables]
    schedule = _Schedule(mech, trajectories, who, options)
    _settle(runs, schedule, options)
    recorded_q = []
    for f in range(frames):
        t0 = f / options.frame_rate
        qs = schedule.frame(t0)
        for r in runs:
            r.step(qs, t0 + 1 / options.frame_rate)
        if options.record >= 0:  # the played-back environment's joints, thinned like its cables
            recorded_q.append(qs[min(options.record, len(who) - 1), -1])
        if progress is not None:
            progress(f + 1, frames)
    return runs, np.asarray(recorded_q)


def make_stepper(mech: Mechanism, model: CableModel, options: CableOptions, meshes) -> CableStepper:
    """The stepper of one cable as ``options`` asks for it."""
    return CableStepper(mech, model, substeps=options.substeps, iterations=options.iterations,
                        damping=options.damping, meshes=meshes, floor=options.floor, device=options.device,
                        threads=options.threads)


class _Schedule:
    """The joints of every environment at each substep: the trajectories, preceded by the settling
    move from the zero position to each one's start."""

    def __init__(self, mech: Mechanism, trajectories: list[Trajectory], who: list[int], options: CableOptions):
        self.trajectories, self.who, self.options = trajectories, np.asarray(who), options
        self.dof = mech.dof
        self.start = np.stack([trajectories[k].at(np.zeros(1))[0] for k in who])

    def _times(self, t0: float) -> np.ndarray:
        """The ends of the substeps of the frame that starts at ``t0``."""
        o = self.options
        return t0 + np.arange(1, o.substeps + 1) / (o.substeps * o.frame_rate)

    def frame(self, t0: float) -> np.ndarray:
        """(envs, substeps, dof) float32 over the frame starting at ``t0`` (trajectory time)."""
        o = self.options
        t = self._times(t0)
        out = np.empty((len(self.who), o.substeps, self.dof), np.float32)
        for k, traj in enumerate(self.trajectories):
            rows = self.who == k
            if rows.any():
                out[rows] = traj.at(t)[None]
        return out

    def settling(self, t0: float) -> np.ndarray:
        """The same over the settling phase, ``t0`` from its start."""
        blend = minimum_jerk(self._times(t0) / SETTLE_MOVE)
        return (self.start[:, None, :] * blend[None, :, None]).astype(np.float32)


def _settle(runs: list["_CableRun"], schedule: _Schedule, options: CableOptions) -> None:
    frames = int(round((SETTLE_MOVE + SETTLE_HOLD) * options.frame_rate))
    for r in runs:
        r.stepper.set_damping(SETTLE_DAMPING)
    for f in range(frames):
        qs = schedule.settling(f / options.frame_rate)
        for r in runs:
            r.stepper.step(r.state, qs, 1 / options.frame_rate)
    for r in runs:
        r.stepper.set_damping(options.damping)
        r.started()


class _CableRun:
    """One cable's environments and what is gathered from them frame by frame."""

    def __init__(self, mech: Mechanism, cable, envs: int, frames: int, options: CableOptions,
                 stepper: Callable[[CableModel], CableStepper], values: bool = False):
        self.model: CableModel = cable_model(mech, cable, density=options.density)
        self.stepper = stepper(self.model)
        self.stepper.set_damping(options.damping)
        self.state: CableState = self.stepper.state(envs)
        self.options = options
        self.links = (*mech.graph.links, "floor")
        self.tally = Tally(self.model, envs, len(self.links), frames, options.record, values)

    def started(self) -> None:
        self.tally.start(self.state)

    def step(self, qs: np.ndarray, t: float) -> None:
        self.stepper.step(self.state, qs, 1 / self.options.frame_rate)
        self.tally.add(self.state, t)

    def result(self) -> CableResult:
        o = self.options
        allowed = o.min_bend_radius if o.min_bend_radius is not None else o.bend_factor * 2 * self.model.radius
        return self.tally.result(allowed, self.links, self.state)
