"""The frame convention every export shares: link frames stay world-aligned at the zero position
(like rswarp's kinematics), with each moving link's origin on its joint's axis."""

from __future__ import annotations

import numpy as np

from ..errors import model_error
from ..kinematics.loops import UnsolvedLoop, passive_map, passive_values
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


def mechanism_of(model):
    """The mechanism to export, and the SmartComponent around it (None if there is none)."""
    from ..rsxml.model import SmartComponent

    if isinstance(model, SmartComponent):
        mechs = [c for c in model.components if isinstance(c, Mechanism)]
        if not mechs:
            raise model_error(model, f"SmartComponent '{model.name}' holds no mechanism to export")
        return mechs[0], model
    return model, None


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


def home_passive(mech: Mechanism) -> dict[int, float]:
    """The passive joints of the loops at the home position, by link index; a loop that cannot be
    solved (unless home is the zero position), or cannot close at home, is the file's error at its
    closing joint."""
    if not mech.graph.closing:
        return {}
    home = mech.home_position()
    try:
        values = passive_values(passive_map(mech.graph), home[None])
    except UnsolvedLoop as exc:
        if not home.any():
            return {}  # the zero position is assembled (the spec): every passive joint at zero
        raise exc.error(mech, "an export cannot start closed at home") from None
    if not all(np.isfinite(v[0]) for v in values.values()):
        j = mech.graph.closing[0]
        raise model_error(mech, "the home position lies past a dead point: a loop cannot close there", j.line)
    return {k: float(v[0]) for k, v in values.items()}
