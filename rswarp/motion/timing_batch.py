"""A batch's moves timed together: ``path_moves`` and ``joint_moves`` time many moves at once in a
few array operations (the per-move primitives of ``timing``, ``topp`` and ``zones`` applied row by
row), so a task of thousands of moves pays a fraction of NumPy's per-call cost on small arrays;
``path_move`` and ``joint_move`` time one step the same way.

Linear and circular moves are padded to a common number of probes per bucket (at most an eighth
more than their own): a padded probe repeats the last one and is kept out of the speed curve's
passes. Samples of all moves are laid end to end; each lookup ``np.interp`` and
``np.searchsorted`` would make is found from an estimate set right by exact comparisons. Each
result is ``(t, q, share)`` (and the ramps a zone's blend reads), or the ``TooLong`` it raises;
moves with ``\\T`` (the time given) and moves past ``BATCH_SAMPLES`` samples in all are timed one
by one (memory stays bounded where a trajectory would be refused as too long)."""

from __future__ import annotations

import numpy as np

from . import sampling, timing, topp, zones

BATCH_SAMPLES = 5_000_000  # samples timed at once (a trajectory's most): moves past them are timed one by one


def path_moves(steps, limits, rate: float, budget: list | None = None, factor=None) -> dict:
    """{id(step): (t, q, share, ramps) or TooLong} of the linear and circular steps; ``budget``:
    [samples left to time at once] (moves past it are left out); ``factor(motion)``: its load's
    per-axis acceleration factors (or None)."""
    budget = [BATCH_SAMPLES] if budget is None else budget
    buckets: dict = {}
    for s in steps:
        if s.kind == "path" and len(s.u) >= 2:
            buckets.setdefault(bucket_size(max(len(s.u), 3)), []).append(s)  # two probes get a third
    out: dict = {}
    for size, group in buckets.items():
        _path_bucket(group, size, limits, rate, out, budget, _factors(group, factor))
    return out


def joint_moves(steps, tcp: dict, limits, rate: float, budget: list | None = None, factor=None) -> dict:
    """{id(step): (t, q, share, ramps) or TooLong} of the joint steps that move, timed by
    ``timing.joint_profiles``; ``tcp``: their TCP paths (``TcpPath``) where measured; ``budget``
    and ``factor`` as ``path_moves``'."""
    group = [s for s in steps if s.kind == "joint" and np.any(s.q1 != s.q0)]
    out: dict = {}
    if not group:
        return out
    q0, q1 = np.array([s.q0 for s in group]), np.array([s.q1 for s in group])
    motions, paths = [s.motion for s in group], [tcp.get(id(s)) for s in group]
    length = np.array([p.length if p is not None else 0.0 for p in paths])
    turn = np.array([p.turn if p is not None else 0.0 for p in paths])
    prof = timing.joint_profiles(q0, q1, motions, limits, timing.share_caps(motions, length, turn),
                                 _factors(group, factor), np.array([s.head for s in group]),
                                 np.array([1.0 - s.tail for s in group]))
    grid = Grid(prof.duration, rate, [BATCH_SAMPLES] if budget is None else budget)
    gone, share = timing.joint_positions(prof, grid.row, grid.t)
    grid.hand_out(group, out, q0[grid.row] + gone, share)
    return out


def _factors(group, factor) -> np.ndarray | None:
    """The steps' load factors (M, dof), or None where no step carries a load."""
    if factor is None:
        return None
    found = [factor(s.motion) for s in group]
    if all(f is None for f in found):
        return None
    dof = len(group[0].q0)
    return np.array([np.ones(dof) if f is None else f for f in found])


def joint_move(step, tcp, limits, rate: float, factor=None):
    """(t, q, share) of one joint step, as ``joint_moves`` times it in a batch."""
    if not np.any(step.q1 != step.q0):
        return np.zeros(0), np.zeros((0, len(step.q0))), np.zeros(0)
    found = joint_moves([step], {id(step): tcp} if tcp is not None else {}, limits, rate, [timing.MAX_SAMPLES + 1],
                        factor)[id(step)]
    return _raised(found)


def path_move(step, limits, rate: float, factor=None):
    """(t, q, share) of one linear or circular step, as ``path_moves`` times it in a batch."""
    found = path_moves([step], limits, rate, [timing.MAX_SAMPLES + 1], factor)[id(step)]
    return _raised(found)


def _raised(found):
    if isinstance(found, Exception):
        raise found
    return found[:3]


def tcp_paths(poses: np.ndarray) -> list:
    """``timing.tcp_path`` of joint moves' TCP poses (M, probes, 4, 4) at once."""
    steps = np.linalg.norm(np.diff(poses[:, :, :3, 3], axis=1), axis=2)
    gone = np.zeros(poses.shape[:2])
    np.cumsum(steps, axis=1, out=gone[:, 1:])
    length = steps.sum(axis=1)
    return [timing.TcpPath(p, g, float(n), timing.turn_between(p[0, :3, :3], p[-1, :3, :3]))
            for p, g, n in zip(poses, gone, length)]


def bucket_size(n: int) -> int:
    """The padded length of a row of ``n`` probes: 16 at least, at most an eighth more than n."""
    if n <= 16:
        return 16
    grain = 1 << max((n - 1).bit_length() - 3, 0)
    return -(-n // grain) * grain


def _path_bucket(group: list, size: int, limits, rate: float, out: dict, budget: list, factors) -> None:
    """Steps of at most ``size`` probes each, timed together (``topp.path_times``) and sampled in
    (moves, size) arrays (``sampling``: the timing's own speed profile, the joints on Hermite
    curves between probes); a ``\\T`` move's profile slowed evenly to its time."""
    split = [timing.split_single(s.u, s.q) for s in group]
    n = np.array([len(u) for u, _ in split])
    u_flat, q_flat = np.concatenate([u for u, _ in split]), np.concatenate([q for _, q in split])
    motions = [s.motion for s in group]
    length, turn = np.array([s.length for s in group]), np.array([s.turn for s in group])
    speeds, accels, _ = timing.move_limits(motions, limits, factors)
    t, v = topp.path_times(u_flat, q_flat, n, timing.share_caps(motions, length, turn), speeds, accels,
                           np.array([s.head for s in group]), np.array([s.tail for s in group]))
    u_all, q_all = _padded(u_flat, n, size), _padded(q_flat, n, size)
    at_probe, v_all = _padded(t, n, size), _padded(v, n, size)
    rows = np.arange(len(group))
    given = np.array([timing.given_time(m) if m.duration is not None else 0.0 for m in motions])
    optimal = at_probe[rows, n - 1]
    slow = given > optimal
    if slow.any():
        at_probe[slow] *= (given[slow] / optimal[slow])[:, None]
        v_all[slow] *= (optimal[slow] / given[slow])[:, None]
    grid = Grid(at_probe[rows, n - 1], rate, budget)
    along = grid.along(at_probe, v_all, u_all, n)
    k = grid.row_index(u_all, n, along)  # along lies in [u[k-1], u[k]]
    grid.hand_out(group, out, sampling.joints_at(q_all, u_all, n, grid.row, k, along), along)


def _padded(flat: np.ndarray, n: np.ndarray, size: int) -> np.ndarray:
    """Rows of ``n`` values each (laid end to end in ``flat``) in a (rows, size, ...) array, each
    padded with its last value."""
    ends = np.cumsum(n)
    out = np.empty((len(n), size) + flat.shape[1:])
    out[:] = flat[ends - 1][:, None]
    row = np.repeat(np.arange(len(n)), n)
    out[row, np.arange(len(flat)) - (ends - n)[row]] = flat
    return out


class Grid:
    """The sample times of moves of ``durations`` at ``rate`` (``timing.samples`` of each), laid
    end to end: ``t``, the move of each (``row``), where each move's start (``first``); moves too
    long for a trajectory keep their ``TooLong``; those past ``budget`` ([samples left]) have none
    (``deferred``: timed one by one, if the trajectory gets that far)."""

    def __init__(self, durations: np.ndarray, rate: float, budget: list):
        self.durations, self.rate = durations, rate
        self.long = ~(durations * rate <= timing.MAX_SAMPLES)
        with np.errstate(invalid="ignore", over="ignore"):
            count = np.where(self.long, 0, np.maximum(np.ceil(durations * rate), 1)).astype(int)
        self.deferred = np.cumsum(count) > budget[0]
        count[self.deferred] = 0
        budget[0] -= int(count.sum())
        self.count, self.step = count, durations / np.maximum(count, 1)
        self.row = np.repeat(np.arange(len(count)), count)
        ends = np.cumsum(count)
        self.first = ends - count
        self.index = np.arange(len(self.row)) - self.first[self.row] + 1  # 1 to count within its move
        self.t = self.at(self.row, self.index)

    def at(self, row: np.ndarray, i: np.ndarray) -> np.ndarray:
        """Sample ``i`` (0 to count) of moves ``row``: ``np.linspace(0, d, count + 1)``'s values."""
        return np.where(i == self.count[row], self.durations[row], i * self.step[row])

    def along(self, at: np.ndarray, v: np.ndarray, u: np.ndarray, n: np.ndarray) -> np.ndarray:
        """The share of the way at each move's samples (``sampling.shares_at``): probes ``u[r, :n[r]]``
        reached at times ``at`` at speeds ``v``, row ``r`` its move's."""
        j = self._probe_before(at, n)
        rows, last = self.row, n[self.row] - 1
        jj = np.minimum(j, last - 1)
        out = sampling.shares_at(self.t - at[rows, jj], u[rows, jj], u[rows, jj + 1] - u[rows, jj], v[rows, jj],
                                 v[rows, jj + 1], at[rows, jj + 1] - at[rows, jj])
        out = np.where(at[rows, j] == self.t, u[rows, j], out)
        return np.where(j == last, u[rows, last], out)

    def _probe_before(self, at: np.ndarray, n: np.ndarray) -> np.ndarray:
        """Per sample, the last probe of its move at or before it (probe times ``at``, rows sorted)."""
        prow = np.repeat(np.arange(len(n)), n)
        pk = np.arange(len(prow)) - (np.cumsum(n) - n)[prow]
        keep = self.count[prow] > 0
        prow, a = prow[keep], at[prow[keep], pk[keep]]
        # the first sample at or after each probe: an estimate, set right by comparing
        with np.errstate(divide="ignore", invalid="ignore"):
            first = np.clip(np.nan_to_num(np.ceil(a / self.step[prow]), nan=1.0), 1, self.count[prow]).astype(int)
        while True:
            down = (first > 1) & (self.at(prow, first - 1) >= a)
            up = (first < self.count[prow]) & (self.at(prow, first) < a)
            if not (down.any() or up.any()):
                break
            first += up.astype(int) - down.astype(int)
        counted = np.cumsum(np.bincount(self.first[prow] + first - 1, minlength=len(self.t)))
        before = np.concatenate([[0], counted])[self.first]  # probes counted before each move's samples
        return counted - before[self.row] - 1

    def row_index(self, u: np.ndarray, n: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``np.clip(np.searchsorted(u[r, :n[r]], x, side="right"), 1, n[r] - 1)`` per sample."""
        rows, top = self.row, n[self.row]
        step = u[rows, 1] - u[rows, 0]
        k = np.clip(np.floor(x / step).astype(int) + 1, 1, top - 1)
        while True:
            up = (k < top) & (u[rows, np.minimum(k, top - 1)] <= x)
            down = (k > 0) & (u[rows, np.maximum(k - 1, 0)] > x)
            if not (up.any() or down.any()):
                break
            k += up.astype(int) - down.astype(int)
        return np.clip(k, 1, top - 1)

    def hand_out(self, steps: list, out: dict, q: np.ndarray, share: np.ndarray) -> None:
        """Each move's (t, q, share, (ramp_in, ramp_out)) of the rows laid end to end (the ramps
        a zone's blend reads, ``zones.ramps``), or its TooLong."""
        ramp_in, ramp_out = zones.ramps(self.t, share, self.first, self.count)
        for r, s in enumerate(steps):
            if self.deferred[r]:
                continue
            if self.long[r]:
                try:
                    timing.samples(float(self.durations[r]), self.rate)
                except timing.TooLong as exc:
                    out[id(s)] = exc
                continue
            lo, hi = self.first[r], self.first[r] + self.count[r]
            out[id(s)] = (self.t[lo:hi], q[lo:hi], share[lo:hi], (float(ramp_in[r]), float(ramp_out[r])))
