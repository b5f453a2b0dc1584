"""Jerk-limited rest-to-rest motion of one axis, as Ruckig computes it, in closed form over arrays:
the symmetric seven-phase profile (jerk +j, 0, -j, cruise, -j, 0, +j) that covers a distance ``d``
in the least time under a top speed ``v``, acceleration ``a`` and jerk ``j``, and the profile of a
longer given duration (the same limits, a lower cruise), which is how synchronized axes that are
not the slowest finish with it. All arguments broadcast; distances are at least 0."""

from __future__ import annotations

import numpy as np

FIT_STEPS = 64  # bisection steps of a cruise speed below a²/j (to the float's precision)


def ramp_time(v: np.ndarray, a: np.ndarray, j: np.ndarray) -> np.ndarray:
    """The time to go from rest to speed ``v`` (and from it back to rest)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return np.where(v * j >= a * a, v / a + a / j, 2.0 * np.sqrt(v / j))


def peak_speed(d: np.ndarray, v: np.ndarray, a: np.ndarray, j: np.ndarray) -> np.ndarray:
    """The cruise speed of the quickest profile over ``d``: ``v``, or the most a shorter distance
    lets the axis reach before it must slow down (``speed * ramp_time(speed) = d``)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        c = a * a / j
        full = 0.5 * (-c + np.sqrt(c * c + 4.0 * d * a))  # the acceleration reaches a
        short = np.cbrt(d * d * j / 4.0)  # it does not
        return np.minimum(v, np.where(d * j * j >= 2.0 * a ** 3, full, short))


def min_time(d: np.ndarray, v: np.ndarray, a: np.ndarray, j: np.ndarray) -> np.ndarray:
    """The least time to cover ``d`` from rest to rest (0 for no distance)."""
    top = peak_speed(d, v, a, j)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return np.where(d > 0, d / top + ramp_time(top, a, j), 0.0)


def cruise_for(d: np.ndarray, v: np.ndarray, a: np.ndarray, j: np.ndarray, duration: np.ndarray) -> np.ndarray:
    """The cruise speed at which the profile over ``d`` takes ``duration`` (at least its least
    time): ``d / speed + ramp_time(speed) = duration``, which falls as the speed rises."""
    top = peak_speed(d, v, a, j)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        slack = duration - a / j
        disc = slack * slack - 4.0 * d / a
        full = 0.5 * a * (slack - np.sqrt(np.maximum(disc, 0.0)))  # a reached: a quadratic's lower root
        ok = (disc >= 0) & (full * j >= a * a)
        lo, hi = np.zeros_like(full), np.broadcast_to(np.minimum(top, a * a / j), full.shape).copy()
        for _ in range(FIT_STEPS):  # a not reached: bisect d / s + 2 sqrt(s / j) = duration
            mid = 0.5 * (lo + hi)
            slow = d / mid + 2.0 * np.sqrt(mid / j) > duration
            lo, hi = np.where(slow, mid, lo), np.where(slow, hi, mid)
        speed = np.where(ok, full, hi)
    return np.where(d > 0, np.minimum(speed, top), 0.0)


def position(t: np.ndarray, d: np.ndarray, cruise: np.ndarray, a: np.ndarray, j: np.ndarray,
             duration: np.ndarray) -> np.ndarray:
    """Where the axis is at times ``t`` (clipped to [0, duration]) on the profile over ``d`` that
    cruises at ``cruise`` with at most ``a`` and ``j``: a ramp up, the cruise, the ramp mirrored."""
    return position2(t, d, cruise, a, j, a, j, duration)


def position2(t: np.ndarray, d: np.ndarray, cruise: np.ndarray, up_a: np.ndarray, up_j: np.ndarray,
              down_a: np.ndarray, down_j: np.ndarray, duration: np.ndarray) -> np.ndarray:
    """``position`` of a profile whose ramp up and ramp down have limits of their own (a ramp
    into a zone gentler than the axes' own)."""
    t = np.clip(t, 0.0, duration)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        up = _phases(cruise, up_a, up_j)
        down = _phases(cruise, down_a, down_j)
        out = np.where(t <= up[3], _ramp(t, *up[:3], up_j),
                       np.where(t >= duration - down[3], d - _ramp(duration - t, *down[:3], down_j),
                                0.5 * cruise * up[3] + cruise * (t - up[3])))
    return np.where(d > 0, np.clip(out, 0.0, d), 0.0)


def _phases(cruise, a, j):
    """(jerk time, constant-acceleration time, peak acceleration, whole ramp time) of a ramp from
    rest to ``cruise``."""
    reached = cruise * j >= a * a
    tj = np.where(reached, a / j, np.sqrt(cruise / j))
    ta = np.where(reached, cruise / np.where(a > 0, a, 1.0) - tj, 0.0)
    return tj, ta, j * tj, 2.0 * tj + ta


def zone_ramp(cruise: np.ndarray, a: np.ndarray, j: np.ndarray, zone: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(acceleration, jerk) of a ramp between rest and ``cruise`` spread over ``zone`` of the way
    (0: none, the axes' own ``a`` and ``j``), its jerk time the axes' own: the least of ``a`` and
    the acceleration whose ramp covers the zone (``cruise²/2a + cruise a/2j``)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        tau = a / j
        room = zone - 0.5 * cruise * tau
        spread = np.where((zone > 0) & (room > 0), np.minimum(a, cruise * cruise / (2.0 * room)), a)
    return spread, spread / tau


def _ramp(t, tj, ta, peak, j):
    """The distance of the ramp from rest at time ``t`` within it: jerk j for ``tj``, then ``peak``
    acceleration for ``ta``, then jerk -j for ``tj``."""
    t1 = np.minimum(t, tj)
    v1, p1 = 0.5 * j * tj * tj, j * tj ** 3 / 6.0
    v2, p2 = v1 + peak * ta, p1 + v1 * ta + 0.5 * peak * ta * ta
    t2 = np.clip(t - tj, 0.0, ta)
    t3 = np.clip(t - tj - ta, 0.0, tj)
    first = j * t1 ** 3 / 6.0
    second = p1 + v1 * t2 + 0.5 * peak * t2 * t2
    third = p2 + v2 * t3 + 0.5 * peak * t3 * t3 - j * t3 ** 3 / 6.0
    return np.where(t <= tj, first, np.where(t <= tj + ta, second, third))
