"""``rswarp export`` and what it prints: the mass table (link, mass, centre of mass), the joints'
drive and limit settings, and the link pairs kept from colliding. JSON is SI (metres, radians);
the text uses the file's length unit."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..export import export
from ..export.frames import mechanism_of
from ..export.physics import DRIVE_HZ, PhysicsOptions
from ..export.srdf import collision_matrix
from ..geometry.mass import DEFAULT_DENSITY
from ..motion.payload import read_payload
from ..rsxml.documents import checked
from ..rsxml.model import Mechanism
from ..rsxml.robot_data import data_file, read_limits, read_robot_data
from .output import Output, Warn, ignore
from .poses import rounded


def run_export(path: str, output: str, layout: str | None = None, mesh_paths: str | None = None,
               collision: str = "convexHull", density: float = DEFAULT_DENSITY, mass: float | None = None,
               drive_hz: float = DRIVE_HZ, armature: float | None = None, effort: float | None = None,
               velocity: float | None = None, collision_matrix_srdf: str | None = None,
               collision_samples: int | None = None, limits: str | None = None, payload: str | None = None,
               warn: Warn = ignore) -> Output:
    """``rswarp export``: the file's model as USD or URDF at ``output`` (``drive_hz`` 0: no drives),
    filtering the pairs an SRDF or a collision sweep of ``collision_samples`` disables; the robot's
    mass and axis limits from ``mass``/``limits``, else its robot-data file, else defaults; the
    ``payload`` (``read_payload``) in the flange link's mass. A cell file (``.toml``): the whole cell."""
    if str(path).lower().endswith(".toml"):  # a cell file: every mechanism in it, on one stage
        from .cell_export import run_cell_export

        return run_cell_export(path, output, layout, mesh_paths, (mass, limits, payload, collision_matrix_srdf,
                               collision_samples), warn, density=density, collision=collision, drive_hz=drive_hz,
                               armature=armature, effort=effort, velocity=velocity, data_physics=data_physics)
    model = checked(path).model
    mech = mechanism_of(model)[0]
    axes, mass, source = robot_figures(path, mech, limits, mass)
    load = read_payload(payload, mech) if isinstance(mech, Mechanism) else None
    if payload is not None and load is None:
        raise InputError(f"{path}: --payload needs a robot (an RSXML Mechanism), not a library")
    disabled = collision_matrix(mech, collision_matrix_srdf, collision_samples)
    physics = PhysicsOptions(density=density, mass=mass, collision=collision, drive_hz=drive_hz or None,
                             armature=armature, effort=effort, velocity=velocity, disabled=disabled,
                             axis_limits=axes.rows if axes is not None else (), mass_source=source, payload=load,
                             rated_payload=axes.payload if axes is not None else None)
    result = export(model, output, layout=layout, mesh_paths=mesh_paths, physics=physics)
    for w in result.warnings:
        warn(w)
    doc = export_dict(result)
    doc["axis_limits"] = axes.summary if axes is not None else "joint speeds assumed 90 deg/s (0.5 m/s): give --limits"
    return Output(doc, export_text(result) + f"\njoint limits: {doc['axis_limits']}")


def data_physics(path: str, mech, disabled=()) -> PhysicsOptions:
    """The physics an export of the robot at ``path`` gets from its robot-data file alone (mass,
    axis limits, rated payload), as ``rswarp export`` with no options: what the demo exports."""
    axes, mass, source = robot_figures(path, mech, None, None)
    return PhysicsOptions(mass=mass, mass_source=source, disabled=tuple(disabled),
                          axis_limits=axes.rows if axes is not None else (),
                          rated_payload=axes.payload if axes is not None else None)


@dataclass(frozen=True)
class _Axes:
    rows: tuple[tuple[str, float, float], ...]
    summary: str
    payload: float | None = None  # kg: the robot data's rated payload


def robot_figures(path: str, mech, limits: str | None, mass: float | None):
    """(axis limits, total mass, where the mass comes from): ``limits``/``mass`` as given, else
    the robot-data file beside ``path``; None where neither has them."""
    if not isinstance(mech, Mechanism):  # a library's XML: its mechanisms are built from it, not read
        if limits is not None:
            raise InputError(f"{path}: --limits needs a robot (an RSXML Mechanism), not a library")
        return None, mass, "--mass" if mass is not None else ""
    data_path = data_file(path)
    data = read_robot_data(str(data_path), mech) if data_path is not None else None
    axis = read_limits(limits, mech) if limits is not None else data.limits if data is not None else None
    axes = None
    if axis is not None:
        names = [j.name for j in mech.graph.active]
        rows = tuple((n, float(v), float(e)) for n, v, e in zip(names, axis.velocity, axis.effort))
        effort = "efforts from it" if np.isfinite(axis.effort).all() else "efforts estimated (not given there)"
        axes = _Axes(rows, f"{axis.summary().split(';')[0]}; {effort}", data.payload if data is not None else None)
    if mass is not None:
        return axes, mass, "--mass"
    if data is not None and data.mass is not None:
        return axes, data.mass, data_path.name
    return axes, None, ""


def export_dict(result) -> dict:
    """The export as JSON: output, warnings, masses, joints, filtered pairs (SI, per radian)."""
    robot = result.physics
    return {
        "output": str(result.output),
        "warnings": list(result.warnings),
        "total_mass": robot.total_mass,
        "payload": None if robot.payload is None else {
            "mass": robot.payload.mass, "cog": list(robot.payload.cog), "inertia": list(robot.payload.inertia),
            "aom": list(robot.payload.aom), "source": robot.payload.source},
        "efforts_sized_for": robot.effort_payload,
        "density": robot.density,
        "collision": robot.collision,
        "links": [{"link": b.link, "mass": b.mass, "center_of_mass": (b.origin + b.com).tolist(),
                   "collision_pieces": sum(len(p.pieces) for p in b.parts)} for b in robot.bodies.values()],
        "joints": [{"joint": j.name, "stiffness": j.stiffness, "damping": j.damping, "armature": j.armature,
                    "limit_stiffness": j.limit_stiffness, "limit_damping": j.limit_damping, "effort": j.effort,
                    "velocity": j.velocity, "inertia": j.inertia} for j in robot.joints.values()],
        "filtered_pairs": [{"link1": a, "link2": b, "reason": reason} for a, b, reason in robot.filtered],
    }


def export_text(result) -> str:
    """The mass table and a line each on drives, collisions and the file written."""
    robot, mech = result.physics, result.mechanism
    lf, unit = mech.length_factor, mech.length_unit or "m"
    rows = [(b.link, f"{b.mass:.3f}", *(rounded(float(v), lf, 1e-4) for v in b.origin + b.com))
            for b in robot.bodies.values() if b.mass > 0]
    lines = []
    if rows:
        head = ("link", "mass kg", f"com x {unit}", f"com y {unit}", f"com z {unit}")
        widths = [max(len(r[i]) for r in [head, *rows]) for i in range(5)]
        lines += ["  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in enumerate(zip(r, widths)))
                  for r in [head, *rows]]
        given = f"the robot's mass from {robot.mass_source}; " if robot.mass_source else ""
        carried = robot.payload.mass if robot.payload is not None else 0.0
        lines.append(f"total {robot.total_mass:.3f} kg ({given}density {robot.density:.6g} kg/m^3; centre of mass "
                     "in the base frame at the zero position)")
        if robot.payload is not None:
            cog = ", ".join(rounded(float(v), lf, 1e-4) for v in robot.payload.cog)
            lines.append(f"payload: {carried:g} kg at ({cog}) {unit} from the flange, {robot.payload.source}; in "
                         f"{mech.flanges[0].link}'s mass above (the robot alone: {robot.total_mass - carried:.3f} kg)")
    if robot.effort_payload:
        lines.append(f"efforts not given by data are sized for {robot.effort_payload}")
    driven = [j for j in robot.joints.values() if j.stiffness > 0]
    if driven:
        hz = math.sqrt(driven[0].stiffness / driven[0].inertia) / (2 * math.pi)
        lines.append(f"drives: {len(driven)} joints hold home, critically damped at {hz:.3g} Hz")
    elif robot.joints:
        lines.append("drives: none (--drive-hz 0)")
    adjacent = sum(1 for *_, r in robot.filtered if r == "adjacent")
    groups: dict[str, list[str]] = {}
    for a, b, r in robot.filtered:
        if r != "adjacent":
            groups.setdefault("touching at home" if r == "overlap at home" else f"matrix '{r}'", []).append(f"{a}/{b}")
    lines.append(f"collisions filtered: {adjacent} jointed pairs" + "".join(
        f", {len(v)} {k} ({', '.join(v)})" for k, v in groups.items()))
    lines.append(f"wrote {result.output}")
    return "\n".join(lines)
