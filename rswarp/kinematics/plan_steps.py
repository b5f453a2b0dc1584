"""The planner's three steps over a batch of motions, so that the kinematics run in a few large
launches, not one per move:

1. ``prepare``: each move's frames, its target's flange pose and every solution of it, and each
   linear or circular move's path probed from where the move before it ends, all solved at once;
2. ``resolve``, move by move: the joints each goes to (the solution the controller picks), and a
   path's joints followed from where the robot is (probes solved again only where a move ended
   elsewhere than its target);
3. ``time_all``: the joint moves' TCP paths posed in one batch, then every move timed and
   sampled in order."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..findings import FAIL, at_time
from . import targets as tg
from . import timing
from .follow import follow
from .ik import IKSolutions
from .paths import path
from .tcp import Frames, frames


@dataclass
class Prepared:
    """What a batch computed for one motion before the robot's way there is known."""

    frames: Frames | None = None
    error: str | None = None
    sol: IKSolutions | None = None  # every solution of the target (turns included)
    row: int = 0
    end: np.ndarray | None = None  # the flange's pose at the target
    start: np.ndarray | None = None  # the flange pose a path's probes assume it starts from
    path: tuple | None = None  # (u, length, turn, flanges) of a linear or circular move
    probe_sol: IKSolutions | None = None  # the probes' branches


@dataclass
class Step:
    """A motion resolved: what ``time_all`` times (kind: skip, wait, joint, path)."""

    motion: object
    kind: str
    why: str | None = None
    q0: np.ndarray | None = None
    q1: np.ndarray | None = None
    u: np.ndarray | None = None  # a path's probes and joints there
    q: np.ndarray | None = None
    length: float = 0.0
    turn: float = 0.0
    findings: list = field(default_factory=list)
    end_conf: tuple | None = None


def prepare(planner, motions) -> list[Prepared]:
    """Frames, targets, their solutions and the paths' probes of ``motions``, in batches."""
    out = [_frames(planner, m) for m in motions]
    _targets(planner, motions, out)
    _paths(planner, motions, out)
    return out


def _frames(planner, m) -> Prepared:
    """The move's frames, made once per tool and work object."""
    if m.kind in ("wait", "absolute"):
        return Prepared()
    key = (m.tool, m.wobj)
    made = planner.frames.get(key)
    if made is None:
        try:
            made = frames(planner.mech, m.tool, m.wobj)
        except ValueError as exc:
            made = str(exc)
        planner.frames[key] = made
    return Prepared(error=made) if isinstance(made, str) else Prepared(made)


def _targets(planner, motions, out: list[Prepared]) -> None:
    """Each target's flange pose: a robtarget's by its frames (and all its solutions), a
    jointtarget's by forward kinematics."""
    poses, owners, joints, absolute = [], [], [], []
    for k, (m, p) in enumerate(zip(motions, out)):
        if p.frames is not None:
            p.end = p.frames.flange(m.targets[-1].pose.matrix()[None])[0]
            poses.append(p.end)
            owners.append(k)
        elif m.kind == "absolute":
            q, why = tg.joint_values(planner.mech, m.targets[0], m.names[0])
            if q is not None and why is None:
                joints.append(q)
                absolute.append(k)
    if poses:
        poses = np.array(poses)
        sol = planner.kin.solutions64(poses)
        checked = [motions[k].targets[-1].conf if motions[k].conf else None for k in owners]
        tg.off_the_axis(planner.kin, poses, sol, float(planner.q[0]), checked)
        for row, k in enumerate(owners):
            out[k].sol, out[k].row = sol, row
    if joints:
        for k, flange in zip(absolute, planner.flanges(np.array(joints))):
            out[k].end = flange


def _paths(planner, motions, out: list[Prepared]) -> None:
    """The probes of every linear and circular move, from the end of the move before it, solved
    in one launch."""
    before = planner.flange_now
    flanges, owners = [], []
    for k, (m, p) in enumerate(zip(motions, out)):
        if m.kind in ("linear", "circular") and p.frames is not None:
            start = before if before is not None else planner.flange_at(planner.q)
            try:
                p.path = probe_path(p.frames, m, start)
            except ValueError as exc:
                p.error = str(exc)
            else:
                p.start = start
                if p.path is not None:
                    flanges.append(p.path[3])
                    owners.append(k)
        if m.kind != "wait" and p.end is not None and p.error is None:
            before = p.end
    if flanges:
        sol = planner.kin.ik64(np.concatenate(flanges))
        at = 0
        for k in owners:
            n = len(out[k].path[0])
            out[k].probe_sol = IKSolutions(sol.q[at:at + n], sol.conf[at:at + n], sol.status[at:at + n],
                                           sol.numerical)
            at += n


def probe_path(fr: Frames, m, start: np.ndarray):
    """(u, length, turn, flanges) of a move's path from flange pose ``start``; None where the
    robot is there already; ValueError for a circle on one line."""
    rel = fr.relative(start[None])[0]
    ends = [t.pose.matrix() for t in m.targets]
    at, length, turn = path(rel, ends[-1], ends[0] if m.kind == "circular" else None)
    if length < timing.STILL and turn < timing.STILL:
        return None
    u = timing.probes(length, turn)
    return u, length, turn, fr.flange(at(u))


def resolve(planner, m, p: Prepared) -> Step:
    """Where a motion takes the robot (``planner.q`` moves on), or why it cannot."""
    ext = tg.external_axes(m, planner.mech.name) if m.kind != "wait" else None
    if ext is not None and planner.ignore_external:
        planner.note(m, f"{ext.split(' (')[0]}: ignored (--external-axes ignore)")
    elif ext is not None:
        return Step(m, "skip", ext)
    if p.error is not None:
        return Step(m, "skip", p.error)
    if m.kind == "wait":
        return Step(m, "wait", q0=planner.q)
    if m.kind == "absolute":
        q1, why = tg.joint_values(planner.mech, m.targets[0], m.names[0])
    else:
        q1, why = tg.pick(p.sol, p.row, m.targets[-1].conf, planner.q, m.conf, m.names[-1], planner.form,
                          planner.bounds)
    if why is not None:
        return Step(m, "skip", why)
    planner.remember(m, q1)
    if m.kind in ("absolute", "joint"):
        step = Step(m, "joint", q0=planner.q, q1=q1)
        planner.q, planner.flange_now = q1, p.end
        return step
    return _follow(planner, m, p)


def _follow(planner, m, p: Prepared) -> Step:
    """A linear or circular move followed from where the robot is."""
    now = planner.flange_now if planner.flange_now is not None else planner.flange_at(planner.q)
    path_, sol = p.path, p.probe_sol
    if p.start is None or np.max(np.abs(now - p.start)) > 1e-9:  # the move before ended elsewhere
        path_ = probe_path(p.frames, m, now)
        sol = planner.kin.ik64(path_[3]) if path_ is not None else None
    if path_ is None:
        return Step(m, "path", q0=planner.q, u=np.zeros(0), q=np.zeros((0, len(planner.q))))
    u, length, turn, flanges = path_
    q, stop, why, conf = follow(planner.kin, sol, planner.q)
    step = Step(m, "path", q0=planner.q, u=u, q=q, length=length, turn=turn, end_conf=conf)
    if stop is not None:
        step.findings.append(at_time("path", f"cannot follow its {'line' if m.kind == 'linear' else 'circle'}: "
                                     f"{why} at {100.0 * stop / len(u):.0f} % of the move", m, None,
                                     severity=FAIL, value=float(u[stop]), limit=1.0, unit="1",
                                     advice="move the path away from the singularity or the limit, or split it "
                                            "with a joint move"))
        step.u = u[:stop]
    if len(step.q) >= 2:
        planner.q = step.q[-1]
        planner.flange_now = flanges[-1] if stop is None else None
    return step


def time_all(planner, steps: list[Step]) -> None:
    """Every step timed and sampled, in order: the joint moves' TCP paths posed in one batch."""
    joint = [s for s in steps if s.kind == "joint" and s.motion.duration is None and np.any(s.q1 != s.q0)]
    tcp = {}
    if joint:
        flanges = planner.flanges(np.concatenate([timing.joint_probes(s.q0, s.q1) for s in joint]))
        n = timing.JOINT_PROBES
        for k, s in enumerate(joint):
            tcp[id(s)] = planner.world(s.motion, flanges[k * n:(k + 1) * n])
    for s in steps:
        planner.time_step(s, tcp.get(id(s)))
