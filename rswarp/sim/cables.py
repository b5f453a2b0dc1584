"""Cable runs: every cable of a mechanism in many environments at once, each environment's robot
following its own joint trajectory kinematically, and what a dress-pack designer asks of them
(``simulate_cables``): peak tension, the tightest bend, clearance and contact per link, whether
the cable is long enough, its twist, and its final shape.

A run is a client of the batch engine: its items are environments, a task runs some of them with
one ``CableSolver`` for all the mechanism's cables (the model ``CableOptions.cable_model`` names). Each run starts from
the rest shape at the zero position (where the file gives the control points): the robot moves to
the trajectory's start in SETTLE_MOVE seconds and holds for SETTLE_HOLD while the cable settles
under more damping; results count from the trajectory's t = 0.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import InputError
from ..kinematics.trajectory import Stacked, Trajectory, assign, minimum_jerk
from ..options import BOUNDS, checked
from ..rsxml.model import Mechanism
from .bodies import Environment
from .cable.extremes import RunningExtremes
from .cable.models import cable_model, make_solver
from .cable.rainflow import Rainflow
from .cable.results import CableResult, one_env
from .cable.solver import FATIGUE_EXPONENT, FATIGUE_FLOOR, GRAVITY, CableOptions, CableSolver, contact_meshes
from .cable.tally import MAX_VALUES_BYTES, CablePiece, CableTally, values_bytes
from .designs import DesignSet
from .engine import Job, run_batch

SETTLE_MOVE, SETTLE_HOLD, SETTLE_DAMPING = 0.5, 0.5, 10.0  # s, s, 1/s
# s a run goes on past the trajectory's end, the robot still at its last point, when no --seconds
# is given: a hose swings on after the last move, and its tightest bend may come then
SWING_AFTER = 1.0
MAX_FRAMES = 1_000_000  # frames of one run (4.6 h at 60 fps)


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
    joints: tuple[tuple[str, bool], ...] = ()  # the active joints: name, and whether rotational
    designs: tuple = ()  # a run of designs: per design (environment), its cables' ``CableInfo``

    @property
    def weights(self) -> tuple[float, ...]:
        """N: each cable's whole weight at the run's density, the most its own weight can press it."""
        return tuple(self.options.density * -GRAVITY[2] * np.pi * c.radius ** 2 * c.length for c in self.cables)

    @property
    def envs(self) -> int:
        return len(self.assignment)


def simulate_cables(mech: Mechanism, trajectories: list[Trajectory], envs: int, seconds: float | None = None,
                    options: CableOptions = CableOptions(),
                    progress: Callable[[float, float], None] | None = None, cluster=None,
                    designs: DesignSet | None = None) -> CableRun:
    """Every cable of ``mech`` in ``envs`` environments, environment e following
    ``trajectories[assign(...)[e]]`` for ``seconds`` (default: the longest trajectory). ``cluster``
    (a ``rswarp.Cluster`` or a Ray address) runs the environments as tasks on Ray. ``progress``
    counts the run's simulated seconds (each environment's share: all of them step together
    here, a Ray task adds its environments' share when it ends). With ``designs``, environment e
    runs design e (``envs`` is their number)."""
    if not mech.cables:
        raise InputError(f"{mech.path or mech.name}: the mechanism has no Cable to simulate")
    if not trajectories:
        raise InputError("no trajectory to follow")
    checked("envs", envs)
    if seconds is None:
        seconds = _trajectory_seconds(trajectories, options)
    frames = run_frames(float(seconds), options)
    job = CableJob(tuple(trajectories), tuple(assign(trajectories, envs)), 0, envs, len(mech.cables), frames, options,
                   designs)
    mechs = designs.mechanisms(mech) if designs is not None else (mech,)
    # a cable the model cannot take fails before anything is built (here, the solver checks the rest)
    for m in mechs if cluster is not None else mechs[:1]:
        cable_model(options).check(m, options, links=designs is None)
    meshes = contact_meshes(mech, options.environment, options.tool)
    if cluster is not None:
        _check_cut_run(mech, envs, frames)
    tools = None if cluster is not None else make_solver(mech, options, meshes, mechs if designs else ())
    tally = run_batch(job, mech, tools=tools, cluster=cluster, progress=progress)
    cables, recorded_q = tally.results()
    times = np.arange(1, frames + 1) / options.frame_rate
    infos = () if designs is None else tools.designs if tools is not None else \
        tuple(cable_model(options).cable_infos(m, options) for m in mechs)
    return CableRun(mech.name, cables, times, tuple(t.source for t in trajectories), job.who, recorded_q, options,
                    meshes.warnings if meshes else (), tuple((j.name, j.revolute) for j in mech.active_joints), infos)


def design_runs(run: CableRun) -> tuple[CableRun, ...]:
    """A run of designs (environment e ran design e) as one run per design, each with its cables'
    own length and segments."""
    out = []
    for e, cables in enumerate(run.designs):
        results = tuple(one_env(c, e, info) for c, info in zip(run.cables, cables))
        out.append(dataclasses.replace(run, cables=results, assignment=(run.assignment[e],), designs=(cables,)))
    return tuple(out)


def _trajectory_seconds(trajectories: list[Trajectory], options: CableOptions) -> float:
    """How long a run over ``trajectories`` lasts when no --seconds is given: the longest, and
    SWING_AFTER more with the robot still at its end where a run may last that long; an InputError
    naming the trajectory when that is no time at all, or longer than a run may be."""
    longest = max(trajectories, key=lambda t: t.duration)
    bound = BOUNDS["seconds"]
    if not longest.duration > 0:
        raise InputError(f"{longest.source}: the trajectory lasts 0 s (one row): a run needs time to pass; give "
                         "--seconds to hold it still for that long")
    if longest.duration > bound.high:
        raise InputError(f"{longest.source}: the trajectory lasts {longest.duration:g} s, longer than a run may be "
                         f"({bound.high:g} s, a day); give --seconds to run its start")
    for seconds in (longest.duration + SWING_AFTER, longest.duration):  # the swing where a run may hold it
        try:
            run_frames(seconds, options)
            return seconds
        except InputError as exc:
            why = exc
    raise InputError(f"{longest.source}: the trajectory lasts {longest.duration:g} s; {why}; give --seconds to "
                     "run its start, or a lower --frame-rate") from None


def run_frames(seconds: float, options: CableOptions) -> int:
    """The frames of a run of ``seconds`` (``InputError`` unless 1 to MAX_FRAMES, settling
    included): checked before any trajectory is made or any state allocated."""
    checked("seconds", seconds)
    frames = int(round(seconds * options.frame_rate))
    settle = int(round((SETTLE_MOVE + SETTLE_HOLD) * options.frame_rate))
    if not 1 <= frames <= MAX_FRAMES - settle:
        raise InputError(f"{seconds:g} s at {options.frame_rate:g} frames per second is {frames} frames and "
                         f"{settle} more to settle; a run takes 1 to {MAX_FRAMES} in all")
    return frames


def _check_cut_run(mech: Mechanism, envs: int, frames: int) -> None:
    """A run cut into tasks keeps each environment's value per frame for the spread: refused now
    where that is over the cap."""
    need = values_bytes(envs, frames, len(mech.cables))
    if need > MAX_VALUES_BYTES:
        raise InputError(f"a cluster run keeps each environment's value per frame for the spread plots: "
                         f"{need / 2**30:.1f} GiB for {envs} environments x {frames} frames, over the cap "
                         f"of {MAX_VALUES_BYTES >> 30} GiB; split the run (fewer environments or seconds)")


@dataclass(frozen=True)
class CableJob(Job):
    """A cable run as the engine's job: its items are environments; ``who[e - first]`` is the
    trajectory environment e follows (a task carries only its environments and their trajectories,
    ``first`` numbering its first)."""

    name = "cable"
    unit = "environment"

    trajectories: tuple[Trajectory, ...]
    who: tuple[int, ...]
    first: int
    envs: int  # environments of the whole run
    cables: int
    frames: int
    options: CableOptions
    designs: DesignSet | None = None  # environment e runs design e

    @property
    def count(self) -> int:
        return self.envs

    def task_items(self, cluster) -> int:
        return cluster.task_envs

    def size(self, span: range) -> float:
        """Progress in simulated seconds: the environments ``span``'s share of the run's."""
        return len(span) / self.envs * self.frames / self.options.frame_rate

    def for_task(self, span: range) -> "CableJob":
        used = sorted({self.who[e - self.first] for e in span})
        renumber = {k: n for n, k in enumerate(used)}
        designs = None if self.designs is None else self.designs.take(range(span.start - self.first,
                                                                            span.stop - self.first))
        return dataclasses.replace(self, trajectories=tuple(self.trajectories[k] for k in used),
                                   who=tuple(renumber[self.who[e - self.first]] for e in span), first=span.start,
                                   designs=designs)

    def tools_key(self) -> tuple:
        env = tuple((e.name, e.path, e.pose.tobytes()) for e in self.options.environment)
        return (dataclasses.replace(self.options, record=-1, threads=None, environment=()), env,
                None if self.designs is None else self.designs.key())

    def files(self) -> tuple[str, ...]:
        return tuple(e.path for e in self.options.environment)

    def tools(self, model, device: str, threads: int | None) -> CableSolver:
        env = tuple(Environment(e.name, model.local(e.path), e.pose) for e in self.options.environment)
        options = dataclasses.replace(self.options, device=device, threads=threads, environment=env)
        tool = self.options.tool
        meshes = model.cached(("contact meshes", env, tool), lambda: contact_meshes(model.mech, env, tool))
        designs = self.designs.mechanisms(model.mech) if self.designs is not None else ()
        return make_solver(model.mech, options, meshes, designs)

    def empty(self) -> CableTally:
        return CableTally(self.envs, self.frames, self.cables)

    def run(self, solver: CableSolver, tally: CableTally, span: range, tick) -> None:
        """Environments ``span``: settled, stepped ``frames`` frames, gathered into one piece."""
        whole = len(span) == self.envs
        record = self.options.record - span.start if span.start <= self.options.record < span.stop else -1
        who = np.asarray([self.who[e - self.first] for e in span])
        schedule = _Schedule(self.trajectories, who, self.options)
        run = _CableEnvs(solver, len(span), self.frames, self.options, record, values=not whole)
        _settle(run, schedule, self.options)
        recorded_q = []
        for f in range(self.frames):
            t0 = f / self.options.frame_rate
            qs = schedule.frame(t0)
            run.step(qs, t0 + 1 / self.options.frame_rate, schedule.bases(t0))
            if record >= 0:  # the played-back environment's joints (playback thins them like its cables)
                recorded_q.append(qs[record, -1])
            tick(self.size(span) / self.frames)
        values = None if whole else tuple(x.values for x in run.extremes)
        tally.add(CablePiece(span.start, run.results(), values, np.asarray(recorded_q)))


class _Schedule:
    """The joints of every environment at each substep: the trajectories, preceded by the settling
    move from the zero position to each one's start."""

    def __init__(self, trajectories: tuple[Trajectory, ...], who: np.ndarray, options: CableOptions):
        self.trajectories, self.who, self.options = trajectories, who, options
        self.start = np.stack([trajectories[k].at(np.zeros(1))[0] for k in who])
        self.dof = self.start.shape[1]
        self.stacked = Stacked.of(trajectories) if len(trajectories) > 1 else None  # all at once, where smooth

    def _times(self, t0: float) -> np.ndarray:
        """The ends of the substeps of the frame that starts at ``t0``."""
        o = self.options
        return t0 + np.arange(1, o.substeps + 1) / (o.substeps * o.frame_rate)

    def frame(self, t0: float) -> np.ndarray:
        """(envs, substeps, dof) float32 over the frame starting at ``t0`` (trajectory time)."""
        t = self._times(t0)
        if self.stacked is not None:
            return self.stacked.at(t)[self.who].astype(np.float32)
        out = np.empty((len(self.who), self.options.substeps, self.dof), np.float32)
        for k, traj in enumerate(self.trajectories):
            rows = self.who == k
            if rows.any():
                out[rows] = traj.at(t)[None]
        return out

    def bases(self, t0: float) -> np.ndarray | None:
        """(envs, substeps, 3) the robot's base moved from its start (a carriage's travel), or None
        where every trajectory's robot stands still."""
        if all(tr.base is None for tr in self.trajectories):
            return None
        t = self._times(t0)
        out = np.zeros((len(self.who), self.options.substeps, 3))
        for k, traj in enumerate(self.trajectories):
            rows = self.who == k
            if rows.any() and traj.base is not None:
                out[rows] = traj.base_at(t)[None]
        return out

    def settling(self, t0: float) -> np.ndarray:
        """The same over the settling phase, ``t0`` from its start."""
        blend = minimum_jerk(self._times(t0) / SETTLE_MOVE)
        return (self.start[:, None, :] * blend[None, :, None]).astype(np.float32)


def _settle(run: "_CableEnvs", schedule: _Schedule, options: CableOptions) -> None:
    frames = int(round((SETTLE_MOVE + SETTLE_HOLD) * options.frame_rate))
    run.solver.set_damping(SETTLE_DAMPING)
    for f in range(frames):
        run.solver.step(run.state, schedule.settling(f / options.frame_rate), 1 / options.frame_rate)
    run.solver.set_damping(options.damping)
    run.start()


class _CableEnvs:
    """A task's environments of every cable: the solver's state and, per cable, what is gathered
    frame by frame."""

    def __init__(self, solver: CableSolver, envs: int, frames: int, options: CableOptions, record: int,
                 values: bool):
        self.solver, self.options, self.record = solver, options, record
        self.state, self.envs = solver.state(envs), envs
        self.extremes = [RunningExtremes(info, len(solver.slots), envs, frames, record, values, solver.dof,
                                         options.max_strain, options.frame_clearances) for info in solver.cables]
        self.flows = None  # per cable, the rainflow count of each segment's curvature, from start()

    def start(self) -> None:
        """After settling: twists counted, the wear map summed and bending cycles counted from here."""
        self.solver.reset_totals(self.state)
        for x, stats in zip(self.extremes, self.solver.statistics(self.state)):
            x.start(stats)
        bends = self.solver.curvatures(self.state)
        if bends is not None:
            self.flows = [Rainflow(b.size, FATIGUE_EXPONENT, FATIGUE_FLOOR / info.allowed_bend_radius)
                          for b, info in zip(bends, self.solver.cables)]
            self._bend(bends)

    def step(self, qs: np.ndarray, t: float, base: np.ndarray | None = None) -> None:
        self.solver.step(self.state, qs, 1 / self.options.frame_rate, base)
        last = self.envs - 1
        for c, (x, stats) in enumerate(zip(self.extremes, self.solver.statistics(self.state))):
            x.add(stats, t, qs[:, -1], lambda c=c: self.solver.points(self.state, c, min(self.record, last)))
        if self.flows is not None:
            self._bend(self.solver.curvatures(self.state))

    def _bend(self, bends: list[np.ndarray]) -> None:
        for flow, b in zip(self.flows, bends):
            flow.add(b.reshape(-1))

    def results(self) -> tuple[CableResult, ...]:
        totals = self.solver.totals(self.state)
        for c, flow in enumerate(self.flows or ()):
            cycles, damage = flow.finish()
            shape = totals[c]["contact_time"].shape
            totals[c]["fatigue_cycles"], totals[c]["fatigue_sum"] = cycles.reshape(shape), damage.reshape(shape)
        failures = (self.solver.failures, self.solver.settle_failures)
        out = tuple(x.result(self.solver.slots, failures, self.solver.points(self.state, c), totals[c])
                    for c, x in enumerate(self.extremes))
        if self.options.floor is None and "floor" in self.solver.slots:  # no floor: nothing to be clear of
            k = self.solver.slots.index("floor")
            for r in out:
                r.clearance[:, k], r.clearance_time[:, k], r.clearance_at[:, k] = np.inf, np.nan, np.nan
        return out
