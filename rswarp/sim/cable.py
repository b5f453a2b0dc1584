"""Host side of cable dynamics (``rswarp.kernels.cable``): a cable as the flat arrays its kernel
takes, the link meshes it touches, and frames of many environments stepped on the shared launcher.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, MeshNotFoundError
from ..geometry.cable import CableRest, cable_rest
from ..geometry.meshes import link_mesh
from ..kernels.types import Chain
from ..rsxml.model import Cable, Mechanism, iter_parts
from .chain import mechanism_chain
from .launch import Launcher, init_warp

DENSITY = 1200.0  # kg/m^3: a hose (DESIGN.md)
POISSON = 0.5  # rubber: incompressible, so G = E / 3
YOUNGS_MODULUS = 5e7  # Pa, where the file gives none: a rubber-like dress-pack hose
GRAVITY = (0.0, 0.0, -9.81)
ATTACHED_FREE = 4.0  # radii (plus a segment) of cable beside an attachment that may lie on its link
MAX_SPEED = 100.0  # m/s: a particle faster than this (on a robot's hose) has blown up
REACH = 0.25  # m: clearances are measured up to this far; farther reads as "beyond"
BIG_FLOOR = 1.0e6  # m: no floor


@dataclass(frozen=True)
class CableModel:
    """One cable as particle arrays (SI). ``link[k] >= 0``: particle k moves rigidly with that link
    from its zero-position point ``x0[k]``. A control point with a ``direction`` at an end of the
    cable gets a ghost particle one segment beyond it, along the direction reversed, held by the
    same link: with the control point it clamps the cable's tangent there. ``cable`` slices the
    cable's own particles out of ``x0`` (ghosts excluded)."""

    name: str
    x0: np.ndarray  # (P, 3)
    rest: np.ndarray  # (P - 1,)
    inv_mass: np.ndarray  # (P,)
    link: np.ndarray  # (P,) int32
    compliance: np.ndarray  # (P,) bending compliance of the curvature at each particle, l^3 / EI
    cable: slice
    radius: float
    touch: np.ndarray  # (P, links) int32: 0 where particle k lies beside its own attachment to link j
    ends: tuple[int, int]  # links clamping the first and last segment, -1 where the end turns freely
    normals: np.ndarray  # (2, 3): the clamps' reference normals, twist-free along the rest shape
    torsion: float  # GJ (N m^2)

    @property
    def particles(self) -> int:
        return len(self.x0)

    @property
    def arc(self) -> np.ndarray:
        """(P,) arc length of each particle from the cable's first own particle (m; ghosts outside)."""
        arc = np.concatenate([[0.0], np.cumsum(self.rest)])
        return arc - arc[self.cable.start]

    @property
    def length(self) -> float:
        """The cable's own length (ghost segments excluded)."""
        return float(self.arc[self.cable.stop - 1])


def cable_model(mech: Mechanism, cable: Cable, density: float = DENSITY, poisson: float = POISSON) -> CableModel:
    """The particle arrays of ``cable`` (its rest shape: ``rswarp.geometry.cable.cable_rest``)."""
    rest = cable_rest(mech, cable)
    links = _attachment_links(mech, cable)
    x0, seg, link = rest.points.copy(), rest.rest.copy(), np.full(len(rest.points), -1, np.int32)
    for anchor, lk in zip(rest.anchors, links):
        if lk >= 0:
            link[anchor] = lk
    x0, seg, link, first = _ghosts(cable, rest, x0, seg, link, links)
    mass = _masses(seg, cable.radius, density)
    inv = np.where(link >= 0, 0.0, 1.0 / mass)
    e_mod = cable.youngs_modulus or YOUNGS_MODULUS
    ei = e_mod * np.pi * cable.radius ** 4 / 4
    gj = e_mod / (2 * (1 + poisson)) * np.pi * cable.radius ** 4 / 2
    lk = np.concatenate([[seg[0]], (seg[:-1] + seg[1:]) / 2, [seg[-1]]])  # the length a curvature spans
    own = slice(first, first + len(rest.points))
    ends = (int(link[0]) if first else -1, int(link[-1]) if own.stop < len(x0) else -1)
    return CableModel(cable.name, x0, seg, inv, link, lk ** 3 / ei, own, cable.radius,
                      _touch(seg, link, len(mech.graph.links), cable.radius), ends, _normals(x0), gj)


def _touch(seg: np.ndarray, link: np.ndarray, n_links: int, radius: float) -> np.ndarray:
    """1 where particle k may touch link j: not within ATTACHED_FREE of a particle held by j, where
    the cable leaves the link's surface on purpose."""
    arc = np.concatenate([[0.0], np.cumsum(seg)])
    out = np.ones((len(link), max(n_links, 1)), np.int32)
    free = ATTACHED_FREE * radius + seg.max()
    for k in np.nonzero(link >= 0)[0]:
        out[np.abs(arc - arc[k]) <= free, link[k]] = 0
    return out


def _normals(x0: np.ndarray) -> np.ndarray:
    """A normal to the first segment and its parallel transport along the chain to the last."""
    t = np.diff(x0, axis=0)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    helper = np.array([0.0, 0.0, 1.0]) if abs(t[0, 2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    n = np.cross(t[0], helper)
    n /= np.linalg.norm(n)
    start = n.copy()
    for a, b in zip(t[:-1], t[1:]):
        n = transport(n, a, b)
    return np.array([start, n])


def transport(n: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``n`` turned by the least rotation taking unit tangent ``a`` to ``b`` (parallel transport)."""
    c, axis = float(a @ b), np.cross(a, b)
    if c <= -0.999:
        return n
    return c * n + np.cross(axis, n) + axis * (axis @ n) / (1 + c)


def _attachment_links(mech: Mechanism, cable: Cable) -> list[int]:
    """Each control point's link index (a part names the link holding it), -1 where unattached."""
    graph = mech.graph
    owner = {p.name: link.name for link in mech.links for p, _ in iter_parts(link)}
    out = []
    for cp in cable.control_points:
        name = cp.attached_to
        out.append(-1 if name is None else graph.link_index(owner.get(name, name)))
    return out


def _ghosts(cable: Cable, rest: CableRest, x0, seg, link, links):
    """Clamp the tangent at attached end points that have a direction (see ``CableModel``)."""
    first = 0
    cps = cable.control_points
    if links[0] >= 0 and cps[0].direction is not None:  # the cable leaves the point along direction
        ghost = x0[0] - seg[0] * cps[0].unit_direction
        x0, seg, link, first = np.vstack([ghost, x0]), np.concatenate([[seg[0]], seg]), np.insert(link, 0, links[0]), 1
    if links[-1] >= 0 and cps[-1].direction is not None:  # it arrives along direction
        ghost = x0[-1] + seg[-1] * cps[-1].unit_direction
        x0, seg, link = np.vstack([x0, ghost]), np.concatenate([seg, [seg[-1]]]), np.append(link, links[-1])
    return x0, seg, link, first


def _masses(rest: np.ndarray, radius: float, density: float) -> np.ndarray:
    """Lumped masses (kg): each particle carries half of each segment beside it."""
    seg = density * np.pi * radius ** 2 * np.asarray(rest, float)
    m = np.zeros(len(seg) + 1)
    m[:-1] += seg / 2
    m[1:] += seg / 2
    return m


@dataclass
class CableState:
    """Many environments of one cable (float32, host arrays filled in place by each frame):
    positions and velocities (envs, P, 3), status (envs,: ``kernels.cable`` RUNNING, NOT_FINITE,
    RUNAWAY), the last frame's statistics (envs, STATS) and clearances (envs, links + 1, the floor
    last) with the particle where each was least."""

    x: np.ndarray
    v: np.ndarray
    status: np.ndarray
    stats: np.ndarray
    clear: np.ndarray
    at: np.ndarray


@dataclass(frozen=True)
class LinkMeshes:
    """The link meshes a cable may touch, in each link's zero-position frame (metres); None for a
    link without geometry. ``warnings``: links whose mesh files are missing (no contact with them)."""

    meshes: tuple
    warnings: tuple[str, ...]


def link_meshes(mech: Mechanism) -> LinkMeshes:
    """Every link's parts as one mesh, as ``rswarp.geometry.meshes.link_mesh`` reads them."""
    out, missing = [], []
    for name in mech.graph.links:
        try:
            mesh = link_mesh(mech, name)
        except MeshNotFoundError as exc:
            missing.append((name, str(exc)))
            mesh = None
        out.append(None if mesh is None or len(mesh.faces) == 0 else
                   (np.asarray(mesh.vertices, np.float64), np.asarray(mesh.faces, np.int64)))
    warnings = [f"{why}: cables do not touch link '{name}'" for name, why in missing[:1]]
    if len(missing) > 1:
        warnings.append(f"{len(missing) - 1} more link(s) without their mesh files, not touched either: "
                        + ", ".join(name for name, _ in missing[1:]))
    return LinkMeshes(tuple(out), tuple(warnings))


class CableStepper:
    """Frames of many environments of one cable on a mechanism: ``step(state, qs, dt)`` advances a
    ``CableState`` in place by one frame of ``qs.shape[1]`` substeps."""

    def __init__(self, mech: Mechanism, model: CableModel, substeps: int = 20, iterations: int = 2,
                 damping: float = 1.0, meshes: LinkMeshes | None = None, floor: float | None = None,
                 device: str = "cpu", threads: int | None = None):
        wp = init_warp()
        from ..kernels.cable import cable_kernel

        if substeps < 1 or iterations < 1:
            raise InputError("substeps and iterations must be at least 1")
        self.model, self.substeps = model, int(substeps)
        chain: Chain = mechanism_chain(mech)
        self.n_links = max(len(chain.parent), 1)
        meshes = meshes or LinkMeshes((None,) * len(chain.parent), ())
        touched = {j for j, m in enumerate(meshes.meshes) if m is not None}
        links = {int(k) for k in model.link if k >= 0} | touched
        self.kernel = cable_kernel(chain, links, model.particles, int(iterations))
        self.launcher = Launcher(device, chunk=64, threads=threads)
        self.launcher.load(self.kernel)
        self._meshes = [None] * self.n_links  # Warp keeps a mesh's BVH only while the Mesh lives
        self.params = self._params(wp, model, meshes, damping, floor)

    def _params(self, wp, model: CableModel, meshes: LinkMeshes, damping: float, floor: float | None):
        from ..kernels.cable_contact import CableParams

        dev = self.launcher.device
        prm = CableParams()
        f32 = lambda a: wp.array(np.asarray(a, np.float32), dtype=wp.float32, device=dev)  # noqa: E731
        prm.rest, prm.w, prm.compliance = f32(model.rest), f32(model.inv_mass), f32(model.compliance)
        prm.link = wp.array(model.link, dtype=wp.int32, device=dev)
        prm.local = wp.array(np.asarray(model.x0, np.float32), dtype=wp.vec3, device=dev)
        prm.touch = wp.array(model.touch, dtype=wp.int32, device=dev)
        ids, spheres = np.zeros(self.n_links, np.uint64), np.zeros((self.n_links, 4), np.float32)
        for j, m in enumerate(meshes.meshes):
            if m is not None:
                self._meshes[j] = wp.Mesh(points=wp.array(m[0].astype(np.float32), dtype=wp.vec3, device=dev),
                                          indices=wp.array(m[1].astype(np.int32).ravel(), dtype=wp.int32, device=dev))
                ids[j] = self._meshes[j].id
                centre = (m[0].min(axis=0) + m[0].max(axis=0)) / 2
                spheres[j] = (*centre, np.linalg.norm(m[0] - centre, axis=1).max())
        prm.mesh = wp.array(ids, dtype=wp.uint64, device=dev)
        prm.sphere = wp.array(spheres, dtype=wp.vec4, device=dev)
        prm.ends = wp.vec2i(*model.ends)
        prm.start_normal, prm.end_normal = wp.vec3(*model.normals[0]), wp.vec3(*model.normals[1])
        prm.gravity = wp.vec3(*GRAVITY)
        prm.radius, prm.damping = float(model.radius), float(damping)
        prm.floor = -BIG_FLOOR if floor is None else float(floor)
        prm.margin, prm.reach, prm.max_speed = float(model.rest.max()), REACH, MAX_SPEED
        return prm

    def state(self, envs: int) -> CableState:
        """``envs`` environments at the rest shape, at rest, running."""
        from ..kernels.cable import STATS

        x = np.ascontiguousarray(np.repeat(np.asarray(self.model.x0, np.float32)[None], envs, axis=0))
        return CableState(x, np.zeros_like(x), np.zeros(envs, np.int32), np.zeros((envs, STATS), np.float32),
                          np.zeros((envs, self.n_links + 1), np.float32), np.zeros((envs, self.n_links + 1), np.int32))

    def set_damping(self, damping: float) -> None:
        self.params.damping = float(damping)

    def step(self, state: CableState, qs: np.ndarray, dt: float) -> None:
        """One frame of length ``dt``: ``qs`` (envs, substeps, dof) the joints at each substep's end."""
        qs = np.ascontiguousarray(qs, np.float32)
        if qs.shape[:2] != (len(state.x), self.substeps):
            raise ValueError(f"qs must have shape ({len(state.x)}, {self.substeps}, dof), got {qs.shape}")
        self.launcher.launch(self.kernel, len(state.x), params=[self.params, float(dt)], inputs=[qs],
                             outputs=[state.x, state.v, state.status, state.stats, state.clear, state.at])
