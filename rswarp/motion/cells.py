"""A cell file wherever a command takes a robot: the robot it places, the planner that drives its
external axes with the robot's (``motion.cell_plan``), and the external axes in what the
commands write (a move's values by logical axis in the JSON, a column per axis in the CSV)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ..rsxml.cell import Cell, read_cell
from ..rsxml.documents import load_mechanism

CELL_SUFFIX = ".toml"


def is_cell(path) -> bool:
    """Whether ``path`` names a cell file (``cell.toml``) rather than a robot's RSXML."""
    return Path(str(path)).suffix.lower() == CELL_SUFFIX


def robot_of(path) -> tuple:
    """(the robot's mechanism, the cell or None) of an RSXML file or a cell file."""
    if is_cell(path):
        cell = read_cell(path)
        return cell.robot.mechanism, cell
    return load_mechanism(path)[0], None


def cell_planner(cell: Cell, device: str, external_axes: str, limits, load_scale):
    """The planner of a task over ``cell`` (its robot's axis ``limits``, each unit's from its
    robot-data file)."""
    from ..kinematics.cell import CellKinematics
    from .cell_plan import CellPlanner

    return CellPlanner(CellKinematics(cell, device), external_axes=external_axes, limits=limits,
                       load_scale=load_scale)


def tool_spec(cell: Cell | None, tool: str | None) -> str | None:
    """``--tool`` where given, else the cell's ``[tool]`` as ``--tool`` writes it."""
    if tool is not None or cell is None or cell.tool is None:
        return tool
    return cell.tool.spec(cell.robot.mechanism)


def external_values(p, row: int | None) -> dict | None:
    """A trajectory row's external axes by logical axis (SI: m, rad); None outside a cell."""
    if p.ext is None or row is None:
        return None
    return {axis or f"{unit}.{joint}": float(p.ext[row, k]) for k, (axis, unit, joint, _) in enumerate(p.ext_axes)}


def csv_columns(p) -> tuple[list[str], np.ndarray]:
    """The CSV's columns after the joints: each external axis by logical axis, in RAPID's units
    (mm, degrees), as a robtarget's extax writes them."""
    if p.ext is None or not p.ext_axes:
        return [], np.zeros((len(p.times), 0))
    names = [axis or f"{unit}.{joint}" for axis, unit, joint, _ in p.ext_axes]
    factor = np.array([np.degrees(1.0) if revolute else 1000.0 for *_, revolute in p.ext_axes])
    return names, p.ext * factor


def cell_floor(cell: Cell) -> float:
    """The height (m) of the robot's base above the world's floor with every unit at home: the
    floor check runs in the robot's frame (a track's carriage holds the robot above the floor)."""
    from ..kinematics.cell import CellKinematics

    ck = CellKinematics(cell)
    return float(ck.robot_base(ck.split(ck.home()[None]))[0, 2, 3])


def cell_bodies(cell: Cell, plan, rows: np.ndarray, poses: np.ndarray) -> tuple:
    """(the robot's link poses (F, links, 4, 4) in the world, the other bodies to draw as
    ``render_frames`` takes them): each unit's links where the trajectory's ``rows`` put its
    joints, the cell's environment meshes where they stand."""
    from ..geometry.meshes import file_mesh, link_mesh
    from ..kinematics.cell import CellKinematics

    ck = CellKinematics(cell)
    joints = ck.split(plan.ext[rows])
    world = ck.robot_base(joints, len(rows))[:, None] @ poses
    extra = []
    for e in cell.externals:
        links = ck.unit_links(e.name, joints[e.name])
        for k, name in enumerate(e.mechanism.graph.links):
            mesh = link_mesh(e.mechanism, name)
            if mesh is not None and len(mesh.faces):
                extra.append((f"{e.name}.{name}", np.asarray(mesh.vertices, float), np.asarray(mesh.faces),
                              links[:, k]))
    for m in cell.environment:  # a mesh on a unit moves with its flange (the work on a face plate)
        mesh = file_mesh(cell.robot.mechanism, Path(m.path))  # in the robot file's length unit, as checked
        pose = ck.unit_flange(m.on, joints[m.on]) @ m.pose if m.on else np.broadcast_to(m.pose, (len(rows), 4, 4))
        extra.append((m.name, np.asarray(mesh.vertices, float), np.asarray(mesh.faces), pose))
    return world, extra


def with_cell_pairs(cell: Cell, p, tally, names: list, tested, tool=None, device: str = "cpu"):
    """(tally, names, tested) of a program's check with the cell's pairs added: every robot link
    (and its tool) against every unit link and environment mesh at every sample (``sim.cell_check``),
    those touching with everything at home left untested."""
    from ..kinematics.cell import CellKinematics
    from ..sim.cell_check import CellChecker, cell_pairs
    from ..sim.tool import tool_body

    ck = CellKinematics(cell, device)
    found = cell_pairs(ck, tool_body(ck.robot.mech, tool) if tool is not None else None)
    if found is None:
        return tally, names, tested
    checker = CellChecker(ck, found, device)
    hit = checker.hits(p.q, p.ext) & checker.checked
    own = tally.hit if tally.hit.shape[1] else np.zeros((len(p.q), len(names)), bool)
    tally = replace(tally, hit=np.concatenate([own, hit], axis=1))
    before = np.ones(len(names), bool) if tested is None else np.asarray(tested, bool)
    return tally, list(names) + found.pair_names(), np.concatenate([before, checker.checked])


BASE_CHUNK = 100_000  # rows of a trajectory whose base poses are made at once


def base_offsets(cell: Cell | None, plan) -> np.ndarray | None:
    """(T, 3) m: where the robot's base has moved from its start, in the frame it starts in, at
    each row of a plan over ``cell`` (a track's carriage carrying it); None where nothing carries
    the robot. An InputError where its carrier turns it: the hose runs in a frame that slides."""
    if cell is None or cell.carrier is None or plan.ext is None:
        return None
    return _offsets(cell, plan.ext)


def carried(cell: Cell | None, trajectory):
    """A trajectory read from a CSV with the cell's external axes (``eax_a`` .. columns, mm and
    degrees) with its robot carried as they say (``Trajectory.base``); as read otherwise."""
    from ..kinematics.cell import CellKinematics
    from ..rsxml.cell import LOGICAL_AXES

    if cell is None or cell.carrier is None or trajectory.ext is None:
        return trajectory
    ck = CellKinematics(cell)
    extax = np.full((len(trajectory.times), 6), 9e9)
    for k, axis in enumerate(trajectory.ext_axes):
        extax[:, LOGICAL_AXES.index(axis)] = trajectory.ext[:, k]
    return replace(trajectory, base=_offsets(cell, ck.joined(ck.unit_joints(extax), len(extax)), ck))


def _offsets(cell: Cell, ext: np.ndarray, ck=None) -> np.ndarray:
    """(T, 3) the robot's base moved from its first row's pose at each row of external joints
    ``ext``; an InputError where the carrier turns it."""
    from ..errors import InputError
    from ..kinematics.cell import CellKinematics

    ck = ck if ck is not None else CellKinematics(cell)
    start = np.linalg.inv(ck.robot_base(ck.split(ext[:1]))[0])
    out = np.empty((len(ext), 3))
    for lo in range(0, len(ext), BASE_CHUNK):
        part = ext[lo:lo + BASE_CHUNK]
        rel = start @ ck.robot_base(ck.split(part), len(part))
        if np.abs(rel[:, :3, :3] - np.eye(3)).max() > 1e-9:
            raise InputError(f"{cell.path}: '{cell.carrier.name}' turns the robot's base as it moves: a hose run takes "
                             "a carrier that slides (a track), not one that turns")
        out[lo:lo + len(rel)] = rel[:, :3, 3]
    return out


def floor_in_robot(cell: Cell | None, mech, floor: float | None) -> float | None:
    """A ``--floor`` height (the file's length unit) in the world of a cell as the robot's frame has
    it (the robot's base stands above the floor on a carriage); as given without a cell."""
    if cell is None or floor is None:
        return floor
    return floor - cell_floor(cell) / mech.length_factor


def with_meshes(cell: Cell, environment) -> Cell:
    """The cell with ``--env`` meshes (``sim.bodies.Environment``, placed in the world) among its own."""
    from ..rsxml.cell import CellMesh

    return replace(cell, environment=cell.environment + tuple(CellMesh(e.name, e.path, e.pose) for e in environment))
