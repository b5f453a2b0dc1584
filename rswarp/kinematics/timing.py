"""How long a move takes and where the robot is meanwhile: rswarp's timing model (ABB's planner
is not public; docs/program.md states the model).

- A joint move (MoveJ, MoveAbsJ) interpolates in joint space, all axes synchronized, on a
  trapezoid that reaches its top speed in ``ACCEL_TIME`` (longer under AccSet): the highest that
  keeps every axis within its speed, the TCP within v_tcp and its turn within v_ori.
- A linear or circular move keeps the TCP on its line or circle, the orientation slerped: the
  path is probed every ``PROBE_STEP`` and solved there, the speed along it is the least of v_tcp,
  v_ori and, probe by probe, what keeps every axis within its speed; it speeds up and slows down
  at a constant rate, so only the stretch that needs it (near a singularity, say) is slow.
- Every move starts and ends at rest; VelSet scales the speeds, ``\\V`` sets the TCP's, ``\\T``
  the move's time."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .paths import turn_between

RATE = 250.0  # samples per second of the trajectory
ACCEL_TIME = 0.25  # s: a move reaches its top speed in this time (AccSet 100 %)
PROBE_STEP = 0.002  # m of the TCP's path between probes of a linear or circular move
PROBE_TURN = 0.02  # rad of its turn between probes
MIN_PROBES = 16  # so a short move speeds up and slows down between its probes
MAX_PROBES = 4000
STILL = 1e-7  # m and rad: a linear move this short is the robot staying where it is
JOINT_PROBES = 64  # probes of a joint move's TCP path, to measure its length and turn
MAX_SAMPLES = 2_000_000  # samples of one move (over two hours at 250 a second)


def profile(duration: float, t: np.ndarray, ta: float) -> np.ndarray:
    """The trapezoid's path parameter in [0, 1] at times ``t`` of a move of ``duration`` that
    speeds up over ``ta``."""
    ta = min(ta, duration / 2)
    v = 1.0 / (duration - ta)
    t = np.clip(t, 0.0, duration)
    s = np.where(t < ta, 0.5 * v / ta * t ** 2, v * (t - ta / 2))
    tail = duration - t
    return np.where(t > duration - ta, 1.0 - 0.5 * v / ta * tail ** 2, s)


def duration_for(cruise: float, ta: float) -> float:
    """The duration of a trapezoid whose cruise alone takes ``cruise`` seconds."""
    if cruise <= 0:
        return 0.0
    return cruise + ta if cruise >= ta else 2.0 * np.sqrt(cruise * ta)


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


def joint_move(q0: np.ndarray, q1: np.ndarray, motion, limits, rate: float, tcp: TcpPath | None):
    r"""(times, q, progress) of a synchronized joint move from q0 to q1: one trapezoid in the
    share of the way, as fast as every axis's speed and acceleration (``limits``) allow, the TCP
    within v_tcp and its turn within v_ori; ``tcp``: the TCP's path (``TcpPath``) at its
    ``joint_probes`` (None with ``\T``, which sets the time)."""
    if not np.any(q1 != q0):
        return np.zeros(0), np.zeros((0, len(q0))), np.zeros(0)
    d = np.abs(q1 - q0)
    moving = d > 0
    top = float(np.min(limits.velocity[moving] * motion.override / d[moving]))  # share of the way a second
    accel = float(np.min(limits.acceleration[moving] * motion.accel / d[moving]))  # a second squared
    axes_top = top
    if tcp is not None:
        v_tcp, v_ori = tcp_speeds(motion)
        top = min(top, v_tcp / tcp.length if tcp.length > 0 else np.inf, v_ori / tcp.turn if tcp.turn > 0 else np.inf)
    if motion.duration is None:
        duration, ta = trapezoid(top, accel)
    else:  # \T: that time, where the axes allow it
        duration = max(given_time(motion), trapezoid(axes_top, accel)[0])
        ta = min(ACCEL_TIME / motion.accel, duration / 2)
    t = samples(duration, rate)
    s = profile(duration, t, ta)
    return t, q0 + s[:, None] * (q1 - q0), s


def trapezoid(top: float, accel: float) -> tuple[float, float]:
    """(duration, ramp time) of the quickest rest-to-rest move over the whole way (1) at a
    speed of at most ``top`` and an acceleration of at most ``accel`` (per second, squared)."""
    ta = top / accel
    if top * ta >= 1.0:  # no cruise: a triangle
        ta = float(np.sqrt(1.0 / accel))
        return 2.0 * ta, ta
    return 1.0 / top + ta, ta


def path_move(u: np.ndarray, q: np.ndarray, length: float, turn: float, motion, limits, rate: float):
    """(times, q, progress) of a linear or circular move solved at probes ``u`` (joints ``q``) of
    a path of ``length`` (m) and ``turn`` (rad): the speed curve's times, sampled at ``rate``."""
    u, q = split_single(u, q)
    speeds, axis_accel = limits.velocity * motion.override, limits.acceleration * motion.accel
    if motion.duration is None:
        v_tcp, v_ori = tcp_speeds(motion)
        nominal = min(v_tcp / length if length > 0 else np.inf, v_ori / turn if turn > 0 else np.inf)
        accel = nominal * motion.accel / ACCEL_TIME
    else:  # \T replaces the speed data: a trapezoid of that time, where the axes and VelSet allow it
        total = given_time(motion)
        ta = min(ACCEL_TIME / motion.accel, total / 2)
        nominal = 1.0 / (total - ta)
        accel = nominal / ta
        # the probes round the trapezoid: its time on them, to be taken out
        free = np.full_like(speeds, np.inf)
        rounded = path_times(u, speed_curve(u, q, nominal, free, accel, free))[-1]
        if motion.vmax is not None and length > 0:
            nominal = min(nominal, motion.vmax / length)
            accel = nominal / ta
    v = speed_curve(u, q, nominal, speeds, accel, axis_accel)
    at_probe = path_times(u, v)
    if motion.duration is not None:
        at_probe = at_probe * (total / rounded)
    t = samples(float(at_probe[-1]), rate)
    along = np.interp(t, at_probe, u)
    k = np.clip(np.searchsorted(u, along, side="right"), 1, len(u) - 1)  # along lies in [u[k-1], u[k]]
    w = ((along - u[k - 1]) / (u[k] - u[k - 1]))[:, None]
    return t, q[k - 1] * (1.0 - w) + q[k] * w, along


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


def speed_curve(u: np.ndarray, q: np.ndarray, nominal: float, speeds: np.ndarray, accel: float,
                axis_accel: np.ndarray) -> np.ndarray:
    """The path speed (du/dt) at each probe ``u`` (joints ``q``): at most ``nominal``, at most what
    keeps each axis within ``speeds``, from rest to rest with at most ``accel`` (du/dt²) and what
    keeps each axis within ``axis_accel``: the least of the limit curve and its forward and
    backward accelerations."""
    dq = np.empty_like(q)  # central differences, one-sided at the ends
    if len(u) > 1:
        dq[1:-1] = (q[2:] - q[:-2]) / (u[2:] - u[:-2])[:, None]
        dq[0] = (q[1] - q[0]) / (u[1] - u[0])
        dq[-1] = (q[-1] - q[-2]) / (u[-1] - u[-2])
    else:
        dq[:] = 0.0
    slope = np.maximum(np.abs(dq), 1e-300)
    with np.errstate(divide="ignore"):
        joint = np.min(speeds / slope, axis=1)
        a = np.minimum(accel, np.min(axis_accel / slope, axis=1))  # du/dt² each probe allows
    w = np.minimum(nominal, joint) ** 2
    w[0] = w[-1] = 0.0
    # v² grows by at most 2 a du from probe to probe, forward from the start and back from the end
    step = 2.0 * np.minimum(a[1:], a[:-1]) * np.diff(u)
    up = np.concatenate([[0.0], np.cumsum(step)])
    forward = up + np.minimum.accumulate(w - up)
    backward = -up + np.minimum.accumulate((w + up)[::-1])[::-1]
    return np.sqrt(np.maximum(np.minimum(forward, backward), 0.0))


def path_times(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The time at each probe of a path travelled at speeds ``v`` (du/dt, constant acceleration
    between probes)."""
    mean = 0.5 * (v[1:] + v[:-1])
    dt = np.diff(u) / np.maximum(mean, 1e-12)
    return np.concatenate([[0.0], np.cumsum(dt)])


