"""Poses shown to people: ZYX Euler angles read back to the same rotation, gimbal lock included."""

import math

import numpy as np

from rswarp.transforms import euler_zyx_matrix
from rswarp.transforms import matrix_euler_zyx as euler_zyx


def test_euler_round_trip():
    rng = np.random.default_rng(0)
    for _ in range(500):
        e = rng.uniform(-math.pi, math.pi, 3)
        e[1] = rng.uniform(-math.pi / 2, math.pi / 2)
        assert np.allclose(euler_zyx_matrix(*euler_zyx(euler_zyx_matrix(*e))), euler_zyx_matrix(*e), atol=1e-12)


def test_gimbal_lock_is_exact_for_float32_input():
    r = euler_zyx_matrix(0.3, math.pi / 2, -0.2).astype(np.float32).astype(np.float64)
    rx, ry, rz = euler_zyx(r)
    assert abs(ry - math.pi / 2) < 1e-6  # atan2: no sqrt blow-up of float32 rounding near 90 degrees
    assert np.allclose(euler_zyx_matrix(rx, ry, rz), r, atol=1e-6)


# -- rswarp fk: what it prints is each link's frame, and it says so --------------------------------------


def _fk(capsys, path, q, *more):
    from rswarp.cli import main

    assert main(["fk", str(path), "--q", q, *more]) == 0
    return capsys.readouterr().out


def test_fk_says_what_it_prints_and_its_numbers_are_the_kinematics_frames(capsys):
    """The IRB 2600 (metres, degrees): a header naming each column and its unit, and every link row
    the frame ``kin.fk`` moves: its rotation, its origin (on its joint's axis) moved with it."""
    import rswarp
    from rswarp.examples import IRB2600
    from rswarp.geometry.frames import link_origins
    from rswarp.transforms import quat_matrix

    values = [10.0, 20.0, -30.0, 40.0, 50.0, 60.0]
    lines = _fk(capsys, IRB2600, ",".join(f"{v:g}" for v in values)).splitlines()
    assert "origin x, y, z in m" in lines[0] and "rx, ry, rz in deg" in lines[0] and "quaternion q1..q4" in lines[0]
    assert "origin on the axis of the joint that moves it" in lines[1]
    header = lines[2].split()
    assert header == ["frame", "x", "[m]", "y", "[m]", "z", "[m]", "rx", "[deg]", "ry", "[deg]", "rz", "[deg]",
                      "q1", "q2", "q3", "q4"]
    rows = {" ".join(line.split()[:2]): [float(v) for v in line.split()[2:]] for line in lines[3:]}
    mech = rswarp.load(IRB2600)
    kin = rswarp.Kinematics(mech)
    q = np.radians(values)[None]
    moved = kin.fk64(q)[0]
    origins = link_origins(mech)
    for k, name in enumerate(kin.links):
        x, y, z, rx, ry, rz, *quat = rows[f"link {name}"]
        r = moved[k, :3, :3]
        np.testing.assert_allclose([x, y, z], r @ origins[name] + moved[k, :3, 3], atol=2e-6)
        np.testing.assert_allclose(euler_zyx_matrix(*np.radians([rx, ry, rz])), r, atol=1e-5)
        np.testing.assert_allclose(quat_matrix(quat), r, atol=1e-5)
    flange = kin.flange(q)[0]
    np.testing.assert_allclose(rows["flange wrist"][:3], flange[:3, 3], atol=2e-6)
    # each link's origin is on its joint's axis, which its parent carries: the parent's motion moves it there
    parent = {"Link2": "Link1", "Link3": "Link2", "Link4": "Link3", "Link5": "Link4", "Link6": "Link5"}
    for child, up in parent.items():
        m = moved[kin.links.index(up)]
        np.testing.assert_allclose(rows[f"link {child}"][:3], m[:3, :3] @ origins[child] + m[:3, 3], atol=2e-6)


def test_fk_frames_at_zero_are_the_datasheet_axes_and_its_json_says_the_same(capsys):
    """At the zero position the IRB 1300-11/0.9's (millimetres) frames sit at its axes: J2 544 mm up,
    J3 425 mm above J2, the wrist 90 mm before the flange (ABB's dimensions). --json has the frame,
    its quaternion and Euler angles in SI, what ``kin.fk`` gives as ``displacement``, and what a
    frame is."""
    import json

    import rswarp
    from rswarp.examples import IRB1300

    lines = _fk(capsys, IRB1300, "0,0,0,0,0,0").splitlines()
    rows = {" ".join(line.split()[:2]): [float(v) for v in line.split()[2:]] for line in lines[3:]}
    assert lines[2].split()[1:3] == ["x", "[mm]"]
    assert rows["link Link2"][2] == 544 and rows["link Link3"][2] == 969 and rows["link Link3"][0] == 50
    assert rows["flange wrist"][0] - rows["link Link6"][0] == 0 and rows["link Link6"][0] - rows["link Link5"][0] == 90
    doc = json.loads(_fk(capsys, IRB1300, "0,0,0,0,90,0", "--json"))
    assert "origin on the axis of the joint" in doc["frames"]
    link5 = doc["links"]["Link5"]
    kin = rswarp.Kinematics(rswarp.load(IRB1300))
    moved = kin.fk64(np.radians([[0, 0, 0, 0, 90, 0]]))[0][kin.links.index("Link5")]
    np.testing.assert_allclose(link5["displacement"], moved, atol=1e-6)
    np.testing.assert_allclose(link5["position"], [0.475, 0.0, 1.009], atol=1e-6)
    np.testing.assert_allclose(link5["quaternion"], [math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0], atol=1e-6)
    np.testing.assert_allclose(link5["euler_zyx"], [0.0, math.pi / 2, 0.0], atol=1e-6)
    np.testing.assert_allclose(np.asarray(link5["matrix"])[:3, 3], link5["position"])
