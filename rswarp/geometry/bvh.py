"""Bounding-volume hierarchies over triangle meshes, as flat arrays the collision kernels walk.

A tree of oriented boxes, split top-down at the median centroid along the axis whose halves have
the least box surface (balanced:
depth about log2 of the leaf count, so a fixed traversal stack always suffices). Each node's box is
fitted to its triangles along their principal axes (Gottschalk's OBBTree), or axis-aligned where
that is smaller: on the slanted, curved surfaces of castings, oriented boxes hug the surface, so a
walk of two trees in near contact opens several times fewer node pairs. Several meshes share one
set of arrays; each has a root index.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LEAF_TRIANGLES = 1
PIECE_POINTS = 7  # per connected piece: a vertex for the inside test, and six extreme vertices
MAX_DEPTH = 40  # a balanced tree of 2**40 leaves: never reached; the kernels size their stack on it


@dataclass(frozen=True)
class Bvh:
    """Boxes (centre, axes, half-sizes along the axes), children, and triangles in leaf order.

    An inner node has ``left >= 0`` and ``right`` its children; a leaf has ``left = -1 - first``
    and ``right`` = its triangle count, ``first`` indexing ``triangles``."""

    center: np.ndarray  # (nodes, 3) float64, mesh frame
    axes: np.ndarray  # (nodes, 3, 3) float64: the box's axes as columns (a rotation)
    half: np.ndarray  # (nodes, 3) float64, along the axes
    left: np.ndarray  # (nodes,) int32
    right: np.ndarray  # (nodes,) int32
    triangles: np.ndarray  # (n, 3, 3) float64: vertices of each triangle, leaf order
    depth: int


def build_bvh(vertices: np.ndarray, faces: np.ndarray, leaf: int = LEAF_TRIANGLES) -> Bvh:
    """The tree of one mesh (vertices (n, 3), faces (m, 3)); the root is node 0."""
    tri = np.asarray(vertices, np.float64)[np.asarray(faces, np.int64)]
    if len(tri) == 0:
        raise ValueError("a mesh without triangles has no bounding-volume tree")
    cent = tri.mean(axis=1)
    lo_t, hi_t = tri.min(axis=1), tri.max(axis=1)
    perm = np.arange(len(tri))
    nodes: list[list] = []  # [lo, hi, left, right, start, stop, depth]
    stack = [(0, len(tri), -1, False, 0)]  # (start, stop, parent, is_right, depth)
    depth = 0
    while stack:
        start, stop, parent, is_right, d = stack.pop()
        idx = perm[start:stop]
        k = len(nodes)
        nodes.append([lo_t[idx].min(axis=0), hi_t[idx].max(axis=0), 0, 0, start, stop, d])
        if parent >= 0:
            nodes[parent][3 if is_right else 2] = k
        depth = max(depth, d)
        if stop - start <= leaf:
            nodes[k][2], nodes[k][3] = -1 - start, stop - start
            continue
        mid = (stop - start) // 2
        perm[start:stop] = _median_split(idx, cent, lo_t, hi_t, mid)
        stack.append((start + mid, stop, k, True, d + 1))
        stack.append((start, start + mid, k, False, d + 1))
    lo = np.array([n[0] for n in nodes])
    hi = np.array([n[1] for n in nodes])
    spans = np.array([[n[4], n[5], n[6]] for n in nodes], np.int64)
    center, axes, half = _fit_boxes(tri[perm], spans, (lo + hi) / 2, (hi - lo) / 2)
    return Bvh(center=center, axes=axes, half=half, left=np.array([n[2] for n in nodes], np.int32),
               right=np.array([n[3] for n in nodes], np.int32), triangles=tri[perm], depth=depth)


def _median_split(idx: np.ndarray, cent: np.ndarray, lo_t: np.ndarray, hi_t: np.ndarray, mid: int) -> np.ndarray:
    """Triangles ``idx`` ordered so the first ``mid`` have the smaller centroids along the axis (of
    three) whose halves have the least box surface: fewer overlapping boxes where two bodies touch
    than the longest axis gives (a third fewer node tests on the IRB 2600's close pairs)."""
    order = idx[np.argpartition(cent[idx], mid, axis=0)]  # column k: the order along axis k
    lo, hi = order[:mid], order[mid:]
    area = 0.0
    for part in (lo, hi):
        e = hi_t[part].max(axis=0) - lo_t[part].min(axis=0)  # (axis, xyz) extents of that half
        area = area + e[:, 0] * e[:, 1] + e[:, 1] * e[:, 2] + e[:, 2] * e[:, 0]
    return order[:, int(np.argmin(area))]


def _fit_boxes(tri: np.ndarray, spans: np.ndarray, center: np.ndarray, half: np.ndarray):
    """Each node's box (node k holds triangles ``spans[k, 0]:spans[k, 1]``, at depth ``spans[k, 2]``):
    along the principal axes of its vertices, or the axis-aligned one (``center``, ``half``) where
    that has less volume. Vectorized: covariances from prefix sums, extents level by level (the
    nodes of one depth hold disjoint triangles)."""
    origin = tri.reshape(-1, 3).mean(axis=0)
    v = tri - origin
    first = np.concatenate([np.zeros((1, 3)), np.cumsum(v.sum(axis=1), axis=0)])
    second = np.concatenate([np.zeros((1, 3, 3)), np.cumsum(np.einsum("tvi,tvj->tij", v, v), axis=0)])
    start, stop = spans[:, 0], spans[:, 1]
    count = 3.0 * (stop - start)
    mean = (first[stop] - first[start]) / count[:, None]
    cov = (second[stop] - second[start]) / count[:, None, None] - np.einsum("ni,nj->nij", mean, mean)
    axes = np.linalg.eigh(cov)[1]
    axes[:, :, 2] = np.cross(axes[:, :, 0], axes[:, :, 1])  # a proper rotation
    lo = np.full((len(spans), 3), np.inf)
    hi = np.full((len(spans), 3), -np.inf)
    for d in np.unique(spans[:, 2]):
        level = np.nonzero(spans[:, 2] == d)[0]
        level = level[np.argsort(start[level])]
        owner = np.repeat(level, stop[level] - start[level])
        rows = np.concatenate([np.arange(a, b) for a, b in zip(start[level], stop[level])])
        local = np.einsum("tvi,tij->tvj", v[rows], axes[owner])  # vertices in the node's axes
        cuts = np.concatenate([[0], np.cumsum(stop[level] - start[level])[:-1]])
        lo[level] = np.minimum.reduceat(local.min(axis=1), cuts)
        hi[level] = np.maximum.reduceat(local.max(axis=1), cuts)
    oriented = np.prod(hi - lo, axis=1) < np.prod(2 * half, axis=1)
    out_axes = np.where(oriented[:, None, None], axes, np.eye(3))
    out_center = np.where(oriented[:, None], origin + np.einsum("nij,nj->ni", axes, (lo + hi) / 2), center)
    out_half = np.where(oriented[:, None], (hi - lo) / 2, half)
    return out_center, out_axes, out_half


def join(trees: list[Bvh]) -> tuple[Bvh, np.ndarray]:
    """Several trees in one set of arrays, and each one's root index."""
    roots, tri_base, node_base = [], 0, 0
    lefts, rights = [], []
    for t in trees:
        roots.append(node_base)
        inner = t.left >= 0
        lefts.append(np.where(inner, t.left + node_base, t.left - tri_base).astype(np.int32))
        rights.append(np.where(inner, t.right + node_base, t.right).astype(np.int32))
        node_base += len(t.left)
        tri_base += len(t.triangles)
    joined = Bvh(center=np.concatenate([t.center for t in trees]), axes=np.concatenate([t.axes for t in trees]),
                 half=np.concatenate([t.half for t in trees]),
                 left=np.concatenate(lefts), right=np.concatenate(rights),
                 triangles=np.concatenate([t.triangles for t in trees]), depth=max(t.depth for t in trees))
    return joined, np.asarray(roots, np.int32)


def quad_slots(left: np.ndarray, right: np.ndarray, lanes: int) -> tuple[np.ndarray, np.ndarray]:
    """For each inner node, the nodes log2(lanes) levels below it (a node that is a leaf above
    that stands for itself): the boxes a walk tests at once. Returns (each node's record, -1 for a
    leaf; (records, lanes) nodes, -1 where fewer)."""
    inner = np.flatnonzero(left >= 0)
    record = np.full(len(left), -1, np.int32)
    record[inner] = np.arange(len(inner))
    slots = inner[:, None]
    while slots.shape[1] < lanes:
        nodes = np.where(slots >= 0, slots, 0)
        opens = (slots >= 0) & (left[nodes] >= 0)
        first = np.where(opens, left[nodes], slots)
        second = np.where(opens, right[nodes], -1)
        slots = np.stack([first, second], axis=2).reshape(len(inner), -1)
    return record, slots.astype(np.int32)


def component_points(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(pieces, PIECE_POINTS, 3): for each connected piece of a mesh, one of its vertices, then its
    vertices of least and greatest x, y and z. If no surfaces cross, a piece lies inside another
    mesh exactly when its first vertex does; the other six must all lie in that mesh's box first
    (a cheap test that spares most inside-queries)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    f = np.asarray(faces, np.int64)
    v = np.asarray(vertices, np.float64)
    n = len(v)
    rows = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
    cols = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    _, label = connected_components(coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n)), directed=False)
    used = np.unique(f)
    out = []
    for piece in np.unique(label[used]):
        idx = used[label[used] == piece]
        p = v[idx]
        out.append(np.concatenate([p[:1], p[p.argmin(axis=0)], p[p.argmax(axis=0)]]))
    return np.asarray(out, np.float64).reshape(-1, PIECE_POINTS, 3)
