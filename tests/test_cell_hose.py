"""A hose on a robot the track carries: the run moves every link with the carriage, in the frame
the robot starts in. Newton's laws say what that must give (the hose is checked against them,
not against rswarp): carried at constant speed, or brought to rest, the hose's shape on the robot
is the shape it has on a robot standing still (Galilean invariance); while the carriage speeds up
the hose lags behind it, and while it slows down the hose runs ahead."""

from __future__ import annotations

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.kinematics.trajectory import Trajectory, minimum_jerk
from rswarp.sim.cable.solver import CableOptions
from rswarp.sim.cables import simulate_cables

TRAVEL, MOVE, RUN = 1.2, 1.2, 3.0  # m the carriage goes, s it takes (minimum jerk), s the run lasts


@pytest.fixture(scope="module")
def runs():
    mech = rswarp.load(examples.IRB2600_DRESSPACK)
    t = np.linspace(0.0, RUN, 301)
    q = np.repeat(mech.home_position()[None], len(t), axis=0)  # the arm holds still: only the carriage moves
    x = TRAVEL * minimum_jerk(t / MOVE)
    base = np.column_stack([x, np.zeros_like(x), np.zeros_like(x)])
    options = CableOptions(record=0)
    moving = simulate_cables(mech, [Trajectory("carried", t, q, base=base)], 1, RUN, options)
    still = simulate_cables(mech, [Trajectory("still", t, q)], 1, RUN, options)
    carried = np.interp(moving.times, t, x)
    # the hose relative to the carriage: its points less the carriage's travel
    rel = np.asarray(moving.cables[0].recorded) - carried[:, None, None] * np.array([1.0, 0.0, 0.0])
    return moving.times, rel - np.asarray(still.cables[0].recorded), carried


def test_the_hose_rides_the_carriage_and_settles_as_on_a_robot_standing_still(runs):
    times, diff, carried = runs
    assert carried[-1] == pytest.approx(TRAVEL)  # the carriage did go 1.2 m, the hose with it
    at_rest = times > MOVE + 1.0
    assert np.abs(diff[at_rest]).max() < 1e-4  # m: carried to rest, the same shape as never moved


def test_the_hose_lags_while_the_carriage_speeds_up_and_leads_while_it_slows(runs):
    times, diff, _ = runs
    mean_x = diff[:, :, 0].mean(axis=1)
    speeding = (times > 0.15 * MOVE) & (times < 0.35 * MOVE)  # a minimum-jerk move's acceleration is greatest here
    slowing = (times > 0.7 * MOVE) & (times < 0.9 * MOVE)
    assert mean_x[speeding].min() < -5e-4  # m: behind the carriage
    assert mean_x[slowing].max() > 5e-4  # m: ahead of it
