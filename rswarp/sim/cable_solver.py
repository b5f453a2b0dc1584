"""The seam between a cable run and the model that simulates one cable. A cable model implements
``CableSolver``: its state (many environments, kept on the device), its step (one frame of
substeps, the robot's joints given per substep), and its per-frame statistics by name, as host
arrays in SI units. Runs, results, reports, playback and Ray read only this interface; a model is
chosen by ``CableOptions.cable_model`` from the registry in ``cable_models``.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar, Mapping

import numpy as np

from ..errors import InputError, MeshNotFoundError
from ..geometry.cable import cable_rest
from ..geometry.meshes import link_mesh
from ..options import checked
from ..rsxml.model import Cable, Mechanism

DENSITY = 1200.0  # kg/m^3: a hose
POISSON = 0.5  # rubber: incompressible, so G = E / 3
YOUNGS_MODULUS = 5e7  # Pa, where the file gives none: a rubber-like dress-pack hose
GRAVITY = (0.0, 0.0, -9.81)
MAX_SPEED = 100.0  # m/s: a point of a robot's hose faster than this has blown up
REACH = 0.25  # m: clearances are measured up to this far; farther reads as +inf
FRAME_RATE = 60.0  # frames per second: results are sampled per frame, substeps between
SUBSTEPS = 10  # per frame: 1.7 ms steps
BEND_FACTOR = 10.0  # the least allowed bend radius, in diameters, unless given

# An environment's status: running, or why it stopped (a model may add codes of its own).
RUNNING, NOT_FINITE, RUNAWAY = 0, 1, 2
FAILURES = {NOT_FINITE: "positions became NaN or infinite",
            RUNAWAY: f"a point passed {MAX_SPEED:g} m/s (runaway energy)"}

# The statistics every model gives per frame, by name: (envs,) arrays unless said, float64, SI.
STATISTICS = {
    "status": "int: RUNNING, or the code of why the environment stopped (values below are then unread)",
    "tension": "N: the greatest axial force along the cable over the frame",
    "bend_radius": "m: the least bend radius over the frame (+inf: straight)",
    "bend_at": "m of arc from the first control point where it was least (NaN: none)",
    "twist": "rad: the twist between the clamped ends at the frame's end, in (-pi, pi]",
    "stretch": "the greatest straight distance between consecutive attachments over their cable length",
    "clearance": "(envs, links + 1) m: the least clearance to each link, then the floor (+inf: beyond reach)",
    "clearance_at": "(envs, links + 1) m of arc where it was least",
}


@dataclass(frozen=True)
class CableOptions:
    """How a run is stepped and judged (SI)."""

    frame_rate: float = FRAME_RATE
    substeps: int = SUBSTEPS
    iterations: int = 2  # solver iterations per substep, as the model uses them
    damping: float = 1.0  # 1/s: velocities decay as exp(-damping t)
    density: float = DENSITY
    bend_factor: float = BEND_FACTOR
    min_bend_radius: float | None = None  # m; default bend_factor x the diameter
    floor: float | None = 0.0  # z of the floor (m); None: no floor
    contact: bool = True  # against the link meshes
    record: int = -1  # the environment whose shapes are kept for playback (--usd); -1: none
    cable_model: str = "chain"  # the model of ``cable_models.CABLE_MODELS``
    device: str = "cpu"
    threads: int | None = None

    def __post_init__(self):
        for name, value in (("frame-rate", self.frame_rate), ("substeps", self.substeps), ("density", self.density),
                            ("min-bend-radius", self.min_bend_radius), ("floor", self.floor)):
            checked(name, value)
        if not (self.iterations >= 1 and math.isfinite(self.damping) and self.damping >= 0 and self.bend_factor > 0):
            raise InputError("iterations must be at least 1, damping finite and >= 0, bend_factor > 0")


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


class CableSolver(ABC):
    """One cable of a mechanism in many environments. ``links`` names the clearance slots (the
    links, then the floor); ``arc`` is the arc length (m, from the first control point) of each
    point ``points`` gives; ``failures`` says why an environment stopped, by status code."""

    kind: ClassVar[str]  # the name that chooses this model (CableOptions.cable_model)
    failures: ClassVar[Mapping[int, str]] = FAILURES

    length: float  # m, along the cable
    torsion_stiffness: float  # GJ, N m^2
    arc: np.ndarray  # (N,) m

    def __init__(self, mech: Mechanism, cable: Cable, options: CableOptions):
        self.name, self.radius = cable.name, float(cable.radius)
        self.links = (*mech.graph.links, "floor")
        self.allowed_bend_radius = allowed_bend_radius(cable, options)

    @classmethod
    def check(cls, mech: Mechanism, cable: Cable, options: CableOptions) -> None:
        """The error (at the cable's line) a run of this cable would give, found without compiling
        or allocating anything: its rest shape, by default."""
        cable_rest(mech, cable)

    @abstractmethod
    def state(self, envs: int) -> Any:
        """``envs`` environments at the rest shape, at rest, running (on the solver's device)."""

    @abstractmethod
    def step(self, state, qs: np.ndarray, dt: float) -> None:
        """One frame of length ``dt``: ``qs`` (envs, substeps, dof) the joints at each substep's end."""

    @abstractmethod
    def set_damping(self, damping: float) -> None:
        """Velocities decay as exp(-damping t) from now on (settling uses more)."""

    @abstractmethod
    def statistics(self, state) -> dict[str, np.ndarray]:
        """The last frame's ``STATISTICS``, by name, as host arrays."""

    @abstractmethod
    def points(self, state, env: int | None = None) -> np.ndarray:
        """The cable's points now: (N, 3) of environment ``env``, or (envs, N, 3) of all, metres."""


def allowed_bend_radius(cable: Cable, options: CableOptions) -> float:
    """The least bend radius a run holds a cable to (m): given, or ``bend_factor`` diameters."""
    if options.min_bend_radius is not None:
        return float(options.min_bend_radius)
    return options.bend_factor * 2 * cable.radius
