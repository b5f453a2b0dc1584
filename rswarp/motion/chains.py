"""Chains of zoned path moves planned as the controller plans them: linear and circular moves that
each end in a zone the next takes at once are one path (``corners``: the corner curves in
Cartesian space), solved along it and timed as one (``topp``: time-optimal under the axes' speeds
and accelerations and the TCP's programmed speed at every probe, looking ahead over the whole
chain), then cut back into moves at the middle of each corner. A chain that cannot be followed
(a corner past a joint limit or out of reach) is left to the moves one by one (``zones``)."""

from __future__ import annotations

import numpy as np

from ..findings import FAIL
from . import corners, sampling, timing, topp, zones
from .follow import follow

MIN_LENGTH = 1e-4  # m: a move shorter is a reorientation, timed on its own
MAX_PROBES = 500_000  # probes of one chain: memory stays bounded (a longer run of zoned moves is cut)


def chains(steps: list) -> list[list]:
    """Runs of two or more steps that make one chain: path moves each ending in a zone, followed at
    once by the next, in the same frames, at the same axis settings, without a time given."""
    out, run, probes = [], [], 0
    for s in steps:
        fits = _chainable(s)
        if run and fits and _joins(run[-1], s) and probes + len(s.u) <= MAX_PROBES:
            run.append(s)
            probes += len(s.u)
            continue
        if len(run) > 1:
            out.append(run)
        run, probes = ([s], len(s.u)) if fits else ([], 0)
    if len(run) > 1:
        out.append(run)
    return out


def _chainable(s) -> bool:
    return s.kind == "path" and s.frames is not None and s.u is not None and len(s.u) >= 2 and \
        s.length > MIN_LENGTH and s.motion.duration is None and not any(f.severity == FAIL for f in s.findings)


def _joins(a, b) -> bool:
    """Whether ``b`` takes ``a``'s zone as one path with it."""
    ma, mb = a.motion, b.motion
    zone = ma.zone
    return zone is not None and not zone.fine and a.frames is b.frames and \
        (ma.override, ma.accel, ma.ramp, ma.held_loads) == (mb.override, mb.accel, mb.ramp, mb.held_loads)


def plan(planner, steps: list, budget: list) -> dict:
    """{id(step): (t, q, share, (ramp_in, ramp_out)) or TooLong} of every step in a chain; each
    member after a chain's first is marked ``chained`` (it takes no blend of its own)."""
    found = []
    for run in chains(steps):
        made = _probed(planner, run)
        if made is not None:
            found.append((run, *made))
    if not found:
        return {}
    _solve(planner, found)
    found = [f for f in found if f[-1] is not None]
    out: dict = {}
    if found:
        _time(planner, found, budget, out)
    return out


def _probed(planner, run: list):
    """(the chain's ``Corners``, its flange poses) of a run of steps."""
    fr = run[0].frames
    start = fr.relative(planner.flanges(run[0].q0[None, :planner.dof]))[0]  # over a cell, the robot's joints
    members = []
    for s in run:
        m = s.motion
        end = m.targets[-1].pose.matrix()
        v_tcp, v_ori = timing.tcp_speeds(m)
        zone = m.zone if s is not run[-1] else None
        members.append(corners.Member(start, end, m.targets[0].pose.matrix() if m.kind == "circular" else None,
                                      v_tcp, v_ori, zone.pzone_tcp if zone else 0.0, zone.pzone_ori if zone else 0.0))
        start = end
    try:
        c = corners.corner_path(members)
    except ValueError:
        return None
    return c, fr.flange(c.poses)


def _solve(planner, found: list) -> None:
    """Each chain's probes solved in one launch and followed from where its first move starts; a
    chain that cannot be followed to its last move's own end is dropped (None). Over a cell the
    steps' joints end with the external axes', which stand still along a chain (a move that moves
    them has no fixed frames and joins none): they are carried along as they are."""
    sol = planner.kin.ik64(np.concatenate([f[2] for f in found]))
    dof, at = planner.dof, 0
    for k, (run, c, flanges) in enumerate(found):
        n = len(flanges)
        part = type(sol)(sol.q[at:at + n], sol.conf[at:at + n], sol.status[at:at + n], sol.numerical)
        at += n
        q, stop, _, _ = follow(planner.kin, part, run[0].q0[:dof])
        ok = stop is None and np.allclose(q[-1], run[-1].q[-1, :dof], atol=1e-6)
        if ok and len(run[0].q0) > dof:
            q = np.hstack([q, np.broadcast_to(run[0].q0[dof:], (len(q), len(run[0].q0) - dof))])
        found[k] = (run, c, flanges, q if ok else None)


def _time(planner, found: list, budget: list, out: dict) -> None:
    """The chains timed in one launch, each sampled move by move."""
    us, qs, caps, counts, heads, tails, motions = [], [], [], [], [], [], []
    for run, c, _, q in found:
        us.append(c.arc / c.total)
        qs.append(q)
        caps.append(corners.caps(c) / c.total)
        counts.append(len(q))
        first, last = run[0], run[-1]
        heads.append(first.head * first.length / c.total)
        tails.append(1.0 - (1.0 - last.tail) * last.length / c.total)  # the lengths of straight stretches
        motions.append(first.motion)
    factors = [planner.load_factor(m) for m in motions]
    load = None if all(f is None for f in factors) else \
        np.array([np.ones(planner.limits.velocity.shape) if f is None else f for f in factors])
    speeds, accels, _ = timing.move_limits(motions, planner.limits, load)
    t, v = topp.path_times(np.concatenate(us), np.concatenate(qs), np.array(counts), np.concatenate(caps), speeds,
                           accels, np.array(heads), np.array(tails))
    at = 0
    for (run, c, _, q), u in zip(found, us):
        n = len(u)
        _split(planner, run, c, u, q, t[at:at + n], v[at:at + n], budget, out)
        at += n


def _split(planner, run, c, u, q, at, v, budget, out) -> None:
    """A timed chain's samples cut into its moves at the middle of each corner: each move sampled
    evenly over its own time, all of them along the chain at once."""
    ends_t, ends_u = at[c.end_probe], u[c.end_probe]
    starts_t = np.concatenate([[0.0], ends_t[:-1]])
    starts_u = np.concatenate([[0.0], ends_u[:-1]])
    local, fine = [], []
    for s, a, b in zip(run, starts_t, ends_t):
        try:
            local.append(timing.samples(float(b - a), planner.rate))
            fine.append(True)
        except timing.TooLong as exc:
            out[id(s)] = exc
            local.append(np.zeros(0))
            fine.append(False)
    count = np.array([len(x) for x in local])
    budget[0] -= int(count.sum())
    row = np.repeat(np.arange(len(run)), count)
    t_all = np.concatenate(local)
    x = sampling.along(at, v, u, starts_t[row] + t_all)
    last = np.cumsum(count) - 1
    x[last[count > 0]] = ends_u[count > 0]  # each move ends where its corner's middle is
    joints = sampling.path_joints(q, u, np.concatenate([starts_u[1:], x]))
    begins, joints = joints[:len(run) - 1], joints[len(run) - 1:]
    share = (x - starts_u[row]) / np.maximum(ends_u - starts_u, 1e-300)[row]
    ramp_in, ramp_out = zones.ramps(t_all, share, last + 1 - count, count)
    for k, s in enumerate(run):
        span = c.arc[c.end_probe[k]] - (c.arc[c.end_probe[k - 1]] if k else 0.0)
        s.turn *= span / s.length
        s.length, s.end_conf = span, None
        if k:
            s.q0, s.chained = begins[k - 1], True
        if fine[k]:
            lo, hi = last[k] + 1 - count[k], last[k] + 1
            out[id(s)] = (local[k], joints[lo:hi], share[lo:hi], (float(ramp_in[k]), float(ramp_out[k])))
