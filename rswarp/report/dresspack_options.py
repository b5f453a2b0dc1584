"""The options ``rswarp cable`` and ``rswarp dresspack`` share: how the task runs, the cell, the
hose's material and ratings. Both commands build their run's options and ratings here, so that
``rswarp cable best.rsxml --program ...`` with the same options (``repeat_command``) runs the
chosen design exactly as the sweep ran it."""

from __future__ import annotations

import shlex
from dataclasses import dataclass, field

import numpy as np

from ..sim.bodies import placed_environments
from ..sim.cable_solver import DENSITY, FRAME_RATE, FRICTION, POISSON, SUBSTEPS, CableOptions
from ..sim.tool import load_tool
from .verdicts import MAX_STRAIN, MAX_TORSION, Ratings


@dataclass(frozen=True)
class SweepOptions:
    """``rswarp cable``'s program-run options, as the CLI names them (the robot file's length unit)."""

    routine: str = "main"
    io: list | None = None
    cycles: int = 1
    external_axes: str = "auto"
    limits: str | None = None
    floor: float | None = 0.0
    environment: list = field(default_factory=list)
    tool: str | None = None
    min_bend_radius: float | None = None
    static_bend_radius: float | None = None
    max_strain: float = MAX_STRAIN
    max_torsion: float = float(np.degrees(MAX_TORSION))
    max_contact_force: float | None = None
    max_clamp_load: float | None = None
    density: float = DENSITY
    poisson: float = POISSON
    friction: float = FRICTION
    frame_rate: float = FRAME_RATE
    substeps: int = SUBSTEPS
    inputs: list | None = None  # --input NAME=VALUE: what the task's live reads give
    rated_cycles: str | None = None  # --rated-cycles N@R: the hose's bending life
    payload: str | None = None  # --payload: a load carried on top of the tool's, slowing the moves


def cable_options(mech, o: SweepOptions, device: str, cable_model: str = "rod", record: int = -1) -> CableOptions:
    """A run's options from the user's (``rswarp cable`` and ``rswarp dresspack`` alike)."""
    return CableOptions(frame_rate=o.frame_rate, substeps=o.substeps, density=o.density, poisson=o.poisson,
                        friction=o.friction, environment=placed_environments(mech, o.environment or []),
                        cable_model=cable_model, min_bend_radius=mech.si_length(o.min_bend_radius),
                        floor=mech.si_length(o.floor), record=record, device=device, tool=load_tool(mech, o.tool),
                        max_strain=o.max_strain)


def ratings_of(mech, o: SweepOptions) -> Ratings:
    return Ratings(o.max_strain, mech.si_length(o.static_bend_radius), np.radians(o.max_torsion),
                   o.max_contact_force, o.max_clamp_load)


# option -> its flag, where rswarp cable takes it
_FLAGS = {"routine": "--routine", "cycles": "--cycles", "external_axes": "--external-axes", "limits": "--limits",
          "tool": "--tool", "min_bend_radius": "--min-bend-radius", "static_bend_radius": "--static-bend-radius",
          "max_strain": "--max-strain", "max_torsion": "--max-torsion", "max_contact_force": "--max-contact-force",
          "max_clamp_load": "--max-clamp-load", "density": "--density", "poisson": "--poisson",
          "friction": "--friction", "frame_rate": "--frame-rate", "substeps": "--substeps",
          "rated_cycles": "--rated-cycles", "payload": "--payload"}


def repeat_command(out: str, programs: list[str], o: SweepOptions, passed: bool) -> str:
    """The ``rswarp cable`` command that runs the chosen design alone, with the options given, into
    a folder beside the sweep's."""
    name = "best" if passed else "closest"
    folder = out.rstrip("/") or "/"
    words = ["rswarp", "cable", f"{folder}/{name}.rsxml", "--program", *programs, "--out", f"{folder}-{name}"]
    default = SweepOptions()
    for key, flag in _FLAGS.items():
        value = getattr(o, key)
        if value != getattr(default, key):
            words += [flag, f"{value:g}" if isinstance(value, float) else str(value)]
    words += ["--no-floor"] if o.floor is None else ["--floor", f"{o.floor:g}"] if o.floor != 0.0 else []
    for pair in o.io or []:
        words += ["--io", pair]
    for pair in o.inputs or []:
        words += ["--input", pair]
    for env in o.environment or []:
        words += ["--env", env]
    return shlex.join(words)
