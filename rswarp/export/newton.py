"""Add a mechanism to a ``newton.ModelBuilder``: a body per link, its joints with limits, and the
home position as the initial joint state, so ``builder.replicate(...)`` gives parallel worlds.

Every body frame is the world frame at the zero position (as in rswarp's kinematics), and each
joint's anchor frames sit on its axis, so Newton's poses equal rswarp's link poses.
"""

from __future__ import annotations

import numpy as np

from ..rsxml.model import Mechanism
from ..transforms import matrix_quat
from .frames import tree_error


def to_newton(mech: Mechanism, builder=None, *, base_pose: np.ndarray | None = None, shapes: bool = True,
              density: float | None = None):
    """Add ``mech`` to ``builder`` (a new ``newton.ModelBuilder`` when None) and return the builder.

    The base link is fixed to the world at ``base_pose`` (4x4, default identity). Bodies are
    labelled with link names, joints with joint names; one articulation holds them all. With
    ``shapes``, each Part's mesh becomes a collision shape of its body (convex hull, ``density``
    in kg/m^3 gives the masses); parts without a mesh file are skipped. Flanges become sites.
    """
    import newton

    if mech.graph.closing:
        raise tree_error(mech, "a Newton model")
    if builder is None:
        builder = newton.ModelBuilder()
    graph = mech.graph
    base = _transform(np.eye(4) if base_pose is None else np.asarray(base_pose, float))
    body = {k: builder.add_link(xform=base, label=link) for k, link in enumerate(mech.link_names)}  # file order
    root = graph.index[graph.base]
    joints = [builder.add_joint_fixed(-1, body[root], parent_xform=base, label=f"{graph.base}_fixed")]
    home = mech.home_position()
    for k, j in graph.tree_order:  # joints parent before child, as eval_fk needs
        joints.append(_add_joint(builder, graph, body, k, j, home, mech.limit(j.name)))
    builder.add_articulation(joints, label=mech.name)
    for fl in mech.flanges:  # flanges as sites: frames on their bodies (bodies are world-aligned at zero)
        builder.add_site(body[graph.index[fl.link]], label=fl.name, xform=_transform(fl.pose.matrix()))
    if shapes:
        _add_shapes(mech, builder, body, density)
    return builder


def _transform(m: np.ndarray):
    """A 4x4 rigid transform as a Warp transform."""
    import warp as wp

    w, x, y, z = matrix_quat(m[:3, :3])
    return wp.transform(wp.vec3(*m[:3, 3]), wp.quat(x, y, z, w))


def _add_joint(builder, graph, body: dict[int, int], k: int, j, home: np.ndarray, limit) -> int:
    """Link k's tree joint: anchors on the axis, limits and the home value of an active joint."""
    import warp as wp

    anchor = wp.transform(wp.vec3(*j.point1), wp.quat_identity())
    kwargs = dict(parent_xform=anchor, child_xform=anchor, axis=wp.vec3(*j.axis), label=j.name)
    col = graph.column(j.name)
    if col >= 0 and limit is not None:
        kwargs.update(limit_lower=float(limit.min), limit_upper=float(limit.max))
    add = builder.add_joint_revolute if j.revolute else builder.add_joint_prismatic
    index = add(body[graph.parent[k]], body[k], **kwargs)
    if col >= 0:
        builder.joint_q[builder.joint_q_start[index]] = float(home[col])
    return index


def _add_shapes(mech: Mechanism, builder, body: dict[int, int], density: float) -> None:
    """Each part's mesh (world at zero position = its body's frame) as a convex-hull shape."""
    import newton

    from ..errors import MeshNotFoundError
    from ..geometry import DEFAULT_DENSITY, part_mesh

    for k, link in enumerate(mech.link_names):
        for part, transform in mech.parts(link):
            if not part.source:
                continue
            try:
                mesh = part_mesh(mech, part, transform)
            except MeshNotFoundError:
                continue
            cfg = newton.ModelBuilder.ShapeConfig(density=DEFAULT_DENSITY if density is None else density)
            nm = newton.Mesh(np.asarray(mesh.vertices, np.float32), np.asarray(mesh.faces, np.int32).ravel())
            builder.add_shape_convex_hull(body[k], mesh=nm, cfg=cfg, label=f"{link}/{part.name}")


def newton_q_columns(mech: Mechanism) -> np.ndarray:
    """For each of Newton's joint coordinates of one world, the column of rswarp's q (-1: none)."""
    graph = mech.graph
    return np.array([graph.column(j.name) for _, j in graph.tree_order], np.int64)
