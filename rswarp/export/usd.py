"""Export a mechanism to OpenUSD with UsdPhysics: what Newton, Isaac Sim and usdview open.

Metres, Z up, kilograms; the robot is the default prim and carries the articulation root. Each
link is a rigid body whose frame stays world-aligned at the zero position with its origin on its
joint's axis; joints sit on the RSXML axis with the joint X axis along it. Flanges are frames with
a Newton site, cables BasisCurves, and RSXML metadata lives in custom data under ``rsxml``.
"""

from __future__ import annotations

import newton_usd_schemas  # noqa: F401 (registers Newton's schemas, NewtonSiteAPI and others, with USD)
import numpy as np
from pxr import Gf, Kind, Sdf, Tf, Usd, UsdGeom, UsdPhysics, Vt

from ..errors import InputError, MeshNotFoundError, model_error
from ..geometry import DEFAULT_DENSITY, mass_properties, part_mesh
from ..rsxml.model import Mechanism, SmartComponent
from ..transforms import matrix_quat, quat_x_to, translated
from .frames import link_origins

GRAPHITE_WHITE = (215 / 255, 215 / 255, 215 / 255)
APPROXIMATIONS = ("convexHull", "convexDecomposition")


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
    mech, sc = _mechanism_of(model)
    if collision not in APPROXIMATIONS:
        raise InputError(f"collision must be one of {', '.join(APPROXIMATIONS)}")
    warnings: list[str] = []
    origins = link_origins(mech)
    names = _Names()
    root = _author_root(stage, mech, sc, names)
    link_path = _author_links(stage, mech, root, origins, names, density, collision, warnings)
    _author_joints(stage, mech, root, link_path, origins, names)
    _author_frames(stage, mech, root, link_path, origins, names)
    return warnings


def _mechanism_of(model) -> tuple[Mechanism, SmartComponent | None]:
    """The mechanism to export, and the SmartComponent around it if there is one."""
    if isinstance(model, SmartComponent):
        mechs = [c for c in model.components if isinstance(c, Mechanism)]
        if not mechs:
            raise model_error(model, f"SmartComponent '{model.name}' holds no mechanism to export")
        return mechs[0], model
    return model, None


def _author_root(stage, mech: Mechanism, sc, names: "_Names") -> str:
    """Stage units and the robot prim: default prim, component kind, metadata, articulation root."""
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    root = UsdGeom.Xform.Define(stage, f"/{names(mech.name)}")
    rp = root.GetPrim()
    stage.SetDefaultPrim(rp)
    Usd.ModelAPI(rp).SetKind(Kind.Tokens.component)
    rp.SetDisplayName(mech.name)
    rp.SetCustomDataByKey("rsxml", _metadata(mech, sc))
    # both authored: Newton's includes the UsdPhysics one, but only where Newton's schemas are
    # registered; usdview or Isaac Sim without them must still see the articulation root
    rp.AddAppliedSchema("PhysicsArticulationRootAPI")
    rp.AddAppliedSchema("NewtonArticulationRootAPI")
    return str(root.GetPath())


def _author_links(stage, mech: Mechanism, root: str, origins: dict, names: "_Names", density: float,
                  collision: str, warnings: list[str]) -> dict[str, str]:
    """A rigid body per link (graph order) with visual and collision meshes and mass; their paths."""
    graph = mech.graph
    link_path: dict[str, str] = {}
    any_mesh = False
    for k in graph.order:
        link = graph.links[k]
        path = link_path[link] = f"{root}/{names(link)}"
        x = UsdGeom.Xform.Define(stage, path)
        x.GetPrim().SetDisplayName(link)
        x.AddTranslateOp().Set(Gf.Vec3d(*origins[link]))
        UsdPhysics.RigidBodyAPI.Apply(x.GetPrim())
        meshes = _link_meshes(mech, link, warnings)
        any_mesh |= bool(meshes)
        _author_parts(stage, path, meshes, origins[link], collision)
        if meshes:
            _mass(stage.GetPrimAtPath(path), [m for _, m in meshes], origins[link], density, warnings, link)
    if not any_mesh:  # one clear line instead of one per part
        warnings[:] = [f"{mech.path or mech.name}: warning: no mesh beside the file for any part (looked for "
                       "<source stem>.stl/.obj/.ply/.glb/.gltf/.off): exported kinematics only, "
                       "bodies and joints without geometry or mass"]
    return link_path


def _author_parts(stage, path: str, meshes, origin: np.ndarray, collision: str) -> None:
    """Visual meshes under ``visuals`` and guide-purpose collision meshes under ``collisions``."""
    visual_names, collision_names = _Names(), _Names()
    for part_name, mesh in meshes:
        visual = _author_mesh(stage, f"{path}/visuals/{visual_names(part_name)}", mesh, origin, _mesh_color(mesh))
        visual.GetPrim().SetDisplayName(part_name)
        col = _author_mesh(stage, f"{path}/collisions/{collision_names(part_name)}", mesh, origin, GRAPHITE_WHITE)
        col.CreatePurposeAttr(UsdGeom.Tokens.guide)
        UsdPhysics.CollisionAPI.Apply(col.GetPrim())
        UsdPhysics.MeshCollisionAPI.Apply(col.GetPrim()).CreateApproximationAttr(collision)
    for group in (f"{path}/visuals", f"{path}/collisions"):
        if stage.GetPrimAtPath(group):
            stage.GetPrimAtPath(group).SetTypeName("Scope")


def _author_joints(stage, mech: Mechanism, root: str, link_path: dict, origins: dict, names: "_Names") -> None:
    """A fixed joint anchoring the base, then every joint of the graph on its axis."""
    graph = mech.graph
    joints = UsdGeom.Scope.Define(stage, f"{root}/joints").GetPath()
    fixed = UsdPhysics.FixedJoint.Define(stage, f"{joints}/{names('root_joint')}")
    fixed.CreateBody1Rel().SetTargets([link_path[graph.base]])
    fixed.CreateLocalPos0Attr(Gf.Vec3f(*origins[graph.base]))
    fixed.CreateLocalPos1Attr(Gf.Vec3f(0, 0, 0))
    home = mech.home_position()
    closing = {id(j) for j in graph.closing}
    for j in graph.joints:
        if j.parent not in link_path or j.child not in link_path:
            continue
        # the child's origin is on its tree joint's axis; a closing joint anchors on its point1
        anchor = np.asarray(j.point1, float) if id(j) in closing else origins[j.child]
        col = graph.column(j.name)
        _author_joint(stage, f"{joints}/{names(j.name)}", j, link_path, origins, anchor, mech.limit(j.name),
                      id(j) in closing, None if col < 0 else float(home[col]))


def _author_joint(stage, path: str, j, link_path: dict, origins: dict, anchor: np.ndarray, lim,
                  closing: bool, home: float | None) -> None:
    """One revolute or prismatic joint: frames on the axis (joint X along it), limits, home."""
    uj = (UsdPhysics.RevoluteJoint if j.revolute else UsdPhysics.PrismaticJoint).Define(stage, path)
    prim = uj.GetPrim()
    prim.SetDisplayName(j.name)
    rot = Gf.Quatf(*quat_x_to(j.axis))
    uj.CreateBody0Rel().SetTargets([link_path[j.parent]])
    uj.CreateBody1Rel().SetTargets([link_path[j.child]])
    uj.CreateLocalPos0Attr(Gf.Vec3f(*(anchor - origins[j.parent])))
    uj.CreateLocalRot0Attr(rot)
    uj.CreateLocalPos1Attr(Gf.Vec3f(*(anchor - origins[j.child])))
    uj.CreateLocalRot1Attr(rot)
    uj.CreateAxisAttr(UsdPhysics.Tokens.x)
    scale = 180.0 / np.pi if j.revolute else 1.0  # UsdPhysics: revolute limits in degrees
    if lim is not None:
        uj.CreateLowerLimitAttr(float(lim.min * scale))
        uj.CreateUpperLimitAttr(float(lim.max * scale))
    if closing:
        uj.CreateExcludeFromArticulationAttr(True)
    prim.SetCustomDataByKey("rsxml", {"active": j.active, "point1": Gf.Vec3d(*j.point1), "point2": Gf.Vec3d(*j.point2)})
    if home is not None:
        kind = "angular" if j.revolute else "linear"
        # initial joint state: PhysX/Isaac Sim's JointStateAPI attribute and Newton's (both degrees/metres)
        for attr in (f"state:{kind}:physics:position", f"newton:{kind}:position"):
            prim.CreateAttribute(attr, Sdf.ValueTypeNames.Float, custom=False).Set(float(home * scale))


def _author_frames(stage, mech: Mechanism, root: str, link_path: dict, origins: dict, names: "_Names") -> None:
    """Flanges (frames with a Newton site), the base frame and the cables."""
    for fl in mech.flanges:
        fx = UsdGeom.Xform.Define(stage, f"{link_path[fl.link]}/{names(fl.name)}")
        fx.GetPrim().SetDisplayName(fl.name)
        fx.AddTransformOp().Set(_gf_matrix(fl.pose.matrix(), origins[fl.link]))
        fx.GetPrim().SetCustomDataByKey("rsxml", {"flange": True})
        site = UsdGeom.Sphere.Define(stage, f"{fx.GetPath()}/site")
        site.CreateRadiusAttr(0.005)
        site.CreateExtentAttr([Gf.Vec3f(-0.005, -0.005, -0.005), Gf.Vec3f(0.005, 0.005, 0.005)])
        site.CreatePurposeAttr(UsdGeom.Tokens.guide)
        site.GetPrim().ApplyAPI("NewtonSiteAPI")
    if mech.base_frame is not None:
        bf = UsdGeom.Xform.Define(stage, f"{root}/{names('BaseFrame')}")
        bf.AddTransformOp().Set(_gf_matrix(mech.base_frame.matrix(), np.zeros(3)))
        bf.GetPrim().SetCustomDataByKey("rsxml", {"baseFrame": True})
    if mech.cables:
        UsdGeom.Scope.Define(stage, f"{root}/cables")
        for c in mech.cables:
            _cable(stage, f"{root}/cables/{names(c.name)}", c)


def _gf_matrix(m: np.ndarray, origin: np.ndarray):
    """A 4x4 pose relative to a world-aligned frame at ``origin``, as Gf.Matrix4d (row vectors)."""
    return Gf.Matrix4d(*translated(m, origin).T.flatten().tolist())


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
    api.CreatePrincipalAxesAttr(Gf.Quatf(*matrix_quat(vectors)))
