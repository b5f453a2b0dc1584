"""The options ``rswarp cable`` and ``rswarp dresspack`` share: how the task runs, the cell
(``config.TaskOptions``), the hose's material and ratings (``config.HoseOptions``). Both commands
build their run's options and ratings here, so that ``rswarp cable best.rsxml --program ...`` with
the same options (``repeat_command``) runs the chosen design exactly as the sweep ran it."""

from __future__ import annotations

import shlex

import numpy as np

from ..config import HoseOptions, TaskOptions
from ..sim.bodies import placed_environments
from ..sim.cable.solver import CableOptions
from ..sim.tool import load_tool
from .verdicts import Ratings


def cable_options(mech, task: TaskOptions, hose: HoseOptions, device: str, record: int = -1) -> CableOptions:
    """A run's options from the user's (``rswarp cable`` and ``rswarp dresspack`` alike): the
    task's floor (None: none; the robot's frame), environment and tool, the hose's material."""
    return CableOptions(frame_rate=hose.frame_rate, substeps=hose.substeps, density=hose.density,
                        poisson=hose.poisson, friction=hose.friction,
                        environment=placed_environments(mech, list(task.environment)), cable_model=hose.cable_model,
                        min_bend_radius=mech.si_length(hose.min_bend_radius), floor=mech.si_length(task.floor),
                        record=record, device=device, tool=load_tool(mech, task.tool), max_strain=hose.max_strain)


def ratings_of(mech, hose: HoseOptions) -> Ratings:
    """The hose's ratings in SI (the static bend radius from the file's length unit, the torsion
    from deg/m to rad/m)."""
    return Ratings(hose.max_strain, mech.si_length(hose.static_bend_radius), np.radians(hose.max_torsion),
                   hose.max_contact_force, hose.max_clamp_load)


# option -> its flag, where rswarp cable takes it (each a field of TaskOptions or of HoseOptions)
_FLAGS = {"routine": "--routine", "cycles": "--cycles", "external_axes": "--external-axes", "limits": "--limits",
          "tool": "--tool", "min_bend_radius": "--min-bend-radius", "static_bend_radius": "--static-bend-radius",
          "max_strain": "--max-strain", "max_torsion": "--max-torsion", "max_contact_force": "--max-contact-force",
          "max_clamp_load": "--max-clamp-load", "density": "--density", "poisson": "--poisson",
          "friction": "--friction", "frame_rate": "--frame-rate", "substeps": "--substeps",
          "rated_cycles": "--rated-cycles", "payload": "--payload"}


def _number(value: float) -> str:
    """A signal's value as short as it reads back the same (``1``, ``0.5``)."""
    short = f"{value:g}"
    return short if float(short) == value else repr(float(value))


def repeat_command(out: str, programs: list[str], task: TaskOptions, hose: HoseOptions, passed: bool) -> str:
    """The ``rswarp cable`` command that runs the chosen design alone, with the options given (those
    that differ from their defaults), into a folder beside the sweep's."""
    name = "best" if passed else "closest"
    folder = out.rstrip("/") or "/"
    words = ["rswarp", "cable", f"{folder}/{name}.rsxml", "--program", *programs, "--out", f"{folder}-{name}"]
    task_default, hose_default = TaskOptions(), HoseOptions()
    for key, flag in _FLAGS.items():
        o, default = (task, task_default) if hasattr(task_default, key) else (hose, hose_default)
        value = getattr(o, key)
        if value != getattr(default, key):
            words += [flag, f"{value:g}" if isinstance(value, float) else str(value)]
    floor = task.floor
    words += ["--no-floor"] if floor is None else ["--floor", f"{floor:g}"] if floor != 0.0 else []
    for signal, value in task.io.items():
        words += ["--io", f"{signal}={_number(value)}"]
    for data, values in task.inputs.items():
        for value in values:
            words += ["--input", f"{data}={value}"]
    for env in task.environment:
        words += ["--env", env]
    return shlex.join(words)
