"""Types the kernels and their hosts share, declared once: joint codes, the flat arrays a
mechanism compiles to (``Chain``), the Warp value types of each precision, and the struct of the
collision kernels' bodies."""

from typing import NamedTuple

import numpy as np
import warp as wp

from .cache import cached

REVOLUTE = 0
PRISMATIC = 1
FIXED = 2  # the root: no joint moves it


class Chain(NamedTuple):
    """A link tree as plain arrays, links in the mechanism file's order. Every link's frame is the
    world frame at the zero position: a link's pose is its parent's times its joint's screw motion."""

    parent: np.ndarray  # int32 (n,): parent link, -1 for the root
    jtype: np.ndarray  # int32 (n,): REVOLUTE, PRISMATIC or FIXED
    qidx: np.ndarray  # int32 (n,): column of q that drives the link's joint, -1 for none
    axis: np.ndarray  # float64 (n, 3): unit joint axis, world at the zero position
    point: np.ndarray  # float64 (n, 3): a point on the axis
    order: np.ndarray  # int32: the tree's links, parents before children, root first
    mimic: np.ndarray  # float64 (n, dof): a passive joint of a solved loop moves by mimic[k] @ q; zeros else
    closed_form: np.ndarray  # float64 (n, SPEC): a closed form (``specs``: balance cylinder, four-bar); kind 0: none
    closed_input: np.ndarray  # float64 (n, dof): the input angle closed_form[k] reads, closed_input[k] @ q
    unknown: np.ndarray  # int32 (n,): the link's joint as an unknown of the loops' Newton solve; -1: none
    newton_rows: np.ndarray  # float64 (rows, specs.ROW): the loops of that solve

    @property
    def root(self) -> int:
        return int(self.order[0])

    def children(self, k: int) -> list[int]:
        return [int(c) for c in self.order if self.parent[c] == k]

    def ancestors(self, links) -> set[int]:
        """The given links and every link on their paths to the root."""
        keep: set[int] = set()
        for k in links:
            k = int(k)
            while k >= 0 and k not in keep:
                keep.add(k)
                k = int(self.parent[k])
        return keep

    def digest(self) -> str:
        """A content hash: kernels made for equal chains are shared."""
        import hashlib

        h = hashlib.sha256()
        for a in self:
            h.update(np.ascontiguousarray(a).tobytes())
            h.update(b"|")
        return h.hexdigest()[:16]


PIECE_POINTS = 7  # points per connected piece of a body (the host's component_points)
WITNESSES = 8  # crossing triangle pairs kept per cell of a pair's witness grid
QUAD = 4  # boxes the crossing walk tests at once: those two levels below a node, lane by lane
witness_vec = wp.types.vector(length=2 * WITNESSES, dtype=wp.int32)  # (A's, B's) triangle, pair after pair


class Scalar(NamedTuple):
    """The Warp types of one precision (float32 for batches, float64 for refinement and checks)."""

    scalar: type
    vec3: type
    mat33: type
    mat34: type  # a pose: rotation columns 0-2, translation column 3
    mat44: type


@cached
def types_of(scalar) -> Scalar:
    return Scalar(scalar, wp.types.vector(3, scalar), wp.types.matrix((3, 3), scalar),
                  wp.types.matrix((3, 4), scalar), wp.types.matrix((4, 4), scalar))


@cached
def node_struct(scalar=wp.float32):
    """A node of a box tree, its fields side by side: a walk's step reads one node, not six arrays."""
    _, V3, M33, M34, M44 = types_of(scalar)

    @wp.struct
    class Node:
        axes: M33  # the box's axes (columns) in its body's frame
        center: V3
        half: V3  # along the axes
        left: wp.int32  # an inner node's children, left and right; a leaf: -1 - first triangle and
        right: wp.int32  # its triangle count
        quad: wp.int32  # an inner node's record of the QUAD boxes below it, -1: a leaf

    return Node


@cached
def bodies_struct(scalar=wp.float32):
    """The struct of everything the collision kernels read about bodies and pairs (one precision)."""
    _, V3, M33, M34, M44 = types_of(scalar)
    V4 = wp.types.vector(QUAD, scalar)

    @wp.struct
    class BodyArrays:
        link: wp.array(dtype=wp.int32)  # the chain link that moves the body, -1: fixed in the world
        pose: wp.array(dtype=M34)  # a fixed body's pose
        root: wp.array(dtype=wp.int32)  # its tree's root node
        mesh: wp.array(dtype=wp.uint64)  # its wp.Mesh, for point-inside queries
        watertight: wp.array(dtype=wp.int32)  # 1: a closed mesh (inside by ray parity)
        center: wp.array(dtype=V3)  # bounding sphere, body frame
        radius: wp.array(dtype=scalar)
        point_start: wp.array(dtype=wp.int32)  # first connected piece (containment)
        point_count: wp.array(dtype=wp.int32)  # pieces
        points: wp.array(dtype=V3)  # PIECE_POINTS per piece
        nodes: wp.array(dtype=node_struct(scalar))  # oriented box trees, all bodies joined
        # the boxes two levels below each inner node (a child that is a leaf stands for itself),
        # QUAD of them lane by lane, for the crossing walk (``quad``)
        quad_slot: wp.array(dtype=wp.types.vector(QUAD, wp.int32))  # the record's nodes, -1: none
        quad_center: wp.array2d(dtype=V4)  # (records, 3): x, y, z of each box's centre
        quad_axes: wp.array2d(dtype=V4)  # (records, 9): entry 3 r + c of each box's axes
        quad_half: wp.array2d(dtype=V4)  # (records, 3); an empty slot's are -FAR (apart from all)
        triangles: wp.array(dtype=V3)  # three vertices per triangle, leaf order
        pair_a: wp.array(dtype=wp.int32)
        pair_b: wp.array(dtype=wp.int32)
        padding: scalar
        # per pair, a grid over the (at most two) joints its relative pose depends on, holding
        # triangle pairs that cross at each cell's centre: tried before any walk (``witness``)
        cell_start: wp.array(dtype=wp.int32)  # its first cell, -1: no grid
        cell_col: wp.array(dtype=wp.int32)  # two per pair: the q column of each grid axis, -1: none
        cell_lo: wp.array(dtype=scalar)  # two per pair: the axis' lower limit
        cell_scale: wp.array(dtype=scalar)  # two per pair: cells per unit of q
        cell_res: wp.array(dtype=wp.int32)  # two per pair: cells along the axis
        cell_count: wp.array(dtype=wp.int32)  # witnesses in each cell, at most WITNESSES
        # per pair, a cell of the triangle pairs that crossed first most often in a sample of
        # states, tried just before a walk (-1: none; ``witness.first_crossings_kernel``)
        usual: wp.array(dtype=wp.int32)
        witness: wp.array(dtype=V3)  # (WITNESSES, cells, 6): each cell's, six vertices each (A's, B's)
        # per pair, a finer grid over the same axes: 1 in a cell whose every pose keeps the bodies
        # further apart than the padding (``witness.certified_function``)
        cert_start: wp.array(dtype=wp.int32)  # its first cell, -1: no grid
        cert_scale: wp.array(dtype=scalar)  # two per pair: cells per unit of q
        cert_res: wp.array(dtype=wp.int32)  # two per pair: cells along the axis
        cert: wp.array(dtype=wp.uint8)
        # each body's convex hull as the graph its support points climb (``hull``), all bodies joined
        hull_vertex: wp.array(dtype=V3)  # body frame
        hull_adj_start: wp.array(dtype=wp.int32)  # per hull vertex and one more: its first neighbour
        hull_adj: wp.array(dtype=wp.int32)  # the neighbours, as indices into hull_vertex
        hull_cube_start: wp.array(dtype=wp.int32)  # per body: its cube map's first cell, -1: no hull
        hull_cube: wp.array(dtype=wp.int32)  # per cell, the hull vertex farthest along its centre
        hull_reach: wp.array(dtype=scalar)  # per body: its hull's farthest vertex from its frame's origin

    return BodyArrays
