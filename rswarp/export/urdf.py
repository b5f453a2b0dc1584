"""Export a mechanism to URDF so that ROS tools and simulators load it without extra arguments.

Link frames are world-aligned at the zero position with their origins on their joints' axes (the
same frames as the USD export). The meshes are written beside the URDF, in metres and in their
link's frame, under ``meshes/<urdf stem>/`` (so robots exported to one folder keep their own):
``<link>_<part>.stl`` for the visuals and the convex collision pieces rswarp computed as
``<link>_<part>_collision[_<i>].stl``. The URDF names them by absolute
path by default, so pinocchio (which resolves a relative mesh path only against package
folders), yourdfpy and Newton find them with no extra arguments; ``mesh_paths="relative"`` writes
``meshes/<stem>/...`` paths for a folder that can be moved (Newton and yourdfpy resolve them against the
URDF's folder; pinocchio then needs ``package_dirs=[folder]``). Flanges become fixed
child links. URDF has no closed chains: a loop's closing joint is left out and its passive joints
become ``<mimic>`` joints of the active ones (as ROS-Industrial's parallel-rod robots do). A passive
joint that is a sum of several active ones (a palletizer's rod turns with J2 - J3) is a chain of
coaxial mimic joints, one per active joint, through massless links ``<joint>_by_<active>``. A loop
that is not linear in the active joints (a four-bar, a balance cylinder) is refused with a clear
error: URDF cannot say it.

Every joint limit carries an effort and a velocity (``physics.JointPhysics``: given, or the
defaults scaled to the robot; never 0, which MuJoCo reads as a joint that cannot move). URDF has
no drives and no armature: simulators take those from their own settings (rswarp's values are in
``export --json``).
"""

from __future__ import annotations

import re
import tempfile
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from ..errors import InputError, model_error
from ..files import cleanup_on_terminate, commit, new_folders
from ..geometry.frames import link_origins
from ..geometry.inertia import BodyPhysics
from ..kinematics.loops import UnsolvedLoop, loops, passive_map
from ..outputs import merge_folder
from ..rsxml.model import Mechanism
from ..transforms import matrix_euler_zyx
from .physics import PhysicsOptions, RobotPhysics, robot_physics
from .srdf import EXPORT_REASONS, srdf_text

SRDF_MARK = "written by rswarp export"

MESHES = "meshes"  # the folder beside the URDF
MESH_PATHS = ("absolute", "relative")


def _f(x: float) -> str:
    """14 significant digits: 9 turned pi/2 by 3e-9 rad; 17 would print the rounding left in
    derived values (a mimic's -1 as -0.9999999999999992)."""
    return f"{float(x):.14g}"


def _origin(m: np.ndarray) -> str:
    rpy = matrix_euler_zyx(m[:3, :3])  # URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll), the same convention
    return f'<origin xyz="{" ".join(_f(v) for v in m[:3, 3])}" rpy="{" ".join(_f(v) for v in rpy)}"/>'


class _Files:
    """Mesh files to write: unique, portable names under ``meshes/``."""

    def __init__(self, stem: str, folder: Path | None = None):
        self.arrays: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self.taken: set[str] = set()  # lower-case: names must differ on case-insensitive disks too
        self.prefix = f"{MESHES}/{stem}"
        self.folder = folder  # where meshes/ will be: absolute paths; None: relative ones

    def add(self, stem: str, vertices: np.ndarray, faces: np.ndarray) -> str:
        base = re.sub(r"[^A-Za-z0-9_.-]", "_", stem) or "mesh"
        name, i = f"{base}.stl", 1
        while name.lower() in self.taken:
            name, i = f"{base}_{i}.stl", i + 1
        self.taken.add(name.lower())
        self.arrays[name] = (vertices, faces)
        return f"{self.prefix}/{name}" if self.folder is None else (self.folder / self.prefix / name).as_posix()

    def write(self, folder: Path) -> None:
        import trimesh

        folder.mkdir()
        for name, (v, f) in self.arrays.items():
            trimesh.Trimesh(v, f, process=False).export(folder / name, file_type="stl")


def to_urdf_text(mech: Mechanism, path: str | Path, physics: PhysicsOptions | RobotPhysics | None = None,
                 files: _Files | None = None) -> tuple[str, list[str]]:
    """The URDF document for a file at ``path``, and warnings; the meshes it names are added to
    ``files`` (written by ``to_urdf``)."""
    graph = mech.graph
    mimics = loop_mimics(mech)
    robot = physics if isinstance(physics, RobotPhysics) else robot_physics(mech, physics)
    files = _Files(Path(path).stem) if files is None else files
    origins = link_origins(mech)
    lines = ['<?xml version="1.0"?>', f"<robot name={quoteattr(mech.name)}>",
             '  <material name="graphite_white"><color rgba="0.843 0.843 0.843 1"/></material>']
    for k in graph.order:
        lines += _link(robot.bodies[graph.links[k]], files)
    taken = set(mech.link_names) | {fl.name for fl in mech.flanges}
    for _, j in graph.tree_order:
        lines += _mimic_chain(mech, j, origins, robot, mimics[j.name], taken) if j.name in mimics else \
            _joint(mech, j, origins, robot)
    lines += _flanges(mech, origins)
    lines.append("</robot>")
    return "\n".join(lines) + "\n", list(robot.warnings)


def _link(body: BodyPhysics, files: _Files) -> list[str]:
    """A <link> with a visual per part, a collision per convex piece, and its inertial."""
    lines = [f"  <link name={quoteattr(body.link)}>"]
    for part in body.parts:
        stem = body.link if part.name == body.link else f"{body.link}_{part.name}"
        mesh = files.add(stem, np.asarray(part.mesh.vertices) - body.origin, np.asarray(part.mesh.faces))
        lines.append(f"    <visual name={quoteattr(part.name)}><geometry><mesh filename={quoteattr(mesh)}/>"
                     '</geometry><material name="graphite_white"/></visual>')
        for i, piece in enumerate(part.pieces):
            suffix = "_collision" if len(part.pieces) == 1 else f"_collision_{i}"
            col = files.add(stem + suffix, piece.vertices - body.origin, piece.faces)
            lines.append(f"    <collision name={quoteattr(part.name)}><geometry><mesh filename={quoteattr(col)}/>"
                         "</geometry></collision>")
    if body.mass > 0:
        c, i = body.com, body.inertia
        xyz = " ".join(_f(v) for v in c)
        lines.append(f'    <inertial><origin xyz="{xyz}" rpy="0 0 0"/><mass value="{_f(body.mass)}"/>'
                     f'<inertia ixx="{_f(i[0, 0])}" ixy="{_f(i[0, 1])}" ixz="{_f(i[0, 2])}" iyy="{_f(i[1, 1])}" '
                     f'iyz="{_f(i[1, 2])}" izz="{_f(i[2, 2])}"/></inertial>')
    return lines + ["  </link>"]


def loop_mimics(mech: Mechanism) -> dict[str, list[tuple[str, float]]]:
    """Each passive tree joint of the loops as (active joint, multiplier) terms of its value; a
    loop whose passive joints are not such sums is the file's error at its closing joint."""
    graph = mech.graph
    if not graph.closing:
        return {}
    try:
        passive = passive_map(graph)
    except UnsolvedLoop as exc:
        raise exc.error(mech, "URDF cannot express") from None
    for k in map(int, ((passive.closed_form[:, 0] != 0) | (passive.unknown >= 0)).nonzero()[0]):
        loop = next(loop for loop in loops(graph) if graph.tree_joint[k] in loop.joints)
        raise model_error(mech, f"joint '{loop.closing.name}' closes a {loop.kind} loop whose passive joints are not "
                                "linear in the active ones: URDF's <mimic> cannot express it (the USD export keeps "
                                "the loop)", loop.closing.line)
    active = [j.name for j in graph.active]
    return {graph.tree_joint[k].name: [(active[c], float(v)) for c, v in enumerate(row) if v != 0.0]
            for k, row in enumerate(passive.mimic) if row.any()}


def _mimic_chain(mech: Mechanism, j, origins: dict, robot: RobotPhysics, terms: list[tuple[str, float]],
                 taken: set) -> list[str]:
    """A passive joint of a loop as coaxial revolute (or prismatic) joints, one per active joint it
    follows, each a <mimic> of that joint; massless links between them (their rotations about one
    axis add up, so the chain turns by the sum)."""
    lines, parent = [], j.parent
    for i, (leader, multiplier) in enumerate(terms):
        last = i == len(terms) - 1
        name, child = (j.name, j.child) if last else (f"{j.name}_by_{leader}", _free(f"{j.name}_by_{leader}", taken))
        if not last:
            lines.append(f"  <link name={quoteattr(child)}/>")
        offset = np.eye(4)
        if i == 0:
            offset[:3, 3] = origins[j.child] - origins[j.parent]
        lim, jp = mech.limit(leader), robot.joints.get(leader)
        lower, upper = sorted((multiplier * lim.min, multiplier * lim.max))
        lines += [f"  <joint name={quoteattr(name)} type={quoteattr('revolute' if j.revolute else 'prismatic')}>",
                  f"    <parent link={quoteattr(parent)}/><child link={quoteattr(child)}/>{_origin(offset)}",
                  f'    <axis xyz="{" ".join(_f(v) for v in j.axis)}"/>',
                  f'    <limit lower="{_f(lower)}" upper="{_f(upper)}" effort="{_f(jp.effort)}" '
                  f'velocity="{_f(jp.velocity)}"/>',
                  f'    <mimic joint={quoteattr(leader)} multiplier="{_f(multiplier)}" offset="0"/>', "  </joint>"]
        parent = child
    return lines


def _free(name: str, taken: set) -> str:
    """``name``, or with a number appended where a link already has it."""
    out, i = name, 1
    while out in taken:
        out, i = f"{name}_{i}", i + 1
    taken.add(out)
    return out


def _joint(mech: Mechanism, j, origins: dict, robot: RobotPhysics) -> list[str]:
    """A tree joint, its origin the child's frame in the parent's; a passive joint outside any loop
    stays at zero and is written fixed."""
    offset = np.eye(4)
    offset[:3, 3] = origins[j.child] - origins[j.parent]
    kind = ("revolute" if j.revolute else "prismatic") if j.active else "fixed"
    lines = [f"  <joint name={quoteattr(j.name)} type={quoteattr(kind)}>",
             f"    <parent link={quoteattr(j.parent)}/><child link={quoteattr(j.child)}/>{_origin(offset)}"]
    if kind != "fixed":
        lines.append(f'    <axis xyz="{" ".join(_f(v) for v in j.axis)}"/>')
        lim, jp = mech.limit(j.name), robot.joints.get(j.name)
        if lim is not None and jp is not None:
            lines.append(f'    <limit lower="{_f(lim.min)}" upper="{_f(lim.max)}" effort="{_f(jp.effort)}" '
                         f'velocity="{_f(jp.velocity)}"/>')
    return lines + ["  </joint>"]


def _flanges(mech: Mechanism, origins: dict) -> list[str]:
    """Each flange as a fixed child link (renamed ``<name>_flange`` where a link has its name)."""
    from ..transforms import translated

    lines, names = [], set(mech.link_names)
    for fl in mech.flanges:
        name = fl.name if fl.name not in names else f"{fl.name}_flange"
        names.add(name)
        lines.append(f"  <link name={quoteattr(name)}/>")
        origin = _origin(translated(fl.pose.matrix(), origins[fl.link]))
        lines.append(f"  <joint name={quoteattr(name + '_joint')} type=\"fixed\"><parent link={quoteattr(fl.link)}/>"
                     f"<child link={quoteattr(name)}/>{origin}</joint>")
    return lines


def to_urdf(mech: Mechanism, path: str | Path, physics: PhysicsOptions | RobotPhysics | None = None, *,
            mesh_paths: str = "absolute", **options) -> list[str]:
    """Write ``mech`` as URDF to ``path`` with its meshes in ``meshes/`` beside it; returns warnings.

    Everything is written into a temporary folder beside the target first; then the meshes are
    moved into ``meshes/`` (files already there that this export does not write are kept) and the
    URDF is renamed into place last, so a reader never sees a URDF naming a missing mesh."""

    path = Path(path)
    if mesh_paths not in MESH_PATHS:
        raise InputError(f"mesh paths must be {' or '.join(MESH_PATHS)}, not {mesh_paths!r}")
    folder = path.parent if str(path.parent) else Path(".")
    files = _Files(path.stem, folder.resolve() if mesh_paths == "absolute" else None)
    srdf = path.with_suffix(".srdf")
    if not isinstance(physics, RobotPhysics):
        physics = robot_physics(mech, physics or PhysicsOptions(**options))
    text, warnings = to_urdf_text(mech, path, physics, files)
    with cleanup_on_terminate(), new_folders(path), \
            tempfile.TemporaryDirectory(dir=folder, prefix=f".{path.stem}.") as tmp:
        tmp = Path(tmp)
        (tmp / path.name).write_text(text)
        # URDF cannot say which pairs never need a contact test: an SRDF beside it does (MoveIt reads
        # it); one the user wrote is left alone
        own_srdf = not srdf.exists() or SRDF_MARK in srdf.read_text(errors="replace")[:400]
        if own_srdf:
            (tmp / srdf.name).write_text(urdf_srdf(mech, physics))
        else:
            warnings.append(f"{srdf}: kept (not written by rswarp); the filtered pairs are in --json")
        if files.arrays:
            files.write(tmp / MESHES)
            with new_folders(folder / files.prefix):  # meshes/ made if missing, removed again on failure
                merge_folder(tmp / MESHES, folder / files.prefix)
        if own_srdf:
            commit(tmp / srdf.name, srdf)
        commit(tmp / path.name, path)
    return warnings


def urdf_srdf(mech: Mechanism, robot: RobotPhysics) -> str:
    """The SRDF of an export's filtered pairs, in MoveIt's words."""
    pairs = [(a, b, EXPORT_REASONS.get(r, r.capitalize())) for a, b, r in robot.filtered]
    return srdf_text(mech.name, pairs, f"{SRDF_MARK}: link pairs the export filters from contact: Adjacent "
                                       "(joined), User (convex pieces within 5 mm at home), and a collision matrix's")
