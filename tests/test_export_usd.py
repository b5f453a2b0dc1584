"""USD export, checked by usd-core's UsdPhysics parser, Newton's importer, and NVIDIA's validator."""

import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rswarp
from rswarp import examples
from rswarp.export.usd_layout import to_usd
from rswarp.geometry.frames import link_origins
from rswarp.kinematics.kinematics import Kinematics

from conftest import DATA

pxr = pytest.importorskip("pxr")
from pxr import Usd, UsdGeom, UsdPhysics  # noqa: E402


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """Each example exported once (flat .usda) and shared by the tests."""
    folder = tmp_path_factory.mktemp("usd")
    out = {}
    for key, path in {"irb2600": examples.IRB2600, "irb2600id": examples.IRB2600ID, "branching": DATA / "branching.rsxml",
                      "parallel": DATA / "parallel_rod.rsxml"}.items():
        mech = rswarp.load(path)
        target = folder / f"{key}.usda"
        warnings = to_usd(mech, target)
        out[key] = (mech, target, warnings)
    return out


def test_stage_conventions(exported):
    mech, path, warnings = exported["irb2600"]
    assert warnings == []
    stage = Usd.Stage.Open(str(path))
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0 and UsdGeom.GetStageUpAxis(stage) == "Z"
    assert UsdPhysics.GetStageKilogramsPerUnit(stage) == 1.0
    root = stage.GetDefaultPrim()
    assert root.GetName() == "IRB2600_12_165__01" and root.GetDisplayName() == "IRB2600_12_165__01"
    assert root.HasAPI(UsdPhysics.ArticulationRootAPI) and "NewtonArticulationRootAPI" in root.GetAppliedSchemas()
    authored = root.GetMetadata("apiSchemas").GetAddedOrExplicitItems()  # without Newton's schemas too
    assert "PhysicsArticulationRootAPI" in authored
    roots = [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.ArticulationRootAPI)]
    assert roots == [root]
    data = root.GetCustomDataByKey("rsxml")
    assert data["modelName"] == "IRB2600_12_165" and list(data["kinematicsFlags"]) == ["Articulated"]
    assert list(data["jointMask"]) == [1] * 6 and data["lengthUnit"] == "m"
    link6 = stage.GetPrimAtPath(f"{root.GetPath()}/Link6")
    visual = stage.GetPrimAtPath(f"{link6.GetPath()}/visuals/Link6")
    assert list(UsdGeom.Mesh(visual).GetDisplayColorAttr().Get()) == [pxr.Gf.Vec3f(215 / 255, 215 / 255, 215 / 255)]
    col = stage.GetPrimAtPath(f"{link6.GetPath()}/collisions/Link6")
    assert col.HasAPI(UsdPhysics.CollisionAPI) and UsdPhysics.MeshCollisionAPI(col).GetApproximationAttr().Get() == "convexHull"
    mass = UsdPhysics.MassAPI(stage.GetPrimAtPath(f"{root.GetPath()}/Link1")).GetMassAttr().Get()
    import trimesh
    volume = trimesh.load(examples.IRB2600.parent / "link_1.stl").volume
    assert mass == pytest.approx(volume * 2700, rel=1e-4)
    j5 = stage.GetPrimAtPath(f"{root.GetPath()}/joints/J5")
    assert j5.GetAttribute("physics:lowerLimit").Get() == pytest.approx(-120) and j5.GetAttribute("physics:upperLimit").Get() == pytest.approx(120)
    assert j5.GetAttribute("state:angular:physics:position").Get() == pytest.approx(30)
    assert stage.GetPrimAtPath(f"{link6.GetPath()}/wrist/site").HasAPI("NewtonSiteAPI")


def test_usd_physics_parser_finds_the_articulation(exported):
    mech, path, _ = exported["irb2600"]
    parsed = UsdPhysics.LoadUsdPhysicsFromRange(Usd.Stage.Open(str(path)), ["/"])
    by_type = {k: v for k, v in parsed.items()}
    assert len(by_type[UsdPhysics.ObjectType.Articulation][0]) == 1
    assert len(by_type[UsdPhysics.ObjectType.RigidBody][0]) == 7
    assert len(by_type[UsdPhysics.ObjectType.FixedJoint][0]) == 1
    paths, descs = by_type[UsdPhysics.ObjectType.RevoluteJoint]
    limits = {str(p).rsplit("/", 1)[-1]: (d.limit.lower, d.limit.upper) for p, d in zip(paths, descs)}
    assert limits == {j: pytest.approx((lo, hi)) for j, lo, hi in
                      [("J1", -180, 180), ("J2", -95, 155), ("J3", -180, 75), ("J4", -400, 400), ("J5", -120, 120), ("J6", -400, 400)]}
    articulation = by_type[UsdPhysics.ObjectType.Articulation][1][0]
    assert len(articulation.articulatedJoints) == 7
    assert len([b for b in articulation.articulatedBodies if not b.isEmpty]) == 7  # plus the world
    assert [str(p).rsplit("/", 1)[-1] for p in articulation.rootPrims] == ["root_joint"]  # fixed base


@pytest.mark.parametrize("key", ["irb2600", "irb2600id", "branching"])
def test_newton_add_usd_matches_our_kinematics(exported, key):
    newton = pytest.importorskip("newton")
    import warp as wp

    mech, path, _ = exported[key]
    builder = newton.ModelBuilder()
    builder.add_usd(str(path))
    model = builder.finalize(device="cpu")
    kin = Kinematics(mech)
    n = 100
    q = np.random.default_rng(11).uniform(*mech.bounds(), (n, mech.dof))
    # Newton's joint coordinates, by joint name
    names = [label.rsplit("/", 1)[-1] for label in model.joint_label]
    starts = model.joint_q_start.numpy()
    home = model.joint_q.numpy()
    active = [j.name for j in mech.active_joints]
    assert home[[starts[names.index(a)] for a in active]] == pytest.approx(mech.home_position(), abs=1e-6)
    origins = link_origins(mech)
    bodies = [label.rsplit("/", 1)[-1] for label in model.body_label]
    state = model.state()
    poses = kin.fk(q)
    for i in range(n):
        jq = home.copy()
        for a, v in zip(active, q[i]):
            jq[starts[names.index(a)]] = v
        newton.eval_fk(model, wp.array(jq, dtype=wp.float32, device="cpu"), model.joint_qd, state)
        body_q = state.body_q.numpy()
        for b, link in enumerate(bodies):
            want = poses[i, kin.links.index(link)].astype(float)
            pos = want[:3, :3] @ origins[link] + want[:3, 3]
            assert np.abs(body_q[b, :3] - pos).max() <= 1e-5
            rot = Rotation.from_quat(body_q[b, 3:]).as_matrix()
            assert np.abs(rot - want[:3, :3]).max() <= 1e-5
    # each flange's site sits where our flange is
    flanges = {f.name: kin.flange(q[-1:], f.name)[0] for f in mech.flanges}
    assert_sites_at_flanges(model, state, flanges, lambda label: label.rsplit("/", 2)[-2])


def assert_sites_at_flanges(model, state, flanges, name_of):
    """World pose of each site shape (its body's pose times the shape's offset) = our flange."""
    body_q = state.body_q.numpy()
    found = 0
    for s, label in enumerate(model.shape_label):
        name = name_of(label)
        if name not in flanges or not label.endswith(("/site", name)):
            continue
        b = model.shape_body.numpy()[s]
        xs = model.shape_transform.numpy()[s]
        body = np.eye(4)
        body[:3, :3] = Rotation.from_quat(body_q[b, 3:]).as_matrix()
        body[:3, 3] = body_q[b, :3]
        local = np.eye(4)
        local[:3, :3] = Rotation.from_quat(xs[3:]).as_matrix()
        local[:3, 3] = xs[:3]
        assert np.abs(body @ local - flanges[name]).max() <= 1e-5, name
        found += 1
    assert found == len(flanges)


def test_passive_loop_closing_joint_is_excluded(exported):
    mech, path, _ = exported["parallel"]
    stage = Usd.Stage.Open(str(path))
    excluded = [p.GetName() for p in stage.Traverse()
                if p.IsA(UsdPhysics.Joint) and UsdPhysics.Joint(p).GetExcludeFromArticulationAttr().Get()]
    assert excluded == ["Rod2"]
    rod1 = stage.GetPrimAtPath(f"{stage.GetDefaultPrim().GetPath()}/joints/Rod1")
    assert rod1.GetCustomDataByKey("rsxml")["active"] is False


def test_cable_as_basis_curves(exported):
    mech, path, _ = exported["irb2600id"]
    stage = Usd.Stage.Open(str(path))
    hose = UsdGeom.BasisCurves(stage.GetPrimAtPath(f"{stage.GetDefaultPrim().GetPath()}/cables/Hose"))
    assert [tuple(p) for p in hose.GetPointsAttr().Get()] == [pytest.approx((0.5385, 0, 1.495)), pytest.approx((1.205, 0, 1.495))]
    assert list(hose.GetWidthsAttr().Get()) == [pytest.approx(0.05)]
    prim = hose.GetPrim()
    assert prim.GetAttribute("rsxml:maxSegmentLength").Get() == pytest.approx(0.05)
    assert list(prim.GetAttribute("rsxml:attachedTo").Get()) == ["Link4", "Link5"]


def test_without_meshes_exports_kinematics_with_one_warning(exported):
    mech, path, warnings = exported["irb2600id"]
    assert len(warnings) == 1 and "exported kinematics only" in warnings[0]
    stage = Usd.Stage.Open(str(path))
    assert not [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]


@pytest.mark.parametrize("key", ["irb2600", "irb2600id", "parallel"])
def test_asset_validator_reports_no_errors(exported, key, tmp_path):
    """Default rules, on the binary (.usdc) export: for .usda the validator's performance rule
    asks for large arrays (the meshes) to be stored in crate files instead."""
    validator = pytest.importorskip("omni.asset_validator")
    mech, _, _ = exported[key]
    path = tmp_path / f"{key}.usdc"
    to_usd(mech, path)
    results = validator.ValidationEngine().validate(str(path))
    errors = [i for i in results.issues() if i.severity in (validator.IssueSeverity.ERROR, validator.IssueSeverity.FAILURE)]
    assert errors == [], "\n".join(f"{i.rule}: {i.message}" for i in errors)


@pytest.mark.parametrize("ext", [".usda", ".usdc"])
def test_export_is_deterministic(tmp_path, ext):
    mech = rswarp.load(examples.IRB2600)
    to_usd(mech, tmp_path / f"a{ext}")
    to_usd(mech, tmp_path / f"b{ext}")
    assert (tmp_path / f"a{ext}").read_bytes() == (tmp_path / f"b{ext}").read_bytes()


def test_export_is_atomic(tmp_path, monkeypatch):
    mech = rswarp.load(examples.IRB2600)
    target = tmp_path / "robot.usda"
    target.write_text("previous")
    import rswarp.export.usd as ex

    def boom(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(ex, "_cable", boom)
    with pytest.raises(RuntimeError):
        to_usd(rswarp.load(examples.IRB2600ID), target)
    assert target.read_text() == "previous" and [p.name for p in tmp_path.iterdir()] == ["robot.usda"]
    with pytest.raises(ValueError, match="must end in"):
        to_usd(mech, tmp_path / "robot.obj")


def test_component_layout_composes_to_the_flat_stage(exported, tmp_path):
    mech, flat_path, _ = exported["irb2600"]
    target = tmp_path / "robot.usda"
    to_usd(mech, target, layout="component")
    assert sorted(p.name for p in (tmp_path / "robot_Payload").iterdir()) == [
        "Contents.usda", "Geometry.usdc", "Materials.usda", "Physics.usda"]
    comp, flat = Usd.Stage.Open(str(target)), Usd.Stage.Open(str(flat_path))
    assert comp.GetRootLayer().GetPrimAtPath("/IRB2600_12_165__01").GetInfo("payload").prependedItems
    assert sorted(str(p.GetPath()) for p in comp.Traverse()) == sorted(str(p.GetPath()) for p in flat.Traverse())
    for p in flat.Traverse():
        q = comp.GetPrimAtPath(p.GetPath())
        assert set(p.GetAppliedSchemas()) == set(q.GetAppliedSchemas()), p.GetPath()
        for a in p.GetAttributes():
            assert q.GetAttribute(a.GetName()).Get() == a.Get(), (p.GetPath(), a.GetName())
        for r in p.GetRelationships():
            assert q.GetRelationship(r.GetName()).GetTargets() == r.GetTargets()
    physics = (tmp_path / "robot_Payload" / "Physics.usda").read_text()
    assert "physics:mass" in physics and "PhysicsRevoluteJoint" in physics
    assert "physics:" not in (tmp_path / "robot_Payload" / "Materials.usda").read_text()


def test_to_newton_builds_bodies_shapes_limits_and_home():
    newton = pytest.importorskip("newton")
    from rswarp.export.newton import to_newton

    mech = rswarp.load(examples.IRB2600)
    builder = to_newton(mech)
    many = newton.ModelBuilder()
    many.replicate(builder, 3)
    model = many.finalize(device="cpu")
    assert model.body_count == 21 and model.shape_count == 21 + 3 and model.articulation_count == 3  # + flange sites
    q = model.joint_q.numpy().reshape(3, 6)
    assert np.allclose(q, mech.home_position())
    lo, hi = mech.bounds()
    assert np.allclose(model.joint_limit_lower.numpy().reshape(3, 6), lo) and np.allclose(model.joint_limit_upper.numpy().reshape(3, 6), hi)
    import trimesh
    volume = trimesh.load(examples.IRB2600.parent / "link_1.stl").volume
    assert model.body_mass.numpy()[1] == pytest.approx(volume * 2700, rel=1e-3)


@pytest.mark.parametrize("name", ["irb2600", "branching"])
def test_to_newton_flange_sites_follow_our_kinematics(name):
    newton = pytest.importorskip("newton")
    import warp as wp

    from rswarp.export.newton import newton_q_columns, to_newton

    mech = rswarp.load({"irb2600": examples.IRB2600, "branching": DATA / "branching.rsxml"}[name])
    model = to_newton(mech).finalize(device="cpu")
    kin = Kinematics(mech)
    state = model.state()
    cols = newton_q_columns(mech)
    for q in np.random.default_rng(5).uniform(*mech.bounds(), (100, mech.dof)):
        newton.eval_fk(model, wp.array(q[cols].astype(np.float32), dtype=wp.float32, device="cpu"), model.joint_qd, state)
        flanges = {f.name: kin.flange(q[None], f.name)[0] for f in mech.flanges}
        assert_sites_at_flanges(model, state, flanges, lambda label: label)


def test_export_command(tmp_path, capsys):
    from rswarp.cli import main

    assert main(["export", str(examples.IRB2600ID), "-o", str(tmp_path / "r.usdc")]) == 0
    captured = capsys.readouterr()
    assert "exported kinematics only" in captured.err and f"wrote {tmp_path / 'r.usdc'}" in captured.out
    assert main(["export", str(examples.IRB2600), "-o", str(tmp_path / "r.usdz")]) == 0
    assert main(["export", str(examples.IRB2600), "-o", str(tmp_path / "r.urdf"), "--json"]) == 0
    capsys.readouterr()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["meshes", "r.srdf", "r.urdf", "r.usdc", "r.usdz"]
    stage = Usd.Stage.Open(str(tmp_path / "r.usdz"))
    assert stage.GetDefaultPrim().GetName() == "IRB2600_12_165__01"
    assert main(["export", str(examples.IRB2600), "-o", str(tmp_path / "r.obj")]) == 1
    assert "must end in .usda, .usdc, .usd, .usdz or .urdf\n" in capsys.readouterr().err
    assert main(["export", str(DATA / "smart" / "Counter.rsxml"), "-o", str(tmp_path / "c.usda")]) == 1
    assert re.match(r".*Counter.rsxml:\d+: SmartComponent 'Counter' holds no mechanism to export\n",
                    capsys.readouterr().err)


def test_smart_component_exports_its_mechanism_with_properties(tmp_path):
    sc = rswarp.load(DATA / "smart" / "Positioner.rsxml")
    assert isinstance(sc, rswarp.SmartComponent)
    warnings = to_usd(sc, tmp_path / "p.usda")
    assert len(warnings) == 1  # no meshes: kinematics only
    stage = Usd.Stage.Open(str(tmp_path / "p.usda"))
    root = stage.GetDefaultPrim()
    data = root.GetCustomDataByKey("rsxml")
    assert root.GetName() == "Turntable" and data["type"] == "ExternalAxis"
    assert data["smartComponent"]["properties"]["Speed"]["value"] == "0.5"
    assert data["smartComponent"]["signals"]["Start"]["signalType"] == "DigitalInput"
    assert data["smartComponent"]["options"]["codeBehind"] == "Positioner.CodeBehind,Positioner.dll"
    a1 = stage.GetPrimAtPath(f"{root.GetPath()}/joints/A1")
    assert a1.GetAttribute("state:angular:physics:position").Get() == pytest.approx(90)


@pytest.mark.parametrize("ext", [".usdc", ".usdz"])
def test_component_layout_in_binary_and_package(tmp_path, ext):
    mech = rswarp.load(examples.IRB2600)
    target = tmp_path / f"robot{ext}"
    to_usd(mech, target, layout="component")
    stage = Usd.Stage.Open(str(target))
    parsed = UsdPhysics.LoadUsdPhysicsFromRange(stage, ["/"])
    assert len(parsed[UsdPhysics.ObjectType.RevoluteJoint][0]) == 6
    assert len([p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]) == 14
    if ext == ".usdz":
        import zipfile

        names = zipfile.ZipFile(target).namelist()
        assert names[0] == "robot.usda" and "robot_Payload/Geometry.usdc" in names
        assert sorted(p.name for p in tmp_path.iterdir()) == ["robot.usdz"]  # the package holds the payload
