"""A batch's moves timed together: ``timing.path_move`` and ``timing.joint_move`` row by row in
a few array operations over many moves at once, the same arithmetic in the same order, so the
same times and joints, for a fraction of the per-move cost of NumPy on small arrays.

Linear and circular moves are padded to a common number of probes per bucket (powers of two):
a padded probe repeats the last one and is kept out of the speed curve's passes. Each result is
``(t, q, share)`` as the one-move function returns it, or the ``TooLong`` it raises; moves with
``\\T`` (the time given) are left to the one-move functions."""

from __future__ import annotations

import numpy as np

from . import timing


def path_moves(steps, limits, rate: float) -> dict:
    """{id(step): (t, q, share) or TooLong} of the linear and circular steps timed by their
    speed data."""
    todo = [s for s in steps if s.kind == "path" and len(s.u) >= 2 and s.motion.duration is None]
    buckets: dict = {}
    for s in todo:
        n = max(len(s.u), 3)  # two probes get a third between them (``timing.split_single``)
        buckets.setdefault(max(16, 1 << (n - 1).bit_length()), []).append(s)
    out: dict = {}
    for size, group in buckets.items():
        _path_bucket(group, size, limits, rate, out)
    return out


def _path_bucket(group: list, size: int, limits, rate: float, out: dict) -> None:
    """Steps of at most ``size`` probes each, timed in (moves, size) arrays."""
    count, dof = len(group), len(limits.velocity)
    u_all, q_all = np.empty((count, size)), np.empty((count, size, dof))
    n = np.empty(count, int)
    nominal, accel = np.empty(count), np.empty(count)
    speeds, axis_accel = np.empty((count, dof)), np.empty((count, dof))
    for r, s in enumerate(group):
        u, q = timing.split_single(s.u, s.q)
        k = n[r] = len(u)
        u_all[r, :k], u_all[r, k:] = u, u[-1]
        q_all[r, :k], q_all[r, k:] = q, q[-1]
        m = s.motion
        v_tcp, v_ori = timing.tcp_speeds(m)
        nominal[r] = min(v_tcp / s.length if s.length > 0 else np.inf, v_ori / s.turn if s.turn > 0 else np.inf)
        accel[r] = nominal[r] * m.accel / timing.ACCEL_TIME
        speeds[r] = limits.velocity * m.override
        axis_accel[r] = limits.acceleration * m.accel
    v = speed_curves(u_all, q_all, n, nominal, speeds, accel, axis_accel)
    at_probe = path_times(u_all, v)
    for r, s in enumerate(group):
        k = n[r]
        try:
            t = timing.samples(float(at_probe[r, k - 1]), rate)
        except timing.TooLong as exc:
            out[id(s)] = exc
            continue
        u, q = u_all[r, :k], q_all[r, :k]
        along = np.interp(t, at_probe[r, :k], u)
        j = np.clip(np.searchsorted(u, along, side="right"), 1, k - 1)  # along lies in [u[j-1], u[j]]
        w = ((along - u[j - 1]) / (u[j] - u[j - 1]))[:, None]
        out[id(s)] = (t, q[j - 1] * (1.0 - w) + q[j] * w, along)


def speed_curves(u: np.ndarray, q: np.ndarray, n: np.ndarray, nominal: np.ndarray, speeds: np.ndarray,
                 accel: np.ndarray, axis_accel: np.ndarray) -> np.ndarray:
    """``timing.speed_curve`` of each row: probes ``u`` (M, N) and joints ``q`` (M, N, dof), the
    first ``n`` of each row its own (the rest repeat its last); per row ``nominal``, ``accel``
    (M,), ``speeds`` and ``axis_accel`` (M, dof). Padded probes have speed 0."""
    rows, last = np.arange(len(u)), n - 1
    pad = np.arange(u.shape[1])[None, :] > last[:, None]
    dq = np.empty_like(q)
    with np.errstate(divide="ignore", invalid="ignore"):  # the padding's zero steps
        dq[:, 1:-1] = (q[:, 2:] - q[:, :-2]) / (u[:, 2:] - u[:, :-2])[:, :, None]
    dq[:, 0] = (q[:, 1] - q[:, 0]) / (u[:, 1] - u[:, 0])[:, None]
    dq[rows, last] = (q[rows, last] - q[rows, last - 1]) / (u[rows, last] - u[rows, last - 1])[:, None]
    dq[pad] = 0.0
    slope = np.maximum(np.abs(dq), 1e-300)
    with np.errstate(divide="ignore"):
        joint = np.min(speeds[:, None, :] / slope, axis=2)
        a = np.minimum(accel[:, None], np.min(axis_accel[:, None, :] / slope, axis=2))
    w = np.minimum(nominal[:, None], joint) ** 2
    w[:, 0] = 0.0
    w[rows, last] = 0.0
    w[pad] = np.inf  # never the least of the backward pass
    step = 2.0 * np.minimum(a[:, 1:], a[:, :-1]) * np.diff(u, axis=1)
    step[pad[:, 1:]] = 0.0
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
