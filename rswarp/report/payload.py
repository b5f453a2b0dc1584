"""The payload on the flange (``--payload``): a mass with its centre of gravity, or a RAPID
tooldata's or loaddata's load read from a module as the controller loads it; and the heaviest
load a planned task moves with."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from ..rapid import data as rd
from ..rapid.loaded import declared
from ..rapid.parse import SUFFIXES
from ..rapid.task import load_task
from ..rapid.values import Mismatch
from ..rsxml.parse import number
from ..rsxml.robot_data import Payload
from ..rsxml.units import MAX_LENGTH

MAX_PAYLOAD = 1e4  # kg: beyond any robot's


def read_payload(spec: str | None, mech) -> Payload | None:
    """``--payload KG[@x,y,z]`` (the robot file's length unit, in the flange's frame) or
    ``MODULE:NAME`` (a tooldata or loaddata of a RAPID module); None without one."""
    if spec is None:
        return None
    head, sep, name = spec.rpartition(":")
    if sep and head and Path(head).suffix.lower() in SUFFIXES:
        return _from_module(head, name.strip())
    mass, at, where = spec.partition("@")
    usage = f"--payload '{spec}': give KG, KG@x,y,z (the file's length unit) or MODULE.mod:TOOLDATA"
    try:
        kg = number(mass)
        cog = [mech.si_length(number(v)) for v in where.split(",")] if at else [0.0, 0.0, 0.0]
    except ValueError:
        raise InputError(usage) from None
    if len(cog) != 3:
        raise InputError(usage)
    _check(kg, cog, spec)
    return Payload(kg, tuple(cog), source=f"--payload {spec}")


def _from_module(path: str, name: str) -> Payload:
    cell = declared(load_task([path]), name)
    where = f"{cell.file}:{cell.line}" if cell.file else "predefined"
    try:
        if cell.type == "tooldata":
            tool = rd.tool(cell.value, f"'{name}'")
            if not tool.robhold:
                raise InputError(f"{where}: '{name}' is a stationary tool (robhold FALSE): its load is not on the "
                                 "robot")
            load = tool.load
        elif cell.type == "loaddata":
            load = rd.load(cell.value, f"'{name}'")
        else:
            raise InputError(f"{where}: '{name}' is a {cell.type}, not a tooldata or loaddata")
    except Mismatch as exc:
        raise InputError(f"{where}: {exc}") from None
    _check(load.mass, load.cog, name)
    return Payload(load.mass, load.cog, load.inertia, load.aom, f"{name}'s load ({Path(where).name})")


def _check(kg: float, cog, what: str) -> None:
    if not 0 <= kg <= MAX_PAYLOAD or not np.all(np.isfinite(cog)) or np.abs(cog).max() > MAX_LENGTH:
        raise InputError(f"--payload {what}: a mass of 0 to {MAX_PAYLOAD:g} kg and a centre of gravity within "
                         f"{MAX_LENGTH:g} m, please")


def task_payload(plan) -> Payload | None:
    """The heaviest load of the tooldata a planned task moves with (held by the robot), or None."""
    loads = {(m.motion.tool.load, m.motion.file, m.motion.line) for m in plan.moves
             if m.motion.tool is not None and m.motion.tool.robhold and m.motion.tool.load is not None}
    if not loads:
        return None
    load, file, line = max(loads, key=lambda x: (x[0].mass, x[1], x[2]))
    if load.mass <= 0:
        return None
    return Payload(load.mass, load.cog, load.inertia, load.aom, f"the tooldata's load of the move at "
                   f"{Path(file).name}:{line}")
