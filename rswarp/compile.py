"""Compile a Mechanism into flat arrays for the kinematics kernels: links in topological order,
each with its parent, joint type, unit axis, axis point and the column of q that drives it."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from .errors import Diagnostic, RsxmlError
from .model import Mechanism

REVOLUTE, PRISMATIC, FIXED = 0, 1, 2


@dataclass(frozen=True, eq=False)
class KinematicTree:
    """Flat arrays (SI, float64) of a mechanism's link tree; row k describes link ``links[k]``."""

    links: tuple[str, ...]  # topological order, base first
    parent: np.ndarray  # int32, -1 for the base link
    jtype: np.ndarray  # int32: REVOLUTE, PRISMATIC or FIXED (the base)
    qidx: np.ndarray  # int32 column of q, -1 where no active joint drives the link
    axis: np.ndarray  # (n, 3) unit joint axis, world at zero position
    point: np.ndarray  # (n, 3) a point on the axis
    joint: tuple[str | None, ...]  # the joint that moves each link
    active: tuple[str, ...]  # active joints in q's column order
    lower: np.ndarray  # (dof,) limits in SI
    upper: np.ndarray
    closing: tuple[str, ...] = ()  # joints left out because they close a loop (allow_loops only)

    @property
    def dof(self) -> int:
        return len(self.active)

    def index(self, link: str) -> int:
        try:
            return self.links.index(link)
        except ValueError:
            raise KeyError(f"no link '{link}' (links: {', '.join(self.links)})") from None


def compile_tree(mech: Mechanism, allow_loops: bool = False) -> KinematicTree:
    """Arrays of the mechanism's link tree. A joint that closes a loop is refused with a clear
    error, or with ``allow_loops`` left out of the tree and listed in ``closing`` (active joints
    enter the tree first, so a passive joint closes each loop)."""
    file = mech.path or mech.name
    by_parent: dict[str, list] = {}
    for j in sorted(mech.joints, key=lambda j: not j.active):
        by_parent.setdefault(j.parent, []).append(j)
    order, moved_by = [mech.base_link], {mech.base_link: None}
    closing = []
    queue = deque([mech.base_link])
    while queue:
        for j in by_parent.get(queue.popleft(), []):
            if j.child in moved_by:
                if not allow_loops:
                    raise RsxmlError(Diagnostic(file, j.line, f"joint '{j.name}' closes a kinematic loop: "
                                                "kinematics, sweeps and URDF need a link tree (parallel rods are not solved yet)"))
                closing.append(j.name)
                continue
            moved_by[j.child] = j
            order.append(j.child)
            queue.append(j.child)
    active = [j.name for j in mech.active_joints]
    n = len(order)
    parent = np.full(n, -1, np.int32)
    jtype = np.full(n, FIXED, np.int32)
    qidx = np.full(n, -1, np.int32)
    axis = np.zeros((n, 3))
    point = np.zeros((n, 3))
    for k, link in enumerate(order):
        j = moved_by[link]
        if j is None:
            continue
        parent[k] = order.index(j.parent)
        jtype[k] = REVOLUTE if j.revolute else PRISMATIC
        qidx[k] = active.index(j.name) if j.active else -1
        axis[k] = j.axis
        point[k] = j.point1
    lower, upper = mech.bounds()
    return KinematicTree(links=tuple(order), parent=parent, jtype=jtype, qidx=qidx, axis=axis, point=point,
                         joint=tuple(None if moved_by[l] is None else moved_by[l].name for l in order),
                         active=tuple(active), lower=lower, upper=upper, closing=tuple(closing))


def screw64(jtype: int, axis: np.ndarray, point: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """(N, 4, 4) float64 rigid motions of one joint for N values (Rodrigues' formula)."""
    n = theta.shape[0]
    m = np.tile(np.eye(4), (n, 1, 1))
    if jtype == REVOLUTE:
        k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        s, c = np.sin(theta)[:, None, None], np.cos(theta)[:, None, None]
        r = np.eye(3) + s * k + (1 - c) * (k @ k)
        m[:, :3, :3] = r
        m[:, :3, 3] = point - r @ point
    elif jtype == PRISMATIC:
        m[:, :3, 3] = theta[:, None] * axis
    return m


def fk64(tree: KinematicTree, q: np.ndarray) -> np.ndarray:
    """(N, n_links, 4, 4) float64 link poses: the reference the float32 kernels are held to."""
    q = np.atleast_2d(np.asarray(q, dtype=np.float64))
    out = np.empty((q.shape[0], len(tree.links), 4, 4))
    for k in range(len(tree.links)):
        if tree.parent[k] < 0:
            out[:, k] = np.eye(4)
            continue
        theta = q[:, tree.qidx[k]] if tree.qidx[k] >= 0 else np.zeros(q.shape[0])
        out[:, k] = out[:, tree.parent[k]] @ screw64(tree.jtype[k], tree.axis[k], tree.point[k], theta)
    return out


def link_origins(mech: Mechanism, tree: KinematicTree | None = None) -> dict[str, np.ndarray]:
    """A frame origin per link for exports (world, zero position; frames stay world-aligned).

    The base sits at the world origin. A moving link's origin is on its joint's axis, at the point
    nearest to where the link leads (its first child joint's axis point, else its first flange), so
    frames sit near their geometry whatever point the file happened to give on the axis."""
    tree = tree or compile_tree(mech)
    leads: dict[str, np.ndarray] = {}
    for j in mech.joints:
        leads.setdefault(j.parent, np.asarray(j.point1, float))
    for f in mech.flanges:
        leads.setdefault(f.link, f.pose.matrix()[:3, 3])
    out = {}
    for k, link in enumerate(tree.links):
        if tree.parent[k] < 0:
            out[link] = np.zeros(3)
            continue
        p, a = tree.point[k], tree.axis[k]
        target = leads.get(link)
        out[link] = p if target is None else p + a * float(np.dot(target - p, a))
    return out
