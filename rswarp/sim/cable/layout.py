"""A mechanism's cables as one set of rigid segments for the Cosserat rod kernel
(``rswarp.kernels.rod``): every segment's rest frame, mass and inertia, the stiffness of each joint
between two segments and of each clamp, which links each segment may touch, and per cable what the
reports need (lengths, arcs, attachments).

Each cable's rest shape (``rswarp.geometry.cable``) is cut into segments; segment i is a rigid
body from point i to point i + 1, its frame's third axis along it, its first carried from segment
to segment by parallel transport, so the rest shape has no twist. The rod's natural shape is
straight: a bowed rest shape is bent, and settles. A control point with ``attachedTo`` holds its
node to the link: with ``direction`` the whole frame (a clamp: tangent along the direction and
roll), without it the point only (a ball joint). A clamp joint is half a segment of the rod."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...geometry.cable import cable_rest
from ...rsxml.model import Cable, Mechanism, iter_parts

ATTACHED_FREE = 4.0  # radii (plus a segment) of cable beside an attachment that may lie on its link
SQUASH = 1.0e-3  # a segment's own weight presses its contact in by at most this share of its radius
YOUNGS_MODULUS = 5e7  # Pa, where the file gives none: a rubber-like dress-pack hose


def shear_coefficient(poisson: float) -> float:
    """Timoshenko's shear coefficient of a solid circular section (Cowper, 1966)."""
    return 6 * (1 + poisson) / (7 + 6 * poisson)


@dataclass(frozen=True)
class Section:
    """A cable's cross-section and material: E A, kappa G A, E I, G J (SI) and its radius."""

    radius: float
    youngs: float
    poisson: float

    @property
    def area(self) -> float:
        return np.pi * self.radius ** 2

    @property
    def shear_modulus(self) -> float:
        return self.youngs / (2 * (1 + self.poisson))

    @property
    def axial(self) -> float:
        return self.youngs * self.area

    @property
    def shear(self) -> float:
        return shear_coefficient(self.poisson) * self.shear_modulus * self.area

    @property
    def bending(self) -> float:
        return self.youngs * np.pi * self.radius ** 4 / 4

    @property
    def torsion(self) -> float:
        return self.shear_modulus * np.pi * self.radius ** 4 / 2

    def stiffness(self, length: float) -> np.ndarray:
        """(kappa G A, kappa G A, E A, E I, E I, G J) over a joint's length."""
        return np.array([self.shear, self.shear, self.axial, self.bending, self.bending, self.torsion]) / length


@dataclass(frozen=True)
class CableLayout:
    """One cable's share of the layout: its bodies ``first`` to ``first + segments``, its nodes'
    rest points and arcs, its attachments (indices into the layout's) with a label each."""

    name: str
    section: Section
    first: int
    segments: int
    points: np.ndarray  # (segments + 1, 3) rest nodes
    arc: np.ndarray  # (segments + 1,) m from the first control point
    attachments: tuple[int, ...]
    labels: tuple[str, ...]

    @property
    def length(self) -> float:
        return float(self.arc[-1])

    @property
    def centres(self) -> np.ndarray:
        """(segments,) the arc of each segment's middle."""
        return (self.arc[:-1] + self.arc[1:]) / 2


@dataclass(frozen=True)
class RodLayout:
    """Every cable of a mechanism as flat arrays (SI), bodies cable after cable. Per body: rest
    centre, frame (quaternion x, y, z, w), half length, mass, inertia (cross-section axes, own
    axis), radius, cable, arc of its start, joint stiffness to the next body (zero at a cable's
    end), contact stiffness, and ``touch`` (bodies, links). Per attachment, sorted by body: body,
    end (+1 its end, -1 its start), link, zero-position point and frame, stiffness; ``attach_first``
    indexes each body's."""

    cables: tuple[CableLayout, ...]
    x: np.ndarray
    q: np.ndarray
    half: np.ndarray
    mass: np.ndarray
    inertia: np.ndarray
    radius: np.ndarray
    cable: np.ndarray
    arc: np.ndarray
    stiff: np.ndarray
    contact_stiff: np.ndarray
    touch: np.ndarray
    attach_body: np.ndarray
    attach_end: np.ndarray
    attach_link: np.ndarray
    attach_point: np.ndarray
    attach_frame: np.ndarray
    attach_stiff: np.ndarray

    @property
    def bodies(self) -> int:
        return len(self.half)

    @property
    def attach_first(self) -> np.ndarray:
        return np.searchsorted(self.attach_body, np.arange(self.bodies + 1)).astype(np.int32)

    @property
    def cable_first(self) -> np.ndarray:
        return np.array([c.first for c in self.cables] + [self.bodies], np.int32)

    def clamps(self) -> tuple[np.ndarray, np.ndarray]:
        """Per cable, its first and last clamp (an attachment with a direction); -1 unless two."""
        a, z = [], []
        for c in self.cables:
            held = [i for i in c.attachments if self.attach_stiff[i, 5] > 0]
            a.append(held[0] if len(held) > 1 else -1)
            z.append(held[-1] if len(held) > 1 else -1)
        return np.array(a, np.int32), np.array(z, np.int32)

    def pairs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Consecutive attachments of each cable: (first, second, cable, cable length between)."""
        rows = []
        for c, cab in enumerate(self.cables):
            for i, j in zip(cab.attachments[:-1], cab.attachments[1:]):
                rows.append((i, j, c, self._node_arc(j) - self._node_arc(i)))
        a = np.array(rows, float).reshape(-1, 4)
        return a[:, 0].astype(np.int32), a[:, 1].astype(np.int32), a[:, 2].astype(np.int32), a[:, 3]

    def _node_arc(self, i: int) -> float:
        k = int(self.attach_body[i])
        return float(self.arc[k] + (1 + self.attach_end[i]) * self.half[k])


def rod_layout(mech: Mechanism, density: float, poisson: float) -> RodLayout:
    """The layout of every cable of ``mech`` (``RsxmlError`` at a cable's line where its numbers do
    not make a cable)."""
    n_links = max(len(mech.graph.links), 1)
    parts = [_cable_parts(mech, c, density, poisson, n_links) for c in mech.cables]
    cables, first, attach_count = [], 0, 0
    for c, p in zip(mech.cables, parts):
        count = len(p["half"])
        own = tuple(range(attach_count, attach_count + len(p["attach_body"])))
        cables.append(CableLayout(c.name, p["section"], first, count, p["points"], p["node_arc"], own, p["labels"]))
        p["attach_body"] = p["attach_body"] + first
        first += count
        attach_count += len(own)
    join = lambda key, dtype=float: np.concatenate([p[key] for p in parts]).astype(dtype)  # noqa: E731
    order = np.argsort(join("attach_body", np.int32), kind="stable")
    attach = {k: join(k, t)[order] for k, t in (("attach_body", np.int32), ("attach_end", float),
                                                 ("attach_link", np.int32), ("attach_point", float),
                                                 ("attach_frame", float), ("attach_stiff", float))}
    if len(order) and not np.array_equal(order, np.arange(len(order))):  # renumber the cables' own lists
        rank = np.argsort(order)
        cables = [CableLayout(c.name, c.section, c.first, c.segments, c.points, c.arc,
                              tuple(int(rank[i]) for i in c.attachments), c.labels) for c in cables]
    return RodLayout(tuple(cables), join("x"), join("q"), join("half"), join("mass"), join("inertia"),
                     join("radius"), np.concatenate([np.full(len(p["half"]), c, np.int32) for c, p in
                                                     enumerate(parts)]),
                     join("arc"), join("stiff"), join("contact_stiff"), join("touch", np.int32), **attach)


def _cable_parts(mech: Mechanism, cable: Cable, density: float, poisson: float, n_links: int) -> dict:
    """One cable's bodies and attachments as arrays (attachment bodies counted within the cable)."""
    rest = cable_rest(mech, cable)
    section = Section(float(cable.radius), float(cable.youngs_modulus or YOUNGS_MODULUS), float(poisson))
    pts, seg = rest.points, rest.rest
    tangents = _unit(np.diff(pts, axis=0))
    cps = cable.control_points
    directions = {rest.anchors[i]: cp.unit_direction for i, cp in enumerate(cps) if cp.direction is not None}
    frames, node_frames = _frames(tangents, directions)
    r = section.radius
    mass = density * section.area * seg
    inertia = np.stack([mass * (3 * r ** 2 + seg ** 2) / 12, mass * r ** 2 / 2], axis=1)
    stiff = np.zeros((len(seg), 6))
    for i in range(len(seg) - 1):
        stiff[i] = section.stiffness((seg[i] + seg[i + 1]) / 2)
    weight = mass * 9.81
    node_arc = np.concatenate([[0.0], np.cumsum(seg)])
    links = _attachment_links(mech, cable)
    att = _attachments(cable, rest.anchors, links, pts, node_frames, seg, section)
    labels = tuple(f"control point {i + 1} on {mech.graph.links[lk]}" for i, lk in enumerate(links) if lk >= 0)
    return {"section": section, "points": pts, "node_arc": node_arc, "x": (pts[:-1] + pts[1:]) / 2, "q": frames,
            "half": seg / 2, "mass": mass, "inertia": inertia, "radius": np.full(len(seg), r), "arc": node_arc[:-1],
            "stiff": stiff, "contact_stiff": np.maximum(section.youngs * seg, weight / (SQUASH * r)),
            "touch": _touch(node_arc, seg, att["attach_body"], att["attach_end"], att["attach_link"], n_links, r),
            "labels": labels, **att}


def _attachments(cable: Cable, anchors, links, pts, node_frames, seg, section: Section) -> dict:
    """Each attached control point: the body end at its node, its link, point, frame, stiffness."""
    rows = []
    for cp, node, lk in zip(cable.control_points, anchors, links):
        if lk < 0:
            continue
        body, end = (0, -1.0) if node == 0 else (node - 1, 1.0)
        k = section.stiffness(seg[body] / 2)
        if cp.direction is None:
            k[3:] = 0.0
        rows.append((body, end, lk, pts[node], node_frames[node], k))
    return {"attach_body": np.array([r[0] for r in rows], np.int32), "attach_end": np.array([r[1] for r in rows]),
            "attach_link": np.array([r[2] for r in rows], np.int32),
            "attach_point": np.array([r[3] for r in rows]).reshape(-1, 3),
            "attach_frame": np.array([r[4] for r in rows]).reshape(-1, 4),
            "attach_stiff": np.array([r[5] for r in rows]).reshape(-1, 6)}


def _frames(tangents: np.ndarray, directions: dict[int, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(per segment, per node) frames as quaternions (x, y, z, w): third axis along the segment (at
    a node, along its control point's direction, else the segment after it), the first carried by
    parallel transport through every tangent in order, so nothing is twisted at rest. In Python
    floats, a vector a tuple: a design sweep lays out every design's segments, and NumPy's calls on
    3-vectors cost many times their arithmetic (each product and sum as NumPy rounds them)."""
    tl = [tuple(t) for t in tangents.tolist()]
    given = {k: tuple(v.tolist()) for k, v in directions.items()}
    start = given.get(0, tl[0])
    normal = _perpendicular(start)
    t_prev = start
    seg_q, node_q = [], []
    for i in range(len(tl) + 1):
        t_node = given.get(i, tl[min(i, len(tl) - 1)])
        normal = transport(normal, t_prev, t_node)
        node_q.append(_quaternion(normal, t_node))
        t_prev = t_node
        if i < len(tl):
            normal = transport(normal, t_prev, tl[i])
            seg_q.append(_quaternion(normal, tl[i]))
            t_prev = tl[i]
    return np.array(seg_q), np.array(node_q)


def transport(n: tuple, a: tuple, b: tuple) -> tuple:
    """``n`` turned by the least rotation taking unit tangent ``a`` to ``b`` (parallel transport),
    kept square to ``b``."""
    c, axis = _dot(a, b), _cross(a, b)
    if c > -0.999:
        x, s, e = _cross(axis, n), _dot(axis, n), 1 + c
        n = tuple(c * n[i] + x[i] + axis[i] * s / e for i in range(3))
    t = _dot(n, b)
    return _unit3(tuple(n[i] - t * b[i] for i in range(3)))


def _perpendicular(t: tuple) -> tuple:
    helper = (0.0, 0.0, 1.0) if abs(t[2]) < 0.9 else (1.0, 0.0, 0.0)
    return _unit3(_cross(t, helper))


def _quaternion(d1: tuple, d3: tuple) -> tuple:
    """The unit quaternion (x, y, z, w) of the frame with axes d1, d3 x d1, d3."""
    d2 = _cross(d3, d1)
    m = ((d1[0], d2[0], d3[0]), (d1[1], d2[1], d3[1]), (d1[2], d2[2], d3[2]))
    w = math.sqrt(max(1e-12, 1 + m[0][0] + m[1][1] + m[2][2])) / 2
    if w > 0.1:
        f = 4 * w
        q = ((m[2][1] - m[1][2]) / f, (m[0][2] - m[2][0]) / f, (m[1][0] - m[0][1]) / f, 4 * w ** 2 / f)
    else:  # near a half turn: from the largest diagonal
        diag = (m[0][0], m[1][1], m[2][2])
        i = diag.index(max(diag))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = math.sqrt(max(1e-12, 1 + m[i][i] - m[j][j] - m[k][k])) * 2
        q = [0.0] * 4
        q[i], q[j], q[k], q[3] = s / 4, (m[j][i] + m[i][j]) / s, (m[k][i] + m[i][k]) / s, (m[k][j] - m[j][k]) / s
    length = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return tuple(v / length for v in q)


def _dot(a: tuple, b: tuple) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a: tuple, b: tuple) -> tuple:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _unit3(v: tuple) -> tuple:
    length = math.sqrt(_dot(v, v))
    return (v[0] / length, v[1] / length, v[2] / length)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def _touch(node_arc, seg, bodies, ends, links, n_links: int, radius: float) -> np.ndarray:
    """1 where body k may touch link j: not within ATTACHED_FREE radii plus a segment of an
    attachment to j, where the cable leaves the link's surface on purpose."""
    centres = (node_arc[:-1] + node_arc[1:]) / 2
    out = np.ones((len(seg), n_links), np.int32)
    free = ATTACHED_FREE * radius + seg.max()
    for body, end, link in zip(bodies, ends, links):
        at = node_arc[body] if end < 0 else node_arc[body + 1]
        out[np.abs(centres - at) <= free, link] = 0
    return out


def _attachment_links(mech: Mechanism, cable: Cable) -> list[int]:
    """Each control point's link index (a part names the link holding it), -1 where unattached."""
    graph = mech.graph
    owner = {p.name: link.name for link in mech.links for p, _ in iter_parts(link)}
    return [-1 if cp.attached_to is None else graph.link_index(owner.get(cp.attached_to, cp.attached_to))
            for cp in cable.control_points]
