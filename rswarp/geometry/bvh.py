"""Bounding-volume hierarchies over triangle meshes, as flat arrays the collision kernels walk.

A tree of axis-aligned boxes in the mesh's own frame, split top-down at the median centroid along
the longest side (balanced: depth about log2 of the leaf count, so a fixed traversal stack always
suffices). Several meshes share one set of arrays; each has a root index.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LEAF_TRIANGLES = 2
MAX_DEPTH = 40  # a balanced tree of 2**40 leaves: never reached; the kernels size their stack on it


@dataclass(frozen=True)
class Bvh:
    """Boxes (centre, half-size), children, and triangles in leaf order.

    An inner node has ``left >= 0`` and ``right`` its children; a leaf has ``left = -1 - first``
    and ``right`` = its triangle count, ``first`` indexing ``triangles``."""

    center: np.ndarray  # (nodes, 3) float64
    half: np.ndarray  # (nodes, 3) float64
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
    nodes: list[list] = []  # [lo, hi, left, right]
    stack = [(0, len(tri), -1, False, 0)]  # (start, stop, parent, is_right, depth)
    depth = 0
    while stack:
        start, stop, parent, is_right, d = stack.pop()
        idx = perm[start:stop]
        k = len(nodes)
        nodes.append([lo_t[idx].min(axis=0), hi_t[idx].max(axis=0), 0, 0])
        if parent >= 0:
            nodes[parent][3 if is_right else 2] = k
        depth = max(depth, d)
        if stop - start <= leaf:
            nodes[k][2], nodes[k][3] = -1 - start, stop - start
            continue
        c = cent[idx]
        axis = int(np.argmax(c.max(axis=0) - c.min(axis=0)))
        mid = (stop - start) // 2
        perm[start:stop] = idx[np.argpartition(c[:, axis], mid)]
        stack.append((start + mid, stop, k, True, d + 1))
        stack.append((start, start + mid, k, False, d + 1))
    lo = np.array([n[0] for n in nodes])
    hi = np.array([n[1] for n in nodes])
    return Bvh(center=(lo + hi) / 2, half=(hi - lo) / 2, left=np.array([n[2] for n in nodes], np.int32),
               right=np.array([n[3] for n in nodes], np.int32), triangles=tri[perm], depth=depth)


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
    joined = Bvh(center=np.concatenate([t.center for t in trees]), half=np.concatenate([t.half for t in trees]),
                 left=np.concatenate(lefts), right=np.concatenate(rights),
                 triangles=np.concatenate([t.triangles for t in trees]), depth=max(t.depth for t in trees))
    return joined, np.asarray(roots, np.int32)


def component_points(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """One vertex of each connected piece of a mesh: if no surfaces cross, a piece lies inside
    another mesh exactly when this vertex does (the containment test of the collision kernels)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    f = np.asarray(faces, np.int64)
    n = len(vertices)
    rows = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
    cols = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    _, label = connected_components(coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n)), directed=False)
    used = np.unique(f)
    _, first = np.unique(label[used], return_index=True)
    return np.asarray(vertices, np.float64)[used[first]]
