"""A tool on the robot's flange (``--tool``): a mesh file placed by ``@x,y,z,rx,ry,rz`` in the
flange's frame, or an RSXML Mechanism of type Tool (its links' parts as one body, its base on the
flange, its first flange its TCP). Read once where the command runs and carried as arrays, so a
task on Ray needs no file of it. The collision checks ride it on the flange's link, against every
other link, the environment and the hoses."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError, model_error
from ..geometry.meshes import file_mesh, link_mesh
from ..rsxml.model import Mechanism
from ..rsxml.parse import number
from ..rsxml.units import MAX_ANGLE, MAX_LENGTH
from ..transforms import euler_zyx_matrix
from .bodies import Body

TCP_GAP = 0.05  # m: a tooldata TCP farther than this from the tool's body is a finding
MECHANISM_SUFFIXES = (".rsxml", ".xml")


@dataclass(frozen=True)
class Tool:
    """The tool's triangles in the flange's frame (m, mounted), and its TCP there where its file
    gives one; compared and hashed by its name and a digest of its arrays."""

    name: str
    source: str  # the --tool text, for the report
    digest: str
    vertices: np.ndarray = field(compare=False, repr=False)
    faces: np.ndarray = field(compare=False, repr=False)
    tcp: np.ndarray | None = field(default=None, compare=False, repr=False)


def load_tool(mech: Mechanism, spec: str | None) -> Tool | None:
    """``--tool PATH[@x,y,z,rx,ry,rz]`` (the robot file's length unit, degrees; R = Rz Ry Rx, ABB's
    Euler ZYX) as a Tool; None without one; an InputError saying what is wrong."""
    if spec is None:
        return None
    if not mech.flanges:
        raise InputError(f"--tool: '{mech.name}' has no flange to mount a tool on")
    path, mount = _mount(mech, spec)
    if Path(path).suffix.lower() in MECHANISM_SUFFIXES:
        mesh, tcp = _mechanism_tool(path)
    else:
        mesh, tcp = _mesh_tool(mech, path), None
    vertices = np.asarray(mesh.vertices, np.float64) @ mount[:3, :3].T + mount[:3, 3]
    faces = np.asarray(mesh.faces, np.int64)
    if not len(faces) or not np.all(np.isfinite(vertices)) or np.abs(vertices).max() > MAX_LENGTH:
        raise InputError(f"--tool {path}: no triangles, or reaching beyond {MAX_LENGTH:g} m")
    digest = hashlib.sha1(vertices.tobytes() + faces.tobytes()).hexdigest()
    return Tool(Path(path).stem, spec, digest, vertices, faces, None if tcp is None else mount @ tcp)


def _mount(mech: Mechanism, spec: str) -> tuple[str, np.ndarray]:
    """The path and the 4x4 mount (m) of ``PATH[@x,y,z,rx,ry,rz]``."""
    path, at, where = spec.rpartition("@")
    if not at:
        return spec, np.eye(4)
    usage = f"--tool '{spec}': give PATH or PATH@x,y,z,rx,ry,rz (the file's length unit and degrees)"
    try:
        values = [number(v) for v in where.split(",")]
    except ValueError:
        raise InputError(usage) from None
    if not path or len(values) != 6:
        raise InputError(usage)
    if max(abs(v) for v in values[3:]) > np.degrees(MAX_ANGLE):
        raise InputError(f"--tool '{spec}': angles within {np.degrees(MAX_ANGLE):.6g} deg ({MAX_ANGLE:g} rad, the "
                         "bound of every angle rswarp reads), please")
    mount = np.eye(4)
    mount[:3, :3] = euler_zyx_matrix(*np.radians(values[3:]))
    mount[:3, 3] = [mech.si_length(v) for v in values[:3]]
    if np.abs(mount[:3, 3]).max() > MAX_LENGTH:
        raise InputError(f"--tool '{spec}': an offset within {MAX_LENGTH:g} m, please")
    return path, mount


def _mesh_tool(mech: Mechanism, path: str):
    try:
        return file_mesh(mech, Path(path))
    except (ValueError, OSError) as exc:
        raise InputError(f"{path}: {exc}") from None


def _mechanism_tool(path: str):
    """A Tool mechanism's parts as one mesh in its base frame, and its first flange's pose."""
    import trimesh

    from ..rsxml.documents import load_mechanism

    tool, _ = load_mechanism(path)
    if tool.type != "Tool":
        raise model_error(tool, f"--tool takes a mechanism of type Tool; '{tool.name}' is a "
                                f"{tool.type or 'mechanism without a type'}")
    meshes = [m for m in (link_mesh(tool, name) for name in tool.graph.links) if m is not None]
    if not meshes:
        raise model_error(tool, f"tool '{tool.name}' has no part with geometry")
    base = tool.base_frame.matrix() if tool.base_frame is not None else np.eye(4)
    inverse = np.linalg.inv(base)
    mesh = trimesh.util.concatenate(meshes)
    mesh.apply_transform(inverse)
    return mesh, (inverse @ tool.flanges[0].pose.matrix() if tool.flanges else None)


def tool_body(mech: Mechanism, tool: Tool | None) -> Body | None:
    """The tool as a collision body riding the flange's link (its zero-position world frame)."""
    import trimesh

    if tool is None:
        return None
    flange = mech.flanges[0]
    at = flange.pose.matrix()
    vertices = tool.vertices @ at[:3, :3].T + at[:3, 3]
    closed = trimesh.Trimesh(tool.vertices, tool.faces, process=False).is_watertight
    return Body(f"tool {tool.name}", mech.graph.link_index(flange.link), vertices, tool.faces, bool(closed),
                tool=True)


def tcp_gap(tool: Tool, tframe: np.ndarray) -> float:
    """How far (m) a TCP (4x4 in the flange's frame) lies from the tool's body: 0 inside it."""
    import trimesh

    mesh = trimesh.Trimesh(tool.vertices, tool.faces, process=False)
    point = np.asarray(tframe, float)[None, :3, 3]
    if mesh.is_watertight and bool(mesh.contains(point)[0]):
        return 0.0
    _, distance, _ = trimesh.proximity.closest_point(mesh, point)
    return float(distance[0])
