"""The payload on the flange (``--payload``): a mass with its centre of gravity, or a RAPID
tooldata's or loaddata's load read from a module as the controller loads it; the heaviest load a
planned task moves with; and how much a load lowers each axis's acceleration and jerk.

The timing rule (docs/payload-timing.md): the robot data's accelerations and jerks hold for the
arm with no load. A load lowers axis i's by J_arm,i / (J_arm,i + J_load,i), both moments of
inertia about axis i at the home pose (masses for a prismatic axis), from the mass model the exports
author too (``geometry.inertia``): the arm's with its armature, the load's its mass at its centre of gravity
plus its own inertia. Loads carried together add up (inertias about one axis add: the parallel-axis
theorem of their rigid union)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from ..geometry.frames import link_poses
from ..geometry.inertia import (
    axis_inertia,
    default_armature,
    joint_axes,
    link_bodies,
    link_geometry,
    subtrees,
    with_payload,
)
from ..rapid import data as rd
from ..rapid.loaded import declared
from ..rapid.moves import NO_LOAD_KG
from ..rapid.parse import SUFFIXES
from ..rapid.task import load_task
from ..rapid.values import Mismatch
from ..rsxml.parse import number
from ..rsxml.robot_data import Payload, robot_data
from ..rsxml.units import MAX_LENGTH

MAX_PAYLOAD = 1e4  # kg: beyond any robot's
FAR_COG = 3.0  # m: a load's centre of gravity this far from the flange is a length in the wrong unit
NO_MASSES = "no link masses (no meshes beside the robot file): the load does not change the timing"


def read_payload(spec: str | None, mech) -> Payload | None:
    """``--payload KG[@x,y,z]`` (the robot file's length unit, in the flange's frame) or
    ``MODULE:NAME`` (a tooldata or loaddata of a RAPID module); None without one."""
    if spec is None:
        return None
    head, sep, name = spec.rpartition(":")
    if sep and head and Path(head).suffix.lower() in SUFFIXES:
        return _from_module(head, name.strip())
    mass, at, where = spec.partition("@")
    usage = (f"--payload '{spec}': give KG, KG@x,y,z (the file's length unit) or MODULE.mod:NAME (a tooldata or "
             "loaddata)")
    try:
        kg = number(mass)
        cog = [mech.si_length(number(v)) for v in where.split(",")] if at else [0.0, 0.0, 0.0]
    except ValueError:
        raise InputError(usage) from None
    if len(cog) != 3:
        raise InputError(usage)
    _check(kg, cog, spec)
    far = float(np.linalg.norm(cog))
    if far > FAR_COG:
        unit = mech.length_unit or "m"
        given = f"{far / mech.length_factor:g} {unit}" + (f" ({far:g} m)" if unit != "m" else "")
        raise InputError(f"--payload '{spec}': a centre of gravity {given} from the flange: the robot file's length "
                         f"unit is {unit}, give x,y,z in it")
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


class LoadFactors:
    """What loads do to one robot's timing: ``factors(*loads)`` (each an ``rd.Load`` or
    ``Payload`` in the flange's frame, or None) is each active axis's acceleration and jerk factor
    with all of them carried at once. The arm's inertias are computed at the first load that
    weighs anything (meshes read: a task with no load pays nothing), each load's once per value."""

    def __init__(self, mech):
        self.mech = mech
        self.dof = len(mech.graph.active)
        self._arm: np.ndarray | None | bool = False  # False: not computed yet; None: no link masses
        self._loads: dict = {}
        self._factors: dict = {}

    @property
    def arm(self) -> np.ndarray | None:
        """The arm's own inertia about each active axis at home, armature included (kg m², kg);
        None where its links have no mass."""
        if self._arm is False:
            self._arm = _arm_inertias(self.mech)
        return self._arm

    @property
    def warning(self) -> str | None:
        """One line where the loads cannot count (the links weigh nothing), else None."""
        return f"{self.mech.path or self.mech.name}: {NO_MASSES}" if self.arm is None else None

    def load_inertias(self, load) -> np.ndarray:
        """The load's inertia about each active axis at home (kg m², kg): its mass at its centre
        of gravity on the flange plus its own inertia (principal moments about its axes of moment)."""
        key = _key(load)
        if key not in self._loads:
            payload = Payload(load.mass, tuple(load.cog), tuple(load.inertia), tuple(load.aom))
            massless, _ = link_bodies(self.mech, {}, [])
            self._loads[key] = _axis_inertias(self.mech, with_payload(self.mech, massless, payload), armature=False)
        return self._loads[key]

    def __call__(self, *loads) -> np.ndarray:
        # each load counts, two of equal value included (a tool and a payload alike weigh twice)
        carried = tuple(sorted(((_key(x), x) for x in loads if _weighs(x)), key=lambda kx: kx[0]))
        found = self._factors.get(tuple(k for k, _ in carried))
        if found is not None:
            return found
        out = np.ones(self.dof)
        if carried and self.arm is not None:
            extra = sum(self.load_inertias(x) for _, x in carried)
            out = np.where(self.arm > 0, self.arm / np.maximum(self.arm + extra, 1e-300), 1.0)
        out.setflags(write=False)
        self._factors[tuple(k for k, _ in carried)] = out
        return out


_BUILT: list = []  # (mechanism, its LoadFactors), the last few robots asked


def load_factors(mech) -> LoadFactors:
    """The robot's ``LoadFactors``, made once per mechanism object (its caches kept with it)."""
    for held, factors in _BUILT:
        if held is mech:
            return factors
    factors = LoadFactors(mech)
    _BUILT.append((mech, factors))
    del _BUILT[:-4]
    return factors


def load_scale(mech, payload: Payload | None = None):
    """What the Planner scales a move's accelerations and jerks by: ``scale(tool_load,
    grip_load)`` -> (dof,), the tool's load (``motion.tool.load`` where the robot holds the tool,
    else None) and GripLoad's (``motion.load``) carried with ``payload`` (``--payload``) on top."""
    factors = load_factors(mech)

    def scale(tool_load, grip_load) -> np.ndarray:
        return factors(tool_load, grip_load, payload)

    return scale


def _arm_inertias(mech) -> np.ndarray | None:
    """Each active axis's inertia of the arm alone, armature included, the links weighing the robot
    data's mass where it gives one; None where no link has a mesh with volume."""
    data = robot_data(mech)
    mass = data.mass if data is not None else None
    try:
        bodies, _ = link_bodies(mech, link_geometry(mech, None, []), [], mass=mass)
    except InputError:  # a mass to share and no mesh volume to share it over: no masses
        if mass is None:
            raise
        return None
    if not sum(b.mass for b in bodies.values()) > 0:
        return None
    return _axis_inertias(mech, bodies, armature=True)


def _axis_inertias(mech, bodies: dict, armature: bool) -> np.ndarray:
    """What each active axis moves at home (``geometry.inertia.axis_inertia``), with the default
    armature or none, in the order of the active axes; 0 for one outside the tree (its factor
    stays 1)."""
    poses, carried = link_poses(mech), subtrees(mech)
    found = {}
    for j, link, axis, point in joint_axes(mech, poses):
        moved = [bodies[c] for c in carried[link] if c in bodies and bodies[c].mass > 0]
        extra = default_armature(mech, bodies, poses, j.revolute) if armature else 0.0
        found[j.name] = axis_inertia(moved, poses, axis, point, j.revolute) + extra
    return np.array([found.get(j.name, 0.0) for j in mech.graph.active], float)


def _weighs(load) -> bool:
    return load is not None and load.mass > NO_LOAD_KG


def _key(load) -> tuple:
    """A load's value (mass, cog, inertia, aom), whatever else it carries (its source)."""
    return (float(load.mass), tuple(map(float, load.cog)), tuple(map(float, load.inertia)),
            tuple(map(float, load.aom)))


def move_loads(motion, payload: Payload | None = None) -> list[tuple[object, str]]:
    """(load, where it comes from) of what a move carries: its tool's load where the robot holds
    the tool, GripLoad's payload, ``payload``; loads that weigh nothing left out."""
    tool, grip = motion.held_loads
    parts = [(tool, f"the tool's tload, from {Path(motion.file).name}:{motion.line}"),
             (grip, getattr(grip, "source", "GripLoad")),
             (payload, payload.source if payload is not None else "")]
    return [(x, why) for x, why in parts if _weighs(x)]


def carried_loads(mech, plan, payload: Payload | None = None) -> list[dict]:
    """Each distinct load the task's moves carry (the tool's, GripLoad's, ``payload``, together
    as one body): its mass, centre of gravity in the flange's frame, where it comes from (the
    first move carrying it), how many moves carry it and the factor each axis's acceleration and
    jerk get (SI)."""
    factors = load_factors(mech)
    out: dict = {}
    seen: dict = {}  # (tool, GripLoad's load) -> the key of what they carry with the payload
    for move in plan.moves:
        m = move.motion
        if m.kind == "wait":
            continue
        held = m.held_loads
        if held not in seen:
            parts = move_loads(m, payload)
            seen[held] = key = tuple(sorted(_key(x) for x, _ in parts))
            if parts and key not in out:
                out[key] = _carried(parts, factors)
        key = seen[held]
        if key:
            out[key]["moves"] += 1
    return list(out.values())


def _carried(parts, factors: LoadFactors) -> dict:
    """Loads carried together as one body: its mass, centre of gravity, sources and factors."""
    mass = sum(x.mass for x, _ in parts)
    cog = sum(x.mass * np.asarray(x.cog, float) for x, _ in parts) / mass
    return {"mass": float(mass), "cog": [float(v) for v in cog], "source": " + ".join(w for _, w in parts),
            "moves": 0, "acceleration_factor": [float(v) for v in factors(*(x for x, _ in parts))]}
