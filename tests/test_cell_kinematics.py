"""A cell's kinematics (``rswarp/kinematics/cell.py``) against poses computed here by hand: the
IRB 2600 on the bundled 4 m track, 400 mm up on its carriage, and the two-axis positioner; the
logical axes as a robtarget's extax gives them (mm, degrees, 9E9 for none)."""

from __future__ import annotations

import numpy as np
import pytest

from rswarp import examples
from rswarp.kinematics.cell import CellKinematics
from rswarp.kinematics.kinematics import Kinematics
from rswarp.rsxml.cell import read_cell
from rswarp.transforms import euler_zyx_matrix

from conftest import DATA

CELL = DATA / "cells" / "irb2600_track_positioner.toml"  # the robot on the track, the positioner


@pytest.fixture(scope="module")
def cell_kin():
    return CellKinematics(read_cell(str(CELL)))


def _frame(x, y, z, rz_deg):
    m = np.eye(4)
    m[:3, :3] = euler_zyx_matrix(0.0, 0.0, np.radians(rz_deg))
    m[:3, 3] = (x, y, z)
    return m


def test_the_robot_rides_the_carriage_where_eax_a_puts_it(cell_kin):
    """eax_a in mm moves the robot's base along the track's x: its flange is the robot's own FK
    on a base at the track's frame, moved d along x, 400 mm up and turned 90 deg."""
    q = np.array([[0.3, -0.2, 0.4, 0.5, 0.6, -0.7]] * 3)
    extax = np.full((3, 6), 9e9)
    extax[:, 0] = [0.0, 1500.0, 3000.0]
    joints = cell_kin.unit_joints(extax)
    assert np.allclose(joints["track"][:, 0], [0.0, 1.5, 3.0])
    world = cell_kin.flange(q, joints)
    own = Kinematics(examples_robot()).fk64(q)
    link, offset = cell_kin.robot.flange_frame()
    for k, d in enumerate([0.0, 1.5, 3.0]):
        base = _frame(0.5 + d, -1.2, 0.4, 90.0)
        assert np.allclose(world[k], base @ own[k, link] @ offset, atol=1e-12)


def test_an_axis_not_given_keeps_its_value_and_the_positioner_turns_in_degrees(cell_kin):
    held = {"track": np.array([2.0]), "stn": np.array([0.1, 0.2])}
    joints = cell_kin.unit_joints([[9e9, 30.0, 9e9, 9e9, 9e9, 9e9]], held)
    assert joints["track"][0, 0] == 2.0
    assert joints["stn"][0] == pytest.approx([np.radians(30.0), 0.2])
    links = cell_kin.unit_links("stn", joints["stn"])
    own = Kinematics(cell_kin.cell.external("stn").mechanism).fk64(joints["stn"])
    assert np.allclose(links, _frame(2.0, 1.5, 0.0, 180.0) @ own, atol=1e-12)


def examples_robot():
    from rswarp.rsxml.documents import load_mechanism

    return load_mechanism(str(examples.IRB2600))[0]
