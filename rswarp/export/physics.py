"""What every export needs to simulate, computed once: per link its meshes, convex collision pieces
and mass; per active joint its drive gains, limit spring, armature and effort/velocity limits;
and the link pairs whose collisions are filtered.

Gains are chosen from the robot itself. A joint's effective inertia is the inertia of everything
it carries about its axis at home, plus its armature. The drive is a critically damped PD loop at
``drive_hz``: stiffness = I·ω², damping = 2·I·ω. The limit spring is the same at ``LIMIT_HZ``. All
values here are SI, per radian for revolute joints. The exports convert them to their units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..geometry import DEFAULT_DENSITY
from ..geometry.convex import METHODS, halfspaces, overlap
from ..geometry.frames import link_poses
from ..geometry.inertia import (
    BodyPhysics,
    axis_inertia,
    default_armature,
    joint_axes,
    link_bodies,
    link_geometry,
    subtrees,
    with_payload,
)
from ..options import checked
from ..rsxml.model import Mechanism
from ..rsxml.robot_data import Payload
from ..rsxml.units import JOINT_VELOCITY

DRIVE_HZ = 10.0  # drive bandwidth: stiff enough to hold a pose within a fraction of a degree
LIMIT_HZ = 100.0  # limit spring bandwidth: holds the limit under gravity, stable at dt = 1 ms
EFFORT_MARGIN = 2.0  # default effort: twice the largest gravity load the joint can ever carry,
ACCELERATION = 10.0  # plus what accelerates its inertia at 10 rad/s^2 (10 m/s^2)
VELOCITY = JOINT_VELOCITY  # default velocity limit: 90 deg/s, 0.5 m/s
CONTACT_MARGIN = 0.005  # pieces closer than this at home count as touching (m)
GRAVITY = 9.81


@dataclass(frozen=True)
class PhysicsOptions:
    """How to make the robot simulate. ``mass`` (kg) scales the density so the links weigh that in
    all; ``drive_hz=None`` leaves the drives out; ``armature``, ``effort`` and ``velocity`` set
    one value for every joint (SI) in place of the defaults scaled to the robot."""

    density: float = DEFAULT_DENSITY
    mass: float | None = None
    collision: str = "convexHull"
    drive_hz: float | None = DRIVE_HZ
    armature: float | None = None
    effort: float | None = None
    velocity: float | None = None
    # per joint (name, velocity, effort), SI, from robot data or --limits; NaN where not published
    axis_limits: tuple[tuple[str, float, float], ...] = ()
    mass_source: str = ""  # where ``mass`` comes from, for the table
    payload: Payload | None = None  # on the flange: authored in its link's mass, and sizing the efforts
    rated_payload: float | None = None  # kg at the flange, sizing the efforts only (the robot data's rating)
    # pairs a collision matrix disables (link, link, MoveIt reason): filtered like the adjacent ones
    disabled: tuple[tuple[str, str, str], ...] = ()

    def __post_init__(self):
        if self.collision not in METHODS:
            raise InputError(f"collision must be one of {', '.join(METHODS)}, not {self.collision!r}")
        if self.drive_hz is not None and not self.drive_hz > 0:
            raise InputError(f"drive_hz must be > 0 (None: no drives), not {self.drive_hz:g}")
        for name in ("density", "mass", "drive_hz", "armature", "effort", "velocity"):
            checked(name.replace("_", "-"), getattr(self, name))


@dataclass(frozen=True)
class JointPhysics:
    """An active joint's dynamics, SI: N·m/rad (N/m), N·m·s/rad (N·s/m), kg·m² (kg), N·m (N)."""

    name: str
    revolute: bool
    inertia: float  # what the joint moves, about its axis at home, armature included
    armature: float
    stiffness: float  # drive; 0 when drives are off
    damping: float
    limit_stiffness: float
    limit_damping: float
    effort: float
    velocity: float


@dataclass(frozen=True)
class RobotPhysics:
    bodies: dict[str, BodyPhysics]
    joints: dict[str, JointPhysics]
    # (link, link, reason): "adjacent", "overlap at home", or a collision matrix's reason in lower case
    filtered: tuple[tuple[str, str, str], ...]
    density: float
    collision: str
    warnings: tuple[str, ...]
    mass_source: str = ""  # where the total mass comes from ("": the density)
    payload: Payload | None = None  # in the flange link's mass
    effort_payload: str = ""  # what the estimated efforts are sized to carry, in words ("": nothing)

    @property
    def total_mass(self) -> float:
        return float(sum(b.mass for b in self.bodies.values()))


def robot_physics(mech: Mechanism, options: PhysicsOptions | None = None, *, geometry: bool = True) -> RobotPhysics:
    """Everything the exports author to make ``mech`` simulate (``geometry=False``: no meshes)."""
    options = options or PhysicsOptions()
    warnings: list[str] = []
    parts = link_geometry(mech, options.collision, warnings) if geometry else {}
    bodies, density = link_bodies(mech, parts, warnings, options.density, options.mass, options.mass_source)
    if options.payload is not None:
        bodies = with_payload(mech, bodies, options.payload)
    poses = link_poses(mech)  # home, asked once by the gains and by the contact filter
    joints = _joints(mech, bodies, poses, options)
    filtered = _filtered(mech, bodies, poses, options.disabled)
    return RobotPhysics(bodies, joints, filtered, density, options.collision, tuple(warnings), options.mass_source,
                        options.payload, _sized_for(options))


def _sized_for(options: PhysicsOptions) -> str:
    """What the estimated efforts carry beyond the robot's links, in words."""
    if options.payload is not None and options.payload.mass > 0:
        return f"the payload {options.payload.mass:g} kg"
    if options.rated_payload:
        return f"the rated payload {options.rated_payload:g} kg at the flange"
    return ""


def _joints(mech: Mechanism, bodies: dict[str, BodyPhysics], poses: dict,
            options: PhysicsOptions) -> dict[str, JointPhysics]:
    carried, rated_bodies = subtrees(mech), _rated(mech, bodies, options)
    out = {}
    for j, link, axis, point in joint_axes(mech, poses):
        moved = [bodies[c] for c in carried[link] if c in bodies and bodies[c].mass > 0]
        rated = [b for b in rated_bodies if b.link in carried[link]]
        armature = default_armature(mech, bodies, poses, j.revolute) if options.armature is None else options.armature
        inertia = axis_inertia(moved, poses, axis, point, j.revolute) + armature
        sizing = inertia + axis_inertia(rated, poses, axis, point, j.revolute)
        out[j.name] = _joint_physics(j, inertia, armature, _gravity_load(mech, j, moved + rated), options, sizing)
    return out


def _rated(mech: Mechanism, bodies: dict[str, BodyPhysics], options: PhysicsOptions) -> list[BodyPhysics]:
    """The rated payload as a point mass at the first flange, where no payload is given: what the
    estimated efforts must carry (it is not authored in the model's masses)."""
    if options.payload is not None or not options.rated_payload or not mech.flanges:
        return []
    flange = mech.flanges[0]
    origin = bodies[flange.link].origin
    return [BodyPhysics(flange.link, origin, (), float(options.rated_payload), flange.pose.matrix()[:3, 3] - origin)]


def _gravity_load(mech: Mechanism, j, moved) -> float:
    """An upper bound of the gravity force or torque on joint ``j`` over every pose: each carried
    mass at the longest lever its chain of joints allows (distances measured at the zero position)."""
    if not j.revolute:
        return GRAVITY * sum(b.mass for b in moved)
    graph = mech.graph
    lever = {j.child: (np.asarray(j.point1, float), 0.0)}  # link -> (its joint's point, chain length)

    def reach(link: str) -> tuple[np.ndarray, float]:
        if link not in lever:
            tj = graph.tree_joint[graph.index[link]]
            anchor, length = reach(tj.parent)
            p = np.asarray(tj.point1, float)
            lever[link] = (p, length + float(np.linalg.norm(p - anchor)))
        return lever[link]

    load = 0.0
    for b in moved:
        anchor, length = reach(b.link)
        load += b.mass * (length + float(np.linalg.norm(b.origin + b.com - anchor)))
    return GRAVITY * load


def _joint_physics(j, inertia: float, armature: float, load: float, options: PhysicsOptions,
                   sizing: float) -> JointPhysics:
    """The joint's drive and limit gains from what it moves (``inertia``); its effort, where no
    data gives one, from its gravity ``load`` and the inertia it must accelerate (``sizing``:
    with the rated payload)."""
    w_limit = 2 * math.pi * LIMIT_HZ
    stiffness = damping = 0.0
    if options.drive_hz is not None:
        w = 2 * math.pi * options.drive_hz
        stiffness, damping = inertia * w * w, 2 * inertia * w
    given = {name: (v, e) for name, v, e in options.axis_limits}
    data_velocity, data_effort = given.get(j.name, (math.nan, math.nan))
    effort = options.effort if options.effort is not None else \
        data_effort if math.isfinite(data_effort) else EFFORT_MARGIN * load + sizing * ACCELERATION
    velocity = options.velocity or (data_velocity if math.isfinite(data_velocity) else VELOCITY[j.revolute])
    return JointPhysics(
        name=j.name, revolute=j.revolute, inertia=inertia, armature=armature, stiffness=stiffness,
        damping=damping, limit_stiffness=inertia * w_limit ** 2, limit_damping=2 * inertia * w_limit,
        effort=effort, velocity=velocity)


def _filtered(mech: Mechanism, bodies: dict[str, BodyPhysics], poses: dict,
              disabled=()) -> tuple[tuple[str, str, str], ...]:
    """Link pairs kept from colliding: joined by a joint, touching at home (their pieces within
    ``CONTACT_MARGIN``), which would otherwise push the robot off its home pose at the start, and
    those a collision matrix disables (``disabled``)."""
    graph = mech.graph
    order = [graph.links[k] for k in graph.order]
    solid = [name for name in order if bodies.get(name) and bodies[name].parts]
    # links without geometry are contracted away (MoveIt's rule): links joined through them are adjacent
    adjacent = graph.adjacent_pairs(has_geometry=solid)
    out = [(*_ordered(a, b, order), "adjacent") for a, b in (tuple(p) for p in adjacent)]
    shapes = {name: _posed(bodies[name], poses[name]) for name in solid}
    for i, a in enumerate(solid):
        for b in solid[i + 1:]:
            if frozenset((a, b)) not in adjacent and _touch(shapes[a], shapes[b]):
                out.append((a, b, "overlap at home"))
    have = {frozenset(t[:2]) for t in out}
    for a, b, reason in disabled:
        if a != b and a in solid and b in solid and frozenset((a, b)) not in have:
            have.add(frozenset((a, b)))
            out.append((*_ordered(a, b, order), reason.lower()))
    return tuple(sorted(set(out), key=lambda t: (order.index(t[0]), order.index(t[1]))))


def _ordered(a: str, b: str, order: list[str]) -> tuple[str, str]:
    return (a, b) if order.index(a) <= order.index(b) else (b, a)


def _posed(body: BodyPhysics, pose: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Each piece at home: (box min, box max, halfspaces)."""
    out = []
    for part in body.parts:
        for piece in part.pieces:
            v = piece.vertices @ pose[:3, :3].T + pose[:3, 3]
            out.append((v.min(axis=0), v.max(axis=0), halfspaces(piece, pose)))
    return out


def _touch(a, b) -> bool:
    for lo_a, hi_a, h_a in a:
        for lo_b, hi_b, h_b in b:
            if np.all(lo_a <= hi_b + CONTACT_MARGIN) and np.all(lo_b <= hi_a + CONTACT_MARGIN) \
                    and overlap(h_a, h_b, CONTACT_MARGIN):
                return True
    return False
