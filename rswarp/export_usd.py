"""Export a mechanism to OpenUSD with UsdPhysics: what Newton, Isaac Sim and usdview open.

Metres, Z up, kilograms; the robot is the default prim and carries the articulation root. Each
link is a rigid body whose frame stays world-aligned at the zero position with its origin on its
joint's axis; joints sit on the RSXML axis with the joint X axis along it. Flanges are frames with
a Newton site, cables BasisCurves, and RSXML metadata lives in custom data under ``rsxml``.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import newton_usd_schemas  # noqa: F401 (registers Newton's schemas, NewtonSiteAPI and others, with USD)
import numpy as np
from pxr import Gf, Kind, Sdf, Tf, Usd, UsdGeom, UsdPhysics, UsdUtils, Vt

from .compile import compile_tree, link_origins
from .errors import MeshNotFoundError
from .geometry import DEFAULT_DENSITY, mass_properties, part_mesh
from .model import Mechanism, SmartComponent

GRAPHITE_WHITE = (215 / 255, 215 / 255, 215 / 255)
APPROXIMATIONS = ("convexHull", "convexDecomposition")
PHYSICS_PREFIXES = ("physics:", "newton:", "state:")  # properties the component layout puts in Physics


def _quat_x_to(axis: np.ndarray):
    """The rotation (Gf.Quatf) taking +X onto ``axis``: the joint frame of a joint about ``axis``."""
    x = np.array([1.0, 0.0, 0.0])
    a = axis / np.linalg.norm(axis)
    c = float(np.dot(x, a))
    if c > 1 - 1e-12:
        return Gf.Quatf(1, 0, 0, 0)
    if c < -1 + 1e-12:
        return Gf.Quatf(0, 0, 0, 1)  # 180 degrees about z
    v = np.cross(x, a)
    w = 1.0 + c
    n = np.sqrt(w * w + v @ v)
    return Gf.Quatf(float(w / n), *(float(t / n) for t in v))


def _matrix_quat(r: np.ndarray):
    """Gf.Quatf of a rotation matrix (column vectors)."""
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(r).as_quat()
    return Gf.Quatf(float(w), float(x), float(y), float(z))


class _Names:
    """Valid, unique prim names; the RSXML name is kept as displayName."""

    def __init__(self):
        self.used: set[str] = set()

    def __call__(self, name: str) -> str:
        base = Tf.MakeValidIdentifier(name or "unnamed")
        out, i = base, 1
        while out in self.used:
            out, i = f"{base}_{i}", i + 1
        self.used.add(out)
        return out


def _metadata(mech: Mechanism, sc: SmartComponent | None) -> dict:
    # typed arrays (Vt): USD cannot infer the type of an empty list
    data = {
        "name": mech.name, "type": mech.type or "", "modelName": mech.model_name or "",
        "kinematicsFlags": Vt.StringArray(list(mech.kinematics_flags)), "lengthUnit": mech.length_unit or "m",
        "angleUnit": mech.angle_unit or "rad", "motionControl": mech.motion_control or "",
        "jointMask": Vt.IntArray(list(mech.joint_mask or ())),
        "homePosition": Vt.DoubleArray([float(v) for v in mech.home_position()]),
        "attributes": {a.key: a.value for a in mech.attributes},
        "attributeDefinitions": {a.key: bool(a.definition) for a in mech.attributes},
    }
    if sc is not None:
        data["smartComponent"] = {
            "name": sc.name, "options": dict(sc.options), "assets": Vt.StringArray(list(sc.assets)),
            "properties": {p.name: {"valueType": p.value_type or "", "value": p.value or "",
                                    "attributes": dict(p.attributes)} for p in sc.properties},
            "signals": {s.name: {"signalType": s.signal_type or "", **dict(s.options)} for s in sc.signals},
            "descriptions": dict(sc.descriptions),
        }
    return data


def _link_meshes(mech: Mechanism, link: str, warnings: list[str]):
    """(part name, trimesh in world at zero position) for each Part of a link that has a mesh."""
    out = []
    for part, transform in mech.parts(link):
        if not part.source:
            continue
        try:
            out.append((part.name, part_mesh(mech, part, transform)))
        except MeshNotFoundError as exc:
            warnings.append(str(exc))
    return out


def _author_mesh(stage, path, mesh, origin: np.ndarray, color):
    m = UsdGeom.Mesh.Define(stage, path)
    pts = np.asarray(mesh.vertices, float) - origin
    m.CreatePointsAttr([Gf.Vec3f(*p) for p in pts.tolist()])
    m.CreateFaceVertexCountsAttr([3] * len(mesh.faces))
    m.CreateFaceVertexIndicesAttr(np.asarray(mesh.faces, int).ravel().tolist())
    m.CreateExtentAttr(UsdGeom.PointBased.ComputeExtent(m.GetPointsAttr().Get()))
    m.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    m.CreateDisplayColorAttr([Gf.Vec3f(*color)])
    normals = np.asarray(mesh.vertex_normals, float)
    m.CreateNormalsAttr([Gf.Vec3f(*n) for n in normals.tolist()])
    m.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    return m


def _mesh_color(mesh) -> tuple[float, float, float]:
    """The mesh's own uniform colour if it defines one, else Graphite White."""
    visual = getattr(mesh, "visual", None)
    try:
        if visual is not None and visual.kind in ("face", "vertex") and visual.defined:
            rgba = np.asarray(visual.main_color, float) / 255.0
            return tuple(float(c) for c in rgba[:3])
    except Exception:
        pass
    return GRAPHITE_WHITE


def build_stage(stage, model, *, density: float = DEFAULT_DENSITY, collision: str = "convexHull") -> list[str]:
    """Author ``model`` (a Mechanism, or a SmartComponent holding one) into ``stage``; returns warnings."""
    sc = None
    if isinstance(model, SmartComponent):
        sc = model
        mechs = [c for c in model.components if isinstance(c, Mechanism)]
        if not mechs:
            raise ValueError(f"SmartComponent '{model.name}' holds no mechanism to export")
        model = mechs[0]
    mech: Mechanism = model
    if collision not in APPROXIMATIONS:
        raise ValueError(f"collision must be one of {', '.join(APPROXIMATIONS)}")
    warnings: list[str] = []
    tree = compile_tree(mech, allow_loops=True)
    origins = link_origins(mech, tree)

    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    names = _Names()
    root_name = names(mech.name)
    root = UsdGeom.Xform.Define(stage, f"/{root_name}")
    stage.SetDefaultPrim(root.GetPrim())
    rp = root.GetPrim()
    Usd.ModelAPI(rp).SetKind(Kind.Tokens.component)
    rp.SetDisplayName(mech.name)
    rp.SetCustomDataByKey("rsxml", _metadata(mech, sc))
    # both authored: Newton's includes the UsdPhysics one, but only where Newton's schemas are
    # registered; usdview or Isaac Sim without them must still see the articulation root
    rp.AddAppliedSchema("PhysicsArticulationRootAPI")
    rp.AddAppliedSchema("NewtonArticulationRootAPI")

    link_path: dict[str, str] = {}
    any_mesh = False
    for link in tree.links:
        path = f"/{root_name}/{names(link)}"
        link_path[link] = path
        x = UsdGeom.Xform.Define(stage, path)
        x.GetPrim().SetDisplayName(link)
        x.AddTranslateOp().Set(Gf.Vec3d(*origins[link]))
        UsdPhysics.RigidBodyAPI.Apply(x.GetPrim())
        meshes = _link_meshes(mech, link, warnings)
        visual_names, collision_names = _Names(), _Names()
        for part_name, mesh in meshes:
            any_mesh = True
            visual = _author_mesh(stage, f"{path}/visuals/{visual_names(part_name)}", mesh, origins[link],
                                  _mesh_color(mesh))
            visual.GetPrim().SetDisplayName(part_name)
            col = _author_mesh(stage, f"{path}/collisions/{collision_names(part_name)}", mesh, origins[link],
                               GRAPHITE_WHITE)
            col.CreatePurposeAttr(UsdGeom.Tokens.guide)
            UsdPhysics.CollisionAPI.Apply(col.GetPrim())
            UsdPhysics.MeshCollisionAPI.Apply(col.GetPrim()).CreateApproximationAttr(collision)
        if meshes:
            _mass(stage.GetPrimAtPath(path), [m for _, m in meshes], origins[link], density, warnings, link)
        for group in (f"{path}/visuals", f"{path}/collisions"):
            if stage.GetPrimAtPath(group):
                stage.GetPrimAtPath(group).SetTypeName("Scope")
    if not any_mesh:  # one clear line instead of one per part
        warnings[:] = [f"{mech.path or mech.name}: warning: no mesh beside the file for any part (looked for "
                       "<source stem>.stl/.obj/.ply/.glb/.gltf/.off): exported kinematics only, "
                       "bodies and joints without geometry or mass"]

    joints = UsdGeom.Scope.Define(stage, f"/{root_name}/joints")
    fixed = UsdPhysics.FixedJoint.Define(stage, f"{joints.GetPath()}/{names('root_joint')}")
    fixed.CreateBody1Rel().SetTargets([link_path[tree.links[0]]])
    fixed.CreateLocalPos0Attr(Gf.Vec3f(*origins[tree.links[0]]))
    fixed.CreateLocalPos1Attr(Gf.Vec3f(0, 0, 0))
    home = dict(zip(tree.active, mech.home_position()))
    for j in mech.joints:
        if j.parent not in link_path or j.child not in link_path:
            continue
        jpath = f"{joints.GetPath()}/{names(j.name)}"
        schema = UsdPhysics.RevoluteJoint if j.revolute else UsdPhysics.PrismaticJoint
        uj = schema.Define(stage, jpath)
        prim = uj.GetPrim()
        prim.SetDisplayName(j.name)
        point = np.asarray(j.point1, float)
        if tree.joint[tree.links.index(j.child)] == j.name:
            anchor = origins[j.child]  # the child's origin is on this joint's axis
        else:
            anchor = point  # a joint closing a loop: any point on the axis
        rot = _quat_x_to(np.asarray(j.axis, float))
        uj.CreateBody0Rel().SetTargets([link_path[j.parent]])
        uj.CreateBody1Rel().SetTargets([link_path[j.child]])
        uj.CreateLocalPos0Attr(Gf.Vec3f(*(anchor - origins[j.parent])))
        uj.CreateLocalRot0Attr(rot)
        uj.CreateLocalPos1Attr(Gf.Vec3f(*(anchor - origins[j.child])))
        uj.CreateLocalRot1Attr(rot)
        uj.CreateAxisAttr(UsdPhysics.Tokens.x)
        lim = mech.limit(j.name)
        scale = 180.0 / np.pi if j.revolute else 1.0  # UsdPhysics: revolute limits in degrees
        if lim is not None:
            uj.CreateLowerLimitAttr(float(lim.min * scale))
            uj.CreateUpperLimitAttr(float(lim.max * scale))
        if j.name in tree.closing:
            uj.CreateExcludeFromArticulationAttr(True)
        prim.SetCustomDataByKey("rsxml", {"active": j.active, "point1": Gf.Vec3d(*j.point1), "point2": Gf.Vec3d(*j.point2)})
        if j.name in home:
            kind = "angular" if j.revolute else "linear"
            value = float(home[j.name] * scale)
            # initial joint state: PhysX/Isaac Sim's JointStateAPI attribute and Newton's (both degrees/metres)
            prim.CreateAttribute(f"state:{kind}:physics:position", Sdf.ValueTypeNames.Float, custom=False).Set(value)
            prim.CreateAttribute(f"newton:{kind}:position", Sdf.ValueTypeNames.Float, custom=False).Set(value)

    for fl in mech.flanges:
        m = fl.pose.matrix()
        fx = UsdGeom.Xform.Define(stage, f"{link_path[fl.link]}/{names(fl.name)}")
        fx.GetPrim().SetDisplayName(fl.name)
        fx.AddTransformOp().Set(_gf_matrix(m, origins[fl.link]))
        fx.GetPrim().SetCustomDataByKey("rsxml", {"flange": True})
        site = UsdGeom.Sphere.Define(stage, f"{fx.GetPath()}/site")
        site.CreateRadiusAttr(0.005)
        site.CreateExtentAttr([Gf.Vec3f(-0.005, -0.005, -0.005), Gf.Vec3f(0.005, 0.005, 0.005)])
        site.CreatePurposeAttr(UsdGeom.Tokens.guide)
        site.GetPrim().ApplyAPI("NewtonSiteAPI")
    if mech.base_frame is not None:
        bf = UsdGeom.Xform.Define(stage, f"/{root_name}/{names('BaseFrame')}")
        bf.AddTransformOp().Set(_gf_matrix(mech.base_frame.matrix(), np.zeros(3)))
        bf.GetPrim().SetCustomDataByKey("rsxml", {"baseFrame": True})
    if mech.cables:
        UsdGeom.Scope.Define(stage, f"/{root_name}/cables")
        for c in mech.cables:
            _cable(stage, f"/{root_name}/cables/{names(c.name)}", c)
    return warnings


def _gf_matrix(m: np.ndarray, origin: np.ndarray):
    """A 4x4 pose relative to a world-aligned frame at ``origin``, as Gf.Matrix4d (row vectors)."""
    rel = m.copy()
    rel[:3, 3] = m[:3, 3] - origin
    return Gf.Matrix4d(*rel.T.flatten().tolist())


def _cable(stage, path: str, c) -> None:
    curve = UsdGeom.BasisCurves.Define(stage, path)
    curve.GetPrim().SetDisplayName(c.name)
    pts = [Gf.Vec3f(*p.position) for p in c.control_points]
    curve.CreateTypeAttr(UsdGeom.Tokens.linear)
    curve.CreateCurveVertexCountsAttr([len(pts)])
    curve.CreatePointsAttr(pts)
    curve.CreateWidthsAttr([float(2 * c.radius)])
    curve.SetWidthsInterpolation(UsdGeom.Tokens.constant)
    curve.CreateExtentAttr(UsdGeom.BasisCurves.ComputeExtent(curve.GetPointsAttr().Get(), curve.GetWidthsAttr().Get()))
    color = (0.125, 0.125, 0.125) if c.color is None else tuple(v / 255 for v in c.color)
    curve.CreateDisplayColorAttr([Gf.Vec3f(*color)])
    prim = curve.GetPrim()
    attrs = {"radius": c.radius, "maxSegmentLength": c.max_segment_length}
    if c.desired_length is not None:
        attrs["desiredLength"] = c.desired_length
    if c.youngs_modulus is not None:
        attrs["youngsModulus"] = c.youngs_modulus
    for key, value in attrs.items():
        prim.CreateAttribute(f"rsxml:{key}", Sdf.ValueTypeNames.Double, custom=True).Set(float(value))
    prim.CreateAttribute("rsxml:attachedTo", Sdf.ValueTypeNames.StringArray, custom=True).Set(
        [p.attached_to or "" for p in c.control_points])
    prim.CreateAttribute("rsxml:direction", Sdf.ValueTypeNames.Vector3fArray, custom=True).Set(
        [Gf.Vec3f(*(p.unit_direction if p.direction is not None else (0, 0, 0))) for p in c.control_points])


def _mass(prim, meshes, origin: np.ndarray, density: float, warnings: list[str], link: str) -> None:
    """Mass, centre of mass and principal inertia from the link's meshes (volume x density)."""
    mass, com, inertia, watertight = mass_properties(meshes, origin, density)
    if not watertight:
        warnings.append(f"link '{link}': mesh is not watertight; mass from its convex hull")
    if not mass > 0:
        warnings.append(f"link '{link}': mesh has no volume; no mass authored")
        return
    values, vectors = np.linalg.eigh(inertia)
    if np.linalg.det(vectors) < 0:
        vectors[:, 2] *= -1
    api = UsdPhysics.MassAPI.Apply(prim)
    api.CreateMassAttr(mass)
    api.CreateCenterOfMassAttr(Gf.Vec3f(*com))
    api.CreateDiagonalInertiaAttr(Gf.Vec3f(*np.maximum(values, 0.0)))
    api.CreatePrincipalAxesAttr(_matrix_quat(vectors))


def to_usd(model, path: str | Path, *, density: float = DEFAULT_DENSITY, collision: str = "convexHull",
           layout: str = "flat") -> list[str]:
    """Write ``model`` to ``path`` (.usda, .usdc or .usdz); returns warnings.

    ``layout="flat"`` writes one file; ``"component"`` writes an asset interface layer that
    payloads ``<stem>_Payload/Contents.usda``, built from geometry, materials and physics layers
    (as Newton's urdf-usd-converter lays assets out). Written to temporary files first, then moved
    into place.
    """
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in (".usda", ".usdc", ".usdz", ".usd"):
        raise ValueError(f"{path}: the USD file must end in .usda, .usdc, .usd or .usdz")
    if layout not in ("flat", "component"):
        raise ValueError("layout must be flat or component")
    folder = path.parent if str(path.parent) else Path(".")
    with tempfile.TemporaryDirectory(dir=folder, prefix=f".{path.stem}.") as tmp:
        tmp = Path(tmp)
        if layout == "flat":
            stage = Usd.Stage.CreateInMemory()
            warnings = build_stage(stage, model, density=density, collision=collision)
            if ext == ".usdz":
                stage.GetRootLayer().Export(str(tmp / f"{path.stem}.usdc"))
                _usdz(tmp / f"{path.stem}.usdc", tmp / path.name)
            else:
                stage.GetRootLayer().Export(str(tmp / path.name))
            os.replace(tmp / path.name, path)
            return warnings
        warnings = _component(model, tmp, path, density, collision)
        if ext == ".usdz":
            _usdz(tmp / f"{path.stem}.usda", tmp / path.name)
            os.replace(tmp / path.name, path)
            return warnings
        payload = tmp / f"{path.stem}_Payload"
        target = folder / f"{path.stem}_Payload"
        if target.exists():
            shutil.rmtree(target)
        os.replace(payload, target)
        os.replace(tmp / path.name, path)
        return warnings


def _usdz(src: Path, dst: Path) -> None:
    if not UsdUtils.CreateNewUsdzPackage(str(src), str(dst)):
        raise OSError(f"could not package {dst}")


def _component(model, tmp: Path, path: Path, density: float, collision: str) -> list[str]:
    """The component layout: interface layer -> payload Contents.usda -> sublayers
    Geometry.usda (meshes, frames, cables), Materials.usda (display colours) and Physics.usda
    (physics schemas, joints, mass); each layer holds only its own opinions."""
    stage = Usd.Stage.CreateInMemory()
    warnings = build_stage(stage, model, density=density, collision=collision)
    full = stage.GetRootLayer()
    root = stage.GetDefaultPrim()
    name = root.GetName()
    payload_dir = tmp / f"{path.stem}_Payload"
    payload_dir.mkdir()

    def new_layer(file: Path):
        """A layer with the stage's units, up axis and default prim."""
        layer = Sdf.Layer.CreateNew(str(file))
        layer.defaultPrim = name
        for key in ("metersPerUnit", "upAxis", "kilogramsPerUnit"):
            if full.pseudoRoot.HasInfo(key):
                layer.pseudoRoot.SetInfo(key, full.pseudoRoot.GetInfo(key))
        return layer

    # geometry as crate: large arrays load fast (the asset validator asks for it too)
    layers = {k: new_layer(payload_dir / f"{k}.{ext}")
              for k, ext in (("Geometry", "usdc"), ("Materials", "usda"), ("Physics", "usda"))}
    # Geometry gets everything, then physics and colours are moved out to their own layers
    Sdf.CopySpec(full, Sdf.Path.absoluteRootPath, layers["Geometry"], Sdf.Path.absoluteRootPath)
    geo = layers["Geometry"]
    for prim in list(stage.Traverse()):
        p = prim.GetPath()
        spec = geo.GetPrimAtPath(p)
        if spec is None:
            continue
        if "/joints" in str(p):
            continue
        schemas = list(prim.GetAppliedSchemas())
        phys = [s for s in schemas if s.startswith("Physics") or s.startswith("Newton")]
        if phys:
            ps = Sdf.CreatePrimInLayer(layers["Physics"], p)
            ps.specifier = Sdf.SpecifierOver
            ps.SetInfo("apiSchemas", Sdf.TokenListOp.Create(prependedItems=phys))
            spec.SetInfo("apiSchemas", Sdf.TokenListOp.Create(prependedItems=[s for s in schemas if s not in phys]))
        for attr in list(spec.attributes):
            target = ("Physics" if attr.name.startswith(PHYSICS_PREFIXES)
                      else "Materials" if attr.name == "primvars:displayColor" else None)
            if target:
                _ensure_over(layers[target], p)
                Sdf.CopySpec(geo, attr.path, layers[target], attr.path)
                spec.RemoveProperty(attr)
        for rel in list(spec.relationships):
            if rel.name.startswith(PHYSICS_PREFIXES):
                spec.RemoveProperty(rel)
    joints = geo.GetPrimAtPath(f"/{name}/joints")
    if joints is not None:
        Sdf.CopySpec(geo, joints.path, layers["Physics"], joints.path)
        del geo.GetPrimAtPath(f"/{name}").nameChildren["joints"]
    for layer in layers.values():
        layer.Save()
    contents = new_layer(payload_dir / "Contents.usda")
    contents.subLayerPaths = ["./Physics.usda", "./Materials.usda", "./Geometry.usdc"]
    contents.Save()
    iface = new_layer(tmp / f"{path.stem}.usda")
    spec = Sdf.CreatePrimInLayer(iface, f"/{name}")
    spec.specifier = Sdf.SpecifierDef
    spec.typeName = "Xform"
    spec.SetInfo("kind", "component")
    spec.SetInfo("displayName", root.GetDisplayName())
    spec.SetInfo("customData", root.GetCustomData())
    spec.SetInfo("payload", Sdf.PayloadListOp.Create(
        prependedItems=[Sdf.Payload(f"./{path.stem}_Payload/Contents.usda")]))
    iface.Save()
    if path.suffix.lower() in (".usdc", ".usd"):  # .usdz is packaged from the .usda by the caller
        Sdf.Layer.FindOrOpen(str(tmp / f"{path.stem}.usda")).Export(str(tmp / path.name))
    return warnings


def _ensure_over(layer, path) -> None:
    """An ``over`` for ``path`` in ``layer`` (parents too), unless a spec is already there."""
    if layer.GetPrimAtPath(path) is None:
        spec = Sdf.CreatePrimInLayer(layer, path)
        spec.specifier = Sdf.SpecifierOver
