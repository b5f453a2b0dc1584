"""The mass model of a robot's links: each link's meshes (and their convex collision pieces) with
its mass, centre of mass and inertia from the meshes' volume at a density (or scaled so the robot
weighs a given mass), a payload on the flange added to its link, and what every joint moves about
its axis at a pose. The exports author these; the planner's payload timing reads the inertias
about the axes (``motion.payload``)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError, MeshNotFoundError
from ..rsxml.model import Mechanism
from ..rsxml.robot_data import Payload
from .convex import Convex, convex_pieces
from .frames import link_origins
from .mass import DEFAULT_DENSITY, mass_properties
from .meshes import part_mesh

ARMATURE_SCALE = 1e-3  # default armature: 1e-3 x total mass x reach^2 (kg m^2), or x total mass (kg)


@dataclass(frozen=True)
class PartGeometry:
    """A part's mesh and its convex collision pieces, world coordinates at the zero position."""

    name: str
    mesh: object  # trimesh.Trimesh
    pieces: tuple[Convex, ...]


@dataclass(frozen=True)
class BodyPhysics:
    """A link's frame origin (world-aligned at zero), geometry, and mass properties in that frame."""

    link: str
    origin: np.ndarray
    parts: tuple[PartGeometry, ...]
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))  # about the centre of mass


def link_geometry(mech: Mechanism, collision: str | None, warnings: list[str]) -> dict[str, tuple[PartGeometry, ...]]:
    """Each link's parts that have a mesh, with their convex pieces by ``collision``'s method (None:
    no pieces, for the masses alone); one warning when no part has one."""
    out, missing = {}, []
    for link in mech.link_names:
        found = []
        for part, transform in mech.parts(link):
            if not part.source:
                continue
            try:
                mesh = part_mesh(mech, part, transform)
            except MeshNotFoundError as exc:
                missing.append(str(exc))
                continue
            pieces = () if collision is None else tuple(convex_pieces(mesh.vertices, mesh.faces, collision))
            found.append(PartGeometry(part.name, mesh, pieces))
        out[link] = tuple(found)
    if not any(out.values()):
        missing = [f"{mech.path or mech.name}: warning: no mesh beside the file for any part (looked for "
                   "<source stem>.stl/.obj/.ply/.glb/.gltf/.off): exported kinematics only, bodies and "
                   "joints without geometry or mass"]
    warnings += missing
    return out


def link_bodies(mech: Mechanism, parts: dict, warnings: list[str], density: float = DEFAULT_DENSITY,
                mass: float | None = None, mass_source: str = "") -> tuple[dict[str, BodyPhysics], float]:
    """(mass properties per link, the density used): at ``density``, or scaled so the robot weighs
    ``mass`` (``mass_source`` says where that figure comes from, for the warning)."""
    origins = link_origins(mech)
    unit = {}
    for link in [mech.graph.links[k] for k in mech.graph.order]:
        geo = parts.get(link, ())
        if not geo:
            unit[link] = None
            continue
        volume, com, inertia, watertight = mass_properties([p.mesh for p in geo], origins[link], 1.0)
        if not watertight:
            warnings.append(f"link '{link}': mesh is not watertight; mass from its convex hull")
        if not volume > 0:
            warnings.append(f"link '{link}': mesh has no volume; no mass authored")
        unit[link] = (volume, com, inertia)  # at unit density: the volume and its moments
    volume = sum(u[0] for u in unit.values() if u is not None and u[0] > 0)
    if mass is not None and not volume > 0:
        if mass_source in ("", "--mass"):
            raise InputError("--mass needs link meshes with volume; this model has none")
        warnings.append(f"{mass_source}: the robot's {mass:g} kg not authored: no link mesh with "
                        "volume to give it to")
    elif mass is not None:
        density = mass / volume
    bodies = {}
    for link, u in unit.items():
        props = {} if u is None or not u[0] > 0 else dict(mass=u[0] * density, com=u[1], inertia=u[2] * density)
        bodies[link] = BodyPhysics(link, origins[link], parts.get(link, ()), **props)
    return bodies, density


def world_inertia(body: BodyPhysics, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The body's centre of mass and inertia (about it) in the world, with the link at ``pose``."""
    r = pose[:3, :3]
    return pose[:3, :3] @ (body.origin + body.com) + pose[:3, 3], r @ body.inertia @ r.T


def subtrees(mech: Mechanism) -> dict[str, list[str]]:
    """Each reached link and the links it carries (itself first)."""
    graph = mech.graph
    carried = {graph.links[k]: [graph.links[k]] for k in graph.order}
    for k in reversed(graph.order):
        p = graph.parent[k]
        if p >= 0:
            carried[graph.links[p]] += carried[graph.links[k]]
    return carried


def with_payload(mech: Mechanism, bodies: dict[str, BodyPhysics], payload: Payload) -> dict[str, BodyPhysics]:
    """The payload added to the mass properties of the link the first flange is on."""
    if not mech.flanges:
        raise InputError(f"--payload: '{mech.name}' has no flange to carry a payload")
    flange = mech.flanges[0]
    at = flange.pose.matrix()
    body = bodies[flange.link]
    com = at[:3, :3] @ np.asarray(payload.cog) + at[:3, 3] - body.origin
    inertia = at[:3, :3] @ payload.inertia_matrix() @ at[:3, :3].T
    mass, com, inertia = combined((body.mass, body.com, body.inertia), (payload.mass, com, inertia))
    return {**bodies, flange.link: replace(body, mass=mass, com=com, inertia=inertia)}


def combined(a, b) -> tuple[float, np.ndarray, np.ndarray]:
    """Two masses (mass, centre, inertia about it; one frame) as one: parallel-axis theorem."""
    mass = a[0] + b[0]
    if not mass > 0:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    com = (a[0] * np.asarray(a[1]) + b[0] * np.asarray(b[1])) / mass
    inertia = np.zeros((3, 3))
    for m, c, i in (a, b):
        d = np.asarray(c) - com
        inertia += np.asarray(i) + m * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return mass, com, inertia


def axis_inertia(moved, poses, axis: np.ndarray, point: np.ndarray, revolute: bool) -> float:
    """What ``moved`` (bodies, their links at ``poses``) weighs about the axis through ``point``:
    the moment of inertia (kg m^2) for a revolute joint, the mass (kg) for a prismatic one."""
    if not revolute:
        return float(sum(b.mass for b in moved))
    total = 0.0
    for b in moved:
        com, inertia = world_inertia(b, poses[b.link])
        r = com - point
        r_perp = r - axis * float(r @ axis)
        total += float(axis @ inertia @ axis) + b.mass * float(r_perp @ r_perp)
    return total


def joint_axes(mech: Mechanism, poses: dict):
    """Each active tree joint with its child link and its axis and point in the world at ``poses``:
    (joint, link, axis, point)."""
    graph = mech.graph
    for k, j in graph.tree_order:
        if graph.column(j.name) < 0:
            continue
        parent = poses[graph.links[graph.parent[k]]]
        axis, point = parent[:3, :3] @ j.axis, parent[:3, :3] @ np.asarray(j.point1, float) + parent[:3, 3]
        yield j, graph.links[k], axis, point


def default_armature(mech: Mechanism, bodies: dict[str, BodyPhysics], poses: dict, revolute: bool) -> float:
    """The armature (motor reflected inertia) a joint gets unless one is given: ``ARMATURE_SCALE``
    x the robot's mass (at least 1 kg) x its reach squared (revolute), or x its mass (prismatic)."""
    graph = mech.graph
    total = sum(b.mass for b in bodies.values())
    reach = max([float(np.linalg.norm(p[:3, 3] - poses[graph.base][:3, 3])) for p in poses.values()]
                + [float(np.linalg.norm(fl.pose.matrix()[:3, 3])) for fl in mech.flanges] + [0.1])
    return ARMATURE_SCALE * max(total, 1.0) * (reach ** 2 if revolute else 1.0)


