"""A timed path sampled as the robot moves along it, smooth: the share of the way at each sample
from the path timing's own profile (``kernels.topp``: between neighbouring probes, the speed
changes at one acceleration and then holds, so the speed is continuous), and the joints between
probes on a cubic Hermite curve whose slopes are the central differences the timing limited (so
the joint speeds are continuous too). Sampled at 4 ms and differentiated, the trajectory keeps the
limits the timing held at the probes; a straight line between probes would not (its speed jumps
at every probe)."""

from __future__ import annotations

import numpy as np

TINY = 1e-12
CHUNK = 16384  # samples evaluated together


def shares_at(tau: np.ndarray, u0: np.ndarray, h: np.ndarray, v0: np.ndarray, v1: np.ndarray,
              span: np.ndarray) -> np.ndarray:
    """The share of the way ``tau`` (s) into a stretch of ``h`` from speed ``v0`` to ``v1`` that
    takes ``span`` s: a speed-up at one acceleration, then the cruise at ``v1``; or the cruise at
    ``v0``, then the slow-down (``kernels.topp.stretch_time``, its acceleration found again from
    the stretch's time). A stretch whose time fits no such profile is taken at its mean speed."""
    faster = np.maximum(v0, v1)
    change = np.abs(v1 - v0)
    room = 2.0 * (faster * span - h)  # = change² / acceleration
    with np.errstate(divide="ignore", invalid="ignore"):
        took = room / change  # the time of the change
        ok = (change > TINY) & (room > TINY) & (took <= span * (1 + 1e-9))
        accel = np.where(ok, change * change / np.where(ok, room, 1.0), 0.0)
        mean = np.where(span > 0, h * tau / span, h)
    took = np.where(ok, took, 0.0)
    up = v1 > v0
    gone_up = np.where(tau < took, v0 * tau + 0.5 * accel * tau * tau, 0.5 * (v0 + v1) * took + v1 * (tau - took))
    cruise = span - took
    late = np.maximum(tau - cruise, 0.0)
    gone_down = v0 * tau - 0.5 * accel * late * late
    gone = np.where(ok, np.where(up, gone_up, gone_down), mean)
    return u0 + np.clip(gone, 0.0, h)


def stretch_before(at: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Per time ``t``, the stretch [at[j], at[j + 1]] of one path's probe times holding it."""
    return np.clip(np.searchsorted(at, t, side="right") - 1, 0, len(at) - 2)


def along(at: np.ndarray, v: np.ndarray, u: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The share of one path's way at times ``t``: probes ``u`` reached at ``at`` at speeds ``v``."""
    j = stretch_before(at, t)
    out = shares_at(t - at[j], u[j], u[j + 1] - u[j], v[j], v[j + 1], at[j + 1] - at[j])
    return np.where(t >= at[-1], u[-1], out)


def joints_at(q: np.ndarray, u: np.ndarray, n: np.ndarray, row: np.ndarray, k: np.ndarray,
              x: np.ndarray) -> np.ndarray:
    """Joints at shares ``x`` on rows ``row`` of probes ``u`` (R, P) and joints ``q`` (R, P, dof),
    row r's first ``n[r]``, each between probes k - 1 and k: the cubic Hermite curve through both,
    its slopes at them central (one-sided at a row's ends, ``kernels.topp.slope``). In chunks, so
    the arithmetic runs in a few cache-sized buffers, not in fresh arrays of every sample."""
    size, dof = u.shape[1], q.shape[2]
    flat_u, flat_q = u.reshape(-1), q.reshape(-1, dof)
    out = np.empty((len(x), dof))
    for lo in range(0, len(x), CHUNK):
        hi = min(lo + CHUNK, len(x))
        r, kk = row[lo:hi], k[lo:hi]
        base, last = r * size, n[r] - 1
        i0, i1 = base + kk - 1, base + kk
        before, after = base + np.maximum(kk - 2, 0), base + np.minimum(kk + 1, last)
        u0, u1 = flat_u.take(i0), flat_u.take(i1)
        h = u1 - u0
        w = ((x[lo:hi] - u0) / h)[:, None]
        q0, q1 = flat_q.take(i0, axis=0), flat_q.take(i1, axis=0)
        s0 = (q1 - flat_q.take(before, axis=0)) * (h / (u1 - flat_u.take(before)))[:, None]
        s1 = (flat_q.take(after, axis=0) - q0) * (h / (flat_u.take(after) - u0))[:, None]
        d = q1 - q0
        c = s0 + s1 - 2.0 * d
        c *= w
        c += 3.0 * d - 2.0 * s0 - s1
        c *= w
        c += s0
        c *= w
        c += q0
        out[lo:hi] = c
    return out


def path_joints(q: np.ndarray, u: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``joints_at`` of one path: probes ``u`` (P,), joints ``q`` (P, dof), shares ``x``."""
    k = np.clip(np.searchsorted(u, x, side="right"), 1, len(u) - 1)
    return joints_at(q[None], u[None], np.array([len(u)]), np.zeros(len(x), int), k, x)
