"""The planner's three steps over a batch of motions, so that the kinematics run in a few large
launches and the arithmetic in a few large arrays, not one per move:

1. ``prepare``: each move's frames, its target's flange pose and every solution of it, and each
   linear or circular move's path probed from where the move before it ends, all solved at once
   (a target or a path the batch holds twice, as a loop's moves do, solved once);
2. ``resolve``, move by move: the joints each goes to (the solution the controller picks), and a
   path's joints followed from where the robot is (probes solved again only where a move ended
   elsewhere than its target; a path already followed from the same joints taken as it was);
3. ``time_all``: the joint moves' TCP paths posed in one batch, the chains of zoned path moves
   planned as one path each (``chains``), every other move timed in arrays over the batch
   (``timing_batch``), then sampled and appended in order."""

from __future__ import annotations

import gc
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from ..findings import FAIL, at_time
from ..kernels.ik import OK
from ..kinematics.ik import IKSolutions
from . import chains, timing, timing_batch, zone_batch
from . import targets as tg
from .follow import follow
from .paths import lines, path, poses_along
from .tcp import Frames, frames


@dataclass
class Prepared:
    """What a batch computed for one motion before the robot's way there is known."""

    frames: Frames | None = None
    error: str | None = None
    sol: IKSolutions | None = None  # every solution of the target (turns included)
    row: int = 0
    within: dict | None = None  # row -> its solutions within reach and limits (made once, shared by the batch)
    end: np.ndarray | None = None  # the flange's pose at the target
    start: np.ndarray | None = None  # the flange pose a path's probes assume it starts from
    path: tuple | None = None  # (u, length, turn, flanges) of a linear or circular move
    probe_sol: IKSolutions | None = None  # the probes' branches
    followed: dict | None = None  # joints a path starts from -> ``follow``'s answer (shared by equal paths)
    along: object = None  # in a cell, where external axes move the frames: share of the way -> its Frames
    ext: tuple | None = None  # in a cell: the external joints (SI) before and after the move


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
    head: float = 0.0  # the share of its way it speeds up over out of the zone before it (0: from a stop)
    tail: float = 1.0  # the share from which it slows into the zone at its end (1: it ends at a stop)
    timed: object = None  # (t, q, share, zones.Ahead) the batch timed it at, or the TooLong it met
    frames: object = None  # a path's fixed frames (None where external axes move them): a chain's, if one
    chained: bool = False  # a move of a chain after its first: the corner before it is the chain's

    def timing(self, compute):
        """(t, q, share): the batch's, else ``compute()``'s; the batch's TooLong raised here."""
        if self.timed is None:
            return compute()
        if isinstance(self.timed, Exception):
            raise self.timed
        return self.timed[:3]

    @property
    def ahead(self):
        """What the batch found of the step's ramps and blend (``zones.Ahead``), or None."""
        return self.timed[3] if isinstance(self.timed, tuple) else None


@contextmanager
def no_gc():
    """Python's cycle collector held off while a batch is planned (and as it was after)."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def prepare(planner, motions) -> list[Prepared]:
    """Frames, targets, their solutions and the paths' probes of ``motions``, in batches."""
    out = [planner.prepared(m) for m in motions]
    _targets(planner, motions, out)
    _paths(planner, motions, out)
    return out


def frames_of(planner, m) -> Prepared:
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


def _by_frames(motions, out: list[Prepared], kinds=None) -> dict:
    """{id(frames): (frames, [move index])} of the moves with frames (of ``kinds``; those with
    frames moving along their way left out)."""
    groups: dict = {}
    for k, (m, p) in enumerate(zip(motions, out)):
        if p.frames is not None and (kinds is None or (m.kind in kinds and p.along is None)):
            groups.setdefault(id(p.frames), (p.frames, []))[1].append(k)
    return groups


def _targets(planner, motions, out: list[Prepared]) -> None:
    """Each target's flange pose: a robtarget's by its frames (and all its solutions, each pose
    and checked confdata solved once), a jointtarget's by forward kinematics."""
    for fr, ks in _by_frames(motions, out).values():
        for k, end in zip(ks, fr.flange(np.array([motions[k].targets[-1].pose.matrix() for k in ks]))):
            out[k].end = end
    rows: dict = {}
    poses, checked = [], []
    joints, absolute = [], []
    for k, (m, p) in enumerate(zip(motions, out)):
        if p.frames is not None:
            conf = m.targets[-1].conf if m.conf else None
            key = (p.end.tobytes(), conf)
            p.row = rows.get(key, -1)
            if p.row < 0:
                p.row = rows[key] = len(poses)
                poses.append(p.end)
                checked.append(conf)
        elif m.kind == "absolute":
            q, why = tg.joint_values(planner.mech, m.targets[0], m.names[0])
            if q is not None and why is None:
                joints.append(q)
                absolute.append(k)
    if poses:
        poses = np.array(poses)
        sol = planner.kin.solutions64(poses)
        tg.off_the_axis(planner.kin, poses, sol, float(planner.q[0]), checked)
        within: dict = {}
        for p in out:
            if p.frames is not None:
                p.sol, p.within = sol, within
    if joints:
        for k, flange in zip(absolute, planner.flanges(np.array(joints))):
            out[k].end = flange


def _paths(planner, motions, out: list[Prepared]) -> None:
    """The probes of every linear and circular move, from the end of the move before it, solved
    in one launch (a path the batch holds twice, from the same start, once)."""
    before = planner.flange_now
    for m, p in zip(motions, out):
        if m.kind in ("linear", "circular") and p.frames is not None:
            p.start = before if before is not None else planner.flange_at(planner.q)
            if m.kind == "circular" or p.along is not None:
                try:
                    p.path = probe_path(p.frames, m, p.start, p.along)
                except ValueError as exc:
                    p.error, p.start = str(exc), None
        if m.kind != "wait" and p.end is not None and p.error is None:
            before = p.end
    for fr, ks in _by_frames(motions, out, ("linear",)).values():
        _lines(fr, [motions[k] for k in ks], [out[k] for k in ks])
    _solve_paths(planner, out)


def _solve_paths(planner, out: list[Prepared]) -> None:
    """Every path's probes solved in one launch, each path once however many moves share it."""
    owners, seen = [], {}
    for p in out:
        if p.path is not None and id(p.path) not in seen:
            seen[id(p.path)] = p.followed = {}
            owners.append(p)
        elif p.path is not None:
            p.followed = seen[id(p.path)]
    if owners:
        sol = planner.kin.ik64(np.concatenate([p.path[3] for p in owners]))
        counts = np.array([len(p.path[0]) for p in owners])
        solved = {}
        for p, at, n in zip(owners, np.cumsum(counts) - counts, counts):
            solved[id(p.path)] = IKSolutions(sol.q[at:at + n], sol.conf[at:at + n], sol.status[at:at + n],
                                             sol.numerical)
        for p in out:
            if p.path is not None:
                p.probe_sol = solved[id(p.path)]


def _lines(fr: Frames, motions: list, out: list[Prepared]) -> None:
    """``probe_path`` of linear moves with frames ``fr``, at once: their probes' flange poses
    made in a few array operations; moves from the same start to the same target share one."""
    rel = fr.relative(np.array([p.start for p in out]))
    ends = np.array([m.targets[-1].pose.matrix() for m in motions])
    length, turn, q0, q1 = lines(rel, ends)
    moving = ~((length < timing.STILL) & (turn < timing.STILL))
    count = np.minimum(np.maximum(length / timing.PROBE_STEP, turn / timing.PROBE_TURN) + 1,
                       timing.MAX_PROBES).astype(int)
    count = np.maximum(count, timing.MIN_PROBES)
    unique, keys = [], {}
    for k, p in enumerate(out):
        if moving[k]:
            key = (p.start.tobytes(), ends[k].tobytes())
            if key not in keys:
                keys[key] = k
                unique.append(k)
    if not unique:
        return
    n = count[unique]
    row = np.repeat(np.arange(len(unique)), n)
    first = np.concatenate([[0], np.cumsum(n)[:-1]])
    u = (np.arange(len(row)) - first[row]) * (1.0 / (n - 1))[row] + 0.0  # np.linspace(0, 1, n), row by row
    u[np.cumsum(n) - 1] = 1.0
    who = np.asarray(unique)[row]
    flanges = fr.flange(poses_along(u, q0[who], q1[who], turn[who] / 2, rel[who, :3, 3], ends[who, :3, 3]))
    made = {}
    for j, k in enumerate(unique):
        lo = first[j]
        made[k] = (u[lo:lo + n[j]], float(length[k]), float(turn[k]), flanges[lo:lo + n[j]])
    for k, p in enumerate(out):
        if moving[k]:
            p.path = made[keys[(p.start.tobytes(), ends[k].tobytes())]]


def probe_path(fr: Frames, m, start: np.ndarray, along=None):
    """(u, length, turn, flanges) of a move's path from flange pose ``start``; None where the
    robot is there already; ValueError for a circle on one line. ``along`` (a cell's external
    axes moving the robot's base or the work object): share of the way -> the Frames there, the
    path probed densely enough for their travel too (``along.travel``: m, rad)."""
    rel = (fr if along is None else along(np.zeros(1))).relative(start[None])[0]
    ends = [t.pose.matrix() for t in m.targets]
    at, length, turn = path(rel, ends[-1], ends[0] if m.kind == "circular" else None)
    if along is None:
        if length < timing.STILL and turn < timing.STILL:
            return None
        u = timing.probes(length, turn)
        return u, length, turn, fr.flange(at(u))
    u = timing.probes(max(length, along.travel[0]), max(turn, along.travel[1]))
    return u, length, turn, along(u).flange(at(u))


def resolve(planner, m, p: Prepared) -> Step:
    """Where a motion takes the robot (``planner.q`` moves on), or why it cannot."""
    if m.kind != "wait":
        why = planner.external(m)  # an axis the robot lacks: ignored as the controller does, or why not
        if why is not None:
            return Step(m, "skip", why)
    if p.error is not None:
        return Step(m, "skip", p.error)
    if m.kind == "wait":
        return Step(m, "wait", q0=planner.q)
    if m.kind == "absolute":
        q1, why = tg.joint_values(planner.mech, m.targets[0], m.names[0])
    else:
        q1, why = _pick(planner, m, p)
    if why is not None:
        return Step(m, "skip", why)
    planner.remember(m, q1)
    if m.kind in ("absolute", "joint"):
        step = Step(m, "joint", q0=planner.q, q1=q1)
        planner.q, planner.flange_now = q1, p.end
        return step
    return _follow(planner, m, p)


def _pick(planner, m, p: Prepared) -> tuple:
    """``targets.pick`` of the move's target. Where its confdata is not checked that is the
    solution the robot reaches soonest of those within reach and limits (``targets.nearest``):
    found among those alone, listed once per pose."""
    cands = None
    if not (m.conf and not p.sol.numerical):  # unchecked
        cands = p.within.get(p.row)
        if cands is None:
            cands = p.within[p.row] = p.sol.q[p.row][p.sol.status[p.row] == OK]
    if cands is None or not len(cands):  # checked, or none to take: as ``targets.pick`` says it
        return tg.pick(p.sol, p.row, m.targets[-1].conf, planner.q, m.conf, m.names[-1], planner.form,
                       planner.bounds, planner.speeds)
    return cands[tg.nearest(cands, planner.q, planner.speeds)].copy(), None


def _follow(planner, m, p: Prepared) -> Step:
    """A linear or circular move followed from where the robot is."""
    now = planner.flange_now if planner.flange_now is not None else planner.flange_at(planner.q)
    path_, sol, memo = p.path, p.probe_sol, p.followed
    if p.start is None or np.max(np.abs(now - p.start)) > 1e-9:  # the move before ended elsewhere
        path_ = probe_path(p.frames, m, now, p.along)
        sol, memo = (planner.kin.ik64(path_[3]) if path_ is not None else None), None
    if path_ is None:
        return Step(m, "path", q0=planner.q, u=np.zeros(0), q=np.zeros((0, planner.dof)))
    u, length, turn, flanges = path_
    key = planner.q.tobytes()
    found = memo.get(key) if memo is not None else None
    if found is None:
        found = follow(planner.kin, sol, planner.q)
        if memo is not None:
            memo[key] = found
    q, stop, why, conf = found
    step = Step(m, "path", q0=planner.q, u=u, q=q, length=length, turn=turn, end_conf=conf,
                frames=p.frames if p.along is None else None)
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
    """Every step timed and sampled, in order: the joint moves' TCP paths posed in one batch,
    the linear and circular moves timed together, then the joint moves."""
    joint = [s for s in steps if s.kind == "joint" and np.any(s.q1 != s.q0)]
    tcp = {}
    if joint:
        poses = planner.joint_tcps(joint)
        tcp = {id(s): path for s, path in zip(joint, timing_batch.tcp_paths(poses))}
    _zone_ramps(steps, tcp, planner.limits)
    budget = [timing_batch.BATCH_SAMPLES]
    chained = chains.plan(planner, steps, budget)
    alone = [s for s in steps if id(s) not in chained]
    timed = timing_batch.path_moves(alone, planner.limits, planner.rate, budget, planner.load_factor)
    timed.update(chained)
    timed.update(timing_batch.joint_moves(steps, tcp, planner.limits, planner.rate, budget, planner.load_factor))
    zone_batch.blends(steps, timed, tcp)
    for s in steps:
        s.timed = timed.get(id(s))
        planner.time_step(s, tcp.get(id(s)))


def _zone_ramps(steps: list[Step], tcp: dict, limits) -> None:
    """Where a move ends in a zone the next move blends into at once, the share of its way from
    which it is in the zone (cut to half of either move, as ``zones.overlap`` cuts it) is where it
    slows down from (``tail``), and the next move speeds up over the same time (``head``: the
    way it goes in that time at its own speed), so the blend starts where the zone does and ends
    with the next move at speed. A joint move's shares are its TCP's, along its probes."""
    moving = ("path", "joint")
    lengths = [_length(s, tcp) if s.kind in moving else 0.0 for s in steps]
    speeds: dict = {}  # step index -> its TCP's top speed, made once
    for k, (prev, nxt) in enumerate(zip(steps, steps[1:])):
        zone = prev.motion.zone
        if zone is None or zone.fine or prev.kind not in moving or nxt.kind not in moving:
            continue
        a, b = lengths[k], lengths[k + 1]
        z = min(zone.pzone_tcp, a / 2, b / 2)
        if z <= 0:
            continue
        prev.tail = _share(prev, tcp, a - z)
        for j in (k, k + 1):
            if j not in speeds:
                speeds[j] = _tcp_speed(steps[j], tcp, limits, lengths[j])
        nxt.head = _share(nxt, tcp, min(z * speeds[k + 1] / speeds[k], b / 2))


def _length(s: Step, tcp: dict) -> float:
    """The TCP's path length of a step (m; 0 where it does not move)."""
    if s.kind == "path":
        return s.length if len(s.u) >= 2 else 0.0
    found = tcp.get(id(s))
    return found.length if s.kind == "joint" and found is not None else 0.0


def _share(s: Step, tcp: dict, gone: float) -> float:
    """The share of a step's way at which its TCP has gone ``gone`` (m) along its path."""
    if s.kind == "path":
        return gone / s.length
    found = tcp[id(s)]
    return float(np.interp(gone, found.gone, np.linspace(0.0, 1.0, len(found.gone))))


def _tcp_speed(s: Step, tcp: dict, limits, length: float) -> float:
    """The TCP's top speed along a step (m/s): its speed data's (v_tcp, and v_ori over its turn),
    VelSet's with a ``\\T``, and a joint move's axes' at their top speeds."""
    m = s.motion
    top = timing.share_cap(m, length, s.turn if s.kind == "path" else tcp[id(s)].turn) * length
    if m.duration is not None:
        top = min(top, length / timing.given_time(m))
    if s.kind == "joint":
        way = np.abs(s.q1 - s.q0)
        moving = way > 0
        if moving.any():
            top = min(top, length * float(np.min(limits.velocity[moving] * m.override / way[moving])))
    return top
