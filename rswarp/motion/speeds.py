"""How fast the TCP goes in each move of a finished plan, against the speed the program asks for,
and which limit holds it where it is slowest: what a programmer asks of a move that takes longer
than its speed data says (``rswarp program``'s ``tcp_speed`` and ``limited_by``, ``--speed-plot``).

The TCP is taken in the move's work object at every sample of the trajectory (``tcp_speed``).
A move's mean speed is its path over its time; its least speed leaves out the ramps from and to
a stop (up to where the speed first stops rising, from where it last stops falling) and keeps
all of a zoned end.
Where it is least, each limit is measured from the samples (axis speed, acceleration and, on a
joint move, jerk by finite differences; the TCP's speed and turn rate against v_tcp and v_ori):
the one nearest its bound holds the move."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import timing
from .tcp_speed import interval_frames, tcp_samples, turn_at

NEAR = 0.1  # a limit within this of its bound holds the move; a zone or a \T otherwise, where there is one
SPEED_COLUMNS = ("velocity", "acceleration", "jerk")
WINDOW = 2  # intervals each side of the slowest one where its acceleration and jerk are measured


@dataclass(frozen=True)
class Speeds:
    """Per sample interval r (rows r-1 to r; index 0 unused): the TCP's speed (m/s) in its move's
    work object, at ``mid`` (s). Per move: its programmed, mean and least speed (m/s, NaN for a
    wait or a move without samples), when the least is (s from the run's start, share of the
    move), whether it starts and ends at rest, and what holds it."""

    mid: np.ndarray
    tcp: np.ndarray
    programmed: np.ndarray
    mean: np.ndarray
    least: np.ndarray
    least_at: np.ndarray
    least_share: np.ndarray
    from_rest: np.ndarray
    to_rest: np.ndarray
    limited_by: list

    def record(self, k: int) -> tuple[dict | None, dict]:
        """Move ``k``'s ``tcp_speed`` (None where it has no speed) and ``limited_by``, for the JSON."""
        if not np.isfinite(self.least[k]):
            return None, self.limited_by[k]
        programmed = None if not np.isfinite(self.programmed[k]) else float(self.programmed[k])
        return ({"programmed_m_s": programmed, "mean_m_s": float(self.mean[k]), "least_m_s": float(self.least[k]),
                 "least_at_s": float(self.least_at[k]), "least_at_share": float(self.least_share[k])},
                self.limited_by[k])


def plan_speeds(kin, p, scale=None) -> Speeds:
    """The ``Speeds`` of plan ``p`` on kinematics ``kin``; ``scale`` (tool's load, GripLoad's) ->
    per-axis acceleration factors, as the planner lowered the limits by the loads (None: none)."""
    moves = p.moves
    first = np.array([m.rows[0] for m in moves], int)
    last = np.array([m.rows[1] for m in moves], int)
    counted = np.array([m.error is None and m.motion.kind != "wait" for m in moves], bool) & (last > first)
    table = interval_frames(kin.mech, p, counted)
    tcp = tcp_samples(kin, p, table)
    times = p.times
    mid = np.zeros(len(times))
    mid[1:] = 0.5 * (times[1:] + times[:-1])
    start = np.array([m.start for m in moves])
    span = np.array([m.end - m.start for m in moves])
    limits = _move_limits(p, [m.motion for m in moves], scale)
    from_rest, to_rest = at_rest(p, limits[1])
    programmed = np.array([_programmed(m.motion) for m in moves])
    dist = np.zeros(len(times))
    dist[1:] = tcp[1:] * np.diff(times)
    mean = np.where(counted & (span > 0), _sums(dist, first, last) / np.where(span > 0, span, 1.0), np.nan)
    at = _least(tcp, first, last, from_rest, to_rest, counted)
    least = np.where(counted, tcp[at], np.nan)
    share = np.where(span > 0, (mid[at] - start) / np.where(span > 0, span, 1.0), 0.0)
    held = _limited(p, at, counted, tcp, turn_at(kin, p, table, at), limits, _zoned(moves))
    return Speeds(mid, tcp, programmed, mean, least, np.where(counted, mid[at], np.nan),
                  np.where(counted, share, np.nan), from_rest, to_rest, held)


def _programmed(m) -> float:
    """The TCP speed the move asks for (m/s) under VelSet; NaN for a wait or a move timed by \\T."""
    if m.kind == "wait" or m.speed is None or m.duration is not None:
        return np.nan
    return timing.tcp_speeds(m)[0]


def at_rest(p, accel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Whether each move starts and ends at rest: it ends so in ``fine``, where the next move
    does not follow at once (a wait, an error, none), or where its samples say so: every axis at
    its end slower than its ``accel`` (M, axes) reaches from rest in one sample, as a stop is."""
    moves = p.moves
    q = p.q if p.ext is None else np.hstack([p.q, p.ext])
    dt = np.maximum(np.diff(p.times), 1e-12)
    first = np.array([m.rows[0] for m in moves], int)
    last = np.array([m.rows[1] for m in moves], int)

    def still(r: np.ndarray) -> np.ndarray:  # interval r (rows r-1 to r) as slow as a stop's
        if len(q) < 2:
            return np.ones(len(r), bool)
        r = np.clip(r, 1, len(q) - 1)
        return np.all(np.abs(q[r] - q[r - 1]) <= accel * dt[r - 1][:, None] ** 2 * (1 + 1e-9), axis=1)

    if not len(moves):  # a run that stopped before its first move
        return np.zeros(0, bool), np.zeros(0, bool)
    empty = last <= first
    stops = empty | still(last - 1) | np.array([m.motion.zone is None or m.motion.zone.fine for m in moves], bool)
    follows = np.array([m.error is None and m.motion.kind != "wait" for m in moves[1:]] + [False], bool)
    stops |= ~(follows & np.append(~empty[1:], False))
    starts = empty | still(first)
    starts[1:] |= stops[:-1]
    starts[0] = True
    return starts, stops


def _sums(values: np.ndarray, first: np.ndarray, last: np.ndarray) -> np.ndarray:
    """The sum of ``values[first:last]`` per move (0 where empty)."""
    c = np.concatenate([[0.0], np.cumsum(values)])
    return c[last] - c[first]


def _least(tcp, first, last, from_rest, to_rest, counted) -> np.ndarray:
    """Per move, the interval (row) where its TCP is slowest, the ramps from and to a stop left
    out (up to where the speed first stops rising, from where it last stops falling; all of it
    where that leaves none); the earliest of equals; the move's first row where it has none."""
    lengths = np.where(counted, last - first, 0)
    at = np.minimum(first, len(tcp) - 1)
    if not lengths.sum():
        return at
    begin = np.cumsum(lengths) - lengths  # each move's first entry in the runs below
    pos = np.arange(lengths.sum()) - np.repeat(begin, lengths)  # the entry's place in its move
    rows = np.repeat(first, lengths) + pos
    owner = np.repeat(np.arange(len(first)), lengths)
    starts = begin[lengths > 0]
    end = pos == np.repeat(lengths - 1, lengths)
    n = len(tcp)
    stopped_rising = end | (tcp[np.minimum(rows + 1, n - 1)] <= tcp[rows])
    stopped_falling = (pos == 0) | (tcp[rows - 1] <= tcp[rows])  # after the last of these it falls to the end
    up = np.minimum.reduceat(np.where(stopped_rising, pos, np.iinfo(int).max), starts)
    down = np.maximum.reduceat(np.where(stopped_falling, pos, -1), starts)
    mine = owner[starts]
    lo = np.where(from_rest[mine], up, 0)
    hi = np.where(to_rest[mine], down, lengths[mine] - 1)
    hi = np.where(lo <= hi, hi, lengths[mine] - 1)
    lo = np.where(lo <= hi, lo, 0)
    grow = np.repeat(np.arange(len(starts)), lengths[mine])
    value = np.where((pos >= lo[grow]) & (pos <= hi[grow]), tcp[rows], np.inf)
    least = np.minimum.reduceat(value, starts)
    hits = np.flatnonzero(value == least[grow])
    firsts = hits[np.searchsorted(grow[hits], np.arange(len(starts)))]
    at[owner[firsts]] = rows[firsts]
    return at


def _zoned(moves) -> np.ndarray:
    """Whether a zone shapes each move: it ends in one, or the move with samples before it does
    (its ramps are spread over the zone, whether or not the two blend)."""
    own = np.array([m.motion.zone is not None and not m.motion.zone.fine for m in moves], bool)
    moving = np.array([m.rows[1] > m.rows[0] for m in moves], bool)
    last = np.maximum.accumulate(np.where(moving, np.arange(len(moves)), -1))  # the last move with samples so far
    before = np.full(len(moves), -1)
    before[1:] = last[:-1]
    return own | ((before >= 0) & own[np.maximum(before, 0)])


def _limited(p, at, counted, tcp, turn, limits, zoned) -> list:
    """What holds each move where it is slowest: the limit whose ratio to its bound is nearest 1
    (``_ratios``), a zone's blend or a ``\\T`` where none comes near; ``none`` for a wait."""
    names, ratios = _ratios(p, at, tcp, turn, limits)
    gap = np.abs(np.nan_to_num(ratios, nan=np.inf) - 1.0)
    best = np.argmin(gap, axis=1)
    near = (gap[np.arange(len(best)), best] <= NEAR).tolist()
    ratio = ratios[np.arange(len(best)), best].tolist()
    timed = [m.motion.duration is not None for m in p.moves]
    out = []
    for k, (c, b) in enumerate(zip(counted.tolist(), best.tolist())):
        if not c:
            out.append({"limit": "none"})
            continue
        limit, axis = names[b]
        held = {"limit": limit, "axis": axis} if axis else {"limit": limit}
        if near[k] or not (timed[k] or zoned[k]):
            out.append({**held, "ratio": ratio[k]})
        else:
            out.append({"limit": "time" if timed[k] else "zone", "ratio": ratio[k], "nearest": held})
    return out


def _ratios(p, at, tcp, turn, limits) -> tuple[list, np.ndarray]:
    """(names, (M, columns) ratios) at each move's slowest interval ``at``: each axis's speed
    there, its greatest acceleration and (joint moves) jerk over the intervals beside it in the
    move, against the move's own limits; the TCP's speed against v_tcp and its turn rate there
    (``turn``, rad/s) against v_ori (NaN where one does not apply)."""
    q = p.q if p.ext is None else np.hstack([p.q, p.ext])
    motions = [m.motion for m in p.moves]
    v, a, j = limits
    qd, dt = _window(p, q, at, WINDOW)
    qdd = np.diff(qd, axis=1) / (0.5 * (dt[:, 1:] + dt[:, :-1]))[..., None]
    qddd = np.diff(qdd, axis=1) / dt[:, 1:-1, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        speed = np.abs(qd[:, WINDOW]) / v
        accel = _most(np.abs(qdd)) / a
        jerk = _most(np.abs(qddd)) / j
    joint = np.array([m.kind in ("joint", "absolute") for m in motions], bool)
    jerk[~joint] = np.nan
    given = np.array([[*timing.tcp_speeds(m)] if m.speed is not None and m.duration is None else [np.nan] * 2
                      for m in motions]).reshape(-1, 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        lin, ori = tcp[at] / given[:, 0], turn / given[:, 1]
    axes = _axis_names(p, q.shape[1])
    names = [(c, x) for c in SPEED_COLUMNS for x in axes] + [("tcp_speed", None), ("orientation_speed", None)]
    return names, np.hstack([speed, accel, jerk, lin[:, None], ori[:, None]])


def _window(p, q: np.ndarray, at: np.ndarray, w: int) -> tuple[np.ndarray, np.ndarray]:
    """The axes' speeds (M, 2w+1, axes) over the intervals at-w .. at+w of each move, NaN for
    those outside it, and the intervals' times (M, 2w+1)."""
    n = len(p.times)
    first = np.array([m.rows[0] for m in p.moves], int)[:, None]
    last = np.array([m.rows[1] for m in p.moves], int)[:, None]
    r = at[:, None] + np.arange(-w, w + 1)[None, :]
    inside = (r >= np.maximum(first, 1)) & (r < last)
    r = np.clip(r, 1, n - 1) if n > 1 else np.zeros_like(r)
    dt = np.maximum(p.times[r] - p.times[np.maximum(r - 1, 0)], 1e-12)
    qd = (q[r] - q[np.maximum(r - 1, 0)]) / dt[..., None]
    qd[~inside] = np.nan
    return qd, dt


def _most(x: np.ndarray) -> np.ndarray:
    """The greatest of each row's values over axis 1, ignoring NaN (NaN where all are)."""
    return np.where(np.isnan(x).all(axis=1), np.nan, np.nan_to_num(x, nan=-np.inf).max(axis=1))


def _axis_names(p, dof: int) -> list[str]:
    """The axes as a programmer names them: J1..J6 for the robot, then the cell's logical axes."""
    robot = [f"J{k + 1}" for k in range(p.q.shape[1])]
    ext = [axis or f"{unit}.{joint}" for axis, unit, joint, _ in p.ext_axes]
    return (robot + ext + [f"axis {k + 1}" for k in range(dof)])[:dof]


def _move_limits(p, motions, scale) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each move's axis speeds, accelerations and jerks (M, axes) as the planner timed it: VelSet,
    AccSet and the load it carries applied (``timing.move_limits``)."""
    axes = len(p.limits.velocity)
    if scale is None:
        return timing.move_limits(motions, p.limits)
    made: dict = {}
    factors = np.ones((len(motions), axes))
    for k, m in enumerate(motions):
        if m.kind == "wait":
            continue
        key = tuple(id(x) for x in m.held_loads)
        if key not in made:
            found = scale(*m.held_loads)
            made[key] = np.ones(axes) if found is None else timing.widened(found, axes)
        factors[k] = made[key]
    return timing.move_limits(motions, p.limits, factors)
