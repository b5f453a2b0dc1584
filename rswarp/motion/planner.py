"""A RAPID task's motions as a joint trajectory: each move's target resolved (``targets``), each
move timed and sampled (``timing``), in the order the task ran them, so CRobT and CJointT are
answered where the robot really is (``Planner`` is the ``rapid.motion.Robot`` the interpreter
asks). A target the robot cannot take is an error at its move's line; the move is skipped and the
rest planned, so one run reports every such target. The robot starts at its home position."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import Diagnostic
from ..findings import FAIL, Finding, at_time
from ..kinematics.ik import ArmConstants
from ..rapid import data as rd
from ..rapid.errors import fail
from ..rapid.motion import Motion, Run
from ..rsxml.robot_data import AxisLimits, axis_limits
from . import misses, plan_steps, timing, timing_batch, zones
from . import targets as tg
from .shortfall import Shortfall
from .tcp import Frames, flange_poses, frames, pose_of

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
    ignored: str | None = None  # external-axis values the robot has no axis for, ignored as the controller does


@dataclass(frozen=True)
class PlannedMove:
    """A motion as planned: its trajectory rows [first, last), its times, what it found."""

    motion: Motion
    target: str
    start: float
    end: float
    rows: tuple[int, int]
    findings: list[Finding] = field(default_factory=list)
    error: str | None = None
    shortfall: Shortfall | None = None  # how far a target it skipped is beyond the reach or a limit

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
    limits: AxisLimits | None = None  # the axis speeds and accelerations the timing used
    into_next: float = 0.0  # s the last pass would end sooner blending into another, as the loop goes on
    ext: np.ndarray | None = None  # (T, external joints) SI, in a cell: each unit's joints in the cell's order
    ext_axes: tuple = ()  # per column of ``ext``: (logical axis, unit, joint, revolute)
    framer: object = None  # in a cell: (tool, wobj, external joints) -> the move's Frames there

    @property
    def cycle_pass(self) -> int | None:
        """The pass ``cycle_s`` times (from 0): the second where there are two or more (it starts
        from a pass, as every later one does), else the first; None without passes."""
        if not self.cycles:
            return None
        return 1 if len(self.cycles) > 1 and self.run.stopped is None and self.run.error is None else \
            len(self.cycles) - 1

    @property
    def cycle_s(self) -> float:
        """The steady cycle: the time of pass ``cycle_pass`` of the main loop up to where the next
        pass takes over (the last one's end into the next pass it would blend into), or of the whole
        routine; None where the run stopped (a live input) before a pass ended."""
        k = self.cycle_pass
        if k is None:
            return None if self.run.stopped is not None or self.run.error is not None else float(self.times[-1])
        return self.cycles[k] - (self.into_next if k == len(self.cycles) - 1 else 0.0)


class Planner:
    """Plans motions as the task makes them; what the interpreter asks of the robot."""

    def __init__(self, kin, rate: float = timing.RATE, external_axes: str = "auto", limits: AxisLimits | None = None,
                 load_scale=None):
        self.kin, self.mech, self.rate = kin, kin.mech, rate
        self.load_scale = load_scale  # (tool's load, GripLoad's) -> per-axis acceleration factors, or None
        self.ignore_external = external_axes == "ignore"
        self.strict_external = external_axes == "error"
        self.ignored: dict = {}  # external axis -> [targets, lowest, highest, file, line]: values ignored
        self.ignored_at: dict = {}  # (file, line, target) -> the axes ignored there, in words
        self.q = np.asarray(self.mech.home_position(), float)
        self.limits = limits if limits is not None else axis_limits(self.mech)
        self.zoned: tuple | None = None  # (segment, zone) of the last move, while the next may blend into it
        self.now, self.count = 0.0, 1
        self.times, self.rows = [np.zeros(1)], [self.q[None]]
        self.moves: list[PlannedMove] = []
        self.targets: dict = {}
        self.errors: list[Diagnostic] = []
        self.repeats: dict = {}  # an error met again (every pass of a loop) is said once, with a count
        self.notes: list[Diagnostic] = []
        self.done = 0
        self.form = kin._ik_form()
        self.arm = isinstance(self.form, ArmConstants)
        self.bounds = self.mech.bounds()
        self.flange_now = None  # the flange's pose at self.q, where a move left it known
        self.frames: dict = {}  # (tool, wobj) -> their Frames, or why no robot moves them
        self.pieces: dict = {}  # move index -> its timed segment (``zones.Segment``), as the blend sees it

    # -- what the interpreter asks ------------------------------------------------------------------
    def revolute(self) -> tuple[bool, ...]:
        return tuple(j.revolute for j in self.mech.graph.active)

    def joints_after(self, motions) -> tuple[float, ...]:
        self.extend(motions)
        return tuple(float(v) for v in self.q)

    def seconds_after(self, motions) -> float:
        self.extend(motions)
        return self.now

    def extax_after(self, motions) -> tuple:
        """The robot alone has no external axes: none (9E9 in RAPID)."""
        return (None,) * 6

    def pose(self, joints, tool: rd.Tool, wobj: rd.WorkObject, extax=()):
        fr = self.query_frames(tool, wobj, extax)
        q = np.asarray(joints, float)[None]
        relative = fr.relative(self.flanges(q))[0]
        conf = tuple(int(c) for c in self.kin.confdata(q)[0]) if self.kin.ik_method != "numerical" else (0, 0, 0, 0)
        return pose_of(relative), conf

    def solve(self, target: rd.RobTarget, tool: rd.Tool, wobj: rd.WorkObject):
        fr = self.query_frames(tool, wobj, target.extax)
        pose = fr.flange(target.pose.matrix()[None])
        sol = self.kin.solutions64(pose)
        tg.off_the_axis(self.kin, pose, sol, float(self.q[0]), [target.conf])
        q, why = tg.pick(sol, 0, target.conf, self.q, True, "the robtarget", self.form, self.bounds, self.speeds)
        return (None, misses.figured(self, pose[0], why)) if q is None else (tuple(float(v) for v in q), None)

    def query_frames(self, tool, wobj, extax=()) -> Frames:
        """The frames CRobT, CalcRobT and CalcJointT answer in (the robot alone: no external axes);
        LookupError for a tool and work object no robot can move."""
        try:
            return frames(self.mech, tool, wobj)
        except ValueError as exc:
            raise LookupError(str(exc)) from None

    @property
    def dof(self) -> int:
        """The robot's own axes (a cell's trajectory has the external axes' columns after them)."""
        return len(self.q)

    @property
    def speeds(self) -> np.ndarray:
        """The robot's own axes' top speeds (which IK solution is reached soonest)."""
        return self.limits.velocity[:self.dof]

    def prepared(self, m: Motion) -> plan_steps.Prepared:
        """What the batch knows of a move before it is resolved: its frames."""
        return plan_steps.frames_of(self, m)

    def target_flange(self, m: Motion) -> np.ndarray | None:
        """The flange pose (robot's frame) a robtarget move asks for, where its frames are known."""
        return misses.target_flange(self, m)

    def joint_tcps(self, steps) -> np.ndarray:
        """(M, JOINT_PROBES, 4, 4): the TCP in the world along joint steps (at ``timing.joint_probes``)."""
        q0, q1 = np.array([s.q0 for s in steps]), np.array([s.q1 for s in steps])
        shares = np.linspace(0, 1, timing.JOINT_PROBES)[None, :, None]
        flanges = self.flanges((q0[:, None] + shares * (q1 - q0)[:, None]).reshape(-1, q0.shape[1]))
        flanges = flanges.reshape(len(steps), timing.JOINT_PROBES, 4, 4)
        return np.array([self.world(s.motion, f) for s, f in zip(steps, flanges)])

    # -- planning -------------------------------------------------------------------------------------
    def extend(self, motions) -> None:
        """Plan the motions not planned yet (``plan_steps``: in batches, then in order)."""
        new = list(motions[self.done:])
        self.done = len(motions)
        with plan_steps.no_gc():  # many small objects, no cycles: the collector's passes are all cost
            prepared = plan_steps.prepare(self, new)
            steps = [self.resolved(m, p) for m, p in zip(new, prepared)]
            plan_steps.time_all(self, steps)

    def resolved(self, m: Motion, p: plan_steps.Prepared) -> plan_steps.Step:
        """Where a motion takes the robot (``plan_steps.resolve``)."""
        return plan_steps.resolve(self, m, p)

    def finish(self, run: Run) -> Plan:
        self.extend(run.motions)
        times, q = np.concatenate(self.times), np.vstack(self.rows)
        moves, errors = misses.explained(self)  # each skipped target by how much; an error per line, counted
        self.notes += self._ignored_notes()
        return Plan(run, self._targets(), moves, times, q, errors, self._cycles(run), self.limits,
                    self._into_next(run))

    def time_step(self, s, tcp) -> None:
        """One resolved step timed, sampled and appended to the trajectory (``tcp``: a joint move's
        TCP along its probes)."""
        m = s.motion
        if s.kind == "path":
            s.findings = misses.path_findings(self, s)  # a path it cannot follow, by how much
        try:
            if s.kind == "skip":
                return self._skip(m, s.why)
            if s.kind == "wait":
                t = np.array([m.seconds]) if m.seconds > 0 else np.zeros(0)
                return self._append(m, t, np.repeat(s.q0[None], len(t), axis=0), [])
            if s.kind == "joint":
                t, seg, share = s.timing(lambda: timing_batch.joint_move(s, tcp, self.limits, self.rate,
                                                                          self.load_factor))
                piece = zones.jointed(t, seg, share, s.q0, tcp, s.ahead) if tcp is not None and len(t) else None
                self._short_time(m, t)
                return self._append(m, t, seg, [], piece)
            if len(s.u) < 2:
                return self._append(m, np.zeros(0), np.zeros((0, len(s.q0))), s.findings)
            t, seg, share = s.timing(lambda: timing_batch.path_move(s, self.limits, self.rate, self.load_factor))
        except timing.TooLong as exc:
            fail(m.file, m.line, f"{m.instruction}: {exc}")
        piece = zones.straight(t, seg, share, s.q0, s.length, s.turn, s.ahead) if len(t) else None
        if s.chained:
            self.zoned = None  # its corner is the chain's, in its samples already
        self._short_time(m, t)
        self._append(m, t, seg, s.findings + self._end_findings(m, t, seg, s.end_conf), piece)

    def _short_time(self, m: Motion, t: np.ndarray) -> None:
        """A warning, once a line, where a move's ``\\T`` is shorter than its axes allow: it takes
        the time they need, as the controller moves it as fast as it can."""
        if m.duration is None or not len(t) or t[-1] <= timing.given_time(m) * (1 + 1e-6):
            return
        key = (m.file, m.line, "\\T")
        if key not in self.repeats:
            self.repeats[key] = 1
            self.note(m, f"{m.instruction} \\T:={m.duration:g}: its axes need {float(t[-1]):.3g} s at their limits, "
                         "and it takes that")

    def flanges(self, q: np.ndarray) -> np.ndarray:
        """Flange poses (N, 4, 4) of joint values (N, dof), in one launch (``tcp.flange_poses``)."""
        return flange_poses(self.kin, q)

    def flange_at(self, q: np.ndarray) -> np.ndarray:
        return self.flanges(q[None])[0]

    def world(self, m: Motion, flanges: np.ndarray) -> np.ndarray:
        """The TCP in the world of flange poses (the flange itself for a stationary tool)."""
        base = self.mech.base_frame.matrix() if self.mech.base_frame is not None else np.eye(4)
        tool = m.tool.tframe.matrix() if m.tool is not None and m.tool.robhold else np.eye(4)
        return base @ flanges @ tool

    def external(self, m: Motion) -> str | None:
        """Why a motion cannot run for an axis the robot (or its cell) lacks, or None. As the
        controller, a target's value for an external axis nothing drives is ignored (tallied, said
        once an axis); a work object a unit moves is an error, unless --external-axes ignore."""
        values = [(axis, v) for axis, v in tg.extax_values(m) if axis not in self.driven]
        if values and self.strict_external:
            axis, v = values[0]
            return (f"'{m.names[-1]}' puts the external axis {axis} at {v:g}: {self.lacks(axis)} "
                    "(--external-axes auto ignores it, as the controller does)")
        for axis, v in values:
            seen = self.ignored.setdefault(axis, [0, v, v, m.file, m.line])
            seen[0], seen[1], seen[2] = seen[0] + 1, min(seen[1], v), max(seen[2], v)
        if values:
            words = ", ".join(sorted({f"{axis} {v:g}" for axis, v in values}))
            self.ignored_at[(m.file, m.line, m.names[-1])] = f"{words}: ignored, {self.lacks(values[0][0])}"
        why = self.uncoordinated(m)
        if why is not None and self.ignore_external:
            self.note(m, f"{why.split(' (')[0]}: ignored (--external-axes ignore)")
            return None
        return why

    driven: tuple = ()  # the logical external axes something drives (a cell's)

    def lacks(self, axis: str) -> str:
        """That nothing drives external ``axis``, in words."""
        return f"'{self.mech.name}' has no such axis"

    def uncoordinated(self, m: Motion) -> str | None:
        """Why the move's work object is moved by a unit the robot does not have, or None."""
        return tg.coordinated(m, self.mech.name)

    def _ignored_notes(self) -> list[Diagnostic]:
        """One warning an external axis whose values were ignored: how many, their range."""
        out = []
        for axis, (count, lo, hi, file, line) in sorted(self.ignored.items()):
            span = f"{lo:g}" if lo == hi else f"{lo:g} to {hi:g}"
            out.append(Diagnostic(file, line, f"{count} target{'s' * (count != 1)} give {axis} ({span}); "
                                              f"{self.lacks(axis)}, and the controller ignores the value: so does "
                                              "rswarp (--external-axes error refuses them)", "warning"))
        return out

    def load_factor(self, m: Motion):
        """The per-axis acceleration factors of the load the move carries (None: the arm's own)."""
        if self.load_scale is None or m.kind == "wait":
            return None
        return self.load_scale(*m.held_loads)

    def note(self, m: Motion, message: str) -> None:
        self.notes.append(Diagnostic(m.file, m.line, message, "warning"))

    def remember(self, m: Motion, q: np.ndarray) -> None:
        """A target the task used, once per place it is written."""
        self.targets.setdefault((m.file, m.line, m.names[-1]), (m.names[-1], m.file, m.line, q))

    def _end_findings(self, m: Motion, t: np.ndarray, seg: np.ndarray, conf) -> list[Finding]:
        """A path move's findings, timed from its start: near the wrist singularity; ending in
        another configuration than its robtarget's under ConfL\\On."""
        out = []
        if self.arm and len(seg):
            k = int(np.argmin(np.abs(seg[:, 4])))
            least = float(np.abs(seg[k, 4]))
            if least < np.radians(SINGULAR_DEG):
                out.append(at_time("singularity", f"passes {np.degrees(least):.2f} deg from the wrist singularity "
                                   "(q5 = 0)", m, t[k], seg[k], joint=self.mech.active_joints[4].name,
                                   value=least, limit=float(np.radians(SINGULAR_DEG)), unit="rad",
                                   advice="move the path or the tool's orientation away from q5 = 0, or use "
                                          "SingArea\\Wrist"))
        if m.conf and len(seg) and self.kin.ik_method != "numerical":
            got = conf if conf is not None else tuple(int(c) for c in self.kin.confdata(seg[-1:, :self.dof])[0])
            if tuple(got) != tuple(m.targets[-1].conf):
                out.append(at_time("configuration", f"ends in configuration {list(got)}, not the robtarget's "
                                   f"{list(m.targets[-1].conf)} (ConfL would stop it)", m, t[-1], seg[-1],
                                   severity=FAIL, advice="teach the robtarget again from the path, or run the "
                                                         "move with ConfL\\Off"))
        return out

    def _skip(self, m: Motion, why: str) -> None:
        self.zoned = None  # the robot stops where the move it cannot make begins
        message = f"{m.instruction}: {why}"
        key = (m.file, m.line, message)
        if key in self.repeats:
            self.repeats[key] += 1
        else:
            self.repeats[key] = 1
            self.errors.append(Diagnostic(m.file, m.line, message))
        self.moves.append(PlannedMove(m, ", ".join(m.names), self.now, self.now, (self.count, self.count), [], why))

    def _append(self, m: Motion, t: np.ndarray, seg: np.ndarray, findings: list[str], piece=None) -> None:
        """A move's samples added; a move that follows a zoned one at once starts inside its zone."""
        if self.zoned is not None and piece is not None:
            seg = self._blend(piece, m)
        if self.count + len(t) > MAX_ROWS:
            hours = MAX_ROWS / self.rate / 3600
            fail(m.file, m.line, f"the trajectory would hold more than {MAX_ROWS} samples ({hours:.1f} h at "
                                 f"{self.rate:g} a second): run fewer --cycles, or a shorter task")
        end = self.now + (float(t[-1]) if len(t) else 0.0)
        findings = [self._timed(f, end, seg) for f in findings]
        label = ", ".join(m.names) if m.kind != "wait" else f"{m.seconds:g} s"
        self.moves.append(PlannedMove(m, label, self.now, end, (self.count, self.count + len(t)), findings))
        if piece is not None:
            self.pieces[len(self.moves) - 1] = piece
        if len(t):
            self.times.append(self.now + t)
            self.rows.append(seg)
        self.now, self.count = end, self.count + len(t)
        blends = piece is not None and m.zone is not None and not m.zone.fine
        self.zoned = (piece, m.zone) if blends else None

    def _timed(self, f: Finding, end: float, seg: np.ndarray) -> Finding:
        """A move's finding timed from the run's start: one timed from the move's start moved on
        by its start, one without a time (a path it stopped following) at the move's end."""
        if f.t_s is not None:
            return replace(f, t_s=self.now + f.t_s)
        return replace(f, t_s=end, joints=tuple(float(v) for v in seg[-1]) if len(seg) else None)

    def _blend(self, piece: zones.Segment, m: Motion) -> np.ndarray:
        """The last move cut where ``piece`` starts inside its zone; ``piece``'s joints with the
        rest of that move added; the overlap halved while the two together pass an axis's limit."""
        prev, zone = self.zoned
        tau = zones.overlap(prev, piece, zone)
        if tau <= 0:
            return piece.q
        kept, q = zones.blend(prev, piece, tau)
        speed, accel = self._blend_limits(self.moves[-1].motion, m)
        if not zones.within(prev, piece, kept, q, tau, speed, accel):
            for k in range(1, zones.TRIES + 1):  # the longest overlap, in steps down, that keeps them
                kept, q = zones.blend(prev, piece, tau * zones.SHORTER ** k)
                if zones.within(prev, piece, kept, q, tau * zones.SHORTER ** k, speed, accel):
                    tau *= zones.SHORTER ** k
                    break
            else:
                return piece.q  # the move after starts from rest
        last = self.moves[-1]
        drop = len(prev.t) - kept
        self.times[-1], self.rows[-1] = self.times[-1][:kept], self.rows[-1][:kept]
        self.now, self.count = last.start + prev.duration - tau, self.count - drop
        self.moves[-1] = replace(last, end=self.now, rows=(last.rows[0], last.rows[1] - drop))
        return q

    def _blend_limits(self, a: Motion, b: Motion) -> tuple[np.ndarray, np.ndarray]:
        """The axes' speeds and accelerations both moves of a blend keep (the lower of each)."""
        factors = [self.load_factor(x) for x in (a, b)]
        load = None if all(f is None for f in factors) else np.array(
            [np.ones(len(self.limits.velocity)) if f is None else timing.widened(f, len(self.limits.velocity))
             for f in factors])
        v, acc, _ = timing.move_limits([a, b], self.limits, load)
        return v.min(axis=0), acc.min(axis=0)

    def _targets(self) -> tuple[Target, ...]:
        found = list(self.targets.values())
        if not found:
            return ()
        q = np.array([f[3] for f in found])
        limit, reach = tg.margins(self.kin, q)
        confs = self.kin.confdata(q) if self.kin.ik_method != "numerical" else [None] * len(q)
        return tuple(Target(name, file, line, joints, None if c is None else tuple(int(v) for v in c), float(limit[k]),
                            None if reach is None else float(reach[k]), self.ignored_at.get((file, line, name)))
                     for k, ((name, file, line, joints), c) in enumerate(zip(found, confs)))

    def _into_next(self, run: Run) -> float:
        """How much sooner the last pass would end if the loop went on: the overlap of its last
        move, in its zone, with the pass's first move, which the next pass would start with."""
        cycle = run.cycle
        if cycle is None or run.stopped is not None or self.zoned is None or len(cycle.starts) < 2:
            return 0.0
        first = self.pieces.get(cycle.starts[-2])
        return 0.0 if first is None else zones.overlap(self.zoned[0], first, self.zoned[1])

    def _cycles(self, run: Run) -> tuple[float, ...]:
        """The time of each pass of the main loop (or of each run of the entry routine)."""
        if run.cycle is None or not self.moves:
            return ()
        starts = [self.moves[k].start if k < len(self.moves) else self.now for k in run.cycle.starts]
        return tuple(float(b - a) for a, b in zip(starts, starts[1:]))


def plan(kin, run: Run, rate: float = timing.RATE, external_axes: str = "auto",
         limits: AxisLimits | None = None) -> Plan:
    """The trajectory of a task already run (no CRobT answered mid-run): ``Planner`` over its motions."""
    return Planner(kin, rate, external_axes, limits).finish(run)

