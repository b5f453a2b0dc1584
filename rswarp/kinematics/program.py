"""A RAPID task's motions as a joint trajectory: each move's target resolved (``targets``), each
move timed and sampled (``timing``), in the order the task ran them, so CRobT and CJointT are
answered where the robot really is (``Planner`` is the ``rapid.motion.Robot`` the interpreter
asks). A target the robot cannot take is an error at its move's line; the move is skipped and the
rest planned, so one run reports every such target. The robot starts at its home position."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import Diagnostic
from ..rapid import data as rd
from ..rapid.errors import fail
from ..rapid.motion import Motion, Run
from ..rsxml.units import JOINT_VELOCITY
from . import targets as tg
from . import timing
from .ik import ArmConstants
from .tcp import Frames, frames, pose_of

SINGULAR_DEG = 1.0  # |q5| below this along a linear or circular move: a finding
MAX_ROWS = 5_000_000  # samples of one trajectory: memory stays bounded (a little over 5 hours at 250/s)


@dataclass(frozen=True)
class Target:
    """A target a move used: its joints (SI), configuration data, the margin to the nearest joint
    limit (rad or m; negative outside) and, for an arm, how much farther the wrist centre could
    reach from axis 2 (m)."""

    name: str
    file: str
    line: int
    joints: np.ndarray
    conf: tuple[int, int, int, int] | None
    limit_margin: float = 0.0
    reach_margin: float | None = None


@dataclass(frozen=True)
class PlannedMove:
    """A motion as planned: its trajectory rows [first, last), its times, what it found."""

    motion: Motion
    target: str
    start: float
    end: float
    rows: tuple[int, int]
    findings: list[str] = field(default_factory=list)
    error: str | None = None

    @property
    def line(self) -> int:
        return self.motion.line

    @property
    def instruction(self) -> str:
        return self.motion.instruction


@dataclass(frozen=True)
class Plan:
    """The task's trajectory (``times`` (T,), ``q`` (T, dof), SI), its moves and targets, the
    errors of targets it could not take, and the time of each pass of its main loop."""

    run: Run
    targets: tuple[Target, ...]
    moves: tuple[PlannedMove, ...]
    times: np.ndarray
    q: np.ndarray
    errors: tuple[Diagnostic, ...] = ()
    cycles: tuple[float, ...] = ()

    @property
    def cycle_s(self) -> float:
        """The time of one pass of the main loop (the last), or of the whole routine."""
        return self.cycles[-1] if self.cycles else float(self.times[-1])


class Planner:
    """Plans motions as the task makes them; what the interpreter asks of the robot."""

    def __init__(self, kin, rate: float = timing.RATE, external_axes: str = "error"):
        self.kin, self.mech, self.rate = kin, kin.mech, rate
        self.ignore_external = external_axes == "ignore"
        self.q = np.asarray(self.mech.home_position(), float)
        self.speeds = np.array([JOINT_VELOCITY[j.revolute] for j in self.mech.graph.active])
        self.now, self.count = 0.0, 1
        self.times, self.rows = [np.zeros(1)], [self.q[None]]
        self.moves: list[PlannedMove] = []
        self.targets: dict = {}
        self.errors: list[Diagnostic] = []
        self.repeats: dict = {}  # an error met again (every pass of a loop) is said once, with a count
        self.notes: list[Diagnostic] = []
        self.done = 0
        self.arm = isinstance(kin._ik_form(), ArmConstants)
        self.flange_now = None  # the flange's pose at self.q, where a move left it known

    # -- what the interpreter asks ------------------------------------------------------------------
    def revolute(self) -> tuple[bool, ...]:
        return tuple(j.revolute for j in self.mech.graph.active)

    def joints_after(self, motions) -> tuple[float, ...]:
        self.extend(motions)
        return tuple(float(v) for v in self.q)

    def pose(self, joints, tool: rd.Tool, wobj: rd.WorkObject):
        fr = self._frames_or_raise(tool, wobj)
        q = np.asarray(joints, float)[None]
        relative = fr.relative(self._flange(q))[0]
        conf = tuple(int(c) for c in self.kin.confdata(q)[0]) if self.kin.ik_method != "numerical" else (0, 0, 0, 0)
        return pose_of(relative), conf

    def solve(self, target: rd.RobTarget, tool: rd.Tool, wobj: rd.WorkObject):
        fr = self._frames_or_raise(tool, wobj)
        sol = self.kin.solutions64(fr.flange(target.pose.matrix()[None]))
        q, why = tg.pick(sol, 0, target.conf, self.q, True, "the robtarget")
        return (None, why) if q is None else (tuple(float(v) for v in q), None)

    def _frames_or_raise(self, tool, wobj) -> Frames:
        try:
            return frames(self.mech, tool, wobj)
        except ValueError as exc:
            raise LookupError(str(exc)) from None

    # -- planning -------------------------------------------------------------------------------------
    def extend(self, motions) -> None:
        """Plan the motions not planned yet."""
        new = list(motions[self.done:])
        self.done = len(motions)
        solved = self._solutions(new)
        for m, pre in zip(new, solved):
            self._plan(m, pre)

    def finish(self, run: Run) -> Plan:
        self.extend(run.motions)
        times, q = np.concatenate(self.times), np.vstack(self.rows)
        errors = tuple(e if self.repeats[(e.file, e.line, e.message)] == 1 else
                       Diagnostic(e.file, e.line, f"{e.message} ({self.repeats[(e.file, e.line, e.message)]} times)")
                       for e in self.errors)
        return Plan(run, self._targets(), tuple(self.moves), times, q, errors, self._cycles(run))

    def _solutions(self, motions: list[Motion]) -> list:
        """Per motion: (frames, inverse kinematics of its end target) in one batch, or an error."""
        out, poses, owners = [], [], []
        for k, m in enumerate(motions):
            if m.kind in ("wait", "absolute"):
                out.append(None)
                continue
            try:
                fr = frames(self.mech, m.tool, m.wobj)
            except ValueError as exc:
                out.append(str(exc))
                continue
            out.append([fr, None])
            poses.append(fr.flange(m.targets[-1].pose.matrix()[None])[0])
            owners.append(k)
        if poses:
            sol = self.kin.solutions64(np.array(poses))
            for row, k in enumerate(owners):
                out[k][1] = (sol, row)
        return out

    def _plan(self, m: Motion, pre) -> None:
        ext = tg.external_axes(m, self.mech.name) if m.kind != "wait" else None
        if ext is not None and self.ignore_external:
            self.notes.append(Diagnostic(m.file, m.line, f"{ext.split(' (')[0]}: ignored (--external-axes ignore)",
                                         "warning"))
        elif ext is not None:
            return self._skip(m, ext)
        if isinstance(pre, str):
            return self._skip(m, pre)
        if m.kind == "wait":
            return self._wait(m)
        if m.kind == "absolute":
            q1, why = tg.joint_values(self.mech, m.targets[0], m.names[0])
        else:
            fr, (sol, row) = pre
            q1, why = tg.pick(sol, row, m.targets[-1].conf, self.q, m.conf, m.names[-1])
        if why is not None:
            return self._skip(m, why)
        self.targets.setdefault((m.file, m.line, m.names[-1]), (m.names[-1], m.file, m.line, q1))
        if m.kind in ("absolute", "joint"):
            fr = None if m.kind == "absolute" else fr
            try:
                t, seg, last = timing.joint_move(self._flange, self._world(m), self.q, q1, m, self.speeds,
                                                 self.rate)
            except timing.TooLong as exc:
                fail(m.file, m.line, f"{m.instruction}: {exc}")
            findings = []
        else:
            try:
                t, seg, findings, last, end_conf = self._cartesian(m, fr)
            except timing.TooLong as exc:
                fail(m.file, m.line, f"{m.instruction}: {exc}")
            except ValueError as exc:
                return self._skip(m, str(exc))
            findings += self._end_findings(m, seg, end_conf)
        self._append(m, t, seg, findings)
        if len(t):
            self.flange_now = last

    def _world(self, m: Motion):
        """The TCP in the world of flange poses (the flange itself for a stationary tool)."""
        base = self.mech.base_frame.matrix() if self.mech.base_frame is not None else np.eye(4)
        tool = m.tool.tframe.matrix() if m.tool is not None and m.tool.robhold else np.eye(4)
        return lambda flanges: base @ flanges @ tool

    def _cartesian(self, m: Motion, fr: Frames):
        """(times, q, findings, the flange's pose at the end, the configuration there) of a linear or
        circular move from where the robot is."""
        if self.flange_now is None:
            self.flange_now = self._flange(self.q[None])[0]
        start = fr.relative(self.flange_now[None])[0]
        ends = [t.pose.matrix() for t in m.targets]
        at, length, turn = timing.path(start, ends[-1], ends[0] if m.kind == "circular" else None)
        still = (np.zeros(0), np.zeros((0, len(self.q))), [], None, None)
        if length < timing.STILL and turn < timing.STILL:  # already there
            return still
        count = int(np.clip(max(length / timing.PROBE_STEP, turn / timing.PROBE_TURN) + 1, timing.MIN_PROBES,
                            timing.MAX_PROBES))
        u = np.linspace(0.0, 1.0, count)
        flanges = fr.flange(at(u))
        q, stop, why, conf = timing.follow(self.kin, flanges, self.q)
        findings = []
        if stop is not None:
            findings.append(f"cannot follow its {'line' if m.kind == 'linear' else 'circle'}: {why} at "
                            f"{100.0 * stop / count:.0f} % of the move")
            u = u[:stop]
        if len(q) < 2:
            return (*still[:2], findings, None, None)
        v_tcp, v_ori = timing.tcp_speeds(m)
        nominal = min(v_tcp / length if length > 0 else np.inf, v_ori / turn if turn > 0 else np.inf)
        accel = nominal * m.accel / timing.ACCEL_TIME
        v = timing.speed_curve(u, q, nominal, self.speeds * m.override, accel)
        at_probe = timing.path_times(u, v)
        if m.duration is not None and m.duration > at_probe[-1]:
            at_probe = at_probe * (m.duration / at_probe[-1])
        t = timing.samples(float(at_probe[-1]), self.rate)
        along = np.interp(t, at_probe, u)
        seg = np.stack([np.interp(along, u, q[:, c]) for c in range(q.shape[1])], axis=1)
        return t, seg, findings, flanges[-1] if stop is None else None, conf

    def _end_findings(self, m: Motion, seg: np.ndarray, conf) -> list[str]:
        out = []
        if self.arm and len(seg):
            least = float(np.degrees(np.min(np.abs(seg[:, 4]))))
            if least < SINGULAR_DEG:
                out.append(f"passes {least:.2f} deg from the wrist singularity (q5 = 0)")
        if m.conf and len(seg) and self.kin.ik_method != "numerical":
            got = conf if conf is not None else tuple(int(c) for c in self.kin.confdata(seg[-1:])[0])
            if tuple(got) != tuple(m.targets[-1].conf):
                out.append(f"ends in configuration {list(got)}, not the robtarget's {list(m.targets[-1].conf)} "
                           "(ConfL would stop it)")
        return out

    def _wait(self, m: Motion) -> None:
        t = np.array([m.seconds]) if m.seconds > 0 else np.zeros(0)
        self._append(m, t, np.repeat(self.q[None], len(t), axis=0), [])

    def _skip(self, m: Motion, why: str) -> None:
        message = f"{m.instruction}: {why}"
        key = (m.file, m.line, message)
        if key in self.repeats:
            self.repeats[key] += 1
        else:
            self.repeats[key] = 1
            self.errors.append(Diagnostic(m.file, m.line, message))
        self.moves.append(PlannedMove(m, ", ".join(m.names), self.now, self.now, (self.count, self.count), [], why))

    def _append(self, m: Motion, t: np.ndarray, seg: np.ndarray, findings: list[str]) -> None:
        if self.count + len(t) > MAX_ROWS:
            hours = MAX_ROWS / self.rate / 3600
            fail(m.file, m.line, f"the trajectory would hold more than {MAX_ROWS} samples ({hours:.1f} h at "
                                 f"{self.rate:g} a second): run fewer --cycles, or a shorter task")
        end = self.now + (float(t[-1]) if len(t) else 0.0)
        label = ", ".join(m.names) if m.kind != "wait" else f"{m.seconds:g} s"
        self.moves.append(PlannedMove(m, label, self.now, end, (self.count, self.count + len(t)), findings))
        if len(t):
            self.times.append(self.now + t)
            self.rows.append(seg)
            self.q = seg[-1]
        self.now, self.count = end, self.count + len(t)

    def _flange(self, q: np.ndarray) -> np.ndarray:
        link, m = self.kin.flange_frame()
        return self.kin.fk64(np.atleast_2d(q))[:, link] @ m

    def _targets(self) -> tuple[Target, ...]:
        found = list(self.targets.values())
        if not found:
            return ()
        q = np.array([f[3] for f in found])
        limit, reach = tg.margins(self.kin, q)
        confs = self.kin.confdata(q) if self.kin.ik_method != "numerical" else [None] * len(q)
        return tuple(Target(name, file, line, joints, None if c is None else tuple(int(v) for v in c), float(limit[k]),
                            None if reach is None else float(reach[k]))
                     for k, ((name, file, line, joints), c) in enumerate(zip(found, confs)))

    def _cycles(self, run: Run) -> tuple[float, ...]:
        """The time of each pass of the main loop (or of each run of the entry routine)."""
        if run.cycle is None or not self.moves:
            return ()
        starts = [self.moves[k].start if k < len(self.moves) else self.now for k in run.cycle.starts]
        return tuple(float(b - a) for a, b in zip(starts, starts[1:]))


def plan(kin, run: Run, rate: float = timing.RATE, external_axes: str = "error") -> Plan:
    """The trajectory of a task already run (no CRobT answered mid-run): ``Planner`` over its motions."""
    return Planner(kin, rate, external_axes).finish(run)
