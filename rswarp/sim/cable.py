"""Host side of cable dynamics (``rswarp.kernels.cable``): a cable as the flat arrays its kernel
takes, and frames of environments stepped on the shared launcher.

Work in progress toward ``simulate_cables`` (issue "Cable dynamics in parallel environments"):
gravity, damping, exact inextensibility, bending, attachments moved by forward kinematics. Not
yet: torsion, contact with the links and the floor, results and reports.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..geometry.cable import CableRest, cable_rest
from ..kernels.types import Chain
from ..rsxml.model import Cable, Mechanism, iter_parts
from .chain import mechanism_chain
from .launch import Launcher, init_warp

DENSITY = 1200.0  # kg/m^3: a hose (DESIGN.md)
YOUNGS_MODULUS = 5e7  # Pa, where the file gives none: a rubber-like dress-pack hose
GRAVITY = (0.0, 0.0, -9.81)


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


def cable_model(mech: Mechanism, cable: Cable, density: float = DENSITY) -> CableModel:
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
    ei = (cable.youngs_modulus or YOUNGS_MODULUS) * np.pi * cable.radius ** 4 / 4
    lk = np.concatenate([[seg[0]], (seg[:-1] + seg[1:]) / 2, [seg[-1]]])  # the length a curvature spans
    return CableModel(cable.name, x0, seg, inv, link, lk ** 3 / ei, slice(first, first + len(rest.points)),
                      cable.radius)


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


class CableStepper:
    """Frames of many environments of one cable on a mechanism: ``step(x, v, qs, dt)`` advances
    positions and velocities (envs, P, 3) in place by one frame of ``qs.shape[1]`` substeps."""

    def __init__(self, mech: Mechanism, model: CableModel, substeps: int = 20, iterations: int = 2,
                 damping: float = 1.0, device: str = "cpu", threads: int | None = None):
        wp = init_warp()
        from ..kernels.cable import cable_kernel

        if substeps < 1 or iterations < 1:
            raise InputError("substeps and iterations must be at least 1")
        self.model, self.substeps, self.damping = model, int(substeps), float(damping)
        chain: Chain = mechanism_chain(mech)
        links = {int(k) for k in model.link if k >= 0}
        self.kernel = cable_kernel(chain, links, len(model.x0), self.substeps, int(iterations), wp.float32)
        self.launcher = Launcher(device, chunk=64, threads=threads)
        self.launcher.load(self.kernel)
        dev = self.launcher.device
        f32 = lambda a: wp.array(np.asarray(a, np.float32), dtype=wp.float32, device=dev)  # noqa: E731
        self.params = [f32(model.rest), f32(model.inv_mass), wp.array(model.link, dtype=wp.int32, device=dev),
                       wp.array(np.asarray(model.x0, np.float32), dtype=wp.vec3, device=dev), f32(model.compliance),
                       wp.vec3(*GRAVITY)]

    def state(self, envs: int) -> tuple[np.ndarray, np.ndarray]:
        """Positions (the rest shape) and velocities (zero) of ``envs`` environments, float32."""
        x = np.repeat(np.asarray(self.model.x0, np.float32)[None], envs, axis=0)
        return np.ascontiguousarray(x), np.zeros_like(x)

    def step(self, x: np.ndarray, v: np.ndarray, qs: np.ndarray, dt: float) -> None:
        """One frame of length ``dt``: ``qs`` (envs, substeps, dof) the joints at each substep's end."""
        qs = np.ascontiguousarray(qs, np.float32)
        if qs.shape[:2] != (len(x), self.substeps):
            raise ValueError(f"qs must have shape ({len(x)}, {self.substeps}, dof), got {qs.shape}")
        self.launcher.launch(self.kernel, len(x), params=[*self.params, float(dt / self.substeps), self.damping],
                             inputs=[qs], outputs=[x, v])
