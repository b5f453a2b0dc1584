"""The particle-chain cable model (``rswarp.kernels.cable``): a cable as a chain of particles kept
inextensible by exact projections and bent by XPBD, frictionless, with contact at the particles.
Here: the flat arrays its kernel takes, and ``ParticleChain``, the ``CableSolver`` that steps many
environments of one cable on the shared launcher, its state kept on the device.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, model_error
from ..geometry.cable import CableRest, cable_rest
from ..kernels.cable import BEND, BEND_AT, MAX_PARTICLES, STATS, STRETCH, TENSION, TWIST, cable_kernel
from ..kernels.cable_contact import CableParams
from ..kernels.types import Chain
from ..kinematics.chain import mechanism_chain
from ..rsxml.model import Cable, Mechanism, iter_parts
from .cable_solver import (
    DENSITY,
    GRAVITY,
    MAX_SPEED,
    POISSON,
    REACH,
    YOUNGS_MODULUS,
    CableOptions,
    CableSolver,
    LinkMeshes,
)
from .launch import Launcher, init_warp

ATTACHED_FREE = 4.0  # radii (plus a segment) of cable beside an attachment that may lie on its link
BIG_FLOOR = 1.0e6  # m: no floor
UNMEASURED = 1.0e29  # the kernel's "nothing within reach" (BIG) reads as +inf


@dataclass(frozen=True)
class ChainArrays:
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

    @property
    def attachment_pairs(self) -> np.ndarray:
        """(pairs, 2) consecutive attached particles of the cable itself (ghosts excluded)."""
        anchors = [k for k in range(self.cable.start, self.cable.stop) if self.link[k] >= 0]
        return np.array(list(zip(anchors[:-1], anchors[1:])), np.int64).reshape(-1, 2)


def chain_arrays(mech: Mechanism, cable: Cable, density: float = DENSITY, poisson: float = POISSON) -> ChainArrays:
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
    return ChainArrays(cable.name, x0, seg, inv, link, lk ** 3 / ei, own, cable.radius,
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
    """Clamp the tangent at attached end points that have a direction (see ``ChainArrays``)."""
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
class ChainState:
    """Many environments of one cable, as Warp arrays on the solver's device: positions and
    velocities (envs, P), status (envs,), and the last frame's statistics: ``stats`` (envs, STATS)
    and the least clearance per link and the floor with the particle where (envs, links + 1)."""

    x: object
    v: object
    status: object
    stats: object
    clear: object
    at: object


class ParticleChain(CableSolver):
    """Frames of many environments of one cable on a mechanism as a particle chain."""

    kind = "chain"

    def __init__(self, mech: Mechanism, cable: Cable, options: CableOptions = CableOptions(),
                 meshes: LinkMeshes | None = None):
        if options.substeps < 1 or options.iterations < 1:
            raise InputError("substeps and iterations must be at least 1")
        super().__init__(mech, cable, options)
        self.arrays = model = chain_arrays(mech, cable, density=options.density)
        self.length, self.torsion_stiffness, self.substeps = model.length, model.torsion, int(options.substeps)
        self.arc = model.arc[model.cable]
        self._arc_of = np.append(model.arc, np.nan)  # particle index -> arc; -1 (none) reads NaN
        chain: Chain = mechanism_chain(mech)
        self.n_links = max(len(chain.parent), 1)
        meshes = meshes or LinkMeshes((None,) * len(chain.parent), ())
        touched = {j for j, m in enumerate(meshes.meshes) if m is not None}
        links = {int(k) for k in model.link if k >= 0} | touched
        self.kernel = cable_kernel(chain, links, model.particles, int(options.iterations))
        self.launcher = Launcher(options.device, chunk=64, threads=options.threads)
        self.launcher.load(self.kernel)
        self._meshes = [None] * self.n_links  # Warp keeps a mesh's BVH only while the Mesh lives
        self.params = self._params(model, meshes, options.damping, options.floor)

    @classmethod
    def check(cls, mech: Mechanism, cable: Cable, options: CableOptions) -> None:
        arrays = chain_arrays(mech, cable, density=options.density)
        if arrays.particles > MAX_PARTICLES:
            raise model_error(mech, f"cable '{cable.name}' would take {arrays.particles} particles, over the "
                                    f"{MAX_PARTICLES} a kernel holds: raise its maxSegmentLength", cable.line)

    def _params(self, model: ChainArrays, meshes: LinkMeshes, damping: float, floor: float | None) -> CableParams:
        wp = init_warp()
        dev = self.launcher.device
        params = CableParams()
        f32 = lambda a: wp.array(np.asarray(a, np.float32), dtype=wp.float32, device=dev)  # noqa: E731
        i32 = lambda a: wp.array(np.asarray(a, np.int32), dtype=wp.int32, device=dev)  # noqa: E731
        params.rest, params.w, params.compliance = f32(model.rest), f32(model.inv_mass), f32(model.compliance)
        params.link, params.touch = i32(model.link), wp.array(model.touch, dtype=wp.int32, device=dev)
        params.local = wp.array(np.asarray(model.x0, np.float32), dtype=wp.vec3, device=dev)
        ids, spheres = np.zeros(self.n_links, np.uint64), np.zeros((self.n_links, 4), np.float32)
        for j, m in enumerate(meshes.meshes):
            if m is not None:
                self._meshes[j] = wp.Mesh(points=wp.array(m[0].astype(np.float32), dtype=wp.vec3, device=dev),
                                          indices=wp.array(m[1].astype(np.int32).ravel(), dtype=wp.int32, device=dev))
                ids[j] = self._meshes[j].id
                centre = (m[0].min(axis=0) + m[0].max(axis=0)) / 2
                spheres[j] = (*centre, np.linalg.norm(m[0] - centre, axis=1).max())
        params.mesh = wp.array(ids, dtype=wp.uint64, device=dev)
        params.sphere = wp.array(spheres, dtype=wp.vec4, device=dev)
        params.ends = wp.vec2i(*model.ends)
        params.start_normal, params.end_normal = wp.vec3(*model.normals[0]), wp.vec3(*model.normals[1])
        params.gravity = wp.vec3(*GRAVITY)
        params.radius, params.damping = float(model.radius), float(damping)
        params.floor = -BIG_FLOOR if floor is None else float(floor)
        params.margin, params.reach, params.max_speed = float(model.rest.max()), REACH, MAX_SPEED
        pairs = model.attachment_pairs
        params.pair_a, params.pair_b = i32(pairs[:, 0]), i32(pairs[:, 1])
        params.pair_length = f32(model.arc[pairs[:, 1]] - model.arc[pairs[:, 0]])
        return params

    def state(self, envs: int) -> ChainState:
        wp = init_warp()
        dev = self.launcher.device
        x = np.ascontiguousarray(np.repeat(np.asarray(self.arrays.x0, np.float32)[None], envs, axis=0))
        zeros = lambda shape, dtype: wp.zeros(shape, dtype=dtype, device=dev)  # noqa: E731
        return ChainState(wp.array(x, dtype=wp.vec3, device=dev), zeros(x.shape[:2], wp.vec3), zeros(envs, wp.int32),
                          zeros((envs, STATS), wp.float32), zeros((envs, self.n_links + 1), wp.float32),
                          zeros((envs, self.n_links + 1), wp.int32))

    def set_damping(self, damping: float) -> None:
        self.params.damping = float(damping)

    def step(self, state: ChainState, qs: np.ndarray, dt: float) -> None:
        qs = np.ascontiguousarray(qs, np.float32)
        envs = state.x.shape[0]
        if qs.shape[:2] != (envs, self.substeps):
            raise ValueError(f"qs must have shape ({envs}, {self.substeps}, dof), got {qs.shape}")
        self.launcher.launch(self.kernel, envs, params=[self.params, float(dt)], inputs=[qs],
                             outputs=[state.x, state.v, state.status, state.stats, state.clear, state.at])

    def statistics(self, state: ChainState) -> dict[str, np.ndarray]:
        stats = state.stats.numpy().astype(np.float64)  # what the host reads: a frame's statistics only
        clear = state.clear.numpy().astype(np.float64)
        bend = stats[:, BEND]
        bend[bend > UNMEASURED] = np.inf
        clear[clear > UNMEASURED] = np.inf
        bend_at = np.where(stats[:, BEND_AT] >= 0, stats[:, BEND_AT], -1).astype(np.int64)
        return {"status": state.status.numpy().copy(), "tension": stats[:, TENSION], "bend_radius": bend,
                "bend_at": self._arc_of[bend_at], "twist": stats[:, TWIST], "stretch": stats[:, STRETCH],
                "clearance": clear, "clearance_at": self._arc_of[state.at.numpy().astype(np.int64)]}

    def points(self, state: ChainState, env: int | None = None) -> np.ndarray:
        own = self.arrays.cable
        if env is None:
            return state.x.numpy()[:, own].astype(np.float64)
        return state.x[env].numpy()[own].astype(np.float64)
