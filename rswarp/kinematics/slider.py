"""Balance cylinders (slider loops) solved in closed form: a cylinder pivots on the loop's common
ancestor, its piston slides along it and is pinned to an arm that one active joint turns. The pin
follows the arm, so the cylinder's angle and the piston's stroke follow from the triangle of
pivot, arm joint and pin (the law of cosines), for every configuration, on the one branch there is.
"""

from __future__ import annotations

import numpy as np

from ..kernels.specs import ANGLE, SPEC, STROKE
from ..rsxml.model import Joint

# a spec: [kind (ANGLE or STROKE), sign, O (2), A0 (2), P (2)], the plane coordinates of the arm
# joint, the pin at zero and the pivot; zeros to SPEC


def slider_specs(graph, loop, ancestor: int, normal: np.ndarray,
                 basis: tuple[np.ndarray, np.ndarray]) -> dict[int, tuple[np.ndarray, dict[int, float]]] | None:
    """For the pivot's and the piston's links: (spec, the arm angle's coefficients by q column);
    None when the loop is not arranged as a cylinder pinned to an arm turned by one active joint.
    ``basis``: the plane's (u, v) (``loops.plane_basis``)."""
    pivot, stroke, closing = _parts(graph, loop, ancestor)
    if pivot is None:
        return None
    arm = graph.index[closing.parent] if graph.index[closing.child] == graph.index[stroke.child] \
        else graph.index[closing.child]
    if graph.parent[arm] != ancestor or not graph.tree_joint[arm].active or not graph.tree_joint[arm].revolute:
        return None
    joint = graph.tree_joint[arm]
    u, v = basis
    flat = lambda p: [float(np.dot(p, u)), float(np.dot(p, v))]  # noqa: E731
    d0 = np.subtract(closing.point1, pivot.point1)
    if np.linalg.norm(np.cross(d0, stroke.axis)) > 1e-6 * np.linalg.norm(d0):
        return None  # the piston must slide along the line from pivot to pin
    geometry = flat(joint.point1) + flat(closing.point1) + flat(pivot.point1)
    coef = {graph.column(joint.name): float(np.sign(np.dot(joint.axis, normal)))}
    spec = lambda kind, sign: np.pad([kind, sign, *geometry], (0, SPEC - 8))  # noqa: E731
    return {graph.index[pivot.child]: (spec(ANGLE, np.sign(np.dot(pivot.axis, normal))), coef),
            graph.index[stroke.child]: (spec(STROKE, np.sign(np.dot(stroke.axis, d0))), coef)}


def _parts(graph, loop, ancestor: int) -> tuple[Joint | None, Joint | None, Joint]:
    """(pivot, stroke, closing): a passive revolute on the ancestor, the passive prismatic after it,
    and the closing joint at the pin; (None, None, closing) for any other arrangement."""
    closing = loop.closing
    stroke = [j for j in loop.joints[:-1] if not j.revolute]
    if len(stroke) != 1 or stroke[0].active or not closing.revolute:
        return None, None, closing
    pivot = graph.tree_joint[graph.index[stroke[0].parent]]
    if pivot is None or pivot.active or not pivot.revolute or graph.index[pivot.parent] != ancestor:
        return None, None, closing
    if graph.index[stroke[0].child] not in (graph.index[closing.parent], graph.index[closing.child]):
        return None, None, closing
    return pivot, stroke[0], closing


def slider_values(spec: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """The pivot's angle or the stroke (by ``spec``) for arm angles ``theta`` (host side, float64;
    ``rswarp.kernels.closed_forms.slider_function`` is the device twin)."""
    kind, sign, o, a0, p = spec[0], spec[1], spec[2:4], spec[4:6], spec[6:8]
    c, s = np.cos(theta), np.sin(theta)
    r = a0 - o
    a = np.stack([o[0] + c * r[0] - s * r[1], o[1] + s * r[0] + c * r[1]], axis=-1)
    d0, d = a0 - p, a - p
    if kind == ANGLE:
        return sign * np.arctan2(d0[0] * d[..., 1] - d0[1] * d[..., 0], d @ d0)
    return sign * (np.linalg.norm(d, axis=-1) - np.linalg.norm(d0))
