"""URDF export, checked by pinocchio's URDF parser and its forward kinematics."""

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.export.urdf import to_urdf
from rswarp.sim.kinematics import Kinematics
from conftest import DATA

pin = pytest.importorskip("pinocchio")


@pytest.mark.parametrize("path", [examples.IRB2600, examples.IRB1300, DATA / "branching.rsxml", DATA / "units_inch.rsxml"],
                         ids=lambda p: p.name)
def test_pinocchio_gives_the_same_flange_poses(path, tmp_path):
    mech = rswarp.load(path)
    urdf = tmp_path / "robot.urdf"
    to_urdf(mech, urdf)
    model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    assert model.nq == mech.dof
    kin = Kinematics(mech)
    q = np.random.default_rng(4).uniform(*mech.bounds(), (25, mech.dof))
    for j in mech.active_joints:
        jid = model.getJointId(j.name)
        lim = mech.limit(j.name)
        assert model.lowerPositionLimit[model.joints[jid].idx_q] == pytest.approx(lim.min)
        assert model.upperPositionLimit[model.joints[jid].idx_q] == pytest.approx(lim.max)
    for f in mech.flanges:
        ours = kin.flange(q, f.name)
        fid = model.getFrameId(f.name)
        for i in range(len(q)):
            qp = pin.neutral(model)
            for j, v in zip(mech.active_joints, q[i]):
                qp[model.joints[model.getJointId(j.name)].idx_q] = v
            pin.forwardKinematics(model, data, qp)
            pin.updateFramePlacements(model, data)
            assert np.abs(data.oMf[fid].homogeneous - ours[i]).max() < 1e-5


def test_meshes_are_referenced_relative_and_scaled(tmp_path):
    mech = rswarp.load(DATA / "meshes" / "Cell.rsxml")
    urdf = tmp_path / "cell.urdf"
    warnings = to_urdf(mech, urdf)
    text = urdf.read_text()
    assert 'scale="0.001 0.001 0.001"' in text  # an OBJ in a millimetre file
    assert "ARM.OBJ" in text and "parts/base.stl" in text
    assert warnings == ["part 'Ghost' of link 'Ghost': no mesh beside the file; left out"]
    model = pin.buildModelFromUrdf(str(urdf))
    assert [model.names[i] for i in range(1, model.njoints)] == ["J1", "J2"]
    irb = rswarp.load(examples.IRB2600)
    to_urdf(irb, tmp_path / "irb.urdf")
    masses = pin.buildModelFromUrdf(str(tmp_path / "irb.urdf")).inertias
    assert masses[1].mass == pytest.approx(143.004, rel=1e-3)  # link_1.stl volume x 2700 kg/m^3


def test_loops_are_refused(tmp_path):
    with pytest.raises(rswarp.RsxmlError, match="closes a kinematic loop"):
        to_urdf(rswarp.load(DATA / "parallel_rod.rsxml"), tmp_path / "x.urdf")
    assert list(tmp_path.iterdir()) == []
