"""``rswarp export CELL.toml -o cell.usda``: one stage holding the whole cell (the IRB 2600 on the
bundled 4 m track, and the two-axis positioner), each mechanism referenced from its own layer at
its frame; in Newton the robot rides the track's carriage and the face plate turns with its joints."""

from __future__ import annotations

import numpy as np
import pytest

from rswarp import examples
from rswarp.cli import main
from rswarp.kinematics.cell import CellKinematics
from rswarp.rsxml.cell import read_cell

from conftest import DATA

pxr = pytest.importorskip("pxr")
from pxr import Usd, UsdGeom, UsdPhysics  # noqa: E402

CELL = DATA / "cells" / "irb2600_track_positioner.toml"  # the robot on the track, the positioner
ROBOT = "IRB2600_12_165__01"


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    out = tmp_path_factory.mktemp("cell") / "out" / "cell.usda"
    assert main(["export", str(CELL), "-o", str(out)]) == 0
    return CellKinematics(read_cell(str(CELL))), out


def _world(stage, path: str) -> np.ndarray:
    """A prim's world transform as a 4x4 with column vectors."""
    m = UsdGeom.Xformable(stage.GetPrimAtPath(path)).ComputeLocalToWorldTransform(Usd.TimeCode.Default())
    return np.array(m).T


def test_the_stage_holds_every_mechanism_at_its_frame(exported):
    kin, out = exported
    assert sorted(p.name for p in (out.parent / "cell_parts").iterdir()) == [f"{ROBOT}.usda", "stn.usda", "track.usda"]
    stage = Usd.Stage.Open(str(out))
    assert stage.GetDefaultPrim().GetPath() == "/World"
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0 and UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    home = {e.name: e.mechanism.home_position()[None] for e in kin.cell.externals}
    assert np.abs(_world(stage, f"/World/{ROBOT}") - kin.robot_base(home)[0]).max() <= 1e-6
    for unit in kin.cell.externals:
        assert np.abs(_world(stage, f"/World/{unit.name}") - unit.frame).max() <= 1e-6
    assert stage.GetPrimAtPath(f"/World/{ROBOT}/Link6").HasAPI(UsdPhysics.RigidBodyAPI)
    fixed = UsdPhysics.FixedJoint(stage.GetPrimAtPath(f"/World/{ROBOT}/joints/root_joint"))
    assert [str(t) for t in fixed.GetBody0Rel().GetTargets()] == ["/World/track/Carriage"]
    # the robot is part of the track's articulation, not one of its own
    assert not stage.GetPrimAtPath(f"/World/{ROBOT}").HasAPI(UsdPhysics.ArticulationRootAPI)
    assert stage.GetPrimAtPath("/World/track").HasAPI(UsdPhysics.ArticulationRootAPI)


def test_newton_moves_the_robot_with_the_track_and_turns_the_face_plate(exported):
    newton = pytest.importorskip("newton")
    import warp as wp

    kin, out = exported
    builder = newton.ModelBuilder()
    builder.add_usd(str(out))
    model = builder.finalize(device="cpu")
    joints = list(model.joint_label)
    bodies = list(model.body_label)
    assert len(bodies) == len(set(bodies)) == 12  # 2 track + 7 robot + 3 positioner links, each once
    starts = model.joint_q_start.numpy()
    state = model.state()

    def body_positions(values: dict) -> np.ndarray:
        q = model.joint_q.numpy().copy()
        for name, v in values.items():
            q[starts[joints.index(name)]] = v
        newton.eval_fk(model, wp.array(q, dtype=wp.float32, device="cpu"), model.joint_qd, state)
        return state.body_q.numpy().copy()

    at_home = body_positions({})
    moved = body_positions({"/World/track/joints/J1": 1.5, "/World/stn/joints/J1": 0.5, "/World/stn/joints/J2": 1.0})
    base = bodies.index(f"/World/{ROBOT}/Base")
    assert moved[base, :3] - at_home[base, :3] == pytest.approx([1.5, 0.0, 0.0], abs=1e-5)
    flange = bodies.index(f"/World/{ROBOT}/Link6")
    assert moved[flange, :3] - at_home[flange, :3] == pytest.approx([1.5, 0.0, 0.0], abs=1e-5)
    # the face plate where the cell's kinematics puts it (its body frame: the link's, moved to its origin)
    stage = Usd.Stage.Open(str(out))
    origin = np.array(stage.GetPrimAtPath("/World/stn/FacePlate").GetAttribute("xformOp:translate").Get())
    links = kin.unit_links("stn", np.array([[0.5, 1.0]]))[0]
    want = links[kin.units["stn"].graph.link_index("FacePlate")]
    plate = bodies.index("/World/stn/FacePlate")
    assert moved[plate, :3] == pytest.approx(want[:3, :3] @ origin + want[:3, 3], abs=1e-5)
    turned = _rotation(moved[plate, 3:])
    assert np.abs(turned - want[:3, :3]).max() <= 1e-5


def _rotation(xyzw) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    return Rotation.from_quat(xyzw).as_matrix()


def test_a_bad_cell_file_exits_1_at_its_line(tmp_path, capsys):
    cell = tmp_path / "bad.toml"
    cell.write_text(f'[robot]\nrsxml = "{examples.IRB2600.as_posix()}"\non = "trak"\n\n[[external]]\nname = "track"\n'
                    f'rsxml = "{examples.TRACK.as_posix()}"\naxes = ["eax_a"]\n')
    assert main(["export", str(cell), "-o", str(tmp_path / "cell.usda")]) == 1
    assert f"{cell}:3:" in capsys.readouterr().err
    assert not (tmp_path / "cell.usda").exists() and not (tmp_path / "cell_parts").exists()


def test_a_cell_takes_no_single_robot_options(tmp_path, exported, capsys):
    kin, _ = exported
    assert main(["export", kin.cell.path, "-o", str(tmp_path / "cell.usdz")]) == 1
    assert "a cell exports to one USD stage" in capsys.readouterr().err
    assert main(["export", kin.cell.path, "-o", str(tmp_path / "cell.usda"), "--mass", "100"]) == 1
    assert "not a cell" in capsys.readouterr().err


def test_a_robot_on_the_floor_is_fixed_to_the_world_at_its_frame(tmp_path):
    """No carrier: the root joint stays on the world, its frame the cell's; a .usdc stage."""
    newton = pytest.importorskip("newton")
    cell = tmp_path / "floor.toml"
    cell.write_text(f'[robot]\nrsxml = "{examples.IRB2600.as_posix()}"\nframe = [1000, 200, 300, 0, 0, 45]\n')
    out = tmp_path / "cell.usdc"
    assert main(["export", str(cell), "-o", str(out)]) == 0
    stage = Usd.Stage.Open(str(out))
    frame = read_cell(str(cell)).robot.frame
    assert np.abs(_world(stage, f"/World/{ROBOT}") - frame).max() <= 1e-6
    assert stage.GetPrimAtPath(f"/World/{ROBOT}").HasAPI(UsdPhysics.ArticulationRootAPI)
    builder = newton.ModelBuilder()
    builder.add_usd(str(out))
    model = builder.finalize(device="cpu")
    state = model.state()
    newton.eval_fk(model, model.joint_q, model.joint_qd, state)
    base = state.body_q.numpy()[list(model.body_label).index(f"/World/{ROBOT}/Base")]
    assert base[:3] == pytest.approx(frame[:3, 3], abs=1e-5)
    assert np.abs(_rotation(base[3:]) - frame[:3, :3]).max() <= 1e-5
