"""URDF export, checked by pinocchio's URDF parser and its forward kinematics."""

import re
from pathlib import Path

import numpy as np
import pytest
import trimesh

import rswarp
from rswarp import examples
from rswarp.export.urdf import to_urdf
from rswarp.kinematics.kinematics import Kinematics

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


def test_meshes_are_written_beside_in_metres(tmp_path):
    """Each part's mesh is written to meshes/<stem>/ in metres in its link's frame (an OBJ of a
    millimetre file included), named by absolute path by default and relative on request."""
    from rswarp.geometry import part_mesh
    from rswarp.geometry.frames import link_origins

    mech = rswarp.load(DATA / "meshes" / "Cell.rsxml")
    urdf = tmp_path / "cell.urdf"
    warnings = to_urdf(mech, urdf)
    text = urdf.read_text()
    files = re.findall(r'<mesh filename="([^"]+)"/>', text)
    assert files and all(f.startswith(str(tmp_path / "meshes" / "cell")) and Path(f).is_file() for f in files)
    assert len(warnings) == 1 and "no mesh for part 'Ghost'" in warnings[0]
    origins = link_origins(mech)
    for part, transform in mech.parts("Arm"):
        ours = trimesh.load(tmp_path / "meshes" / "cell" / "Arm.stl")  # the part is the link: one name
        expected = part_mesh(mech, part, transform).bounds - origins["Arm"]
        assert np.abs(ours.bounds - expected).max() < 1e-6
    model = pin.buildModelFromUrdf(str(urdf))
    assert [model.names[i] for i in range(1, model.njoints)] == ["J1", "J2"]
    to_urdf(mech, tmp_path / "moved" / "cell.urdf", mesh_paths="relative")
    assert 'filename="meshes/cell/' in (tmp_path / "moved" / "cell.urdf").read_text()
    irb = rswarp.load(examples.IRB2600)
    to_urdf(irb, tmp_path / "irb.urdf")
    masses = pin.buildModelFromUrdf(str(tmp_path / "irb.urdf")).inertias
    assert masses[1].mass == pytest.approx(143.004, rel=1e-3)  # link_1.stl volume x 2700 kg/m^3


def test_loops_urdf_cannot_express_are_refused(tmp_path):
    """A four-bar is not linear in its active joint: refused, nothing written (parallelograms become
    mimic joints: tests/test_loops.py)."""
    with pytest.raises(rswarp.RsxmlError, match="closes a four-bar loop"):
        to_urdf(rswarp.load(DATA / "loops" / "four_bar.rsxml"), tmp_path / "x.urdf")
    assert list(tmp_path.iterdir()) == []
