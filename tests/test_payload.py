"""The payload on the flange (issue "Robot data and outputs users trust", item 3): ``--payload``
as a mass or as a RAPID tooldata's or loaddata's load, authored in the flange link's mass and
sizing the efforts. The combined inertia is held against pinocchio's own sum of inertias."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from rswarp.errors import InputError
from rswarp.examples import IRB2600, IRB2600_DRESSPACK, IRB2600_PROGRAM
from rswarp.export.physics import PhysicsOptions, robot_physics
from rswarp.motion.payload import read_payload
from rswarp.report.cables import run_cables
from rswarp.report.exports import run_export
from rswarp.rsxml.documents import load_mechanism
from rswarp.rsxml.robot_data import Payload
from rswarp.transforms import quat_matrix

from conftest import DATA

MODULE = DATA / "rapid" / "payload.mod"


def robot():
    return load_mechanism(IRB2600)[0]


def test_a_payload_read_from_a_mass_or_a_rapid_load():
    mech = robot()
    box = read_payload(f"{MODULE}:lBox", mech)
    assert box.mass == 8 and box.cog == pytest.approx((0.05, 0.0, 0.15)) and box.inertia == (0.05, 0.08, 0.1)
    assert box.aom == pytest.approx((0.7071068, 0, 0.7071068, 0), abs=1e-6) and "payload.mod:4" in box.source
    gripper = read_payload(f"{MODULE}:TGRIPPER", mech)  # RAPID names are not case-sensitive
    assert gripper.mass == 3 and gripper.cog == pytest.approx((0.0, 0.0, 0.08))
    assert read_payload("5@0,0,0.1", mech).cog == (0.0, 0.0, 0.1)


@pytest.mark.parametrize("spec, message", [
    ("{m}:tStand", r"payload.mod:6: 'tStand' is a stationary tool \(robhold FALSE\)"),
    ("{m}:nCount", r"payload.mod:8: 'nCount' is a num, not a tooldata or loaddata"),
    ("{m}:tBad", r"payload.mod:7: the load of 'tBad' has a negative mass"),
    ("{m}:nothing", r"no data named 'nothing' in payload.mod"),
    ("five", r"give KG, KG@x,y,z"),
    ("5@1,2", r"give KG, KG@x,y,z"),
    ("-2", r"a mass of 0 to"),
])
def test_a_payload_given_wrong_is_a_one_line_error(spec, message):
    with pytest.raises(InputError, match=message):
        read_payload(spec.format(m=MODULE), robot())


def _link6(urdf):
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    pin.forwardKinematics(model, data, np.zeros(model.nq))
    j = model.getJointId("J6")
    return pin, model.inertias[j], data.oMi[j]


def test_the_export_carries_the_payload_in_the_flange_links_mass(tmp_path):
    """pinocchio reads both URDFs: Link6 with the box equals Link6 without it plus the box,
    placed at the flange and turned by its axes of moment, by pinocchio's sum of inertias."""
    bare = run_export(str(IRB2600), str(tmp_path / "bare" / "r.urdf"))
    loaded = run_export(str(IRB2600), str(tmp_path / "box" / "r.urdf"), payload=f"{MODULE}:lBox")
    assert loaded.doc["total_mass"] == pytest.approx(bare.doc["total_mass"] + 8.0)
    assert loaded.doc["payload"]["mass"] == 8 and "payload: 8 kg" in loaded.text
    pin, without, o_j = _link6(tmp_path / "bare" / "r.urdf")
    _, with_box, _ = _link6(tmp_path / "box" / "r.urdf")
    flange = np.array([[0.0, 0, 1, 1.03], [0, 1, 0, 0], [-1, 0, 0, 1.26], [0, 0, 0, 1]])  # the RSXML's wrist
    in_joint = o_j.inverse().homogeneous @ flange
    r = in_joint[:3, :3] @ quat_matrix((0.7071068, 0, 0.7071068, 0))
    box = pin.Inertia(8.0, (in_joint @ [0.05, 0.0, 0.15, 1.0])[:3], r @ np.diag([0.05, 0.08, 0.1]) @ r.T)
    expected = without + box
    assert with_box.mass == pytest.approx(expected.mass)
    assert np.allclose(with_box.lever, expected.lever, atol=1e-9)
    assert np.allclose(with_box.inertia, expected.inertia, atol=1e-9)


def test_estimated_efforts_carry_the_payload():
    """No data gives the IRB 2600's efforts: they are sized for the rated 12 kg at the flange, and
    a heavier payload 0.2 m out raises axis 5's by at least twice its gravity moment's growth."""
    mech = robot()
    plain = robot_physics(mech, PhysicsOptions(), geometry=False)
    sized = robot_physics(mech, PhysicsOptions(rated_payload=12.0), geometry=False)
    heavy = robot_physics(mech, PhysicsOptions(payload=Payload(20.0, (0.0, 0.0, 0.2))), geometry=False)
    lever = 0.085  # axis 5 to the flange on the IRB 2600
    assert sized.joints["J5"].effort - plain.joints["J5"].effort >= 2 * 9.81 * 12.0 * lever
    assert heavy.joints["J5"].effort - plain.joints["J5"].effort >= 2 * 9.81 * 20.0 * (lever + 0.2)
    assert sized.effort_payload == "the rated payload 12 kg at the flange" and not plain.effort_payload


def test_a_cable_run_over_a_program_names_its_payload(tmp_path):
    out = run_cables(str(IRB2600_DRESSPACK), str(tmp_path / "run"), program=[str(IRB2600_PROGRAM)], seconds=0.2)
    assert out.doc["payload"]["mass"] == 3.0 and "payload: 3 kg" in out.text


def test_the_bundled_robots_estimated_efforts_are_the_docs():
    """docs/export.md quotes these: with the rated 12 kg at the flange, J1 to J6 4063, 2745, 806,
    454, 28 and 7 N m; without a payload axis 5 had 7.5 N m."""
    from rswarp.report.exports import data_physics

    mech = robot()
    options = data_physics(str(IRB2600), mech)
    rated = [j.effort for j in robot_physics(mech, options).joints.values()]
    bare = robot_physics(mech, dataclasses.replace(options, rated_payload=None)).joints["J5"].effort
    assert rated == pytest.approx([4063, 2745, 806, 454, 28.4, 7.2], rel=0.01)
    assert bare == pytest.approx(7.5, rel=0.01)
