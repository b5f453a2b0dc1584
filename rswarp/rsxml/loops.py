"""The kinematic loops of a mechanism (parallel rods, parallelograms, balance cylinders) and the
kind of each, asked of the link graph at the zero position, which the spec defines as assembled.

A loop is a closing joint and the tree paths from its two links to their common ancestor
(``LinkGraph.loop``). Planar loops (revolute axes all parallel, prismatic axes across them) are
described by their corners: the joints at one point of the plane (coaxial joints, such as J2 and
J3 of a palletizer on one shaft, share a corner). Four revolute corners whose opposite sides are
equal make a parallelogram; other four-corner revolute loops are four-bars; planar loops with a
prismatic joint are sliders (a balance cylinder); anything else is general.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import Joint

PARALLELOGRAM, FOUR_BAR, SLIDER, GENERAL = "parallelogram", "four-bar", "slider", "general"
TOLERANCE = 1e-6  # relative: parallel axes, coincident corners, equal sides


@dataclass(frozen=True)
class Loop:
    """One loop: its joints in loop order (the closing joint last), its kind, and for planar loops
    the joint names at each corner, in loop order."""

    closing: Joint
    joints: tuple[Joint, ...]
    kind: str
    corners: tuple[tuple[str, ...], ...] = ()

    @property
    def passive(self) -> tuple[Joint, ...]:
        return tuple(j for j in self.joints if not j.active)

    @property
    def active(self) -> tuple[Joint, ...]:
        return tuple(j for j in self.joints if j.active)

    def as_dict(self) -> dict:
        return {"closing": self.closing.name, "kind": self.kind, "joints": [j.name for j in self.joints],
                "passive": [j.name for j in self.passive], "corners": [list(c) for c in self.corners]}


def loops(graph, first: int | None = None) -> tuple[Loop, ...]:
    """The loops of a link graph (the ``first`` ones only, when given), in the order of its closing
    joints. Each costs a walk of its own length: a file with many long loops is asked for a few."""
    out = []
    for closing in graph.closing[:first]:
        joints = graph.loop(closing)
        kind, corners = classify(joints)
        out.append(Loop(closing, joints, kind, corners))
    return tuple(out)


def classify(joints: tuple[Joint, ...]) -> tuple[str, tuple[tuple[str, ...], ...]]:
    """The loop's kind and, for a planar loop, its corners."""
    normal = _plane_normal(joints)
    if normal is None:
        return GENERAL, ()
    corners, points = _corners(joints, normal)
    if any(not j.revolute for j in joints):
        return SLIDER, corners
    if len(corners) == 4 and _parallelogram(points):
        return PARALLELOGRAM, corners
    if len(corners) == 4:
        return FOUR_BAR, corners
    return GENERAL, corners


def _plane_normal(joints: tuple[Joint, ...]) -> np.ndarray | None:
    """The common direction of the revolute axes, if the loop is planar (prismatic axes across it)."""
    revolute = [j.axis for j in joints if j.revolute]
    if not revolute:
        return None
    n = revolute[0]
    if any(np.linalg.norm(np.cross(n, a)) > TOLERANCE for a in revolute[1:]):
        return None
    if any(abs(float(np.dot(n, j.axis))) > TOLERANCE for j in joints if not j.revolute):
        return None
    return n


def _corners(joints: tuple[Joint, ...], normal: np.ndarray) -> tuple[tuple[tuple[str, ...], ...], list[np.ndarray]]:
    """Revolute joints projected on the loop's plane, coaxial neighbours merged (also across the
    loop's ends); prismatic joints are no corner."""
    u = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    flat = [(j.name, np.array([np.dot(j.point1, u), np.dot(j.point1, v)])) for j in joints if j.revolute]
    scale = max((np.linalg.norm(p) for _, p in flat), default=1.0) or 1.0
    names: list[list[str]] = []
    points: list[np.ndarray] = []
    for name, p in flat:
        if points and np.linalg.norm(p - points[-1]) <= TOLERANCE * scale:
            names[-1].append(name)
        else:
            names.append([name])
            points.append(p)
    if len(points) > 1 and np.linalg.norm(points[0] - points[-1]) <= TOLERANCE * scale:
        names[0] = names.pop() + names[0]
        points.pop()
    return tuple(tuple(n) for n in names), points


def _parallelogram(points: list[np.ndarray]) -> bool:
    """Opposite sides equal and the quadrilateral not crossed (a crossed one is an
    anti-parallelogram, a four-bar on its other branch)."""
    sides = [np.linalg.norm(points[(i + 1) % 4] - points[i]) for i in range(4)]
    scale = max(sides)
    if scale <= 0 or min(sides) <= TOLERANCE * scale:
        return False
    equal = abs(sides[0] - sides[2]) <= TOLERANCE * scale and abs(sides[1] - sides[3]) <= TOLERANCE * scale
    diagonal_a, diagonal_b = points[2] - points[0], points[3] - points[1]
    return equal and np.allclose(points[0] + diagonal_a / 2, points[1] + diagonal_b / 2, atol=TOLERANCE * scale)
