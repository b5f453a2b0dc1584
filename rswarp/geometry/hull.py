"""A body's convex hull as the graph the collision kernels climb to find support points
(``rswarp.kernels.hull``): its vertices, their neighbours along the hull's edges, and a cube map of
directions giving each a vertex to start from.

The hull's vertices are the mesh's own vertices (qhull picks them, it moves none), so the mesh lies
within the hull exactly. On a convex polytope a vertex that no neighbour improves on along a
direction is the farthest along it, so the climb needs no other search."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

CUBE = 32  # as ``kernels.hull.CUBE``: cells along each side of a cube-map face


@dataclass(frozen=True)
class SupportGraph:
    """Hull vertices (mesh frame), neighbours as CSR (``start`` has one entry more than vertices),
    the cube map's start vertex per cell, and the farthest vertex's distance from the origin."""

    vertices: np.ndarray  # (h, 3) float64
    start: np.ndarray  # (h + 1,) int32
    neighbours: np.ndarray  # (e,) int32, local indices
    cube: np.ndarray  # (6 * CUBE * CUBE,) int32, local indices
    reach: float


def support_graph(vertices: np.ndarray) -> SupportGraph | None:
    """The support graph of the hull of ``vertices``; None where the points span no volume (a
    flat or degenerate mesh: qhull refuses it, and the kernels then leave the pair to the walk)."""
    from scipy.spatial import ConvexHull, QhullError

    points = np.asarray(vertices, np.float64)
    if len(points) < 4:
        return None
    try:
        hull = ConvexHull(points)
    except (QhullError, ValueError):
        return None
    keep = np.asarray(hull.vertices, np.int64)
    local = np.full(len(points), -1, np.int64)
    local[keep] = np.arange(len(keep))
    tri = local[hull.simplices]
    edges = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    edges = np.concatenate([edges, edges[:, ::-1]])  # both ways, each once: sorted by (from, to)
    key = np.unique(edges[:, 0] * len(keep) + edges[:, 1])
    start = np.concatenate([[0], np.cumsum(np.bincount(key // len(keep), minlength=len(keep)))]).astype(np.int32)
    hv = points[keep]
    return SupportGraph(hv, start, (key % len(keep)).astype(np.int32), _cube_map(hv),
                        float(np.linalg.norm(hv, axis=1).max()))


def cube_directions() -> np.ndarray:
    """(6 * CUBE * CUBE, 3): each cube-map cell's central direction, in the kernels' cell order
    (face 2 axis + (negative), then the next axis' row, then the one after's column)."""
    c = (np.arange(CUBE) + 0.5) / CUBE * 2 - 1
    u, v = np.meshgrid(c, c, indexing="ij")
    rows = []
    for face in range(6):
        axis, sign = face // 2, -1.0 if face % 2 else 1.0
        d = np.zeros((CUBE * CUBE, 3))
        d[:, axis] = sign
        d[:, (axis + 1) % 3] = u.ravel()
        d[:, (axis + 2) % 3] = v.ravel()
        rows.append(d)
    return np.concatenate(rows)


def _cube_map(hull_vertices: np.ndarray) -> np.ndarray:
    """Each cell's start vertex: in float32 (a near tie picked either way is as good a start, and
    the float64 product of every direction with every vertex took most of a checker's setup)."""
    return (_DIRECTIONS @ hull_vertices.T.astype(np.float32)).argmax(axis=1).astype(np.int32)


_DIRECTIONS = cube_directions().astype(np.float32)
