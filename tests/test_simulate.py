"""Exports that simulate: the IRB 2600 exported by rswarp, loaded by Newton's own importers
(``add_usd``, ``add_urdf``) and stepped by Newton's MuJoCo and Featherstone solvers with gravity
and contacts on. Drives hold home; with the drives off, the limits hold."""

import math

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.export import export

newton = pytest.importorskip("newton")
wp = pytest.importorskip("warp")
pytest.importorskip("mujoco")

STEPS, DT = 2000, 1e-3  # 2 s at 1 ms


@pytest.fixture(scope="module")
def irb(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sim")
    mech = rswarp.load(examples.IRB2600)
    out = {"mech": mech}
    out["usd"] = export(mech, folder / "irb.usda")
    out["free"] = export(mech, folder / "free.usda", drive_hz=None)
    out["urdf"] = export(mech, folder / "irb.urdf")
    return out


def simulate(model, solver_name: str, q0: np.ndarray | None = None):
    """Step ``model`` 2 s from its initial joint state (or ``q0``) holding it as the drive target;
    returns the joint values sampled every 10 steps, shape (samples, dof)."""
    state0, state1, control = model.state(), model.state(), model.control()
    if q0 is not None:
        state0.joint_q.assign(q0.astype(np.float32))
    control.joint_target_q.assign(state0.joint_q)
    newton.eval_fk(model, state0.joint_q, state0.joint_qd, state0)
    if solver_name == "mujoco":
        solver = newton.solvers.SolverMuJoCo(model, use_mujoco_cpu=wp.get_device().is_cpu)
    else:
        solver = newton.solvers.SolverFeatherstone(model)
    contacts = model.contacts()
    samples = []
    for i in range(STEPS):
        state0.clear_forces()
        if solver_name != "mujoco":  # MuJoCo finds its own contacts
            model.collide(state0, contacts)
        solver.step(state0, state1, control, contacts, DT)
        state0, state1 = state1, state0
        if i % 10 == 9:
            samples.append(state0.joint_q.numpy().copy())
    return np.array(samples)


def load_usd(path):
    builder = newton.ModelBuilder()
    builder.add_usd(str(path))
    return builder.finalize(device="cpu")


@pytest.mark.parametrize("solver", ["mujoco", "featherstone"])
def test_usd_export_holds_home(irb, solver):
    model = load_usd(irb["usd"].output)
    home = model.joint_q.numpy().copy()
    assert np.allclose(np.degrees(home), np.degrees(irb["mech"].home_position()), atol=1e-4)
    q = simulate(model, solver)
    assert np.all(np.isfinite(q))
    drift = np.degrees(np.abs(q - home)).max(axis=0)
    assert drift.max() < 1.0, f"{solver}: drift per joint {np.round(drift, 3)} deg"


@pytest.mark.parametrize("solver", ["mujoco", "featherstone"])
def test_limits_hold_with_the_drives_off(irb, solver):
    """The arm falls under gravity onto its limits (J2 swings to its 155 deg stop) and stays within 2 deg."""
    model = load_usd(irb["free"].output)
    assert not model.joint_target_ke.numpy().any()
    lower, upper = model.joint_limit_lower.numpy(), model.joint_limit_upper.numpy()
    q = simulate(model, solver)
    assert np.all(np.isfinite(q))
    past = np.degrees(np.maximum(lower - q, q - upper)).max(axis=0)
    assert past.max() < 2.0, f"{solver}: past the limits by {np.round(past, 3)} deg"
    assert np.degrees(q[:, 1]).max() > 150  # it did fall onto the J2 stop, or the test proves nothing


def test_urdf_export_holds_home_in_newton_mujoco(irb):
    """URDF has no drives, armature or filtered pairs (those go to an SRDF): the test applies
    rswarp's values (``export --json``) to what ``add_urdf`` loaded, as a user would; the limits,
    efforts, masses and collision meshes come from the file."""
    mech, robot = irb["mech"], irb["urdf"].physics
    builder = newton.ModelBuilder()
    builder.add_urdf(str(irb["urdf"].output))
    link_of = [builder.body_label[b].rsplit("/", 1)[-1] for b in builder.shape_body]
    for a, b, _ in robot.filtered:
        for sa in (i for i, link in enumerate(link_of) if link == a):
            for sb in (i for i, link in enumerate(link_of) if link == b):
                builder.add_shape_collision_filter_pair(sa, sb)
    model = builder.finalize(device="cpu")
    names = [label.rsplit("/", 1)[-1] for label in model.joint_label]
    dofs = [names.index(j.name) - 1 for j in mech.active_joints]  # one fixed root joint, then one DOF each
    effort = model.joint_effort_limit.numpy()
    assert np.all(effort > 0) and effort[dofs] == pytest.approx([robot.joints[j.name].effort for j in mech.active_joints],
                                                                 rel=1e-6)
    for attr, key in (("joint_target_ke", "stiffness"), ("joint_target_kd", "damping"), ("joint_armature", "armature")):
        values = getattr(model, attr).numpy()
        values[dofs] = [getattr(robot.joints[j.name], key) for j in mech.active_joints]
        getattr(model, attr).assign(values)
    home = np.zeros(model.joint_coord_count)
    home[dofs] = mech.home_position()
    q = simulate(model, "mujoco", home)
    assert np.all(np.isfinite(q))
    drift = np.degrees(np.abs(q - home)).max(axis=0)
    assert drift.max() < 1.0, f"drift per joint {np.round(drift, 3)} deg"


def test_urdf_loads_in_pinocchio_and_yourdfpy_without_package_dirs(irb, monkeypatch, tmp_path):
    pin = pytest.importorskip("pinocchio")
    yourdfpy = pytest.importorskip("yourdfpy")
    monkeypatch.chdir(tmp_path)  # elsewhere: nothing resolves against the working folder
    path = str(irb["urdf"].output)
    model = pin.buildModelFromUrdf(path)
    collision = pin.buildGeomFromUrdf(model, path, pin.GeometryType.COLLISION)
    visual = pin.buildGeomFromUrdf(model, path, pin.GeometryType.VISUAL)
    assert collision.ngeoms == visual.ngeoms == 7
    urdf = yourdfpy.URDF.load(path)
    assert len(urdf.scene.geometry) == 7
    assert np.allclose(urdf.scene.bounds, pin_bounds(pin, model, visual), atol=1e-5)


def pin_bounds(pin, model, geom):
    """The visual meshes' box at q = 0, placed by pinocchio."""
    import trimesh

    data, gdata = model.createData(), geom.createData()
    pin.updateGeometryPlacements(model, data, geom, gdata, pin.neutral(model))
    points = []
    for obj, placement in zip(geom.geometryObjects, gdata.oMg):
        v = trimesh.load(obj.meshPath).vertices
        points.append(v @ placement.rotation.T + placement.translation)
    points = np.vstack(points)
    return np.stack([points.min(axis=0), points.max(axis=0)])


def test_mass_option_gives_the_robot_weight_everywhere(tmp_path):
    from pxr import Usd, UsdPhysics

    from rswarp.export.newton import to_newton

    mech = rswarp.load(examples.IRB2600)
    result = export(mech, tmp_path / "r.usda", mass=272.0)
    assert result.physics.total_mass == pytest.approx(272.0)
    stage = Usd.Stage.Open(str(tmp_path / "r.usda"))
    masses = [UsdPhysics.MassAPI(p).GetMassAttr().Get() for p in stage.Traverse() if p.HasAPI(UsdPhysics.MassAPI)]
    assert len(masses) == 7 and sum(masses) == pytest.approx(272.0, rel=1e-6)
    assert load_usd(tmp_path / "r.usda").body_mass.numpy().sum() == pytest.approx(272.0, rel=1e-5)
    model = to_newton(mech, mass=272.0).finalize(device="cpu")
    assert model.body_mass.numpy().sum() == pytest.approx(272.0, rel=1e-5)


def test_drives_are_critically_damped_at_the_bandwidth(irb):
    """DriveAPI gains per degree, Newton's per radian: K = I w^2 and D = 2 I w with w = 2 pi 10 Hz."""
    from pxr import Usd, UsdPhysics

    robot = irb["usd"].physics
    stage = Usd.Stage.Open(str(irb["usd"].output))
    model = load_usd(irb["usd"].output)
    w = 2 * math.pi * 10.0
    for k, j in enumerate(irb["mech"].active_joints):
        jp = robot.joints[j.name]
        assert jp.stiffness == pytest.approx(jp.inertia * w * w) and jp.damping == pytest.approx(2 * jp.inertia * w)
        assert jp.inertia > jp.armature > 0 and jp.limit_stiffness > jp.stiffness
        prim = stage.GetPrimAtPath(f"/IRB2600_12_165__01/joints/{j.name}")
        drive = UsdPhysics.DriveAPI(prim, "angular")
        assert drive.GetStiffnessAttr().Get() == pytest.approx(jp.stiffness * math.pi / 180, rel=1e-6)
        assert drive.GetTargetPositionAttr().Get() == pytest.approx(math.degrees(irb["mech"].home_position()[k]), abs=1e-4)
        assert prim.GetAttribute("newton:armature").Get() == pytest.approx(jp.armature, rel=1e-6)
        assert model.joint_target_ke.numpy()[k] == pytest.approx(jp.stiffness, rel=1e-5)
        assert model.joint_limit_ke.numpy()[k] == pytest.approx(jp.limit_stiffness, rel=1e-5)
        assert model.joint_armature.numpy()[k] == pytest.approx(jp.armature, rel=1e-5)
    free = Usd.Stage.Open(str(irb["free"].output))
    assert not any(p.HasAPI(UsdPhysics.DriveAPI, "angular") for p in free.Traverse())


def test_filtered_pairs_in_usd_and_newton(irb):
    """Jointed links and the Link4/Link6 hulls that overlap at home do not collide."""
    from pxr import Usd, UsdPhysics

    from rswarp.export.newton import to_newton

    robot = irb["usd"].physics
    assert [(a, b) for a, b, r in robot.filtered if r != "adjacent"] == [("Link4", "Link6")]
    assert len(robot.filtered) == 7
    stage = Usd.Stage.Open(str(irb["usd"].output))
    root = "/IRB2600_12_165__01"
    targets = UsdPhysics.FilteredPairsAPI(stage.GetPrimAtPath(f"{root}/Link4")).GetFilteredPairsRel().GetTargets()
    assert {str(t) for t in targets} == {f"{root}/Link5", f"{root}/Link6"}
    builder = to_newton(irb["mech"])
    labels = builder.shape_label
    pairs = {frozenset((labels[a].split("/")[0], labels[b].split("/")[0])) for a, b in builder.shape_collision_filter_pairs}
    assert frozenset(("Link4", "Link6")) in pairs and frozenset(("Link1", "Link6")) not in pairs
