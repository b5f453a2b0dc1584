"""Collision geometry computed once, by rswarp: a convex hull per part, or a convex decomposition
with CoACD, so that exported files hold explicit convex meshes and loaders compute nothing.

Results are cached on disk by the mesh's content (and the method and its settings), so a
re-export or a library build reuses them. The cache folder is ``$RSWARP_CACHE_DIR`` or
``~/.cache/rswarp``; a cache that cannot be read or written is skipped, never an error.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..files import cache_root

METHODS = ("convexHull", "convexDecomposition")
CACHE_VERSION = "2"
# CoACD settings: concavity threshold 0.05 (its default) and at most 16 pieces per part, enough for
# robot castings; the seed makes the decomposition, and so the export, repeatable.
COACD = dict(threshold=0.05, max_convex_hull=16, seed=0)
EXACT_HULL_VERTICES = 100_000  # meshes up to this many vertices get qhull's exact hull
HULL_DIRECTIONS = 1024


@dataclass(frozen=True)
class Convex:
    """One convex piece: vertices (n, 3) float64 and triangles (m, 3) int32, outward wound."""

    vertices: np.ndarray
    faces: np.ndarray


def cache_dir() -> Path:
    return cache_root() / "collision"


def convex_pieces(vertices: np.ndarray, faces: np.ndarray, method: str = "convexHull") -> list[Convex]:
    """The convex pieces standing in for a mesh (in its own coordinates), from the cache when the
    same mesh was seen before with the same method."""
    if method not in METHODS:
        raise ValueError(f"collision must be one of {', '.join(METHODS)}")
    vertices = np.ascontiguousarray(vertices, np.float64)
    faces = np.ascontiguousarray(faces, np.int64)
    key = _key(vertices, faces, method)
    pieces = _cached(key)
    if pieces is None:
        pieces = _hull(vertices) if method == "convexHull" else _decompose(vertices, faces)
        _store(key, pieces)
    return pieces


def _key(vertices: np.ndarray, faces: np.ndarray, method: str) -> str:
    h = hashlib.sha256()
    for part in (CACHE_VERSION, method, repr(sorted(COACD.items())) if method == "convexDecomposition" else ""):
        h.update(part.encode())
    h.update(vertices.tobytes())
    h.update(faces.tobytes())
    return h.hexdigest()


def _hull(vertices: np.ndarray) -> list[Convex]:
    import trimesh

    hull = trimesh.convex.convex_hull(_support_points(vertices))  # qhull, faces wound outward
    return [Convex(np.asarray(hull.vertices, np.float64), np.asarray(hull.faces, np.int32))]


def _support_points(vertices: np.ndarray) -> np.ndarray:
    """Vertices that the hull is built from. A large mesh is first reduced to its extreme points
    along ``HULL_DIRECTIONS`` directions: their hull lies within the exact hull and touches it in
    every one of them, while qhull over millions of points would take seconds and give a hull too
    fine for any solver (MuJoCo and Newton cap hull vertices far lower)."""
    if len(vertices) <= EXACT_HULL_VERTICES:
        return vertices
    i = np.arange(HULL_DIRECTIONS) + 0.5  # a Fibonacci sphere: directions spread evenly
    z = 1 - 2 * i / HULL_DIRECTIONS
    phi = np.pi * (1 + 5 ** 0.5) * i
    dirs = np.stack([np.sqrt(1 - z * z) * np.cos(phi), np.sqrt(1 - z * z) * np.sin(phi), z], axis=1)
    best = np.full(HULL_DIRECTIONS, -np.inf)
    index = np.zeros(HULL_DIRECTIONS, np.int64)
    rows = np.arange(HULL_DIRECTIONS)
    for start in range(0, len(vertices), 8192):  # chunks of 1024 x 8192: 64 MB at most
        proj = dirs @ vertices[start:start + 8192].T  # a row per direction: argmax runs along memory
        k = proj.argmax(axis=1)
        value = proj[rows, k]
        better = value > best
        best[better], index[better] = value[better], k[better] + start
    return vertices[np.unique(index)]


def _decompose(vertices: np.ndarray, faces: np.ndarray) -> list[Convex]:
    import coacd

    coacd.set_log_level("error")
    parts = coacd.run_coacd(coacd.Mesh(vertices, faces.astype(np.int32)), **COACD)
    # each piece is convex already; its hull makes the winding and the vertex set canonical
    return [p for v, _ in parts for p in _hull(np.asarray(v, np.float64))]


def _cached(key: str) -> list[Convex] | None:
    try:
        with np.load(cache_dir() / f"{key}.npz") as data:
            n = int(data["count"])
            return [Convex(data[f"v{i}"], data[f"f{i}"]) for i in range(n)]
    except Exception:  # missing, unreadable or from another version: recompute
        return None


def _store(key: str, pieces: list[Convex]) -> None:
    arrays = {"count": np.array(len(pieces))}
    for i, p in enumerate(pieces):
        arrays[f"v{i}"], arrays[f"f{i}"] = p.vertices, p.faces
    folder = cache_dir()
    with contextlib.suppress(OSError):
        folder.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=".", suffix=".npz", dir=folder)
        try:
            with os.fdopen(fd, "wb") as fh:
                np.savez(fh, **arrays)
            os.replace(tmp, folder / f"{key}.npz")
        finally:
            Path(tmp).unlink(missing_ok=True)


def halfspaces(piece: Convex, pose: np.ndarray | None = None) -> np.ndarray:
    """The piece as halfspaces ``n·x + d <= 0`` (rows [n, d]), optionally posed by a 4x4."""
    from scipy.spatial import ConvexHull

    v = piece.vertices if pose is None else piece.vertices @ pose[:3, :3].T + pose[:3, 3]
    return ConvexHull(v).equations


def overlap(a: np.ndarray, b: np.ndarray, margin: float = 0.0) -> bool:
    """Whether two convex pieces given as halfspaces come within ``margin`` of each other: a point
    inside both, each grown by the margin (a linear feasibility problem; exact for convex sets up
    to the growth of the faces at sharp corners)."""
    from scipy.optimize import linprog

    h = np.vstack([a, b])
    res = linprog(np.zeros(3), A_ub=h[:, :3], b_ub=margin - h[:, 3], bounds=[(None, None)] * 3, method="highs")
    return res.status == 0
