"""The kinematic loops of a mechanism (parallel rods, parallelograms, balance cylinders), the kind of
each, and how their passive joints follow the active ones, asked of the link graph at the zero
position, which the spec defines as assembled.

A loop is a closing joint and the tree paths from its two links to their common ancestor
(``LinkGraph.loop``). Planar loops (revolute axes all parallel, prismatic axes across them) are
described by their corners: the joints at one point of the plane (coaxial joints, such as J2 and
J3 of a palletizer on one shaft, share a corner). Four revolute corners whose opposite sides are
equal make a parallelogram; other four-corner revolute loops are four-bars; planar loops with a
prismatic joint are sliders (a balance cylinder); anything else is general.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ..errors import model_error
from ..kernels.specs import FOUR_BAR as FOUR_BAR_SPEC
from ..kernels.specs import ROW, SPEC
from ..rsxml.graph import LinkGraph
from ..rsxml.model import Joint
from .fourbar import four_bar_specs, four_bar_values
from .newton_loop import newton_loop_values, newton_rows
from .slider import slider_specs, slider_values

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
    return tuple(make_loop(graph, closing) for closing in graph.closing[:first])


def make_loop(graph, closing: Joint) -> Loop:
    """The loop a closing joint closes, with its kind."""
    joints = graph.loop(closing)
    kind, corners = classify(joints)
    return Loop(closing, joints, kind, corners)


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


def plane_basis(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors u, v in a loop's plane, (u, v, normal) right-handed: a turn about the
    normal turns plane coordinates counter-clockwise."""
    u = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    return u, np.cross(normal, u)


def _corners(joints: tuple[Joint, ...], normal: np.ndarray) -> tuple[tuple[tuple[str, ...], ...], list[np.ndarray]]:
    """Revolute joints projected on the loop's plane, coaxial neighbours merged (also across the
    loop's ends); prismatic joints are no corner."""
    u, v = plane_basis(normal)
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


class UnsolvedLoop(ValueError):
    """A loop whose passive joints rswarp cannot yet follow from the active ones (with its joint)."""

    def __init__(self, loop: Loop, why: str):
        super().__init__(why)
        self.loop = loop

    def error(self, mech, what: str):
        """The file's error at the closing joint: "joint 'X' closes a kinematic loop that ``what``:
        why"."""
        j = self.loop.closing
        return model_error(mech, f"joint '{j.name}' closes a kinematic loop that {what}: {self}", j.line)


@dataclass(frozen=True)
class PassiveMap:
    """How each link's passive tree joint follows the active joints (rows by link index):
    ``mimic[k] @ q`` (parallelograms), or a closed form ``closed_form[k]`` (a spec laid out in
    ``rswarp.kernels.specs``, kind 0 for none: balance cylinders, four-bars) of the input angle
    ``closed_input[k] @ q``, or unknown ``unknown[k]`` of the damped Newton solve of the loops in
    ``newton_rows``."""

    mimic: np.ndarray
    closed_form: np.ndarray
    closed_input: np.ndarray
    unknown: np.ndarray  # int32 (n,): the link's joint in a Newton solve's unknowns, -1 for none
    newton_rows: np.ndarray  # (rows, ROW): the loops of the Newton solve (``newton_loop``)


_PASSIVE: "weakref.WeakKeyDictionary[LinkGraph, PassiveMap | UnsolvedLoop]" = weakref.WeakKeyDictionary()


def passive_map(graph: LinkGraph) -> PassiveMap:
    """``find_passive_map`` of a graph, found once per graph and shared (nobody writes to it); the
    same ``UnsolvedLoop`` on every ask for a loop rswarp cannot solve."""
    if graph not in _PASSIVE:
        try:
            _PASSIVE[graph] = find_passive_map(graph)
        except UnsolvedLoop as exc:
            _PASSIVE[graph] = exc
    found = _PASSIVE[graph]
    if isinstance(found, UnsolvedLoop):
        raise found
    return found


def find_passive_map(graph: LinkGraph) -> PassiveMap:
    """Every passive joint of the loops, as the active joints fix it: in parallelograms a signed sum
    of active joints (opposite sides keep their angle, as they are parallel at the zero position),
    in balance cylinders and four-bars a closed form, in any other loop a damped Newton solve with
    continuation (``newton_loop``). ``UnsolvedLoop`` for a loop none of them takes, a
    passive joint two loops would set, or parallelograms whose passive joints the active ones do
    not fix."""
    dof, n = len(graph.active), len(graph.links)
    out = PassiveMap(np.zeros((n, dof)), np.zeros((n, SPEC)), np.zeros((n, dof)), np.full(n, -1, np.int32),
                     np.zeros((0, ROW)))
    rows, unknown, solved, claimed = [], {}, [], {}
    for closing in graph.closing:  # one loop at a time: the first that cannot be solved stops the walk
        loop = make_loop(graph, closing)
        solved.append(loop)
        if loop.kind == PARALLELOGRAM:
            rows += _opposite_sides(graph, loop)
            for j in loop.joints[:-1]:
                if not j.active:
                    unknown.setdefault(graph.link_index(j.child), len(unknown))
            continue
        why = _add_closed(graph, loop, out) if loop.kind in (SLIDER, FOUR_BAR) else f"its loop is {loop.kind}"
        out = _add_newton(graph, loop, out, why) if why else out
        for k in _set_by(out, loop, graph):
            if claimed.setdefault(k, loop) is not loop:
                raise UnsolvedLoop(loop, f"its passive joint '{graph.tree_joint[k].name}' is in another loop too")
    if unknown:
        if set(unknown) & set(claimed):
            loop = claimed[min(set(unknown) & set(claimed))]
            raise UnsolvedLoop(loop, "its passive joints are in a parallelogram too")
        _solve_parallelograms(graph, rows, unknown, solved, out.mimic)
    for a in vars(out).values():  # found once and shared (passive_map): nobody writes to it
        a.setflags(write=False)
    return out


def _set_by(out: PassiveMap, loop: Loop, graph) -> list[int]:
    """The links whose passive joints ``loop`` sets (closed forms and Newton solves)."""
    links = [graph.index[j.child] for j in loop.joints[:-1] if not j.active]
    return [k for k in links if out.closed_form[k, 0] != 0 or out.unknown[k] >= 0]


def _add_newton(graph, loop: Loop, out: PassiveMap, why: str) -> PassiveMap:
    """The loop as rows of a Newton solve (``newton_loop``); ``UnsolvedLoop`` saying why neither a
    closed form (``why``) nor the solve takes it."""
    first = int(out.unknown.max()) + 1
    rows, unknowns, refused = newton_rows(graph, loop, first)
    if refused:
        raise UnsolvedLoop(loop, f"{why}, and a Newton solve cannot take it: {refused}")
    rows[:, 0] = len(np.unique(out.newton_rows[:, 0]))
    unknown = out.unknown.copy()
    for k, u in unknowns.items():
        unknown[k] = u
    return PassiveMap(out.mimic, out.closed_form, out.closed_input, unknown, np.concatenate([out.newton_rows, rows]))


def _add_closed(graph, loop: Loop, out: PassiveMap) -> str | None:
    """A balance cylinder's or a four-bar's specs into ``out``; why not, where the closed form does
    not take the loop."""
    normal = _plane_normal(loop.joints)
    if loop.kind == FOUR_BAR:
        _, points = _corners(loop.joints, normal)
        specs, why = four_bar_specs(graph, loop, points, _sides(graph, loop), normal)
        if why:
            return f"its loop is a four-bar, but {why}"
    else:
        specs = slider_specs(graph, loop, graph.common_ancestor(loop.closing), normal, plane_basis(normal))
        if specs is None:
            return ("its slider is not a cylinder pivoting on the loop's base and pinned to an arm one active joint "
                    "turns")
    for k, (spec, coef) in specs.items():
        out.closed_form[k] = spec
        for col, c in coef.items():
            out.closed_input[k, col] = c
    return None


def _solve_parallelograms(graph, rows, unknown: dict, solved: list, mimic: np.ndarray) -> None:
    """The passive joints of the parallelograms from their opposite-side equations (linear)."""
    a_p, a_q = np.zeros((len(rows), len(unknown))), np.zeros((len(rows), mimic.shape[1]))
    for r, terms in enumerate(rows):
        for k, coef in terms.items():
            col = graph.column(graph.tree_joint[k].name)
            if col >= 0:
                a_q[r, col] += coef
            elif k in unknown:
                a_p[r, unknown[k]] += coef
    solution, *_ = np.linalg.lstsq(a_p, -a_q, rcond=None)
    if np.linalg.matrix_rank(a_p) < len(unknown) or not np.allclose(a_p @ solution, -a_q, atol=1e-9):
        raise UnsolvedLoop(solved[0], "the active joints do not fix its passive joints")
    for k, i in unknown.items():
        mimic[k] = np.where(np.abs(solution[i]) < 1e-12, 0.0, solution[i])


def _opposite_sides(graph, loop: Loop) -> list[dict[int, float]]:
    """Two equations of a parallelogram: each pair of opposite sides turns by the same angle about
    the loop's normal. A side's angle is the signed sum of the tree joints from the loop's common
    ancestor down to it: {link index of a tree joint: its sign}."""
    normal = _plane_normal(loop.joints)
    ancestor = graph.common_ancestor(loop.closing)
    sides = _sides(graph, loop)

    def angle(link: int) -> dict[int, float]:
        terms = {}
        while link != ancestor:
            terms[link] = float(np.sign(np.dot(graph.tree_joint[link].axis, normal)))
            link = graph.parent[link]
        return terms

    eqs = []
    for a, b in ((sides[0], sides[2]), (sides[1], sides[3])):
        eq = angle(a)
        for k, s in angle(b).items():
            eq[k] = eq.get(k, 0.0) - s
        eqs.append(eq)
    return eqs


def _sides(graph, loop: Loop) -> list[int]:
    """The links between consecutive corners of a four-corner loop, in loop order: walking the
    loop's joints, each joint's far link, kept where the next joint starts a new corner."""
    corner_of = {name: c for c, names in enumerate(loop.corners) for name in names}
    links = _walk(graph, loop)
    sides = []
    for i, (joint, link) in enumerate(links):
        nxt = links[(i + 1) % len(links)][0]
        if corner_of[joint.name] != corner_of[nxt.name]:
            sides.append(link)
    return sides


def _walk(graph, loop: Loop) -> list[tuple[Joint, int]]:
    """(joint, the link after it) around the loop, in the order of ``loop.joints``: from the closing
    joint's parent up to the common ancestor, down to its child, then across the closing joint."""
    out, link = [], graph.index[loop.closing.parent]
    for j in loop.joints:
        nxt = graph.index[j.parent] if graph.index[j.child] == link else graph.index[j.child]
        out.append((j, nxt))
        link = nxt
    return out


def passive_values(passive, q) -> dict[int, np.ndarray]:
    """Each solved passive joint's values at ``q`` (N, dof), by its link's index, float64; NaN where
    its loop cannot close. ``passive``: a ``PassiveMap``, or a ``Chain`` (the same rows)."""
    q = np.atleast_2d(np.asarray(q, np.float64))
    out = {}
    for k in np.nonzero(np.any(passive.mimic != 0, axis=1) | (passive.closed_form[:, 0] != 0))[0]:
        spec = passive.closed_form[k]
        out[int(k)] = closed_values(spec, q @ passive.closed_input[k]) if spec[0] else q @ passive.mimic[k]
    if len(passive.newton_rows):
        x = newton_loop_values(passive.newton_rows, q, int(passive.unknown.max()) + 1)
        out.update({int(k): x[:, u] for k, u in enumerate(passive.unknown) if u >= 0})
    return out


def closed_values(spec: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """A passive joint's closed form (``PassiveMap.closed_form``) at input angles ``theta``, float64."""
    return four_bar_values(spec, theta) if spec[0] == FOUR_BAR_SPEC else slider_values(spec, theta)
