"""The two time-optimal building blocks against the libraries that define them: the jerk-limited
rest-to-rest profile (``scurve``) against Ruckig's durations, and the path parameterization
(``kernels/topp.py``) against the trapezoid a straight path has in closed form and TOPP-RA's time
on a curved one."""

from __future__ import annotations

import numpy as np
import pytest

from rswarp.motion import scurve
from rswarp.motion.topp import path_times


def _ruckig(d, v, a, j) -> float:
    ruckig = pytest.importorskip("ruckig")
    n = len(d)
    inp, out = ruckig.InputParameter(n), ruckig.Trajectory(n)
    inp.current_position, inp.target_position = [0.0] * n, list(d)
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = list(v), list(a), list(j)
    ruckig.Ruckig(n).calculate(inp, out)
    return out.duration


def test_the_least_time_is_ruckigs_and_each_profile_of_that_time_keeps_its_limits():
    """Seeded random moves of six axes, short (acceleration not reached) to long (cruising)."""
    rng = np.random.default_rng(48)
    for _ in range(40):
        d = rng.uniform(1e-4, 5, 6) * rng.choice([1e-3, 1e-1, 1.0], 6)
        v, a, j = rng.uniform(1, 9, 6), rng.uniform(2, 40, 6), rng.uniform(20, 2000, 6)
        least = scurve.min_time(d, v, a, j)
        duration = least.max()
        assert duration == pytest.approx(_ruckig(d, v, a, j), rel=1e-9)
        cruise = scurve.cruise_for(d, v, a, j, duration)  # every axis finishing with the slowest
        t = np.linspace(0.0, duration, 4001)
        p = scurve.position(t[:, None], d, cruise, a, j, duration)
        assert np.allclose(p[0], 0.0) and np.allclose(p[-1], d, rtol=1e-9, atol=1e-12)
        speed = np.diff(p, axis=0) / np.diff(t)[:, None]
        assert (speed >= -1e-9).all() and (speed.max(axis=0) <= v * (1 + 1e-6)).all()
        accel = np.diff(speed, axis=0) / np.diff(t)[1:, None]
        assert (np.abs(accel).max(axis=0) <= a * 1.01).all()


def test_a_straight_path_takes_its_trapezoid_whatever_its_probes():
    """q = 2u on one axis at 1 rad/s and 2 rad/s²: 2 / 1 + 1 / 2 = 2.5 s, on 11 probes as on 1001."""
    for n in (11, 1001):
        u = np.linspace(0.0, 1.0, n)
        t = path_times(u, (2.0 * u)[:, None], np.array([n]), np.array([1e9]), np.array([[1.0]]), np.array([[2.0]]))[0]
        assert t[-1] == pytest.approx(2.5, rel=1e-12)
    u = np.linspace(0.0, 1.0, 101)  # the path's own cap: at most 0.25 of the way a second
    t = path_times(u, (2.0 * u)[:, None], np.array([101]), np.array([0.25]), np.array([[1.0]]), np.array([[2.0]]))[0]
    assert t[-1] == pytest.approx(1 / 0.25 + 0.5 / 2.0, rel=1e-12)


def test_a_curved_path_takes_no_less_than_topp_ras_time_and_little_more():
    """A half circle in two joints, 1 rad/s and 2 rad/s² each: its bend (q'' x) limits the
    acceleration. TOPP-RA on 4 001 grid points against ours on 1 001 probes: never shorter, within
    0.5 %. Capped at 0.2 of the way a second, a zone's ramp at each end (speeding up evenly over
    the first fifth, slowing over the last) takes longer than the axes alone would."""
    toppra = pytest.importorskip("toppra")
    from toppra import algorithm, constraint

    u = np.linspace(0.0, 1.0, 1001)
    q = np.stack([np.cos(np.pi * u), np.sin(np.pi * u)], axis=1)
    limits = np.array([[-1.0, 1.0], [-1.0, 1.0]])
    solver = algorithm.TOPPRA([constraint.JointVelocityConstraint(limits),
                               constraint.JointAccelerationConstraint(2.0 * limits)],
                              toppra.SplineInterpolator(u, q), gridpoints=np.linspace(0.0, 1.0, 4001),
                              parametrizer="ParametrizeConstAccel")
    reference = solver.compute_trajectory(0, 0).duration
    args = (np.array([len(u)]), np.array([1e9]), np.array([[1.0, 1.0]]), np.array([[2.0, 2.0]]))
    ours = path_times(u, q, *args)[0][-1]
    assert reference <= ours <= reference * 1.005
    capped = (args[0], np.array([0.2]), *args[2:])
    free = path_times(u, q, *capped)[0][-1]
    ramped = path_times(u, q, *capped, head=np.array([0.2]), tail=np.array([0.8]))[0][-1]
    assert ramped == pytest.approx(0.6 / 0.2 + 2 * 0.2 / (0.2 / 2), rel=0.01) and ramped > free
