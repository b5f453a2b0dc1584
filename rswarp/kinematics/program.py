"""A RAPID routine as a joint trajectory: each target resolved by inverse kinematics with its
configuration data, each move timed and sampled.

The timing model (ABB's own planner is not public):
- every move starts and ends at rest: zones are read but corners are not blended (as if every
  zone were ``fine``), so durations are an upper bound on the controller's;
- a move's path parameter follows a trapezoid: it reaches its top speed in ``ACCEL_TIME``;
- the top speed is the highest that keeps every axis within its default speed
  (``rsxml.units.JOINT_VELOCITY``), the TCP within v_tcp and its turn within v_ori;
- MoveJ and MoveAbsJ interpolate in joint space, all axes synchronized; MoveL moves the TCP on
  its straight line with the orientation slerped, MoveC on the circle through the start, the
  circle point and the end; both are sampled and solved by inverse kinematics at every sample,
  keeping the configuration the move starts in.
The robot starts at its home position (the file's HomePosition, else zero)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from ..errors import Diagnostic, RsxmlError
from ..rapid import data as rd
from ..rapid.module import Module
from ..rapid.steps import Move, Wait
from ..rsxml.units import JOINT_VELOCITY
from .ik import ArmConstants

RATE = 250.0  # samples per second of the trajectory
ACCEL_TIME = 0.25  # s: a move reaches its top speed in this time
SINGULAR_DEG = 1.0  # |q5| below this along a move: a finding
PATH_PROBES = 64  # samples of a joint move's TCP path to measure its length and turn


@dataclass(frozen=True)
class Target:
    """A target a move uses: its joints (SI), configuration data, the margin to the nearest joint
    limit (rad or m; negative outside) and, for an arm, how much farther the wrist centre could
    reach from axis 2 (m)."""

    name: str
    line: int
    joints: np.ndarray
    conf: tuple[int, int, int, int] | None
    limit_margin: float
    reach_margin: float | None


@dataclass(frozen=True)
class PlannedMove:
    line: int
    instruction: str
    target: str
    start: float
    end: float
    rows: tuple[int, int]  # the trajectory rows it covers, [first, last)
    findings: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class Plan:
    """The routine's targets, moves and trajectory (``times`` (T,), ``q`` (T, dof), SI)."""

    module: Module
    targets: tuple[Target, ...]
    moves: tuple[PlannedMove, ...]
    times: np.ndarray
    q: np.ndarray


def flange_pose(mech, move: Move, target: rd.RobTarget) -> np.ndarray:
    """The flange pose (the mechanism's frame, metres) that puts the move's TCP on ``target``: the
    work object's uframe x oframe x the target, in the world that the RSXML BaseFrame places the
    robot in, times the tool frame's inverse."""
    world = move.wobj.matrix() @ target.pose.matrix()
    base = mech.base_frame.matrix() if mech.base_frame is not None else np.eye(4)
    return np.linalg.inv(base) @ world @ np.linalg.inv(move.tool.tframe.matrix())


def tcp_pose(mech, move: Move, flange: np.ndarray) -> np.ndarray:
    """The TCP pose in the work object of flange poses (N, 4, 4)."""
    base = mech.base_frame.matrix() if mech.base_frame is not None else np.eye(4)
    return np.linalg.inv(move.wobj.matrix()) @ base @ flange @ move.tool.tframe.matrix()


def jointtarget_values(mech, target: rd.JointTarget, path: str, line: int) -> np.ndarray:
    """A jointtarget's robax (degrees, mm) as the active joints' SI values, in order."""
    joints = mech.graph.active
    if len(joints) > len(target.robax):
        raise RsxmlError(Diagnostic(path, line, f"a jointtarget holds 6 axes; '{mech.name}' has {len(joints)}"))
    vals = target.robax[:len(joints)]
    if any(abs(v) >= rd.NO_VALUE for v in vals):
        raise RsxmlError(Diagnostic(path, line, "a jointtarget's axis of this robot is 9E9 (not used)"))
    return np.array([np.radians(v) if j.revolute else v / 1000.0 for v, j in zip(vals, joints)])


def _margins(kin, q: np.ndarray) -> tuple[float, float | None]:
    lower, upper = kin.mech.bounds()
    limit = float(np.min(np.minimum(q - lower, upper - q)))
    form = kin._ik_form()
    if not isinstance(form, ArmConstants):
        return limit, None
    w2, p2, p3, c0 = (np.asarray(v) for v in (form.w2, form.p2, form.p3, form.c0))
    across = lambda v: np.linalg.norm(v - (v @ w2) * w2)  # noqa: E731
    reach = across(p3 - p2) + across(c0 - p3)
    wrist, _ = kin.wrist_flange64(q[None])
    link = kin.graph.link_index(kin.graph.active[1].child)
    j2 = kin.fk64(q[None])[0, link]
    return limit, float(reach - across(wrist[0] - (j2[:3, :3] @ p2 + j2[:3, 3])))


def resolve(kin, module: Module, move: Move, k: int) -> Target:
    """Target ``k`` of a move: its joints by the confdata it carries; ``RsxmlError`` at the move's
    line when it is out of reach or no solution has its confdata."""
    mech, target, name = kin.mech, move.targets[k], move.names[k]
    if isinstance(target, rd.JointTarget):
        q = jointtarget_values(mech, target, module.path, move.line)
        conf = tuple(int(c) for c in kin.confdata(q[None])[0]) if kin.ik_method != "numerical" else None
        return Target(name, move.line, q, conf, *_margins(kin, q))
    if move.tool.robhold is False or move.wobj.robhold:
        raise RsxmlError(Diagnostic(module.path, move.line, "a stationary tool or a work object the robot holds "
                                                            "(robhold) is not supported"))
    pose = flange_pose(mech, move, target)
    sol = kin.ik64(pose[None])
    if not sol.ok.any():
        why = "out of reach" if not (sol.status == 2).any() else "reachable only outside the joint limits"
        raise RsxmlError(Diagnostic(module.path, move.line, f"robtarget '{name}' is {why}"))
    if sol.numerical:
        q = sol.q[0][np.argmax(sol.ok[0])]
        return Target(name, move.line, q, None, *_margins(kin, q))
    q, found = kin.ik64(pose[None], conf=target.conf)
    if not found[0]:
        have = sorted({tuple(int(v) for v in c) for c in sol.conf[0][sol.ok[0]]})
        raise RsxmlError(Diagnostic(module.path, move.line, f"robtarget '{name}' has no solution with confdata "
                                    f"{list(target.conf)}; its solutions have {', '.join(map(str, map(list, have)))}"))
    return Target(name, move.line, q[0], tuple(target.conf), *_margins(kin, q[0]))


def profile(duration: float, t: np.ndarray) -> np.ndarray:
    """The trapezoid's path parameter in [0, 1] at times ``t`` of a move of ``duration``."""
    ta = min(ACCEL_TIME, duration / 2)
    v = 1.0 / (duration - ta)
    t = np.clip(t, 0.0, duration)
    s = np.where(t < ta, 0.5 * v / ta * t ** 2, v * (t - ta / 2))
    tail = duration - t
    return np.where(t > duration - ta, 1.0 - 0.5 * v / ta * tail ** 2, s)


def duration_for(cruise: float) -> float:
    """The duration of a trapezoid whose cruise alone takes ``cruise`` seconds."""
    if cruise <= 0:
        return 0.0
    return cruise + ACCEL_TIME if cruise >= ACCEL_TIME else 2.0 * np.sqrt(cruise * ACCEL_TIME)


def joint_speeds(mech) -> np.ndarray:
    return np.array([JOINT_VELOCITY[j.revolute] for j in mech.graph.active])


def cartesian_path(start: np.ndarray, end: np.ndarray, circle: np.ndarray | None = None):
    """``at(u)`` poses (N, 4, 4) along the straight line (or the circle through ``circle``) from
    ``start`` to ``end``, orientation slerped; the path's length (m) and turn (rad)."""
    rots = Rotation.from_matrix(np.stack([start[:3, :3], end[:3, :3]]))
    slerp = Slerp([0.0, 1.0], rots)
    turn = float((rots[0].inv() * rots[1]).magnitude())
    p0, p1 = start[:3, 3], end[:3, 3]
    if circle is None:
        length = float(np.linalg.norm(p1 - p0))

        def point(u):
            return p0 + np.outer(u, p1 - p0)
    else:
        point, length = _arc(p0, circle[:3, 3], p1)

    def at(u):
        u = np.atleast_1d(u)
        out = np.tile(np.eye(4), (len(u), 1, 1))
        out[:, :3, :3] = slerp(u).as_matrix()
        out[:, :3, 3] = point(u)
        return out

    return at, length, turn


def _arc(a: np.ndarray, b: np.ndarray, c: np.ndarray):
    """(point(u), length) of the circle arc from a through b to c."""
    ab, ac = b - a, c - a
    n = np.cross(ab, ac)
    if np.linalg.norm(n) < 1e-9:
        raise ValueError("the three points of a MoveC are on one line")
    centre = a + (np.cross(n, ab) * (ac @ ac) + np.cross(ac, n) * (ab @ ab)) / (2 * (n @ n))
    r = float(np.linalg.norm(a - centre))
    e1 = (a - centre) / r
    e2 = np.cross(n / np.linalg.norm(n), e1)
    angle = lambda p: np.mod(np.arctan2((p - centre) @ e2, (p - centre) @ e1), 2 * np.pi)  # noqa: E731
    sweep = angle(c)

    def point(u):
        t = np.asarray(u) * sweep
        return centre + r * (np.outer(np.cos(t), e1) + np.outer(np.sin(t), e2))

    return point, r * sweep


def _tcp_world(mech, move: Move, flange: np.ndarray) -> np.ndarray:
    base = mech.base_frame.matrix() if mech.base_frame is not None else np.eye(4)
    return base @ flange @ move.tool.tframe.matrix()


def _flange_of(mech, move: Move, tcp: np.ndarray) -> np.ndarray:
    base = mech.base_frame.matrix() if mech.base_frame is not None else np.eye(4)
    return np.linalg.inv(base) @ tcp @ np.linalg.inv(move.tool.tframe.matrix())


def _flange_fk(kin, q: np.ndarray) -> np.ndarray:
    link, m = kin.flange_frame()
    return kin.fk64(np.atleast_2d(q))[:, link] @ m


def _samples(duration: float, rate: float) -> np.ndarray:
    n = max(int(np.ceil(duration * rate)), 1)
    return np.linspace(0.0, duration, n + 1)[1:]


def _joint_move(kin, move: Move, q0: np.ndarray, q1: np.ndarray, rate: float):
    """(times, q) of a synchronized joint move from q0 to q1."""
    probes = q0 + np.linspace(0, 1, PATH_PROBES)[:, None] * (q1 - q0)
    tcp = _tcp_world(kin.mech, move, _flange_fk(kin, probes))
    length = float(np.linalg.norm(np.diff(tcp[:, :3, 3], axis=0), axis=1).sum())
    turn = float(Rotation.from_matrix(tcp[0, :3, :3].T @ tcp[-1, :3, :3]).magnitude())
    cruise = max(float(np.max(np.abs(q1 - q0) / joint_speeds(kin.mech))), length / move.speed.v_tcp,
                 turn / move.speed.v_ori)
    duration = duration_for(cruise)
    if duration == 0:
        return np.zeros(0), np.zeros((0, len(q0)))
    t = _samples(duration, rate)
    return t, q0 + profile(duration, t)[:, None] * (q1 - q0)


def _follow(kin, flanges: np.ndarray, q0: np.ndarray):
    """Joint values along flange poses, each the solution nearest the one before (turns of the
    turning axes followed); (q, the first sample that has none or flips configuration, why)."""
    sol = kin.ik64(flanges)
    lower, upper = kin.mech.bounds()
    turning = [3, 5] if isinstance(kin._ik_form(), ArmConstants) else []
    out = np.empty((len(flanges), len(q0)))
    prev, branch = q0, None
    for k in range(len(flanges)):
        cand = sol.q[k].copy()
        for c in turning:
            cand[:, c] += 2 * np.pi * np.round((prev[c] - cand[:, c]) / (2 * np.pi))
        ok = sol.ok[k] & np.all((cand >= lower) & (cand <= upper), axis=1)
        if not ok.any():
            why = "out of reach" if not sol.ok[k].any() else "a joint limit"
            return out[:k], k, why
        dist = np.where(ok, np.abs(cand - prev).max(axis=1), np.inf)
        best = int(np.argmin(dist))
        if branch is not None and best // 2 != branch // 2 and not sol.numerical:
            return out[:k], k, "a configuration flip"
        branch = best if branch is None else branch
        out[k] = prev = cand[best]
    return out, None, ""


def _cartesian_move(kin, move: Move, q0: np.ndarray, ends: list[np.ndarray], rate: float):
    """(times, q, findings) of a MoveL (one end) or MoveC (circle point, end) from q0."""
    mech = kin.mech
    start = _tcp_world(mech, move, _flange_fk(kin, q0)[0])
    world = [move.wobj.matrix() @ t.pose.matrix() for t in move.targets]
    at, length, turn = cartesian_path(start, world[-1], world[0] if len(world) == 2 else None)
    cruise = max(length / move.speed.v_tcp, turn / move.speed.v_ori)
    findings = []
    for _ in range(3):  # slowed until no axis is faster than its default speed
        duration = duration_for(cruise)
        if duration == 0:
            return np.zeros(0), np.zeros((0, len(q0))), findings
        t = _samples(duration, rate)
        flanges = _flange_of(mech, move, at(profile(duration, t)))
        q, stop, why = _follow(kin, flanges, q0)
        steps = np.diff(np.vstack([q0, q]), axis=0) / np.diff(np.r_[0.0, t[:len(q)]])[:, None]
        over = float(np.max(np.abs(steps) / joint_speeds(mech), initial=0.0))
        if over <= 1.0 + 1e-9 or stop is not None:
            break
        cruise *= over * 1.02
    if stop is not None:
        findings.append(f"cannot follow its line: {why} at {100.0 * stop / len(t):.0f} % of the move")
        t = t[:len(q)]
    return t, q, findings


def _end_findings(kin, move: Move, q: np.ndarray, target, complete: bool) -> list[str]:
    out = []
    if isinstance(kin._ik_form(), ArmConstants) and len(q):
        least = float(np.degrees(np.min(np.abs(q[:, 4]))))
        if least < SINGULAR_DEG:
            out.append(f"passes {least:.2f} deg from the wrist singularity (q5 = 0)")
    if (move.instruction in ("MoveL", "MoveC") and target.conf is not None and len(q) and complete
            and kin.ik_method != "numerical"):
        got = tuple(int(c) for c in kin.confdata(q[-1:])[0])
        if got != tuple(target.conf):
            out.append(f"ends in configuration {list(got)}, not the robtarget's {list(target.conf)}")
    return out


def plan(kin, module: Module, rate: float = RATE) -> Plan:
    """The routine's trajectory: targets resolved, moves timed and sampled at ``rate``."""
    mech = kin.mech
    q = np.asarray(mech.home_position(), float)
    times, rows, moves, targets = [np.zeros(1)], [q[None]], [], {}
    now, count = 0.0, 1
    for step in module.steps:
        if isinstance(step, Wait):
            t = _samples(step.seconds, rate) if step.seconds > 0 else np.zeros(0)
            seg, findings, label, target = np.repeat(q[None], len(t), axis=0), [], "WaitTime", f"{step.seconds:g} s"
        else:
            resolved = [resolve(kin, module, step, k) for k in range(len(step.targets))]
            for r in resolved:
                targets.setdefault((r.name, r.line), r)
            if step.instruction in ("MoveJ", "MoveAbsJ"):
                t, seg = _joint_move(kin, step, q, resolved[-1].joints, rate)
                findings = []
            else:
                t, seg, findings = _cartesian_move(kin, step, q, [r.joints for r in resolved], rate)
            findings += _end_findings(kin, step, seg, resolved[-1], not findings)
            label, target = step.instruction, ", ".join(step.names)
        end = now + (float(t[-1]) if len(t) else 0.0)
        moves.append(PlannedMove(step.line, label, target, now, end, (count, count + len(t)), findings))
        if len(t):
            times.append(now + t)
            rows.append(seg)
            q = seg[-1]
        now, count = end, count + len(t)
    return Plan(module, tuple(targets.values()), tuple(moves), np.concatenate(times), np.vstack(rows))
