"""The frame convention every export shares: link frames stay world-aligned at the zero position
(like rswarp's kinematics), with each moving link's origin on its joint's axis."""

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


def tree_error(mech: Mechanism, what: str):
    """The error for a mechanism with a loop, where ``what`` needs a link tree."""
    from ..errors import model_error

    j = mech.graph.closing[0]
    return model_error(mech, f"joint '{j.name}' closes a kinematic loop: {what} needs a link tree "
                             "(parallel rods are not solved yet)", j.line)
