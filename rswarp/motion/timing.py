"""How long a move takes and where the robot is meanwhile (ABB's planner is not public; the
field's time-optimal planners stand in for it, docs/program.md states the model).

- A joint move (MoveJ, MoveAbsJ) goes rest to rest as Ruckig times it: each axis's least time
  under its speed, acceleration and jerk (``scurve``), the slowest axis's time for all, every axis
  finishing with it; on the straight line in joint space where the axes can share the slowest
  one's profile (phase-synchronized), each on its own profile of that time where they cannot. The
  TCP's path at v_tcp and its turn at v_ori cap each axis's speed.
- A linear or circular move keeps the TCP on its line or circle, the orientation slerped: the
  path is probed every ``PROBE_STEP`` and solved there, and timed as TOPP-RA times a path
  (``topp``): as fast as every axis's speed and acceleration allow, the TCP within v_tcp and its
  turn within v_ori, so only the stretch that needs it (near a singularity, say) is slow.
- Every move starts and ends at rest; VelSet scales the speeds, AccSet the accelerations (and its
  ramp the jerks), ``\\V`` sets the TCP's speed, ``\\T`` the move's time (the profile slowed
  evenly to it, where the axes allow it)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import scurve
from .paths import turn_between

RATE = 250.0  # samples per second of the trajectory
PROBE_STEP = 0.002  # m of the TCP's path between probes of a linear or circular move
PROBE_TURN = 0.02  # rad of its turn between probes
MIN_PROBES = 16  # so a short move speeds up and slows down between its probes
MAX_PROBES = 4000
STILL = 1e-7  # m and rad: a linear move this short is the robot staying where it is
JOINT_PROBES = 64  # probes of a joint move's TCP path, to measure its length and turn
MAX_SAMPLES = 2_000_000  # samples of one move (over two hours at 250 a second)
SHARED = 1e-9  # relative slack of the limits an axis meets on the slowest axis's profile
ZONE_RAMP = 0.85  # of the acceleration and jerk a joint move's ramps take in a zone: where two moves blend,
# their accelerations add on an axis both speed up or slow down, and the blend keeps the limits


class TooLong(ValueError):
    """A move that would take more samples than a trajectory holds."""


def samples(duration: float, rate: float) -> np.ndarray:
    if not duration * rate <= MAX_SAMPLES:
        raise TooLong(f"it would take {duration:.3g} s, {duration * rate:.3g} samples at {rate:g} a second (at most "
                      f"{MAX_SAMPLES:g} a move): check its speed")
    n = max(int(np.ceil(duration * rate)), 1)
    return np.linspace(0.0, duration, n + 1)[1:]


def joint_probes(q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Joint values along a joint move, where its TCP path is measured."""
    return q0 + np.linspace(0, 1, JOINT_PROBES)[:, None] * (q1 - q0)


@dataclass(frozen=True)
class TcpPath:
    """A joint move's TCP at its ``joint_probes``: the world poses, the length gone at each (m),
    the whole length (the steps summed as NumPy sums them) and the turn from first to last (rad)."""

    poses: np.ndarray
    gone: np.ndarray
    length: float
    turn: float


def tcp_path(poses: np.ndarray) -> TcpPath:
    """The ``TcpPath`` of one joint move's TCP poses (``timing_batch.tcp_paths`` makes many)."""
    steps = np.linalg.norm(np.diff(poses[:, :3, 3], axis=0), axis=1)
    gone = np.concatenate([[0.0], np.cumsum(steps)])
    return TcpPath(poses, gone, float(steps.sum()), turn_between(poses[0, :3, :3], poses[-1, :3, :3]))


def split_single(u: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A path of two probes (one cut at its second by a limit) with a third between them, the
    joints halfway: the robot starts and stops at rest, so it speeds up to the middle and slows
    down from it (two probes both at rest would take an endless time)."""
    if len(u) != 2:
        return u, q
    return np.array([u[0], 0.5 * (u[0] + u[1]), u[1]]), np.vstack([q[0], 0.5 * (q[0] + q[1]), q[1]])


def probes(length: float, turn: float) -> np.ndarray:
    """Where a path of ``length`` (m) and ``turn`` (rad) is probed: every PROBE_STEP or PROBE_TURN."""
    count = int(min(max(length / PROBE_STEP, turn / PROBE_TURN) + 1, MAX_PROBES))
    return np.linspace(0.0, 1.0, max(count, MIN_PROBES))


def given_time(motion) -> float:
    """A move's ``\\T`` under VelSet's override (VelSet 50 makes \\T:=5 last 10 s)."""
    return motion.duration / motion.override


def tcp_speeds(motion) -> tuple[float, float]:
    """(m/s, rad/s) a move may go at: its speeddata under VelSet's override and top speed."""
    v_tcp = motion.speed.v_tcp * motion.override
    if motion.vmax is not None:
        v_tcp = min(v_tcp, motion.vmax)
    return v_tcp, motion.speed.v_ori * motion.override


def share_cap(m, length: float, turn: float) -> float:
    """A move's top speed along its way (share of the way a second): the TCP's path of ``length``
    at v_tcp and its ``turn`` at v_ori; with ``\\T`` (which replaces the speed data) VelSet's top
    speed alone."""
    if m.duration is None:
        v_tcp, v_ori = tcp_speeds(m)
        return min(v_tcp / length if length > 0 else np.inf, v_ori / turn if turn > 0 else np.inf)
    return m.vmax / length if m.vmax is not None and length > 0 else np.inf


def share_caps(motions, length: np.ndarray, turn: np.ndarray) -> np.ndarray:
    """``share_cap`` of each move."""
    return np.array([share_cap(m, a, b) for m, a, b in zip(motions, length, turn)], float)


def move_limits(motions, limits, factors: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each move's axis speeds, accelerations and jerks (M, dof): the robot's under VelSet's
    override, AccSet's acceleration and ramp, and the load's ``factors`` (M, dof) where given."""
    override = np.array([m.override for m in motions])[:, None]
    accel = np.array([m.accel for m in motions])[:, None]
    ramp = np.array([m.ramp for m in motions])[:, None]
    load = 1.0 if factors is None else factors
    speed = limits.velocity[None, :] * override
    if any(limits.external):
        speed = np.minimum(speed, external_caps(motions, limits) * override)
    return speed, limits.acceleration[None, :] * accel * load, limits.jerks()[None, :] * ramp * load


def widened(factors, axes: int) -> np.ndarray:
    """A load's per-axis acceleration factors over a cell's ``axes``: the load slows the robot's
    own axes, not the external ones after them (factor 1)."""
    factors = np.asarray(factors, float)
    return np.concatenate([factors, np.ones(axes - len(factors))])


def external_caps(motions, limits) -> np.ndarray:
    """(M, dof) each move's speeddata caps on a cell's external axes (v_leax for one that slides,
    v_reax for one that turns; inf for the robot's own axes and a wait)."""
    ext = np.array(limits.external, bool)
    slide = np.array(limits.linear if len(limits.linear) == len(ext) else [False] * len(ext), bool)
    out = np.full((len(motions), len(ext)), np.inf)
    for k, m in enumerate(motions):
        if m.speed is not None:
            out[k, ext & slide] = m.speed.v_leax
            out[k, ext & ~slide] = m.speed.v_reax
    return out


@dataclass(frozen=True)
class JointProfiles:
    """Joint moves' rest-to-rest profiles (M moves, dof axes): each move's duration, each axis's
    way (signed), the slowest axis (``lead``), whether the axes share one profile of the share of
    the way (``phased``: on the straight line in joint space) and that profile (``share``: cruise,
    then acceleration and jerk up, then down, per move), else each axis's own cruise speed,
    acceleration and jerk (M, dof)."""

    duration: np.ndarray
    way: np.ndarray
    lead: np.ndarray
    phased: np.ndarray
    share: tuple
    cruise: np.ndarray
    accel: np.ndarray
    jerk: np.ndarray


def joint_profiles(q0: np.ndarray, q1: np.ndarray, motions, limits, caps: np.ndarray,
                   factors: np.ndarray | None = None, head: np.ndarray | None = None,
                   tail: np.ndarray | None = None) -> JointProfiles:
    """Ruckig's time-synchronized profiles of joint moves from ``q0`` to ``q1`` (M, dof): the
    slowest axis's least time (at least a ``\\T``), each axis's speed capped by the move's
    ``caps`` (share of the way a second). A phased move speeds up over at least ``head`` and
    slows down over at least ``tail`` of its way (zones' shares, 0: none), as a path does."""
    v, a, j = move_limits(motions, limits, factors)
    way = q1 - q0
    dist = np.abs(way)
    with np.errstate(invalid="ignore"):
        v = np.where(dist > 0, np.minimum(v, caps[:, None] * dist), v)
    least = scurve.min_time(dist, v, a, j)
    rows, lead = np.arange(len(way)), np.argmax(least, axis=1)
    given = np.array([given_time(m) if m.duration is not None else 0.0 for m in motions])
    duration = np.maximum(least[rows, lead], given)
    d_l, v_l, a_l, j_l = dist[rows, lead], v[rows, lead], a[rows, lead], j[rows, lead]
    c_l = scurve.cruise_for(d_l, v_l, a_l, j_l, duration)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(d_l[:, None] > 0, dist / d_l[:, None], 0.0)
        unit = np.where(d_l > 0, 1.0 / d_l, 0.0)  # the lead's way as the share of the way
    top = 1.0 + SHARED
    peak = np.minimum(a_l, np.sqrt(c_l * j_l))
    phased = np.all((r * c_l[:, None] <= v * top) & (r * peak[:, None] <= a * top) & (r * j_l[:, None] <= j * top),
                    axis=1)
    share = (c_l * unit, a_l * unit, j_l * unit, a_l * unit, j_l * unit)
    head = np.zeros(len(way)) if head is None else head
    tail = np.zeros(len(way)) if tail is None else tail
    zoned = phased & (d_l > 0) & ((head > 0) | (tail > 0))
    if zoned.any():
        share, duration = _zoned(share, duration, zoned, scurve.peak_speed(d_l, v_l, a_l, j_l) * unit, given,
                                 head, tail)
    own = scurve.cruise_for(dist, v, a, j, duration[:, None])
    return JointProfiles(duration, way, lead, phased, share, own, a, j)


def _zoned(share: tuple, duration: np.ndarray, zoned: np.ndarray, top: np.ndarray, given: np.ndarray,
           head: np.ndarray, tail: np.ndarray) -> tuple[tuple, np.ndarray]:
    """The share profiles of the zoned moves made again: ramps spread over their zones
    (``scurve.zone_ramp``), the fastest cruise the way then allows (at most ``top``), slowed to a
    ``\\T``; each found by bisection (the time falls and the ramps' way grows with the cruise)."""
    k = np.flatnonzero(zoned)
    a, j, h, t = share[1][k] * ZONE_RAMP, share[2][k] * ZONE_RAMP, head[k], tail[k]

    def shape(c):
        ua, uj = scurve.zone_ramp(c, a, j, h)
        da, dj = scurve.zone_ramp(c, a, j, t)
        tu, td = scurve.ramp_time(c, ua, uj), scurve.ramp_time(c, da, dj)
        return (ua, uj, da, dj), 0.5 * c * (tu + td), 1.0 / c + 0.5 * (tu + td)

    c = _bisect(lambda x: shape(x)[1] <= 1.0, top[k])  # the fastest cruise whose ramps fit in the way
    c = np.where(shape(top[k])[1] <= 1.0, top[k], c)
    slow = given[k] > shape(c)[2]
    if slow.any():  # a \T longer than that: the cruise that takes it
        c = np.where(slow, _bisect(lambda x: shape(x)[2] > given[k], c, keep_high=True), c)
    limits, _, took = shape(c)
    out = [x.copy() for x in share]
    for n, x in enumerate((c, *limits)):
        out[n][k] = x
    duration = duration.copy()
    duration[k] = took
    return tuple(out), duration


def _bisect(ok, high: np.ndarray, keep_high: bool = False) -> np.ndarray:
    """Per entry, the greatest x in (0, high] with ``ok(x)`` (``ok`` true below a threshold), or,
    with ``keep_high``, the least x where it turns false (true below: the time still longer)."""
    lo, hi = np.zeros_like(high), high.copy()
    for _ in range(scurve.FIT_STEPS):
        mid = 0.5 * (lo + hi)
        good = ok(mid)
        lo, hi = np.where(good, mid, lo), np.where(good, hi, mid)
    return hi if keep_high else lo


def joint_positions(p: JointProfiles, row: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(way gone (S, dof), share of the way) at times ``t`` of moves ``row``: the shared profile's,
    or, for axes each on its own profile, the slowest axis's share."""
    c, ua, uj, da, dj = (x[row] for x in p.share)
    share = scurve.position2(t, np.ones(len(row)), c, ua, uj, da, dj, p.duration[row])
    gone = share[:, None] * p.way[row]
    own = ~p.phased[row]
    if own.any():  # axes each on its own profile of the move's time
        r, tt = row[own], t[own][:, None]
        gone[own] = np.sign(p.way[r]) * scurve.position(tt, np.abs(p.way[r]), p.cruise[r], p.accel[r], p.jerk[r],
                                                        p.duration[r][:, None])
        lead = p.lead[r]
        d_l = np.abs(p.way[r, lead])
        with np.errstate(divide="ignore", invalid="ignore"):
            share[own] = np.where(d_l > 0, np.abs(gone[own][np.arange(len(r)), lead]) / d_l, 1.0)
    return gone, share

