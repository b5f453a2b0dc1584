"""Types the kernels and their hosts share, declared once: joint codes, the flat arrays a
mechanism compiles to (``Chain``), and the Warp value types of each precision."""

from functools import lru_cache
from typing import NamedTuple

import numpy as np
import warp as wp

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


class Scalar(NamedTuple):
    """The Warp types of one precision (float32 for batches, float64 for refinement and checks)."""

    scalar: type
    vec3: type
    mat33: type
    mat34: type  # a pose: rotation columns 0-2, translation column 3
    mat44: type


@lru_cache(maxsize=None)
def types_of(scalar) -> Scalar:
    return Scalar(scalar, wp.types.vector(3, scalar), wp.types.matrix((3, 3), scalar),
                  wp.types.matrix((3, 4), scalar), wp.types.matrix((4, 4), scalar))
