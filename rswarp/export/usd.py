"""Export a mechanism to OpenUSD with UsdPhysics: what Newton, Isaac Sim and usdview open.

Metres, Z up, kilograms; the robot is the default prim and carries the articulation root. Each
link is a rigid body whose frame stays world-aligned at the zero position with its origin on its
joint's axis; joints sit on the RSXML axis with the joint X axis along it. Flanges are frames with
a Newton site, cables BasisCurves, and RSXML metadata lives in custom data under ``rsxml``.
"""

from __future__ import annotations

import newton_usd_schemas  # noqa: F401 (registers Newton's schemas, NewtonSiteAPI and others, with USD)
import numpy as np
from pxr import Gf, Kind, Sdf, Usd, UsdGeom, UsdPhysics, Vt

from ..rsxml.model import Mechanism, SmartComponent
from ..transforms import translated
from .frames import mechanism_of
from .names import PrimNames
from .physics import PhysicsOptions, RobotPhysics, robot_physics
from .usd_bodies import author_filtered_pairs, author_links
from .usd_joints import author_joints


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


def build_stage(stage, model, physics: PhysicsOptions | RobotPhysics | None = None) -> list[str]:
    """Author ``model`` (a Mechanism, or a SmartComponent holding one) into ``stage``; returns warnings."""
    mech, sc = mechanism_of(model)
    robot = physics if isinstance(physics, RobotPhysics) else robot_physics(mech, physics)
    warnings = list(robot.warnings)
    names = PrimNames(warnings)
    root = _author_root(stage, mech, sc, names)
    link_path = author_links(stage, mech, root, robot, names)
    author_filtered_pairs(stage, robot, link_path)
    author_joints(stage, mech, root, link_path, robot, names)
    _author_frames(stage, mech, root, link_path, {k: b.origin for k, b in robot.bodies.items()}, names)
    return warnings


def _author_root(stage, mech: Mechanism, sc, names: PrimNames) -> str:
    """Stage units and the robot prim: default prim, component kind, metadata, articulation root."""
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    root = UsdGeom.Xform.Define(stage, f"/{names(mech.name, what='mechanism')}")
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


def _author_frames(stage, mech: Mechanism, root: str, link_path: dict, origins: dict, names: PrimNames) -> None:
    """Flanges (frames with a Newton site), the base frame and the cables."""
    for fl in mech.flanges:
        fx = UsdGeom.Xform.Define(stage, f"{link_path[fl.link]}/{names(fl.name, what='flange')}")
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
            _cable(stage, f"{root}/cables/{names(c.name, what='cable')}", c)


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
