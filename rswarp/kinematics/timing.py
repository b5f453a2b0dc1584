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

import numpy as np

from .ik import ArmConstants

RATE = 250.0  # samples per second of the trajectory
ACCEL_TIME = 0.25  # s: a move reaches its top speed in this time (AccSet 100 %)
PROBE_STEP = 0.002  # m of the TCP's path between probes of a linear or circular move
PROBE_TURN = 0.02  # rad of its turn between probes
MIN_PROBES = 16  # so a short move speeds up and slows down between its probes
MAX_PROBES = 4000
STILL = 1e-7  # m and rad: a linear move this short is the robot staying where it is
JOINT_PROBES = 64  # probes of a joint move's TCP path, to measure its length and turn
JUMP = 0.5  # rad: an axis moving more between two probes has left its branch
MAX_SAMPLES = 2_000_000  # samples of one move (over two hours at 250 a second)
FLIP = 0.5  # rad of axes 1 to 3 between probes: a change of configuration, which a path cannot follow


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


def joint_move(flange_of, world, q0: np.ndarray, q1: np.ndarray, motion, speeds: np.ndarray, rate: float):
    """(times, q, the flange's pose at q1 or None) of a synchronized joint move from q0 to q1;
    ``flange_of(q)`` poses the flange, ``world(flanges)`` the TCP."""
    if not np.any(q1 != q0):
        return np.zeros(0), np.zeros((0, len(q0))), None
    axes = float(np.max(np.abs(q1 - q0) / (speeds * motion.override)))
    cruise, last = axes, None
    if motion.duration is None:
        probes = q0 + np.linspace(0, 1, JOINT_PROBES)[:, None] * (q1 - q0)
        flanges = flange_of(probes)
        tcp = world(flanges)
        length = float(np.linalg.norm(np.diff(tcp[:, :3, 3], axis=0), axis=1).sum())
        turn = turn_between(tcp[0, :3, :3], tcp[-1, :3, :3])
        v_tcp, v_ori = tcp_speeds(motion)
        cruise, last = max(axes, length / v_tcp, turn / v_ori), flanges[-1]
    ta = ACCEL_TIME / motion.accel
    duration = duration_for(cruise, ta) if motion.duration is None else max(motion.duration, duration_for(axes, ta))
    t = samples(duration, rate)
    return t, q0 + profile(duration, t, ta)[:, None] * (q1 - q0), last


def tcp_speeds(motion) -> tuple[float, float]:
    """(m/s, rad/s) a move may go at: its speeddata under VelSet's override and top speed."""
    v_tcp = motion.speed.v_tcp * motion.override
    if motion.vmax is not None:
        v_tcp = min(v_tcp, motion.vmax)
    return v_tcp, motion.speed.v_ori * motion.override


def path(start: np.ndarray, end: np.ndarray, circle: np.ndarray | None = None):
    """``at(u)`` poses (N, 4, 4) along the straight line (or the circle through ``circle``) from
    ``start`` to ``end``, orientation slerped; the path's length (m) and turn (rad). ValueError
    for a circle whose points are on one line."""
    q0, q1 = quaternion(start[:3, :3]), quaternion(end[:3, :3])
    if q0 @ q1 < 0:
        q1 = -q1
    turn = float(2.0 * np.arccos(min(1.0, abs(float(q0 @ q1)))))
    p0, p1 = start[:3, 3], end[:3, 3]
    if circle is None:
        length = float(np.linalg.norm(p1 - p0))

        def point(u):
            return p0 + np.outer(u, p1 - p0)
    else:
        point, length = _arc(p0, circle[:3, 3], p1)

    def at(u):
        u = np.atleast_1d(u)
        out = np.zeros((len(u), 4, 4))
        out[:, :3, :3] = rotations(slerp(q0, q1, u, turn / 2))
        out[:, :3, 3] = point(u)
        out[:, 3, 3] = 1.0
        return out

    return at, length, turn


def quaternion(m: np.ndarray) -> np.ndarray:
    """The unit quaternion (w, x, y, z) of a rotation matrix."""
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    k = int(np.argmax([tr, m[0, 0], m[1, 1], m[2, 2]]))
    if k == 0:
        s = 2.0 * np.sqrt(tr + 1.0)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    elif k == 1:
        s = 2.0 * np.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [(m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
    elif k == 2:
        s = 2.0 * np.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s]
    else:
        s = 2.0 * np.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    return q / np.linalg.norm(q)


def slerp(q0: np.ndarray, q1: np.ndarray, u: np.ndarray, half: float) -> np.ndarray:
    """Quaternions (N, 4) a share ``u`` of the way from q0 to q1 (``half``: half the angle between)."""
    if half < 1e-9:
        out = q0 + np.outer(u, q1 - q0)
    else:
        s = np.sin(half)
        out = np.outer(np.sin((1 - u) * half) / s, q0) + np.outer(np.sin(u * half) / s, q1)
    return out / np.linalg.norm(out, axis=1, keepdims=True)


def rotations(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (N, 3, 3) of unit quaternions (N, 4), (w, x, y, z)."""
    w, x, y, z = q.T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], 1)


def turn_between(a: np.ndarray, b: np.ndarray) -> float:
    """The angle (rad) of the rotation from matrix ``a`` to ``b``."""
    c = (np.trace(a.T @ b) - 1.0) / 2.0
    return float(np.arccos(np.clip(c, -1.0, 1.0)))


def _arc(a: np.ndarray, b: np.ndarray, c: np.ndarray):
    """(point(u), length) of the circle arc from a through b to c."""
    ab, ac = b - a, c - a
    n = np.cross(ab, ac)
    scale = max(np.linalg.norm(ab), np.linalg.norm(ac), 1e-9)
    if np.linalg.norm(n) < 1e-6 * scale * scale or min(np.linalg.norm(ab), np.linalg.norm(ac),
                                                        np.linalg.norm(c - b)) < 1e-6:
        raise ValueError("the start, the circle point and the end of a circle are on one line (or two coincide)")
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


def speed_curve(u: np.ndarray, q: np.ndarray, nominal: float, speeds: np.ndarray, accel: float) -> np.ndarray:
    """The path speed (du/dt) at each probe ``u`` (joints ``q``): at most ``nominal``, at most what
    keeps each axis within ``speeds``, from rest to rest with at most ``accel`` (du/dt²): the
    least of the limit curve and its forward and backward accelerations."""
    dq = np.gradient(q, u, axis=0) if len(u) > 1 else np.zeros_like(q)
    with np.errstate(divide="ignore"):
        joint = np.min(speeds / np.maximum(np.abs(dq), 1e-300), axis=1)
    w = np.minimum(nominal, joint) ** 2
    w[0] = w[-1] = 0.0
    forward = 2 * accel * u + np.minimum.accumulate(w - 2 * accel * u)
    backward = -2 * accel * u + np.minimum.accumulate((w + 2 * accel * u)[::-1])[::-1]
    return np.sqrt(np.maximum(np.minimum(forward, backward), 0.0))


def path_times(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The time at each probe of a path travelled at speeds ``v`` (du/dt, constant acceleration
    between probes)."""
    mean = 0.5 * (v[1:] + v[:-1])
    dt = np.diff(u) / np.maximum(mean, 1e-12)
    return np.concatenate([[0.0], np.cumsum(dt)])


def follow(kin, flanges: np.ndarray, q0: np.ndarray):
    """Joint values along flange poses, continuous from ``q0``: (q, the first probe the path cannot
    reach or follow, why, the configuration data at the end or None). An arm keeps its shoulder
    and elbow; its wrist changes branch only where the path passes the wrist singularity; axes 4
    and 6 keep their turns."""
    sol = kin.ik64(flanges)
    if not isinstance(kin._ik_form(), ArmConstants) or sol.numerical:
        return (*_follow_each(kin, sol, q0), None)
    lower, upper = kin.mech.bounds()
    count = len(flanges)
    out = np.empty((count, len(q0)))
    k, prev, branch = 0, q0, None
    while k < count:
        picked = _pick(sol, k, prev, branch, lower, upper)
        if picked is None:
            why = "out of reach" if not sol.ok[k].any() else "a joint limit" if branch is not None else "out of reach"
            return out[:k], k, why, None
        best, start = picked
        if branch is not None and best // 2 != branch // 2 or np.max(np.abs(start[:3] - prev[:3])) > FLIP:
            return out[:k], k, "a configuration flip", None
        seg = _segment(sol, k, best, start, lower, upper)
        out[k:k + len(seg)] = seg
        prev, branch, k = seg[-1], best, k + len(seg)
    quarter = np.floor(out[-1, [0, 3, 5]] / (0.5 * np.pi)).astype(int)
    return out, None, "", (int(quarter[0]), int(quarter[1]), int(quarter[2]), int(sol.conf[-1, branch, 3]))


def _aligned(cand: np.ndarray, prev: np.ndarray) -> np.ndarray:
    """Candidates with axes 4 and 6 turned whole turns to lie nearest ``prev``."""
    cand = cand.copy()
    for c in (3, 5):
        cand[..., c] += 2 * np.pi * np.round((prev[c] - cand[..., c]) / (2 * np.pi))
    return cand


def _pick(sol, k: int, prev: np.ndarray, branch, lower, upper):
    """(branch, its aligned joints) at probe ``k`` nearest ``prev``: among all at the start, else
    the branch and its wrist twin."""
    options = range(sol.q.shape[1]) if branch is None else (branch, branch ^ 1)
    best, start, dist = None, None, np.inf
    for b in options:
        if not sol.ok[k, b]:
            continue
        cand = _aligned(sol.q[k, b], prev)
        if np.any(cand < lower) or np.any(cand > upper):
            continue
        d = float(np.max(np.abs(cand - prev)))
        if d < dist:
            best, start, dist = b, cand, d
    return None if best is None else (best, start)


def _segment(sol, k: int, b: int, start: np.ndarray, lower, upper) -> np.ndarray:
    """Branch ``b`` from probe ``k`` on, turns unwrapped from ``start``, up to (not including) the
    first probe where it is not a solution, leaves the limits, or jumps."""
    seg = sol.q[k:, b].copy()
    for c in (3, 5):
        seg[:, c] = np.unwrap(seg[:, c])
    seg += (start - seg[0])[None, :] * np.isin(np.arange(seg.shape[1]), (3, 5))[None, :]
    bad = ~sol.ok[k:, b] | np.any((seg < lower) | (seg > upper), axis=1) | ~np.all(np.isfinite(seg), axis=1)
    jump = np.r_[False, np.max(np.abs(np.diff(seg, axis=0)), axis=1) > JUMP]
    stop = np.flatnonzero(bad | jump)
    end = int(stop[0]) if len(stop) and stop[0] > 0 else (1 if len(stop) else len(seg))
    return seg[:end]


def _follow_each(kin, sol, q0: np.ndarray):
    """``follow`` one probe at a time, for mechanisms without the arm's branches: the solution
    nearest the one before."""
    lower, upper = kin.mech.bounds()
    out = np.empty((sol.q.shape[0], len(q0)))
    prev = q0
    for k in range(len(out)):
        cand = sol.q[k]
        ok = sol.ok[k] & np.all((cand >= lower) & (cand <= upper), axis=1)
        if not ok.any():
            return out[:k], k, "out of reach" if not sol.ok[k].any() else "a joint limit"
        dist = np.where(ok, np.abs(cand - prev).max(axis=1), np.inf)
        out[k] = prev = cand[int(np.argmin(dist))]
    return out, None, ""
