"""A robot program's trajectory checked in one batch, a client of the batch engine: at every
sample the joint limits, self-collisions (the collision kernels; pairs a collision matrix
disables, or that touch at the home position, skipped), the environment meshes, the floor (each
link's convex hull, or for a robot without meshes its joint and flange points) and the nearness of
the wrist singularity."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .bodies import Environment, collision_bodies
from .collisions import Checker
from .engine import Job, run_batch
from .tool import Tool, tool_body

CHUNK = 4096  # samples per chunk
SINGULAR = np.radians(1.0)  # |q5| below this is near the wrist singularity


@dataclass
class ProgramTally:
    """Per sample: colliding pairs (T, pairs), the lowest point's height (T,), joints outside their
    limits (T,); filled by chunks, in place."""

    hit: np.ndarray
    low: np.ndarray
    outside: np.ndarray

    def merge(self, other: "ProgramTally") -> None:
        done = ~np.isnan(other.low)
        self.hit[done], self.low[done], self.outside[done] = other.hit[done], other.low[done], other.outside[done]


@dataclass(frozen=True)
class ProgramTools:
    checker: Checker | None
    points: tuple  # (link, (P, 3) points in its zero-position frame, the body's name) for the floor
    kinematics: object


@dataclass(frozen=True)
class ProgramJob(Job):
    name = "program"
    unit = "sample"

    q: np.ndarray  # (T, dof) the trajectory's samples
    lower: np.ndarray
    upper: np.ndarray
    environment: tuple[Environment, ...]
    checked: np.ndarray | None  # (pairs,) the pairs tested, None without meshes
    tool: Tool | None = None  # on the flange

    @property
    def count(self) -> int:
        return -(-len(self.q) // CHUNK)

    def task_items(self, cluster) -> int:
        return max(1, cluster.task_samples // CHUNK)

    def size(self, span: range) -> float:
        return float(max(0, min(span.stop * CHUNK, len(self.q)) - span.start * CHUNK))

    def local_spans(self) -> list[range]:
        return [range(k, k + 1) for k in range(self.count)]

    def files(self) -> tuple[str, ...]:
        return tuple(e.path for e in self.environment)

    def tools_key(self) -> tuple:
        return tuple((e.name, e.path, e.pose.tobytes()) for e in self.environment) + (self.tool,)

    def tools(self, model, device: str, threads: int | None) -> ProgramTools:
        env = tuple(Environment(e.name, model.local(e.path), e.pose) for e in self.environment)
        return program_tools(model.mech, env, device, threads, tool=self.tool)

    def empty(self) -> ProgramTally:
        pairs = 0 if self.checked is None else len(self.checked)
        return ProgramTally(np.zeros((len(self.q), pairs), bool), np.full(len(self.q), np.nan),
                            np.zeros(len(self.q), bool))

    def run(self, tools: ProgramTools, tally: ProgramTally, span: range, tick) -> None:
        for k in span:
            rows = slice(k * CHUNK, min((k + 1) * CHUNK, len(self.q)))
            q = self.q[rows]
            tally.outside[rows] = np.any((q < self.lower - 1e-9) | (q > self.upper + 1e-9), axis=1)
            tally.low[rows] = lowest(tools, q)
            if tools.checker is not None:
                hit, _ = tools.checker.verdicts(q)
                tally.hit[rows] = hit & self.checked


def program_tools(mech, environment: tuple[Environment, ...], device: str = "cpu", threads: int | None = None,
                  padding: float = 0.0, leads: tuple = (), tool: Tool | None = None) -> ProgramTools:
    """The collision kernels of the links, meshes, the ``tool`` and cable ``leads`` (``hose_leads``;
    none for a robot without link meshes; pairs closer than ``padding`` count as touching), and the
    points whose height is the floor's check (the tool's among them)."""
    from ..kinematics.kinematics import Kinematics

    kin = Kinematics(mech, device, threads=threads)
    mounted = tool_body(mech, tool)
    try:
        bodies = collision_bodies(mech, environment, leads, mounted)
    except InputError:
        if not environment:
            bodies = None  # a robot without link meshes
        else:
            try:
                collision_bodies(mech, (), leads)
            except InputError:
                raise InputError("--env meshes are checked against the links' meshes; this robot has none") \
                    from None
            raise  # the robot has meshes: the --env mesh is what failed, and its error says so
    checker = Checker(mech, bodies, padding, device, threads) if bodies is not None else None
    return ProgramTools(checker, floor_points(mech, bodies, mounted), kin)


def checked_pairs(mech, tools: ProgramTools, disabled=()) -> np.ndarray | None:
    """(pairs,) the pairs a program is checked for: all but the ``disabled`` (link1, link2) and
    those touching at the home position; None without meshes."""
    if tools.checker is None:
        return None
    names = tools.checker.bodies.pair_names()
    off = {frozenset(p[:2]) for p in disabled}
    home = tools.checker.verdicts(mech.home_position()[None])[0][0]
    return np.array([frozenset(n) not in off for n in names], bool) & ~home


def floor_points(mech, bodies, tool=None) -> tuple:
    """(link, points) whose lowest world height is the robot's: each moving link's convex hull, or
    its joints' axis points and the flange where no link has a mesh; and each point where a link
    holds a cable, a radius lower (the clamp's hose bottom, at zero)."""
    import trimesh

    graph = mech.graph
    level = _level_links(mech)
    if bodies is not None:
        out = [(b.link, np.asarray(trimesh.Trimesh(b.vertices, b.faces, process=False).convex_hull.vertices), b.name)
               for b in bodies.bodies if b.link >= 0 and b.link not in level]
    else:
        out = [(graph.link_index(j.child), np.array([j.point1], float), j.child) for j in mech.joints
               if j.child in graph.links and graph.link_index(j.child) not in level]
        out += [(graph.link_index(f.link), f.pose.matrix()[None, :3, 3], f.link) for f in mech.flanges]
        if tool is not None:  # with meshes, among the bodies
            hull = trimesh.Trimesh(tool.vertices, tool.faces, process=False).convex_hull.vertices
            out.append((tool.link, np.asarray(hull), tool.name))
    # where a link holds a cable (a tool's clamp, say, beyond the link's mesh): lowered by its radius
    for cable in mech.cables:
        for p in cable.control_points:
            if p.attached_to in graph.links and graph.link_index(p.attached_to) not in level:
                out.append((graph.link_index(p.attached_to), np.array([p.position], float) - [0.0, 0.0, cable.radius],
                            f"{cable.name} on {p.attached_to}"))
    return tuple(out)


def _level_links(mech) -> set[int]:
    """The base, and the links only a vertical first axis moves: they stand on the floor, and
    their heights never change."""
    graph = mech.graph
    out = {graph.link_index(graph.base)}
    first = graph.active[0] if graph.active else None
    if first is not None and abs(abs(first.axis[2]) - 1.0) < 1e-9 and first.parent == graph.base:
        out.add(graph.link_index(first.child))
    return out


def lowest(tools: ProgramTools, q: np.ndarray) -> np.ndarray:
    """(N,) the lowest height (m, world) of the robot at each configuration."""
    poses = tools.kinematics.fk64(q)
    low = np.full(len(q), np.inf)
    for link, pts, _ in tools.points:
        m = poses[:, link]
        z = m[:, 2, :3] @ pts.T  # a matrix product (BLAS): einsum's loop took most of a long program's check
        low = np.minimum(low, z.min(axis=1) + m[:, 2, 3])
    return low


def check_program(mech, q: np.ndarray, environment: tuple[Environment, ...] = (), disabled=(),
                  device: str = "cpu", threads: int | None = None, cluster=None, progress=None,
                  tool: Tool | None = None):
    """(tally, tools) of the trajectory ``q`` with the ``tool`` on the flange: ``disabled`` (link1,
    link2) pairs are not tested, nor those touching at the home position."""
    tools = program_tools(mech, tuple(environment), device, threads, tool=tool)
    checked = checked_pairs(mech, tools, disabled)
    lower, upper = mech.bounds()
    job = ProgramJob(np.ascontiguousarray(q, np.float64), lower, upper, tuple(environment), checked, tool)
    return run_batch(job, mech, tools=tools, device=device, threads=threads, cluster=cluster, progress=progress), \
        tools, checked


def lowest_body(tools: ProgramTools, q: np.ndarray) -> str:
    """The name of the body (a link, the tool, a cable's clamp) lowest in the world at one configuration."""
    poses = tools.kinematics.fk64(q[None])[0]
    heights = [(float(np.min(pts @ poses[link, 2, :3] + poses[link, 2, 3])), name) for link, pts, name in tools.points]
    return min(heights)[1]
