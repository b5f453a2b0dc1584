"""Export a mechanism to URDF so that ROS tools can use RSXML robots.

Link frames are world-aligned at the zero position with their origins on their joints' axes (the
same frames as the USD export). Parts reference their mesh files by a path relative to the URDF,
scaled to metres. Flanges become fixed child links. URDF has no closed chains: a mechanism with a
loop is refused with a clear error.
"""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from ..files import atomic_write
from ..geometry import DEFAULT_DENSITY, METRIC_EXTENSIONS, mass_properties, part_mesh, part_mesh_path
from ..rsxml.model import Mechanism
from ..transforms import matrix_euler_zyx, translated
from .frames import link_origins, tree_error



def _f(x: float) -> str:
    return f"{float(x):.9g}"


def _origin(m: np.ndarray) -> str:
    rpy = matrix_euler_zyx(m[:3, :3])  # URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll), the same convention
    return f'<origin xyz="{" ".join(_f(v) for v in m[:3, 3])}" rpy="{" ".join(_f(v) for v in rpy)}"/>'


def to_urdf_text(mech: Mechanism, path: str | Path, density: float = DEFAULT_DENSITY) -> tuple[str, list[str]]:
    """The URDF document for a file at ``path`` (mesh paths are relative to it), and warnings."""
    graph = mech.graph
    if graph.closing:
        raise tree_error(mech, "URDF")
    origins = link_origins(mech)
    warnings: list[str] = []
    lines = ['<?xml version="1.0"?>', f"<robot name={quoteattr(mech.name)}>",
             '  <material name="graphite_white"><color rgba="0.843 0.843 0.843 1"/></material>']
    for k in graph.order:
        lines += _link(mech, graph.links[k], origins, Path(path).resolve().parent, density, warnings)
    for k, j in graph.tree_order:
        lines += _joint(mech, j, origins)
    lines += _flanges(mech, origins)
    lines.append("</robot>")
    if warnings and not any("<mesh " in line for line in lines):
        warnings = [f"{mech.path or mech.name}: warning: no mesh beside the file for any part: exported "
                    "kinematics only (links without geometry or inertia)"]
    return "\n".join(lines) + "\n", warnings


def _link(mech: Mechanism, link: str, origins: dict, folder: Path, density: float, warnings: list[str]) -> list[str]:
    """A <link> with a visual and a collision per Part that has a mesh, and its inertial."""
    lines, meshes = [f"  <link name={quoteattr(link)}>"], []
    for part, transform in mech.parts(link):
        mesh_file = part_mesh_path(mech, part) if part.source else None
        if mesh_file is None:
            if part.source:
                warnings.append(f"part '{part.name}' of link '{link}': no mesh beside the file; left out")
            continue
        scale = 1.0 if mesh_file.suffix.lower() in METRIC_EXTENSIONS else mech.length_factor
        rel = translated(transform, origins[link])
        file = Path(os.path.relpath(mesh_file.resolve(), folder)).as_posix()
        geometry = (f'<geometry><mesh filename={quoteattr(file)} scale="{_f(scale)} {_f(scale)} {_f(scale)}"/>'
                    "</geometry>")
        lines.append(f"    <visual name={quoteattr(part.name)}>{_origin(rel)}{geometry}"
                     '<material name="graphite_white"/></visual>')
        lines.append(f"    <collision name={quoteattr(part.name)}>{_origin(rel)}{geometry}</collision>")
        meshes.append(part_mesh(mech, part, transform))
    if meshes:
        lines.append(_inertial(meshes, origins[link], density))
    return lines + ["  </link>"]


def _joint(mech: Mechanism, j, origins: dict) -> list[str]:
    """A tree joint, its origin the child's frame in the parent's; a passive joint outside any loop
    stays at zero and is written fixed."""
    offset = np.eye(4)
    offset[:3, 3] = origins[j.child] - origins[j.parent]
    kind = ("revolute" if j.revolute else "prismatic") if j.active else "fixed"
    lines = [f"  <joint name={quoteattr(j.name)} type={quoteattr(kind)}>",
             f"    <parent link={quoteattr(j.parent)}/><child link={quoteattr(j.child)}/>{_origin(offset)}"]
    if kind != "fixed":
        lines.append(f'    <axis xyz="{" ".join(_f(v) for v in j.axis)}"/>')
        lim = mech.limit(j.name)
        if lim is not None:
            # RSXML carries no effort or velocity limits; URDF requires the attributes
            lines.append(f'    <limit lower="{_f(lim.min)}" upper="{_f(lim.max)}" effort="0" velocity="0"/>')
    return lines + ["  </joint>"]


def _flanges(mech: Mechanism, origins: dict) -> list[str]:
    """Each flange as a fixed child link (renamed ``<name>_flange`` where a link has its name)."""
    lines, names = [], set(mech.link_names)
    for fl in mech.flanges:
        name = fl.name if fl.name not in names else f"{fl.name}_flange"
        names.add(name)
        lines.append(f"  <link name={quoteattr(name)}/>")
        lines.append(f"  <joint name={quoteattr(name + '_joint')} type=\"fixed\"><parent link={quoteattr(fl.link)}/>"
                     f"<child link={quoteattr(name)}/>{_origin(translated(fl.pose.matrix(), origins[fl.link]))}</joint>")
    return lines


def _inertial(meshes, origin: np.ndarray, density: float) -> str:
    mass, c, i, _ = mass_properties(meshes, origin, density)
    return (f'    <inertial><origin xyz="{" ".join(_f(v) for v in c)}" rpy="0 0 0"/><mass value="{_f(mass)}"/>'
            f'<inertia ixx="{_f(i[0, 0])}" ixy="{_f(i[0, 1])}" ixz="{_f(i[0, 2])}" iyy="{_f(i[1, 1])}" '
            f'iyz="{_f(i[1, 2])}" izz="{_f(i[2, 2])}"/></inertial>')


def to_urdf(mech: Mechanism, path: str | Path, density: float = DEFAULT_DENSITY) -> list[str]:
    """Write ``mech`` as URDF to ``path`` (atomically); returns warnings."""
    text, warnings = to_urdf_text(mech, path, density)
    atomic_write(path, text.encode())
    return warnings
