"""Add a mechanism to a ``newton.ModelBuilder``: a body per link, its joints with limits, and the
home position as the initial joint state, so ``builder.replicate(...)`` gives parallel worlds.

Every body frame is the world frame at the zero position (as in rswarp's kinematics), and each
joint's anchor frames sit on its axis, so Newton's poses equal rswarp's link poses.
"""

from __future__ import annotations

import numpy as np

from .compile import PRISMATIC, REVOLUTE, compile_tree
from .model import Mechanism


def to_newton(mech: Mechanism, builder=None, *, base_pose: np.ndarray | None = None, shapes: bool = True,
              density: float | None = None):
    """Add ``mech`` to ``builder`` (a new ``newton.ModelBuilder`` when None) and return the builder.

    The base link is fixed to the world at ``base_pose`` (4x4, default identity). Bodies are
    labelled with link names, joints with joint names; one articulation holds them all. With
    ``shapes``, each Part's mesh becomes a collision shape of its body (convex hull, ``density``
    in kg/m^3 gives the masses); parts without a mesh file are skipped. Flanges become sites.
    """
    import newton
    import warp as wp

    tree = compile_tree(mech)
    if builder is None:
        builder = newton.ModelBuilder()
    home = mech.home_position()
    body = {}
    joints = []
    base = np.eye(4) if base_pose is None else np.asarray(base_pose, float)
    base_xf = wp.transform(wp.vec3(*base[:3, 3]), wp.quat_from_matrix(wp.mat33(*base[:3, :3].flatten())))
    for link in mech.link_names:  # bodies in the file's order, like Kinematics.fk's links
        body[tree.index(link)] = builder.add_link(xform=base_xf, label=link)
    for k, link in enumerate(tree.links):  # joints parent before child, as eval_fk needs
        if tree.parent[k] < 0:
            joints.append(builder.add_joint_fixed(-1, body[k], parent_xform=base_xf, label=f"{link}_fixed"))
            continue
        anchor = wp.transform(wp.vec3(*tree.point[k]), wp.quat_identity())
        kwargs = dict(parent_xform=anchor, child_xform=anchor, axis=wp.vec3(*tree.axis[k]), label=tree.joint[k])
        qi = tree.qidx[k]
        if qi >= 0 and np.isfinite(tree.lower[qi]):
            kwargs.update(limit_lower=float(tree.lower[qi]), limit_upper=float(tree.upper[qi]))
        if tree.jtype[k] == REVOLUTE:
            j = builder.add_joint_revolute(body[tree.parent[k]], body[k], **kwargs)
        elif tree.jtype[k] == PRISMATIC:
            j = builder.add_joint_prismatic(body[tree.parent[k]], body[k], **kwargs)
        joints.append(j)
        if qi >= 0:
            builder.joint_q[builder.joint_q_start[j]] = float(home[qi])
    builder.add_articulation(joints, label=mech.name)
    for fl in mech.flanges:  # flanges as sites: frames on their bodies (bodies are world-aligned at zero)
        m = fl.pose.matrix()
        builder.add_site(body[tree.index(fl.link)], label=fl.name, xform=wp.transform(
            wp.vec3(*m[:3, 3]), wp.quat_from_matrix(wp.mat33(*m[:3, :3].flatten()))))
    if shapes:
        _add_shapes(mech, tree, builder, body, density)
    return builder


def _add_shapes(mech: Mechanism, tree, builder, body: dict[int, int], density: float) -> None:
    """Each part's mesh (world at zero position = its body's frame) as a convex-hull shape."""
    import newton

    from .errors import MeshNotFoundError
    from .geometry import DEFAULT_DENSITY, part_mesh

    for k, link in enumerate(tree.links):
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
    tree = compile_tree(mech)
    return np.array([tree.qidx[k] for k in range(len(tree.links)) if tree.parent[k] >= 0], np.int64)
