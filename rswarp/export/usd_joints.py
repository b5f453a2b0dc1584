"""Joints in USD: frames on the axis, limits, drives, and Newton's joint attributes (armature,
limit spring, velocity limit). USD measures revolute quantities per degree."""

from __future__ import annotations

import math

import numpy as np
from pxr import Gf, Sdf, UsdGeom, UsdPhysics

from ..rsxml.model import Mechanism
from ..transforms import quat_x_to
from .physics import JointPhysics, RobotPhysics

JOINTS = "joints"  # the scope holding every joint


def author_joints(stage, mech: Mechanism, root: str, link_path: dict, physics: RobotPhysics, names) -> None:
    """A fixed joint anchoring the base, then every joint of the graph on its axis."""
    graph = mech.graph
    joints = UsdGeom.Scope.Define(stage, f"{root}/{JOINTS}").GetPath()
    origin = {link: body.origin for link, body in physics.bodies.items()}
    fixed = UsdPhysics.FixedJoint.Define(stage, f"{joints}/{names('root_joint', what='joint')}")
    fixed.CreateBody1Rel().SetTargets([link_path[graph.base]])
    fixed.CreateLocalPos0Attr(Gf.Vec3f(*origin[graph.base]))
    fixed.CreateLocalPos1Attr(Gf.Vec3f(0, 0, 0))
    home = mech.home_position()
    passive = _passive_at_home(mech)
    closing = {id(j) for j in graph.closing}
    for j in graph.joints:
        if j.parent not in link_path or j.child not in link_path:
            continue
        # the child's origin is on its tree joint's axis; a closing joint anchors on its point1
        anchor = np.asarray(j.point1, float) if id(j) in closing else origin[j.child]
        prim = _author_joint(stage, f"{joints}/{names(j.name, what='joint')}", j, link_path, origin, anchor,
                             mech.limit(j.name), id(j) in closing)
        col = graph.column(j.name)
        if j.name in passive:  # a loop's passive joint starts where the loop closes at home
            _author_state(prim, j.revolute, passive[j.name])
        if col >= 0:
            _author_state(prim, j.revolute, float(home[col]))
            if j.name in physics.joints:
                _author_dynamics(prim, j.revolute, physics.joints[j.name], float(home[col]))


def _author_joint(stage, path: str, j, link_path: dict, origin: dict, anchor: np.ndarray, lim, closing: bool):
    """One revolute or prismatic joint: frames on the axis (joint X along it), limits."""
    uj = (UsdPhysics.RevoluteJoint if j.revolute else UsdPhysics.PrismaticJoint).Define(stage, path)
    prim = uj.GetPrim()
    prim.SetDisplayName(j.name)
    rot = Gf.Quatf(*quat_x_to(j.axis))
    uj.CreateBody0Rel().SetTargets([link_path[j.parent]])
    uj.CreateBody1Rel().SetTargets([link_path[j.child]])
    uj.CreateLocalPos0Attr(Gf.Vec3f(*(anchor - origin[j.parent])))
    uj.CreateLocalRot0Attr(rot)
    uj.CreateLocalPos1Attr(Gf.Vec3f(*(anchor - origin[j.child])))
    uj.CreateLocalRot1Attr(rot)
    uj.CreateAxisAttr(UsdPhysics.Tokens.x)
    scale = _per_unit(j.revolute)
    if lim is not None:
        uj.CreateLowerLimitAttr(float(lim.min * scale))
        uj.CreateUpperLimitAttr(float(lim.max * scale))
    if closing:
        uj.CreateExcludeFromArticulationAttr(True)
    prim.SetCustomDataByKey("rsxml", {"active": j.active, "point1": Gf.Vec3d(*j.point1), "point2": Gf.Vec3d(*j.point2)})
    return prim


def _per_unit(revolute: bool) -> float:
    """USD units per SI unit of a joint coordinate: degrees per radian, or 1 for metres."""
    return 180.0 / math.pi if revolute else 1.0


def _passive_at_home(mech: Mechanism) -> dict[str, float]:
    """The loops' passive joints at home, by name; none where rswarp cannot solve a loop (the
    stage then holds the loop as the file gives it, its passive joints at zero)."""
    from ..errors import RsxmlError
    from .frames import home_passive

    try:
        return {mech.graph.tree_joint[k].name: v for k, v in home_passive(mech).items()}
    except RsxmlError:
        return {}


def _author_state(prim, revolute: bool, home: float) -> None:
    """The initial joint state: PhysX/Isaac Sim's JointStateAPI attribute and Newton's."""
    kind = "angular" if revolute else "linear"
    for attr in (f"state:{kind}:physics:position", f"newton:{kind}:position"):
        prim.CreateAttribute(attr, Sdf.ValueTypeNames.Float, custom=False).Set(float(home * _per_unit(revolute)))


def _author_dynamics(prim, revolute: bool, jp: JointPhysics, home: float) -> None:
    """The position drive holding home (UsdPhysics.DriveAPI) and Newton's joint attributes."""
    per = _per_unit(revolute)  # gains per degree: divide the SI (per radian) values by it
    if jp.stiffness > 0 or jp.damping > 0:
        drive = UsdPhysics.DriveAPI.Apply(prim, "angular" if revolute else "linear")
        drive.CreateTypeAttr(UsdPhysics.Tokens.force)
        drive.CreateTargetPositionAttr(float(home * per))
        drive.CreateTargetVelocityAttr(0.0)
        drive.CreateStiffnessAttr(float(jp.stiffness / per))
        drive.CreateDampingAttr(float(jp.damping / per))
        drive.CreateMaxForceAttr(float(jp.effort))
    prim.ApplyAPI("NewtonJointAPI")
    prim.CreateAttribute("newton:armature", Sdf.ValueTypeNames.Float, custom=False).Set(float(jp.armature))
    prim.CreateAttribute("newton:limitStiffness", Sdf.ValueTypeNames.Float, custom=False).Set(
        float(jp.limit_stiffness / per))
    prim.CreateAttribute("newton:limitDamping", Sdf.ValueTypeNames.Float, custom=False).Set(
        float(jp.limit_damping / per))
    prim.CreateAttribute("newton:velocityLimit", Sdf.ValueTypeNames.Float, custom=False).Set(float(jp.velocity * per))
