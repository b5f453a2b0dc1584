"""Planar four-bars solved in closed form: one active joint sets the angle at its corner, which
fixes the diagonal across it; the opposite corner then lies on two circles, on the side it lies at
the zero position (the spec's assembled pose), so the solution never jumps to the other branch.
Beyond a dead point the circles do not meet: the passive joints are NaN, never a wrong pose.

Corners V0..V3 run in loop order from the driven corner V0; side Sk joins Vk and Vk+1. Every
angle is measured against S3, which the solution holds still: a joint's value only depends on the
difference of its two sides' turns, so which side is the real ground does not matter.
"""

from __future__ import annotations

import numpy as np

from ..kernels.specs import DEAD_TOLERANCE, FOUR_BAR, SPEC
from ..rsxml.model import Joint

# a spec: [FOUR_BAR, V0 (2), V1 (2), V2 (2), V3 (2), w (3)]: the corners at zero in plane
# coordinates, and the joint's value as w . (turn of S0, S1, S2), each side's turn against S3


def four_bar_specs(graph, loop, points: list[np.ndarray], sides: list[int],
                   normal: np.ndarray) -> tuple[dict[int, tuple[np.ndarray, dict[int, float]]], str | None]:
    """For each passive tree joint's link: (spec, the driven angle's coefficients by q column), and
    None; or ({}, why) when the four-bar is not one the active joints drive (one active tree joint,
    single joints at four revolute corners, a passive closing joint)."""
    tree = loop.joints[:-1]
    driven = [i for i, j in enumerate(tree) if j.active]
    if len(loop.joints) != 4 or loop.closing.active:
        return {}, "its corners are not four single revolute joints with a passive closing joint"
    if len(driven) != 1:
        return {}, (f"{len(driven)} of its joints are active: a four-bar moves with exactly one"
                    if driven else "none of its joints is active: nothing drives it")
    d = driven[0]
    corners = [points[(d + i) % 4] for i in range(4)]
    rotated = {sides[(d + i) % 4]: i for i in range(4)}  # link -> its side, counted from S0
    sign = lambda j: float(np.sign(np.dot(j.axis, normal)))  # noqa: E731  (a joint turns its child by sign * value)

    def turn_weights(j: Joint) -> np.ndarray:
        """w with w . turns = the joint's value: sign * (turn of child - turn of parent)."""
        w = np.zeros(4)
        w[rotated[graph.index[j.child]]] += sign(j)
        w[rotated[graph.index[j.parent]]] -= sign(j)
        return w[:3]

    active = tree[d]
    coef = {graph.column(active.name): float(turn_weights(active)[0])}  # theta: S0's turn against S3
    geometry = np.concatenate(corners)
    return {graph.index[j.child]: (np.pad([FOUR_BAR, *geometry, *turn_weights(j)], (0, SPEC - 12)), coef)
            for j in tree if not j.active}, None


def four_bar_values(spec: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """The passive joint's value (rad) for driven angles ``theta``, NaN past a dead point (host
    side, float64; ``rswarp.kernels.closed_forms.four_bar_function`` is the device twin)."""
    v0, v1_0, v2_0, v3 = spec[1:3], spec[3:5], spec[5:7], spec[7:9]
    w = spec[9:12]
    theta = np.asarray(theta, np.float64)
    c, s = np.cos(theta), np.sin(theta)
    r = v1_0 - v0
    v1 = np.stack([v0[0] + c * r[0] - s * r[1], v0[1] + s * r[0] + c * r[1]], axis=-1)
    l1, l2 = np.linalg.norm(v2_0 - v1_0), np.linalg.norm(v3 - v2_0)
    side = np.sign(_cross(v3 - v1_0, v2_0 - v1_0))
    d = v3 - v1
    dd = np.linalg.norm(d, axis=-1)
    a = (l1 * l1 - l2 * l2 + dd * dd) / (2 * dd)
    h2 = l1 * l1 - a * a
    h = np.sqrt(np.maximum(h2, 0.0))
    h = np.where(h2 < -DEAD_TOLERANCE * l1 * l1, np.nan, h)
    perp = np.stack([-d[..., 1], d[..., 0]], axis=-1) / dd[..., None]
    v2 = v1 + (a / dd)[..., None] * d + (side * h)[..., None] * perp
    turn1 = _angle(v2_0 - v1_0, v2 - v1)
    turn2 = _angle(v3 - v2_0, v3 - v2)
    return w[0] * theta + w[1] * turn1 + w[2] * turn2


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The signed angle that turns a onto b (counter-clockwise positive)."""
    return np.arctan2(_cross(a, b), np.sum(a * b, axis=-1))
