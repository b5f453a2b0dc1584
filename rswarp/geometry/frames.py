"""Link frames as every export and the mass model share them: world-aligned at the zero position
(like rswarp's kinematics), each moving link's origin on its joint's axis; and each link's pose at
a set of joint values along the tree (passive joints at zero), from the link graph alone."""

from __future__ import annotations

import numpy as np

from ..rsxml.model import Mechanism


def link_origins(mech: Mechanism) -> dict[str, np.ndarray]:
    """A frame origin per link (world, zero position), asked of the link graph.

    The base sits at the world origin. A moving link's origin is on its joint's axis, at the point
    nearest to where the link leads (its first joint's axis point, else its first flange), so
    frames sit near their geometry whatever point the file happened to give on the axis."""
    graph = mech.graph
    flanges: dict[str, np.ndarray] = {}
    for f in mech.flanges:
        flanges.setdefault(f.link, f.pose.matrix()[:3, 3])
    out = {graph.base: np.zeros(3)} if graph.base in graph.index else {}
    for k, j in graph.tree_order:
        link = graph.links[k]
        p, a = np.asarray(j.point1, float), np.asarray(j.axis, float)
        leads = graph.joints_from(link)
        target = np.asarray(leads[0].point1, float) if leads else flanges.get(link)
        out[link] = p if target is None else p + a * float(np.dot(target - p, a))
    return out


def link_poses(mech: Mechanism, q: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """World pose (4x4) of each reached link at joint values ``q`` (SI, default home); passive
    joints stay at zero. Link frames are the world frame at the zero position, so each tree joint
    is a rotation about (or a slide along) its world axis composed onto its parent's pose."""
    from scipy.spatial.transform import Rotation

    graph = mech.graph
    q = mech.home_position() if q is None else np.asarray(q, float)
    poses = {graph.base: np.eye(4)} if graph.base in graph.index else {}
    for k, j in graph.tree_order:
        col = graph.column(j.name)
        value = float(q[col]) if col >= 0 else 0.0
        m = np.eye(4)
        if j.revolute:
            m[:3, :3] = Rotation.from_rotvec(j.axis * value).as_matrix()
            m[:3, 3] = np.asarray(j.point1, float) - m[:3, :3] @ np.asarray(j.point1, float)
        else:
            m[:3, 3] = j.axis * value
        poses[graph.links[k]] = poses[graph.links[graph.parent[k]]] @ m
    return poses
