"""Add a mechanism to a ``newton.ModelBuilder``: a body per link, its joints with limits, and the
home position as the initial joint state, so ``builder.replicate(...)`` gives parallel worlds.

Every body frame is the world frame at the zero position (as in rswarp's kinematics), and each
joint's anchor frames sit on its axis, so Newton's poses equal rswarp's link poses.
"""

from __future__ import annotations

import numpy as np

from ..geometry.inertia import BodyPhysics
from ..rsxml.model import Mechanism
from ..transforms import matrix_quat
from .frames import home_passive
from .physics import JointPhysics, PhysicsOptions, RobotPhysics, robot_physics


def to_newton(mech: Mechanism, builder=None, *, base_pose: np.ndarray | None = None, shapes: bool = True,
              physics: PhysicsOptions | RobotPhysics | None = None, **options):
    """Add ``mech`` to ``builder`` (a new ``newton.ModelBuilder`` when None) and return the builder.

    The base link is fixed to the world at ``base_pose`` (4x4, default identity). Bodies are
    labelled with link names, joints with joint names; one articulation holds them all. Active
    joints get rswarp's drive gains (position mode, target home), limit spring, armature and
    effort/velocity limits (``physics``, or its fields as keywords). With ``shapes``, each part's
    convex collision pieces become shapes of its body and the bodies get the links' masses; link
    pairs joined by a joint or touching at home do not collide. Flanges become sites. A loop's
    closing joint joins its bodies outside the articulation (Newton's solvers keep it closed as a
    constraint); its passive joints start where the loop closes at home.
    """
    import newton

    if not isinstance(physics, RobotPhysics):
        physics = robot_physics(mech, physics or PhysicsOptions(**options), geometry=shapes)
    if builder is None:
        builder = newton.ModelBuilder()
    graph = mech.graph
    base = _transform(np.eye(4) if base_pose is None else np.asarray(base_pose, float))
    body = {k: _add_body(builder, base, link, physics.bodies.get(link)) for k, link in enumerate(mech.link_names)}
    root = graph.index[graph.base]
    joints = [builder.add_joint_fixed(-1, body[root], parent_xform=base, label=f"{graph.base}_fixed")]
    home = mech.home_position()
    passive = home_passive(mech)
    for k, j in graph.depth_first:  # parents before children, as eval_fk needs; depth first, as MuJoCo
        joints.append(_add_joint(builder, graph, body, k, j, home, mech.limit(j.name), physics.joints.get(j.name)))
        if k in passive:  # a loop's passive joint starts where the loop closes at home
            builder.joint_q[builder.joint_q_start[joints[-1]]] = passive[k]
    builder.add_articulation(joints, label=mech.name)
    for j in graph.closing:  # a loop closes outside the articulation (the USD export's excludeFromArticulation)
        _add_closing(builder, graph, body, j)
    for fl in mech.flanges:  # flanges as sites: frames on their bodies (bodies are world-aligned at zero)
        builder.add_site(body[graph.index[fl.link]], label=fl.name, xform=_transform(fl.pose.matrix()))
    if shapes:
        _add_shapes(mech, builder, body, physics)
    return builder


def _add_body(builder, base, link: str, bp: BodyPhysics | None) -> int:
    """A body with the link's mass properties (its frame is the world frame at zero)."""
    import warp as wp

    if bp is None or not bp.mass > 0:
        return builder.add_link(xform=base, label=link)
    com = bp.origin + bp.com
    return builder.add_link(xform=base, label=link, mass=float(bp.mass), com=wp.vec3(*com),
                            inertia=wp.mat33(*np.asarray(bp.inertia, float).ravel()))


def _transform(m: np.ndarray):
    """A 4x4 rigid transform as a Warp transform."""
    import warp as wp

    w, x, y, z = matrix_quat(m[:3, :3])
    return wp.transform(wp.vec3(*m[:3, 3]), wp.quat(x, y, z, w))


def _add_joint(builder, graph, body: dict[int, int], k: int, j, home: np.ndarray, limit,
               jp: JointPhysics | None) -> int:
    """Link k's tree joint: anchors on the axis; an active joint's limits, dynamics and home."""
    import newton
    import warp as wp

    anchor = wp.transform(wp.vec3(*j.point1), wp.quat_identity())
    kwargs = dict(parent_xform=anchor, child_xform=anchor, axis=wp.vec3(*j.axis), label=j.name)
    col = graph.column(j.name)
    if col >= 0 and limit is not None:
        kwargs.update(limit_lower=float(limit.min), limit_upper=float(limit.max))
    if col >= 0 and jp is not None:
        mode = newton.JointTargetMode.POSITION if jp.stiffness > 0 else newton.JointTargetMode.NONE
        kwargs.update(target_q=float(home[col]), target_ke=jp.stiffness, target_kd=jp.damping, actuator_mode=mode,
                      limit_ke=jp.limit_stiffness, limit_kd=jp.limit_damping, armature=jp.armature,
                      effort_limit=jp.effort, velocity_limit=jp.velocity)
    add = builder.add_joint_revolute if j.revolute else builder.add_joint_prismatic
    index = add(body[graph.parent[k]], body[k], **kwargs)
    if col >= 0:
        builder.joint_q[builder.joint_q_start[index]] = float(home[col])
    return index


def _add_closing(builder, graph, body: dict[int, int], j) -> int:
    """A loop's closing joint between its two bodies, anchored on its axis (frames are world at zero)."""
    import warp as wp

    anchor = wp.transform(wp.vec3(*j.point1), wp.quat_identity())
    add = builder.add_joint_revolute if j.revolute else builder.add_joint_prismatic
    return add(body[graph.index[j.parent]], body[graph.index[j.child]], parent_xform=anchor, child_xform=anchor,
               axis=wp.vec3(*j.axis), label=j.name)


def _add_shapes(mech: Mechanism, builder, body: dict[int, int], physics: RobotPhysics) -> None:
    """Each part's convex pieces (world at zero position = its body's frame) as convex-hull shapes
    of no density (the body has its mass), then the filtered pairs."""
    import newton

    shapes: dict[str, list[int]] = {}
    cfg = newton.ModelBuilder.ShapeConfig(density=0.0)
    for k, link in enumerate(mech.link_names):
        bp = physics.bodies.get(link)
        for part in bp.parts if bp is not None else ():
            for i, piece in enumerate(part.pieces):
                nm = newton.Mesh(np.asarray(piece.vertices, np.float32), np.asarray(piece.faces, np.int32).ravel())
                label = f"{link}/{part.name}" if len(part.pieces) == 1 else f"{link}/{part.name}/{i}"
                shapes.setdefault(link, []).append(
                    builder.add_shape_convex_hull(body[k], mesh=nm, cfg=cfg, label=label))
    for a, b, _ in physics.filtered:
        for sa in shapes.get(a, ()):
            for sb in shapes.get(b, ()):
                builder.add_shape_collision_filter_pair(sa, sb)


def newton_q_columns(mech: Mechanism) -> np.ndarray:
    """For each of Newton's joint coordinates of one world, the column of rswarp's q (-1: none;
    closing joints come last)."""
    graph = mech.graph
    return np.array([graph.column(j.name) for _, j in graph.depth_first] + [-1] * len(graph.closing), np.int64)
