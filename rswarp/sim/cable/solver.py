"""The seam between a cable run and the model that simulates a mechanism's cables. A cable model
implements ``CableSolver``: its state (many environments of every cable, kept on the device, so
cables can meet each other), its step (one frame of substeps, the robot's joints given per
substep), its per-frame statistics per cable by name, and its totals (the wear map), as host
arrays in SI units. Runs, results, reports, playback and Ray read only this interface; a model is
chosen by ``CableOptions.cable_model`` from the registry in ``models``.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar, Mapping

import numpy as np

from ...config import DENSITY, FRAME_RATE, FRICTION, POISSON, SUBSTEPS
from ...errors import InputError, MeshNotFoundError
from ...geometry.meshes import link_mesh
from ...kernels.rod.slots import NOT_FINITE, RUNAWAY
from ...kernels.rod.slots import RUNNING as RUNNING  # the seam's: a status every model writes
from ...options import checked
from ...rsxml.model import Cable, Mechanism
from ..bodies import Environment, environment_body

SLIP = 1.0e-3  # m/s: a contact sliding slower than this grips (the static regime)
GRAVITY = (0.0, 0.0, -9.81)
MAX_SPEED = 100.0  # m/s: a point of a robot's hose faster than this has blown up
REACH = 0.25  # m: clearances are measured up to this far; farther reads as +inf
ITERATIONS = 2  # Gauss-Newton iterations per substep
BEND_FACTOR = 10.0  # the least allowed bend radius, in diameters, unless given

# An environment's status: RUNNING, or why it stopped, NOT_FINITE or RUNAWAY (the codes as the rod
# kernel writes them, ``rswarp.kernels.rod.slots``; a model may add codes of its own).
FAILURES = {NOT_FINITE: "positions became NaN or infinite",
            RUNAWAY: f"a point passed {MAX_SPEED:g} m/s (runaway energy)"}

# What a model gives per cable and frame, by name: (envs,) float64 arrays unless said, SI; an arc
# is metres along the cable from its first control point (NaN: nowhere).
STATISTICS = {
    "status": "int: RUNNING, or the code of why the environment stopped (values below are then unread)",
    "tension": "N: the greatest axial force along the cable over the frame (E A times its stretch)",
    "tension_at": "arc where it was greatest",
    "bend_radius": "m: the least bend radius over the frame (+inf: straight)",
    "bend_at": "arc where it was least",
    "twist": "rad: the twist between the first and last clamps at the frame's end (0 with fewer than two)",
    "twist_rate": "rad/m: the greatest twist per metre over the frame",
    "torque": "N m: the greatest torque the cable carries about itself over the frame",
    "torque_at": "arc where it was greatest",
    "stretch": "the greatest straight distance between consecutive attachments over their cable length",
    "normal_force": "N: the greatest normal force on a segment's contact over the frame (0: none)",
    "sliding_speed": "m/s: the fastest a touching segment slid over the frame",
    "contact_at": "arc of the greatest normal force",
    "pinch": "N: the hardest a segment was pressed from opposite sides over the frame (0: never)",
    "pinch_at": "arc where it was hardest",
    "pinch_slots": "(envs, 2) the slots that pressed it (-1: none)",
    "clearance": "(envs, slots) m: the least clearance to each slot (+inf: beyond reach)",
    "clearance_at": "(envs, slots) arc where it was least",
    "clamp_force": "(envs, attachments, 3) N: the force the cable pulls each attachment's link with, at the "
                   "frame's end (world axes)",
    "clamp_moment": "(envs, attachments, 3) N m: the moment about the control point, likewise",
    "clamp_force_peak": "(envs, attachments) N: the greatest force over the frame",
    "clamp_moment_peak": "(envs, attachments) N m: the greatest moment over the frame",
}
# What a model sums per cable since ``reset_totals``: the wear map, per segment.
TOTALS = {
    "contact_time": "(envs, segments) s in contact with anything",
    "peak_normal": "(envs, segments) N: the greatest normal force on the segment",
    "wear": "(envs, segments, slots) J: normal force times sliding distance, per slot touched (Archard)",
    "bend_cycles": "(envs, segments) times the segment bent tighter than the allowed radius and back",
}
FATIGUE_EXPONENT = 4.0  # Miner's sum of count x curvature range^m: the exponent of the hose's S-N line
FATIGUE_FLOOR = 0.1  # a curvature range under this share of the allowed one's is not counted as a cycle


@dataclass(frozen=True)
class CableOptions:
    """How a run is stepped and judged (SI)."""

    frame_rate: float = FRAME_RATE
    substeps: int = SUBSTEPS
    iterations: int = ITERATIONS  # solver iterations per substep, as the model uses them
    damping: float = 1.0  # 1/s: velocities decay as exp(-damping t)
    density: float = DENSITY
    poisson: float = POISSON
    friction: float = FRICTION
    bend_factor: float = BEND_FACTOR
    min_bend_radius: float | None = None  # m; default bend_factor x the diameter
    floor: float | None = 0.0  # z of the floor (m); None: no floor
    contact: bool = True  # against the link meshes
    environment: tuple[Environment, ...] = ()  # meshes placed in the world
    max_strain: float = 0.005  # axial strain past which a cable is taut: when it first is, is noted
    tool: object = None  # a sim.tool.Tool on the flange, which the cables touch and the videos draw
    record: int = -1  # the environment whose shapes are kept for playback (--usd); -1: none
    # each frame's least clearance to every mesh measured whole (the clearance series, its plot);
    # False: only where it lowers the least so far (a design sweep's verdicts, the same bit for
    # bit), the series then NaN
    frame_clearances: bool = True
    cable_model: str = "rod"  # the model of ``models.CABLE_MODELS``
    device: str = "cpu"
    threads: int | None = None

    def __post_init__(self):
        for name, value in (("frame-rate", self.frame_rate), ("substeps", self.substeps), ("density", self.density),
                            ("poisson", self.poisson), ("friction", self.friction),
                            ("min-bend-radius", self.min_bend_radius), ("floor", self.floor),
                            ("max-strain", self.max_strain)):
            checked(name, value)
        if not (1 <= self.iterations <= 100 and math.isfinite(self.damping) and self.damping >= 0
                and self.bend_factor > 0):
            raise InputError("iterations must be 1 to 100, damping finite and >= 0, bend_factor > 0")


@dataclass(frozen=True)
class ContactMeshes:
    """The meshes a cable may touch (metres): per link, in its zero-position frame (None for a link
    without geometry), then the environment's, each (name, vertices, faces, 4x4 pose in the world).
    ``warnings``: links whose mesh files are missing (no contact with them)."""

    links: tuple
    environment: tuple = ()
    warnings: tuple[str, ...] = ()
    tool: tuple = ()  # (name, link, vertices, faces): the tool riding its link, in its zero-position frame


def contact_meshes(mech: Mechanism, environment: tuple[Environment, ...] = (), tool=None) -> ContactMeshes:
    """Every link's parts as one mesh (``rswarp.geometry.meshes.link_mesh``), the environment's,
    and the ``tool``'s (``sim.tool.Tool``) on the flange."""
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
    placed, taken = [], {*mech.graph.links, "floor", "cables"}
    for env in environment:
        body = environment_body(mech, env, taken)
        taken.add(body.name)
        placed.append((body.name, body.vertices, body.faces, body.pose))
    mounted = ()
    if tool is not None:
        from ..tool import tool_body

        body = tool_body(mech, tool)
        mounted = ((body.name, body.link, body.vertices, body.faces),)
    return ContactMeshes(tuple(out), tuple(placed), tuple(warnings), mounted)


@dataclass(frozen=True)
class CableInfo:
    """One cable as its model sees it: its name, length and radius (m), the least bend radius it is
    held to, its stiffness (E A in N, E I and G J in N m^2), the arc (m from its first control
    point) of each point ``points`` gives and of each segment's middle (the wear map's places),
    and its attachments, named."""

    name: str
    length: float
    radius: float
    allowed_bend_radius: float
    axial_stiffness: float
    bending_stiffness: float
    torsion_stiffness: float
    arc: np.ndarray
    segments: np.ndarray
    attachments: tuple[str, ...]


class CableSolver(ABC):
    """Every cable of a mechanism in many environments. ``cables`` describes each; ``slots`` names
    what a cable can touch, in the order of every per-slot array (the links, the environment's
    meshes, then "floor" and "cables": any cable, itself included); ``failures`` says why an
    environment stopped, by status code (``settle_failures``: while it settled, before t = 0);
    ``dof`` is the mechanism's joints that ``step`` takes."""

    kind: ClassVar[str]  # the name that chooses this model (CableOptions.cable_model)
    designs_at_once: ClassVar[bool] = False  # it takes ``designs=``: environment e runs design e
    failures: Mapping[int, str] = FAILURES
    settle_failures: Mapping[int, str] = FAILURES

    cables: tuple[CableInfo, ...]
    slots: tuple[str, ...]
    dof: int

    @classmethod
    @abstractmethod
    def check(cls, mech: Mechanism, options: CableOptions, links: bool = True) -> None:
        """The error (at a cable's line) a run would give, found without compiling or allocating;
        with ``links``, a rest shape that starts inside a link too (a sweep's designs that do are
        failing rows of it, not errors)."""

    @abstractmethod
    def state(self, envs: int) -> Any:
        """``envs`` environments at the rest shape, at rest, running (on the solver's device)."""

    @abstractmethod
    def step(self, state, qs: np.ndarray, dt: float, base: np.ndarray | None = None) -> None:
        """One frame of length ``dt``: ``qs`` (envs, substeps, dof) the joints at each substep's end;
        ``base`` (envs, substeps, 3) where the robot's base has moved from its start then (a track's
        carriage: the hose runs in the frame the robot starts in, the world's, carriage and all)."""

    @abstractmethod
    def set_damping(self, damping: float) -> None:
        """Velocities decay as exp(-damping t) from now on (settling uses more)."""

    @abstractmethod
    def statistics(self, state) -> list[dict[str, np.ndarray]]:
        """The last frame's ``STATISTICS``, per cable, by name, as host arrays."""

    @abstractmethod
    def reset_totals(self, state) -> None:
        """Start the ``TOTALS`` afresh (after settling)."""

    @abstractmethod
    def totals(self, state) -> list[dict[str, np.ndarray]]:
        """The ``TOTALS`` since ``reset_totals``, per cable, as host arrays."""

    @abstractmethod
    def points(self, state, cable: int, env: int | None = None) -> np.ndarray:
        """Cable ``cable``'s points now: (N, 3) of environment ``env``, or (envs, N, 3) of all, metres."""

    def curvatures(self, state) -> list[np.ndarray] | None:
        """Per cable, each environment's segments' curvature now (envs, segments), 1/m, for the
        fatigue count; None for a model that does not give it (no fatigue reported)."""
        return None


def allowed_bend_radius(cable: Cable, options: CableOptions) -> float:
    """The least bend radius a run holds a cable to (m): given, or ``bend_factor`` diameters."""
    if options.min_bend_radius is not None:
        return float(options.min_bend_radius)
    return options.bend_factor * 2 * cable.radius
