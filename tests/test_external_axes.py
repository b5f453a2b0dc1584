"""External axes (issue 49): the two bundled ExternalAxis mechanisms, a 4 m track (one prismatic axis)
and a tilt-and-turn positioner, read, check, export (USD, URDF) and run their forward kinematics
like a robot. The FK is checked against rotation matrices written here, the exports by usd-core's
UsdPhysics and yourdfpy, the robot data by what each file says."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
import trimesh

import rswarp
from rswarp import examples
from rswarp.cli import main
from rswarp.export.urdf import to_urdf
from rswarp.export.usd_layout import to_usd
from rswarp.rsxml.robot_data import JERK_RULE, robot_data

TILT_Z = 0.9  # m: the positioner's tilt axis (axis 1, along +x through y = 0) above the floor
PLATE_TOP = 0.8  # m: its face plate's top (the flange) at the zero position, on the turn axis x = y = 0
MOUNT_Z = 0.4  # m: the track carriage's mounting face (the flange) above the floor
TRAVEL = 4.0  # m: the track's stroke, 0 to 4000 mm
EXAMPLES = {"track": examples.TRACK, "positioner": examples.POSITIONER}
IDS = list(EXAMPLES)
DEG = np.pi / 180


@pytest.fixture(scope="module")
def track():
    return rswarp.load(examples.TRACK)


@pytest.fixture(scope="module")
def positioner():
    return rswarp.load(examples.POSITIONER)


def rot(axis, angle: float) -> np.ndarray:
    """The 3x3 rotation by ``angle`` (rad) about the unit vector along ``axis`` (Rodrigues)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross


def about(axis, point, angle: float) -> np.ndarray:
    """The 4x4 rotation by ``angle`` about the line through ``point`` along ``axis``."""
    m = np.eye(4)
    m[:3, :3] = rot(axis, angle)
    m[:3, 3] = np.asarray(point, float) - m[:3, :3] @ np.asarray(point, float)
    return m


def flange64(kin, q) -> np.ndarray:
    """The first flange's poses in float64: its link's pose (``fk64``) times its zero-position pose."""
    link, zero = kin.flange_frame()
    return kin.fk64(np.atleast_2d(np.asarray(q, float)))[:, link] @ zero


def positioner_flange(tilt: float, turn: float) -> np.ndarray:
    """The face plate's centre frame, computed here: the plate at the zero position (centre on the
    turn axis, PLATE_TOP high, axes the world's) tilted about the tilt axis (+x at TILT_Z), then
    turned about the tilted plate's normal through its tilted centre."""
    zero = np.eye(4)
    zero[2, 3] = PLATE_TOP
    tilted = about((1, 0, 0), (0, 0, TILT_Z), tilt) @ zero
    normal, centre = tilted[:3, 2], tilted[:3, 3]
    return about(normal, centre, turn) @ tilted


@pytest.mark.parametrize("path", list(EXAMPLES.values()), ids=IDS)
def test_each_example_loads_and_checks_clean(path, capsys):
    report = rswarp.check(path)
    assert report.kind == "Mechanism" and report.all_diagnostics == []
    mech = report.model
    assert mech.type == "ExternalAxis" and (mech.length_unit, mech.angle_unit) == ("mm", "deg")
    assert len(mech.flanges) == 1 and mech.home_position().tolist() == [0.0] * mech.dof
    for link in mech.links:  # every part has its STL beside the RSXML, small
        for part, _ in mech.parts(link.name):
            mesh = path.parent / f"{part.source.rsplit('.', 1)[0]}.stl"
            assert mesh.is_file() and mesh.stat().st_size < 50_000, mesh
    assert main(["check", str(path)]) == 0
    assert capsys.readouterr().out.strip() == f"{path}: OK (Mechanism; 0 errors, 0 warnings)"
    assert main(["info", "--json", str(path)]) == 0
    model = json.loads(capsys.readouterr().out)["model"]
    assert model["type"] == "ExternalAxis" and model["dof"] == mech.dof


def test_track_is_one_prismatic_axis_of_four_metres(track):
    (j,) = track.active_joints
    assert j.type == "Prismatic" and np.allclose(j.axis, (1, 0, 0))
    assert [float(b[0]) for b in track.bounds()] == [0.0, TRAVEL]


@pytest.mark.parametrize("d", [0.0, 0.001, 1.234567, 2.5, TRAVEL])
def test_track_flange_moves_along_x_by_the_joint_value(track, d):
    """The carriage's mounting face moves +x by exactly the joint value and keeps its height and
    orientation; the float32 kernels agree to float32's precision."""
    kin = rswarp.Kinematics(track)
    expected = np.eye(4)
    expected[:3, 3] = (d, 0.0, MOUNT_Z)
    assert np.abs(flange64(kin, [d])[0] - expected).max() < 1e-12
    assert np.abs(kin.flange(np.array([[d]]))[0] - expected).max() < 1e-6


def test_positioner_axes_and_limits(positioner):
    tilt, turn = positioner.active_joints
    assert tilt.type == turn.type == "Rotational"
    assert np.allclose(tilt.axis, (1, 0, 0)) and np.allclose(turn.axis, (0, 0, 1))
    lo, hi = positioner.bounds()
    np.testing.assert_allclose(lo, [-90 * DEG, -3600 * DEG])
    np.testing.assert_allclose(hi, [90 * DEG, 3600 * DEG])


Q_POSITIONER = [(0.0, 0.0), (90.0, 0.0), (-90.0, 45.0), (30.0, 3600.0), (-37.5, -1234.5), (12.3, 271.0)]


@pytest.mark.parametrize("tilt,turn", Q_POSITIONER)
def test_positioner_fk_matches_rotation_matrices(positioner, tilt, turn):
    kin = rswarp.Kinematics(positioner)
    q = np.array([[tilt * DEG, turn * DEG]])
    expected = positioner_flange(tilt * DEG, turn * DEG)
    ours = flange64(kin, q)[0]
    assert np.abs(ours[:3, 3] - expected[:3, 3]).max() < 1e-9
    assert np.abs(ours[:3, :3] - expected[:3, :3]).max() < 1e-9
    assert np.abs(kin.flange(q)[0] - expected).max() < 1e-5  # float32 kernels (3600 deg loses digits)


def test_positioner_fk_batch_of_random_joint_values(positioner):
    kin = rswarp.Kinematics(positioner)
    q = np.random.default_rng(49).uniform(*positioner.bounds(), (64, 2))
    ours = flange64(kin, q)
    expected = np.stack([positioner_flange(*row) for row in q])
    assert np.abs(ours - expected).max() < 1e-9
    # the plate's centre stays on the circle of radius TILT_Z - PLATE_TOP about the tilt axis
    radius = np.hypot(ours[:, 1, 3], ours[:, 2, 3] - TILT_Z)
    assert np.abs(radius - (TILT_Z - PLATE_TOP)).max() < 1e-12 and np.abs(ours[:, 0, 3]).max() < 1e-12


@pytest.fixture(scope="module")
def usd_stages(tmp_path_factory):
    """Each example exported once to .usdc, opened with usd-core."""
    pxr = pytest.importorskip("pxr")
    folder = tmp_path_factory.mktemp("usd")
    stages = {}
    for key, path in EXAMPLES.items():
        out = folder / f"{key}.usdc"
        assert to_usd(rswarp.load(path), out) == []
        stages[key] = pxr.Usd.Stage.Open(str(out))
    return stages


@pytest.mark.parametrize("key,joints", [
    ("track", {"J1": ("PhysicsPrismaticJoint", (1, 0, 0), 0.0, TRAVEL)}),
    ("positioner", {"J1": ("PhysicsRevoluteJoint", (1, 0, 0), -90.0, 90.0),
                    "J2": ("PhysicsRevoluteJoint", (0, 0, 1), -3600.0, 3600.0)}),
], ids=IDS)
def test_usd_has_the_joints_with_types_axes_and_limits(usd_stages, key, joints):
    """Prismatic limits in metres (the stage's unit), revolute ones in degrees; the joint frame's X
    (``physics:axis``) turned onto the RSXML axis by ``localRot0`` in the parent link's frame (the
    world's axes at the zero position); one articulation, the base fixed to the world."""
    from pxr import Gf, UsdPhysics

    stage = usd_stages[key]
    root = stage.GetDefaultPrim()
    assert root.HasAPI(UsdPhysics.ArticulationRootAPI) and root.GetCustomDataByKey("rsxml")["type"] == "ExternalAxis"
    found = {p.GetName(): p for p in stage.Traverse() if p.GetParent().GetName() == "joints"}
    assert set(joints) <= set(found)
    for name, (type_name, axis, lo, hi) in joints.items():
        prim = found[name]
        assert prim.GetTypeName() == type_name and prim.GetAttribute("physics:axis").Get() == "X"
        x = Gf.Rotation(Gf.Quatd(prim.GetAttribute("physics:localRot0").Get())).TransformDir(Gf.Vec3d(1, 0, 0))
        assert np.abs(np.array(x) - axis).max() < 1e-6
        assert prim.GetAttribute("physics:lowerLimit").Get() == pytest.approx(lo)
        assert prim.GetAttribute("physics:upperLimit").Get() == pytest.approx(hi)
    parsed = UsdPhysics.LoadUsdPhysicsFromRange(stage, ["/"])
    assert len(parsed[UsdPhysics.ObjectType.Articulation][0]) == 1
    assert len(parsed[UsdPhysics.ObjectType.FixedJoint][0]) == 1


def test_urdf_has_a_prismatic_joint_in_metres_that_yourdfpy_follows(track, tmp_path, capsys):
    """``rswarp export -o x.urdf`` (which reads the robot data beside the RSXML): the limit and the
    speed in metres; yourdfpy places the mount where our FK does."""
    yourdfpy = pytest.importorskip("yourdfpy")
    path = tmp_path / "track.urdf"
    assert main(["export", str(examples.TRACK), "-o", str(path)]) == 0
    assert "IRBT2005_4m.robot.toml" in capsys.readouterr().out
    text = path.read_text()
    assert '<joint name="J1" type="prismatic">' in text and '<axis xyz="1 0 0"/>' in text
    assert '<limit lower="0" upper="4" ' in text and 'velocity="2"/>' in text  # m, m/s
    urdf = yourdfpy.URDF.load(str(path))
    assert urdf.actuated_joint_names == ["J1"] and len(urdf.scene.geometry) == 2
    kin = rswarp.Kinematics(track)
    for d in (0.0, 1.5, TRAVEL):
        urdf.update_cfg({"J1": d})
        assert np.abs(urdf.get_transform("mount", "Rail") - flange64(kin, [d])[0]).max() < 1e-9


def test_urdf_positioner_follows_our_fk_in_yourdfpy(positioner, tmp_path):
    """The library's export (no robot data asked for: rswarp's default speeds), loaded by yourdfpy:
    limits in radians, the face plate's frame where our FK puts it."""
    yourdfpy = pytest.importorskip("yourdfpy")
    path = tmp_path / "positioner.urdf"
    assert to_urdf(positioner, path) == []
    urdf = yourdfpy.URDF.load(str(path), load_meshes=False)
    assert urdf.actuated_joint_names == ["J1", "J2"]
    limits = {j.name: (j.limit.lower, j.limit.upper) for j in urdf.robot.joints if j.type == "revolute"}
    assert limits == {"J1": pytest.approx((-np.pi / 2, np.pi / 2)), "J2": pytest.approx((-20 * np.pi, 20 * np.pi))}
    kin = rswarp.Kinematics(positioner)
    for tilt, turn in Q_POSITIONER:
        q = [tilt * DEG, turn * DEG]
        urdf.update_cfg(dict(zip(("J1", "J2"), q)))
        assert np.abs(urdf.get_transform("faceplate", "Stand") - flange64(kin, q)[0]).max() < 1e-9


def test_cli_exports_the_positioner_with_its_speeds(tmp_path, capsys):
    """``rswarp export`` to .usdc and .urdf; the URDF's speeds are the robot data's (rad/s)."""
    for suffix in (".usdc", ".urdf"):
        out = tmp_path / f"positioner{suffix}"
        assert main(["export", str(examples.POSITIONER), "-o", str(out)]) == 0 and out.is_file()
        assert "estimated in IRBP_A250.robot.toml" in capsys.readouterr().out
    text = (tmp_path / "positioner.urdf").read_text()
    assert f'velocity="{150 * DEG:.14g}"/>' in text and f'velocity="{180 * DEG:.14g}"/>' in text


def test_robot_data_loads_with_speeds_and_sources(track, positioner):
    """Speeds in SI (a prismatic axis's mm/s become m/s), accelerations given, jerks rswarp's rule;
    every figure marked an estimate, with the words of where it comes from."""
    cases = [(track, "IRBT2005_4m.robot.toml", [2.0], [2.5], None),
             (positioner, "IRBP_A250.robot.toml", [150 * DEG, 180 * DEG], [300 * DEG, 360 * DEG], 250.0)]
    for mech, name, speed, accel, payload in cases:
        data = robot_data(mech)
        assert data is not None and data.path.endswith(name) and data.payload == payload
        limits = data.limits
        assert limits.names == tuple(j.name for j in mech.active_joints) and not limits.assumed
        np.testing.assert_allclose(limits.velocity, speed)
        np.testing.assert_allclose(limits.acceleration, accel)
        np.testing.assert_allclose(limits.jerks(), np.asarray(accel) / 0.05)
        velocity, acceleration, jerk = limits.sources()
        assert velocity.startswith("estimate:") and acceleration.startswith("estimate:") and jerk == JERK_RULE
        assert limits.estimates().all()


def _script(path):
    """The generator script at ``path``, imported as a module (its ``main`` not run)."""
    spec = importlib.util.spec_from_file_location(f"{path.stem}_{path.parent.name}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


SOURCE = Path(__file__).resolve().parents[1] / "examples"  # the scripts: in the checkout, not installed


@pytest.mark.parametrize("script,builders", [
    ("track/make_meshes.py", {"track_rail": "rail", "track_carriage": "carriage"}),
    ("positioner/make_meshes.py", {"positioner_floor": "floor_plate", "positioner_column": "column",
                                   "positioner_tilt_arm": "tilt_arm", "positioner_turn_housing": "turn_housing",
                                   "positioner_faceplate": "face_plate"}),
    ("cells/make_part.py", {"weld_part": "part"}),
], ids=["track", "positioner", "weld part"])
def test_committed_meshes_are_what_the_script_builds(script, builders):
    """The STL files beside each generator script are what it builds (so the script documents
    them), closed surfaces; read from the source tree, where the scripts are."""
    module = _script(SOURCE / script)
    for stem, builder in builders.items():
        committed = trimesh.load((SOURCE / script).parent / f"{stem}.stl")
        built = getattr(module, builder)()
        assert committed.is_watertight
        np.testing.assert_allclose(committed.bounds, built.bounds, atol=1e-3)
        assert committed.volume == pytest.approx(built.volume, rel=1e-6)


def test_a_sweep_of_the_track_says_where_its_flange_travels(tmp_path, capsys):
    """A track has no J1 axis to measure a reach from: its sweep gives the flange's travel, 0 to
    4000 mm along x to within its voxels, at its 400 mm height."""
    from rswarp.cli import main

    assert main(["sweep", str(examples.TRACK), "--samples", "4096", "--out", str(tmp_path / "sweep")]) == 0
    out = capsys.readouterr().out
    line = next(t for t in out.splitlines() if "flange travel" in t)
    x = [float(v) for v in line.split(" x ")[1].split(",")[0].replace("mm", "").split(" to ")]
    assert -30 <= x[0] <= 0 and 4000 <= x[1] <= 4030 and "reach" not in out
    assert "flange height: 400 mm to 400 mm" in out
