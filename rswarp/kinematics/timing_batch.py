"""A batch's moves timed together: ``timing.path_move`` and ``timing.joint_move`` row by row in
a few array operations over many moves at once, the same arithmetic in the same order, so the
same times and joints, for a fraction of the per-move cost of NumPy on small arrays.

Linear and circular moves are padded to a common number of probes per bucket (at most an eighth
more than their own): a padded probe repeats the last one and is kept out of the speed curve's
passes. Samples of all moves are laid end to end; each lookup ``np.interp`` and
``np.searchsorted`` would make is found from an estimate set right by exact comparisons. Each
result is ``(t, q, share)`` as the one-move function returns it (and the ramps a zone's blend
reads), or the ``TooLong`` it raises; moves with ``\\T`` (the time given) are left to the
one-move functions, and so are moves past ``BATCH_SAMPLES`` samples in all (memory stays bounded
where a trajectory would be refused as too long)."""

from __future__ import annotations

import numpy as np

from . import timing, zones

BATCH_SAMPLES = 5_000_000  # samples timed at once (a trajectory's most): moves past them are timed one by one


def path_moves(steps, limits, rate: float, budget: list | None = None) -> dict:
    """{id(step): (t, q, share) or TooLong} of the linear and circular steps timed by their
    speed data; ``budget``: [samples left to time at once] (moves past it are left out)."""
    budget = [BATCH_SAMPLES] if budget is None else budget
    buckets: dict = {}
    for s in steps:
        if s.kind == "path" and len(s.u) >= 2 and s.motion.duration is None:
            buckets.setdefault(bucket_size(max(len(s.u), 3)), []).append(s)  # two probes get a third
    out: dict = {}
    for size, group in buckets.items():
        _path_bucket(group, size, limits, rate, out, budget)
    return out


def joint_moves(steps, tcp: dict, limits, rate: float, budget: list | None = None) -> dict:
    """{id(step): (t, q, share) or TooLong} of the joint steps with a TCP path in ``tcp`` (those
    timed by their speed data), ``timing.joint_move`` of each; ``budget`` as ``path_moves``'."""
    group = [s for s in steps if s.kind == "joint" and id(s) in tcp]
    out: dict = {}
    if not group:
        return out
    q0, q1 = np.array([s.q0 for s in group]), np.array([s.q1 for s in group])
    motions, paths = [s.motion for s in group], [tcp[id(s)] for s in group]
    d = np.abs(q1 - q0)
    moving = d > 0
    override, accel_set = np.array([m.override for m in motions]), np.array([m.accel for m in motions])
    v_tcp, v_ori = np.array([timing.tcp_speeds(m) for m in motions]).T
    length, turn = np.array([p.length for p in paths]), np.array([p.turn for p in paths])
    with np.errstate(divide="ignore", invalid="ignore"):
        top = np.where(moving, limits.velocity * override[:, None] / d, np.inf).min(axis=1)
        accel = np.where(moving, limits.acceleration * accel_set[:, None] / d, np.inf).min(axis=1)
        top = np.minimum(top, np.minimum(np.where(length > 0, v_tcp / length, np.inf),
                                         np.where(turn > 0, v_ori / turn, np.inf)))
    ta = top / accel  # ``timing.trapezoid``
    triangle = top * ta >= 1.0
    ta = np.where(triangle, np.sqrt(1.0 / accel), ta)
    duration = np.where(triangle, 2.0 * ta, 1.0 / top + ta)
    grid = Grid(duration, rate, [BATCH_SAMPLES] if budget is None else budget)
    share = _trapezoids(grid, duration, np.minimum(ta, duration / 2))
    q = q0[grid.row] + share[:, None] * (q1 - q0)[grid.row]
    grid.hand_out(group, out, q, share)
    return out


def _trapezoids(grid: "Grid", duration: np.ndarray, ta: np.ndarray) -> np.ndarray:
    """``timing.profile`` of each move's samples (its ramp ``ta`` already at most half its time)."""
    d, ta = duration[grid.row], ta[grid.row]
    v = 1.0 / (d - ta)
    t = np.clip(grid.t, 0.0, d)
    s = np.where(t < ta, 0.5 * v / ta * t ** 2, v * (t - ta / 2))
    tail = d - t
    return np.where(t > d - ta, 1.0 - 0.5 * v / ta * tail ** 2, s)


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


def _path_bucket(group: list, size: int, limits, rate: float, out: dict, budget: list) -> None:
    """Steps of at most ``size`` probes each, timed in (moves, size) arrays."""
    split = [timing.split_single(s.u, s.q) for s in group]
    n = np.array([len(u) for u, _ in split])
    u_all = _padded(np.concatenate([u for u, _ in split]), n, size)
    q_all = _padded(np.concatenate([q for _, q in split]), n, size)
    motions = [s.motion for s in group]
    v_tcp, v_ori = np.array([timing.tcp_speeds(m) for m in motions]).T
    length, turn = np.array([s.length for s in group]), np.array([s.turn for s in group])
    accel_set, override = np.array([m.accel for m in motions]), np.array([m.override for m in motions])
    with np.errstate(divide="ignore", invalid="ignore"):
        nominal = np.minimum(np.where(length > 0, v_tcp / length, np.inf), np.where(turn > 0, v_ori / turn, np.inf))
    accel = nominal * accel_set / timing.ACCEL_TIME
    speeds = limits.velocity[None, :] * override[:, None]
    axis_accel = limits.acceleration[None, :] * accel_set[:, None]
    v = speed_curves(u_all, q_all, n, nominal, speeds, accel, axis_accel)
    at_probe = path_times(u_all, v)
    grid = Grid(at_probe[np.arange(len(group)), n - 1], rate, budget)
    along = grid.interp(at_probe, u_all, n)
    k = grid.row_index(u_all, n, along)  # along lies in [u[k-1], u[k]]
    lo, hi = u_all[grid.row, k - 1], u_all[grid.row, k]
    w = ((along - lo) / (hi - lo))[:, None]
    seg = q_all[grid.row, k - 1] * (1.0 - w) + q_all[grid.row, k] * w
    grid.hand_out(group, out, seg, along)


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

    def interp(self, at: np.ndarray, u: np.ndarray, n: np.ndarray) -> np.ndarray:
        """``np.interp(t, at[r, :n[r]], u[r, :n[r]])`` of each move's samples, row ``r`` its move's."""
        j = self._probe_before(at, n)
        rows, last = self.row, n[self.row] - 1
        jj = np.minimum(j, last - 1)
        a0, a1 = at[rows, jj], at[rows, jj + 1]
        u0, u1 = u[rows, jj], u[rows, jj + 1]
        out = (u1 - u0) / (a1 - a0) * (self.t - a0) + u0
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


def speed_curves(u: np.ndarray, q: np.ndarray, n: np.ndarray, nominal: np.ndarray, speeds: np.ndarray,
                 accel: np.ndarray, axis_accel: np.ndarray) -> np.ndarray:
    """``timing.speed_curve`` of each row: probes ``u`` (M, N) and joints ``q`` (M, N, dof), the
    first ``n`` of each row its own (the rest repeat its last); per row ``nominal``, ``accel``
    (M,), ``speeds`` and ``axis_accel`` (M, dof). Padded probes have speed 0. An axis at a time:
    the least over the axes is the same whatever their order."""
    rows, last = np.arange(len(u)), n - 1
    pad = np.arange(u.shape[1])[None, :] > last[:, None]
    span = np.empty_like(u)  # the du of each probe's difference: central, one-sided at the ends
    span[:, 1:-1] = u[:, 2:] - u[:, :-2]
    span[:, 0], span[:, -1] = u[:, 1] - u[:, 0], 1.0  # (the last column is set apart)
    joint, a = np.full(u.shape, np.inf), np.full(u.shape, np.inf)
    for c in range(q.shape[2]):
        col = np.ascontiguousarray(q[:, :, c])
        dq = np.empty_like(col)
        dq[:, 1:-1] = col[:, 2:] - col[:, :-2]
        dq[:, 0] = col[:, 1] - col[:, 0]
        dq[rows, last] = col[rows, last] - col[rows, last - 1]
        with np.errstate(divide="ignore", invalid="ignore"):  # the padding's zero steps
            dq /= span
            dq[rows, last] = (col[rows, last] - col[rows, last - 1]) / (u[rows, last] - u[rows, last - 1])
        dq[pad] = 0.0
        slope = np.maximum(np.abs(dq, out=dq), 1e-300, out=dq)
        with np.errstate(divide="ignore"):
            np.minimum(joint, speeds[:, c, None] / slope, out=joint)
            np.minimum(a, axis_accel[:, c, None] / slope, out=a)
    np.minimum(accel[:, None], a, out=a)
    w = np.minimum(nominal[:, None], joint) ** 2
    w[:, 0] = 0.0
    w[rows, last] = 0.0
    w[pad] = np.inf  # never the least of the backward pass
    step = 2.0 * np.minimum(a[:, 1:], a[:, :-1]) * np.diff(u, axis=1)
    up = np.zeros_like(u)
    np.cumsum(step, axis=1, out=up[:, 1:])
    forward = up + np.minimum.accumulate(w - up, axis=1)
    backward = -up + np.minimum.accumulate((w + up)[:, ::-1], axis=1)[:, ::-1]
    v = np.sqrt(np.maximum(np.minimum(forward, backward), 0.0))
    v[pad] = 0.0
    return v


def path_times(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``timing.path_times`` of each row (padded probes add no time)."""
    mean = 0.5 * (v[:, 1:] + v[:, :-1])
    dt = np.diff(u, axis=1) / np.maximum(mean, 1e-12)
    out = np.zeros_like(u)
    np.cumsum(dt, axis=1, out=out[:, 1:])
    return out
