"""The bodies a collision sweep tests: each link with geometry (its parts as one mesh, in the
link's frame: the world at the zero position) and each environment mesh placed in the world, as
the flat arrays of ``rswarp.kernels.collide``; and the pairs to test."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError, MeshNotFoundError
from ..geometry.bvh import MAX_DEPTH, build_bvh, component_points, join, quad_slots
from ..geometry.hull import support_graph
from ..geometry.meshes import file_mesh, link_mesh
from ..rsxml.model import Mechanism
from ..rsxml.parse import number
from ..rsxml.units import MAX_LENGTH


@dataclass(frozen=True)
class Environment:
    """A mesh placed in the world (a floor, a pedestal, a wall): a file read in the mechanism's
    length unit, moved by ``pose`` (4x4, metres)."""

    name: str
    path: str
    pose: np.ndarray = field(default_factory=lambda: np.eye(4), compare=False)


@dataclass(frozen=True)
class Body:
    """A link or an environment mesh: its triangles in its own frame (metres)."""

    name: str
    link: int  # chain link index, -1 for an environment body
    vertices: np.ndarray = field(repr=False)
    faces: np.ndarray = field(repr=False)
    watertight: bool
    pose: np.ndarray = field(default_factory=lambda: np.eye(4), repr=False)  # fixed pose (environment)
    tool: bool = False  # the tool on the flange, riding its link


@dataclass(frozen=True)
class CollisionBodies:
    """Bodies, the pairs tested (indices into ``bodies``), and warnings about the geometry."""

    bodies: tuple[Body, ...]
    pairs: tuple[tuple[int, int], ...]
    adjacent: frozenset[frozenset[str]]
    warnings: tuple[str, ...]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(b.name for b in self.bodies)

    def pair_names(self) -> list[tuple[str, str]]:
        return [(self.bodies[a].name, self.bodies[b].name) for a, b in self.pairs]

    @property
    def links(self) -> tuple[int, ...]:
        return tuple(b.link for b in self.bodies if b.link >= 0)


def placed_environments(mech: Mechanism, specs: list[str]) -> tuple[Environment, ...]:
    """Environment meshes given as ``MESH@x,y,z`` (the mesh file, and where its origin goes in the
    world, in the file's length unit) as placed meshes; anything else is an InputError."""
    out = []
    for spec in specs:
        path, at, where = spec.rpartition("@")
        usage = f"--env '{spec}': give MESH@x,y,z, a mesh file and three numbers in the file's length unit"
        try:
            xyz = [number(v) for v in where.split(",")]
        except ValueError as exc:
            raise InputError(f"{usage} ({exc})" if at and path else usage) from None
        if not at or not path or len(xyz) != 3:
            raise InputError(usage)
        pose = np.eye(4)
        pose[:3, 3] = [mech.si_length(v) for v in xyz]
        if not np.all(np.abs(pose[:3, 3]) <= MAX_LENGTH):
            raise InputError(f"--env '{spec}': a position within {MAX_LENGTH:g} m of the origin, please")
        out.append(Environment(Path(path).stem, path, pose))
    return tuple(out)


def collision_bodies(mech: Mechanism, environment: tuple[Environment, ...] = (),
                     leads: tuple[Body, ...] = (), tool: Body | None = None) -> CollisionBodies:
    """The links with geometry, the environment meshes, the ``tool`` on the flange and the cables'
    ``leads`` (``hose_leads``); pairs: every two links not joined by a joint (links without
    geometry contracted away, as MoveIt does), each environment mesh with every link, the tool with
    every link but the one it is mounted on and with every environment mesh, and each lead with
    every body but its own link's."""
    graph = mech.graph
    bodies, warnings = [], []
    for k in graph.order:
        name = graph.links[k]
        try:
            mesh = link_mesh(mech, name)
        except MeshNotFoundError as exc:
            warnings.append(f"{exc}: link '{name}' left out of the collision sweep")
            continue
        if mesh is None:
            continue
        bodies.append(_body(name, int(k), mesh, np.eye(4), warnings))
        _within_reach(bodies[-1], f"link '{name}'")
    if not bodies:
        raise InputError(f"{mech.path or mech.name}: no link has a mesh: there is nothing to test for collisions")
    links = [b.name for b in bodies]
    for env in environment:
        bodies.append(environment_body(mech, env, {b.name for b in bodies}, warnings))
    adjacent = graph.adjacent_pairs(has_geometry=links)
    pairs = [(i, j) for i in range(len(links)) for j in range(i + 1, len(links))
             if frozenset((links[i], links[j])) not in adjacent]
    pairs += [(i, j) for j in range(len(links), len(bodies)) for i in range(len(links))]
    if tool is not None:  # an environment mesh second, as in every pair with one
        at = len(bodies)
        pairs += [(i, at) for i, b in enumerate(bodies) if 0 <= b.link != tool.link]
        pairs += [(at, j) for j, b in enumerate(bodies) if b.link < 0]
        bodies.append(tool)
    for lead in leads:
        pairs += [(i, len(bodies)) for i, b in enumerate(bodies) if b.link != lead.link]
        bodies.append(lead)
    return CollisionBodies(tuple(bodies), tuple(pairs), adjacent, tuple(warnings))


def hose_leads(mech: Mechanism, allowed) -> tuple[Body, ...]:
    """Where a link clamps a cable, the clamp and the cable's lead out of it as a capsule riding on
    the link: the cable's radius, over sqrt(2 R r), the length in which a cable bent no tighter than
    its allowed radius R (``allowed(cable)``, m) leaves the clamp's line by less than its radius r.
    A link inside it presses the cable against its clamp, or bends it tighter than allowed."""
    import trimesh

    graph, out = mech.graph, []
    for cable in mech.cables:
        r = float(cable.radius)
        length = float(np.sqrt(2 * allowed(cable) * r))
        points = cable.control_points
        for i, p in enumerate(points):
            if p.attached_to not in graph.links or p.direction is None:
                continue
            d = p.unit_direction
            ways = [s for s, far in ((1.0, i < len(points) - 1), (-1.0, i > 0)) if far]
            for sign in ways:
                mesh = trimesh.creation.capsule(height=length, radius=r, count=[8, 8])
                mesh.apply_translation([0.0, 0.0, length / 2])
                mesh.apply_transform(trimesh.geometry.align_vectors([0.0, 0.0, 1.0], sign * d))
                mesh.apply_translation(p.position)
                name = f"{cable.name} clamp on {p.attached_to}" + ("" if len(ways) == 1 else f" ({'+-'[sign < 0]})")
                out.append(Body(name, graph.link_index(p.attached_to), np.asarray(mesh.vertices, np.float64),
                                np.asarray(mesh.faces, np.int64), True))
    return tuple(out)


def environment_body(mech: Mechanism, env: Environment, taken: set[str], warnings: list[str] | None = None) -> Body:
    """An environment mesh as a body in the world; an InputError where its name is ``taken`` (a
    link's or another mesh's), or it is unreadable, empty or out of reach."""
    if env.name in taken:
        raise InputError(f"environment mesh '{env.name}' has the name of another body; rename its file")
    body = _body(env.name, -1, _environment_mesh(mech, env), env.pose, [] if warnings is None else warnings)
    _within_reach(body, f"{env.path}: the environment mesh")
    return body


def placed_body(name: str, mesh, pose: np.ndarray, warnings: list[str]) -> Body:
    """A mesh (a cell unit's link) as a body posed by the caller (``link`` -1), within reach."""
    body = _body(name, -1, mesh, pose, warnings)
    _within_reach(body, f"'{name}'")
    return body


def _body(name: str, link: int, mesh, pose: np.ndarray, warnings: list[str]) -> Body:
    if not mesh.is_watertight:
        warnings.append(f"'{name}': mesh is not closed; whether it contains another body is judged by its "
                        "winding number")
    return Body(name, link, np.asarray(mesh.vertices, np.float64), np.asarray(mesh.faces, np.int64),
                bool(mesh.is_watertight), np.asarray(pose, np.float64))


def _within_reach(body: Body, what: str) -> None:
    """A body placed within ``MAX_LENGTH`` of the origin, with triangles: anything else is not a
    cell's geometry, and float32 kernels could not judge it exactly."""
    if not len(body.faces):
        raise InputError(f"{what} has no triangles")
    placed = body.vertices @ body.pose[:3, :3].T + body.pose[:3, 3]
    if not np.all(np.isfinite(placed)) or np.abs(placed).max() > MAX_LENGTH:
        far = float(np.nanmax(np.abs(np.where(np.isfinite(placed), placed, np.inf))))
        raise InputError(f"{what} reaches {far:.3g} m from the origin; a cell lies within {MAX_LENGTH:g} m "
                         "(the bound of every length rswarp reads)")


def _environment_mesh(mech: Mechanism, env: Environment):
    """An environment mesh, read like a part's (the file's length unit unless glTF), unmoved."""
    try:
        return file_mesh(mech, Path(env.path))
    except FileNotFoundError:
        raise InputError(f"{env.path}: no such environment mesh") from None
    except (ValueError, OSError) as exc:
        raise InputError(f"{env.path}: {exc}") from None


# -- device arrays ---------------------------------------------------------------------------------


class DeviceBodies:
    """The bodies as ``rswarp.kernels.collide`` structs on a device: the box trees, the pieces'
    points, the bounding spheres and the ``wp.Mesh`` objects (which the structs refer to) are made
    once; ``struct(scalar)`` gives the arrays in a precision."""

    def __init__(self, bodies: CollisionBodies, padding: float, device):
        import warp as wp

        self.bodies, self.padding, self.device = bodies, padding, device
        self.tree, self.roots = join([build_bvh(b.vertices, b.faces) for b in bodies.bodies])
        if self.tree.depth > MAX_DEPTH:  # a median split halves every level: unreachable
            raise RuntimeError(f"a collision tree is {self.tree.depth} levels deep, over {MAX_DEPTH}")
        self.points = [component_points(b.vertices, b.faces) for b in bodies.bodies]
        self.spheres = [_sphere(b.vertices) for b in bodies.bodies]
        self.hulls = [support_graph(b.vertices) for b in bodies.bodies]
        self.meshes = [wp.Mesh(points=wp.array(b.vertices.astype(np.float32), dtype=wp.vec3, device=device),
                               indices=wp.array(b.faces.astype(np.int32).ravel(), dtype=wp.int32, device=device),
                               support_winding_number=True)
                       for b in bodies.bodies]
        self._structs: dict = {}

    def struct(self, scalar):
        if scalar not in self._structs:
            self._structs[scalar] = self._make(scalar)
        return self._structs[scalar]

    def _make(self, scalar):
        import warp as wp

        from ..kernels.types import bodies_struct, types_of

        S, V3, M33, M34, _ = types_of(scalar)
        bodies, tree = self.bodies.bodies, self.tree
        # boxes and spheres grown by a hair, each body by its own size and place: rounding to
        # float32 must never shrink them, and a far or huge body must not swell the others' boxes
        # (which would make every walk visit every node pair)
        body_grow = np.array([1e-6 * (np.abs(b.vertices).max(initial=0.0) + np.abs(b.pose[:3, 3]).max() + 1.0)
                              for b in bodies])
        grow = np.repeat(body_grow, np.diff(np.append(self.roots, len(tree.center))))[:, None]
        centre, radius = zip(*self.spheres)
        s = bodies_struct(scalar)()
        arr = lambda a, t: wp.array(np.ascontiguousarray(a), dtype=t, device=self.device)  # noqa: E731
        s.link = arr(np.array([b.link for b in bodies], np.int32), wp.int32)
        s.pose = arr(np.array([b.pose[:3] for b in bodies]), M34)
        s.root = arr(self.roots, wp.int32)
        s.mesh = arr(np.array([m.id for m in self.meshes], np.uint64), wp.uint64)
        s.watertight = arr(np.array([b.watertight for b in bodies], np.int32), wp.int32)
        s.center, s.radius = arr(np.array(centre), V3), arr(np.array(radius) * (1 + 1e-6) + body_grow, S)
        counts = np.array([len(p) for p in self.points], np.int32)
        s.point_start = arr(np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int32), wp.int32)
        s.point_count = arr(counts, wp.int32)
        s.points = arr(np.concatenate(self.points).reshape(-1, 3), V3)
        half = tree.half * (1 + 1e-6) + grow
        s.nodes = self._nodes(scalar, half, self._set_quads(s, scalar, half))
        s.triangles = arr(tree.triangles.reshape(-1, 3), V3)
        pairs = np.array(self.bodies.pairs, np.int32).reshape(-1, 2)
        s.pair_a, s.pair_b = arr(pairs[:, 0], wp.int32), arr(pairs[:, 1], wp.int32)
        s.padding = S(self.padding)
        self._set_witnesses(s, scalar, None)
        self._set_certified(s, scalar, None)
        self._set_hulls(s, scalar)
        return s

    def _set_hulls(self, s, scalar) -> None:
        """Each body's hull support graph (``rswarp.geometry.hull``), all bodies joined; a body
        without one (flat, or too few points) gets cube start -1."""
        import warp as wp

        from ..kernels.types import types_of

        arr = lambda a, t: wp.array(np.ascontiguousarray(a), dtype=t, device=self.device)  # noqa: E731
        verts, starts, adj, cube, cube_start, reach = [np.zeros((0, 3))], [], [], [np.zeros(1, np.int32)], [], []
        first = edges = cells = 0
        for h in self.hulls:
            if h is None:
                cube_start.append(-1)
                reach.append(0.0)
                continue
            verts.append(h.vertices)
            starts.append(h.start[:-1] + edges)
            adj.append(h.neighbours + first)
            cube.append(h.cube + first)
            cube_start.append(cells + 1)  # cell 0 is a placeholder: the arrays are never empty
            reach.append(h.reach)
            first, edges, cells = first + len(h.vertices), edges + len(h.neighbours), cells + len(h.cube)
        starts.append(np.array([edges]))
        s.hull_vertex = arr(np.concatenate(verts) if first else np.zeros((1, 3)), types_of(scalar)[1])
        s.hull_adj_start = arr(np.concatenate(starts).astype(np.int32), wp.int32)
        s.hull_adj = arr(np.concatenate(adj).astype(np.int32) if adj else np.zeros(1, np.int32), wp.int32)
        s.hull_cube_start = arr(np.array(cube_start, np.int32), wp.int32)
        s.hull_cube = arr(np.concatenate(cube).astype(np.int32), wp.int32)
        s.hull_reach = arr(np.array(reach), scalar)

    def _nodes(self, scalar, half: np.ndarray, record: np.ndarray):
        """The tree's nodes as one array of ``node_struct``s."""
        import warp as wp

        from ..kernels.types import node_struct

        node = node_struct(scalar)
        nodes = np.zeros(len(self.tree.left), node.numpy_dtype())
        nodes["axes"], nodes["center"], nodes["half"] = self.tree.axes, self.tree.center, half
        nodes["left"], nodes["right"], nodes["quad"] = self.tree.left, self.tree.right, record
        return wp.array(nodes, dtype=node, device=self.device)

    def _set_quads(self, s, scalar, half: np.ndarray) -> np.ndarray:
        """The boxes two levels below each inner node, four lane by lane (``quad_slots``); an
        empty slot's half-sizes are -FAR, so it is apart from every box. Returns each node's record."""
        import warp as wp

        from ..kernels.geometry import FAR
        from ..kernels.types import QUAD

        record, slots = quad_slots(self.tree.left, self.tree.right, QUAD)
        lanes = lambda a: np.where(slots[:, None, :] >= 0, a[slots].transpose(0, 2, 1), 0.0)  # noqa: E731
        halves = np.where(slots[:, None, :] >= 0, half[slots].transpose(0, 2, 1), -FAR)
        V4 = wp.types.vector(QUAD, scalar)
        arr = lambda a: wp.array(np.ascontiguousarray(a), dtype=V4, device=self.device)  # noqa: E731
        s.quad_slot = wp.array(slots, dtype=wp.types.vector(QUAD, wp.int32), device=self.device)
        s.quad_center = arr(lanes(self.tree.center))
        s.quad_axes = arr(lanes(self.tree.axes.reshape(-1, 9)))
        s.quad_half = arr(halves)
        return record

    def set_witnesses(self, grid, scalar) -> None:
        """Give the struct of one precision its witness grids (``rswarp.sim.witness``)."""
        self._set_witnesses(self.struct(scalar), scalar, grid)

    def _set_witnesses(self, s, scalar, grid) -> None:
        import warp as wp

        from ..kernels.types import WITNESSES, types_of

        pairs = len(self.bodies.pairs)
        arr = lambda a, t: wp.array(np.ascontiguousarray(a), dtype=t, device=self.device)  # noqa: E731
        if grid is None:
            s.cell_start = arr(np.full(pairs, -1, np.int32), wp.int32)
            s.cell_col = arr(np.full(2 * pairs, -1, np.int32), wp.int32)
            s.cell_res = arr(np.ones(2 * pairs, np.int32), wp.int32)
            index = np.full((WITNESSES, 2), -1, np.int32)
            lo = scale = np.zeros(2 * pairs)
        else:
            s.cell_start, s.cell_col = arr(grid.start, wp.int32), arr(grid.col, wp.int32)
            s.cell_res, index = arr(grid.res, wp.int32), grid.witness
            lo, scale = grid.lo, grid.scale
        s.cell_lo, s.cell_scale = arr(lo, scalar), arr(scale, scalar)
        usual = np.full(pairs, -1, np.int32) if grid is None or grid.usual is None else grid.usual
        s.usual = arr(usual.astype(np.int32), wp.int32)
        # each witness's two triangles stored whole (one read, not an index and two triangles), every
        # cell's first witness before any second: the first, which mostly crosses, stays in cache
        index = index.reshape(-1, WITNESSES, 2)
        s.cell_count = arr((index[:, :, 0] >= 0).sum(axis=1).astype(np.int32), wp.int32)
        tri = self.tree.triangles[np.maximum(index, 0)]  # (cells, WITNESSES, 2, 3, 3)
        s.witness = arr(tri.transpose(1, 0, 2, 3, 4).reshape(-1, 3), types_of(scalar)[1])

    def set_certified(self, grid, scalar) -> None:
        """Give the struct of one precision its certified grids (``rswarp.sim.certified_cells``)."""
        self._set_certified(self.struct(scalar), scalar, grid)

    def _set_certified(self, s, scalar, grid) -> None:
        import warp as wp

        pairs = len(self.bodies.pairs)
        arr = lambda a, t: wp.array(np.ascontiguousarray(a), dtype=t, device=self.device)  # noqa: E731
        if grid is None:  # no pair has a grid
            start, res, scale, value = np.full(pairs, -1), np.ones(2 * pairs), np.zeros(2 * pairs), np.zeros(1)
        else:
            start, res, scale, value = grid.start, grid.res, grid.scale, grid.value
        s.cert_start, s.cert_res = arr(start.astype(np.int32), wp.int32), arr(res.astype(np.int32), wp.int32)
        s.cert_scale, s.cert = arr(scale, scalar), arr(value.astype(np.uint8), wp.uint8)


def _sphere(vertices: np.ndarray) -> tuple[np.ndarray, float]:
    """A bounding sphere: the box centre and the farthest vertex from it."""
    c = (vertices.min(axis=0) + vertices.max(axis=0)) / 2
    return c, float(np.sqrt(((vertices - c) ** 2).sum(axis=1).max()))
