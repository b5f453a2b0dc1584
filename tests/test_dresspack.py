"""The bundled dress pack (issue "A dress pack that means something"): the IRB 2600's process
hose over its pick-and-place program. Its answers are held against what the robot's own forward
kinematics and the hose's weight say, not against the run itself."""

from __future__ import annotations

import json

import numpy as np
import pytest

import rswarp
from rswarp.examples import IRB2600_DRESSPACK, IRB2600_PROGRAM
from rswarp.kinematics.kinematics import Kinematics
from rswarp.report.cables import run_cables
from rswarp.report.program import program_plan

G = 9.81


@pytest.fixture(scope="module")
def hose():
    mech = rswarp.load(IRB2600_DRESSPACK)
    return mech, mech.cables[0]


def clamp_distance(mech, cable, q: np.ndarray) -> np.ndarray:
    """The straight distance between the hose's two clamps at each configuration."""
    kin = Kinematics(mech)
    poses = kin.fk64(q)
    ends = [p for p in cable.control_points if p.attached_to]
    at = [poses[:, mech.link_names.index(p.attached_to)] @ np.r_[p.position, 1.0] for p in ends]
    return np.linalg.norm(at[0][:, :3] - at[1][:, :3], axis=1)


def test_the_hose_is_long_enough_over_the_whole_joint_range(hose):
    """desiredLength (1.05 m) exceeds the greatest clamp distance anywhere in the limits by at
    least 20 %: the README's rule; the file's comment gives that distance."""
    mech, cable = hose
    lo, hi = mech.bounds()
    q = np.random.default_rng(0).uniform(lo, hi, (100_000, 6))
    far = clamp_distance(mech, cable, q).max()
    assert far == pytest.approx(0.8467, abs=1e-3)  # the figure the file's comment and the docs give
    assert cable.desired_length >= 1.20 * far
    assert cable.radius == pytest.approx(0.015) and cable.desired_length == pytest.approx(1.05)


def test_the_program_run_answers_what_a_dress_pack_engineer_asks(hose, tmp_path):
    mech, cable = hose
    out = run_cables(str(IRB2600_DRESSPACK), str(tmp_path / "run"), envs=1, program=str(IRB2600_PROGRAM))
    doc = json.loads((tmp_path / "run" / "report.json").read_text())
    c = doc["cables"][0]
    env = c["environments"][0]
    assert env["status"] == "ok" and out.code == 0
    # long enough: the report's greatest clamp distance is the robot's own, over the program
    _, plan = program_plan(str(IRB2600_DRESSPACK), str(IRB2600_PROGRAM))
    ratio = clamp_distance(mech, cable, plan.q).max() / c["length_m"]
    assert env["max_attachment_distance_ratio"] == pytest.approx(ratio, abs=2e-3)
    assert not env["taut"]
    # the clamps hold at least the hose's weight; the tension stays far below a pull of 1 %
    weight = c["length_m"] * 1200.0 * np.pi * cable.radius ** 2 * G
    assert sum(c["summary"]["clamp_force_N"]) >= weight
    assert 0.0 <= env["peak_tension_N"] < 0.01 * c["axial_stiffness_N"]
    # the hose bends, no tighter than its own radius; it hangs over the forearm (Link4), its
    # nearest link, within a few millimetres and never pressed into it
    assert cable.radius < env["min_bend_radius_m"] < 1.0
    clear = {k: v["min_clearance_m"] for k, v in env["clearance"].items() if k.startswith("Link")}
    assert min(clear, key=clear.get) == "Link4"
    assert -0.5 * cable.radius < clear["Link4"] < 0.02
    # the RelTool move turns J6 by 45 deg: the hose carries a twist of that order between its clamps
    assert np.radians(20) < env["max_twist_rad"] < np.radians(70)
