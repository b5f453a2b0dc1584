"""Joint trajectories for cable runs: the CSV of the design notes (docs/design.md) read with file:line errors,
and smooth
random trajectories within the limits (issue "Cable dynamics in parallel environments")."""

from __future__ import annotations

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.kinematics.trajectory import assign, joint_speed_limits, random_trajectory, read_trajectory

from conftest import DATA

TRAJ = DATA / "trajectories"


@pytest.fixture(scope="module")
def irb1300():
    return rswarp.load(examples.IRB1300)


def test_csv_in_file_units_interpolates_linearly(irb1300):
    t = read_trajectory(TRAJ / "irb1300_wave.csv", irb1300)
    assert t.duration == 2.5 and t.q.shape == (3, 6)
    np.testing.assert_allclose(t.q[1], np.radians([30, 10, -20, 45, 30, 90]))  # degrees in the file
    np.testing.assert_allclose(t.at([0.5])[0], np.radians([15, 5, -10, 22.5, 15, 45]))
    np.testing.assert_allclose(t.at([1.75])[0], np.radians([0, 15, -5, 0, 0, 0]))
    np.testing.assert_allclose(t.at([-1.0, 9.0]), t.q[[0, -1]])  # held at both ends
    assert read_trajectory(TRAJ / "bom.csv", irb1300).q.shape == (1, 6)  # a UTF-8 BOM is fine


@pytest.mark.parametrize("name, message", [
    ("beyond_limits.csv", r"beyond_limits.csv:3: J5 = 300 is outside its limits \[-130, 130\]"),
    ("bad_header.csv", r"bad_header.csv:1: the header must be 'time,J1,J2,J3,J4,J5,J6'"),
    ("time_backwards.csv", r"time_backwards.csv:3: time 0 s does not come after 0 s"),
    ("nan_cell.csv", r"nan_cell.csv:3: a non-finite number 'nan'"),
])
def test_bad_trajectories_name_their_line(irb1300, name, message):
    with pytest.raises(rswarp.RsxmlError, match=message):
        read_trajectory(TRAJ / name, irb1300)


def test_random_trajectories_are_smooth_within_limits_and_speeds(irb1300):
    t = random_trajectory(irb1300, seconds=20.0, seed=3)
    times = np.linspace(0.0, 20.0, 2001)  # sampled at 100 Hz
    q = t.at(times)
    lower, upper = irb1300.bounds()
    assert t.duration == 20.0 and (q >= lower - 1e-12).all() and (q <= upper + 1e-12).all()
    speed = np.abs(np.diff(q, axis=0)) / np.diff(times)[:, None]
    top = joint_speed_limits(irb1300)  # the IRB 1300's robot data
    assert (speed.max(axis=0) <= top * 1.001).all() and not np.allclose(top, np.radians(90))
    assert (speed.max(axis=0) > top / 4).all()  # and it moves
    accel = np.abs(np.diff(speed, axis=0)).max(axis=0) / np.diff(times).max()
    assert (accel < 20 * top).all()  # no jumps in speed
    np.testing.assert_array_equal(random_trajectory(irb1300, 20.0, seed=3).at(times), q)  # reproducible
    assert not np.allclose(random_trajectory(irb1300, 20.0, seed=4).at(times), q)


def test_environments_take_trajectories_round_robin():
    assert assign([object(), object(), object()], 7) == [0, 1, 2, 0, 1, 2, 0]
    with pytest.raises(rswarp.InputError, match="at least one trajectory"):
        assign([], 3)
