"""Whether one body contains a piece of another, as device code: a point of each connected piece
of the inner body tested inside the outer one, by ray parity on a closed mesh and by the
generalized winding number on an open one. The sweep asks it where the surfaces do not cross."""

import warp as wp

from .cache import cached
from .geometry import FAR
from .types import PIECE_POINTS, bodies_struct, types_of


@cached
def containment_functions(scalar=wp.float32):
    """enclosed(m, a, b, r, t): whether either body contains a piece of the other."""
    S, V3, M33, M34, M44 = types_of(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def in_box(m: BodyArrays, node: int, p: V3) -> bool:
        o = wp.transpose(m.nodes[node].axes) * (p - m.nodes[node].center)
        h = m.nodes[node].half
        return wp.abs(o[0]) <= h[0] and wp.abs(o[1]) <= h[1] and wp.abs(o[2]) <= h[2]

    @wp.func
    def point_inside(m: BodyArrays, body: int, p: wp.vec3) -> bool:
        """Whether a point lies inside a body: on a closed mesh, the parity of three rays' crossings
        (two of three agreeing, so a ray that grazes an edge is outvoted; a quarter of the
        cost of the winding number), else the generalized winding number."""
        if m.watertight[body] == 0:
            q = wp.mesh_query_point_sign_winding_number(m.mesh[body], p, wp.float32(FAR))
            return q.result and q.sign < wp.float32(0.0)
        # three directions off every axis and plane; the third asked only when the first two differ
        votes = wp.mesh_query_ray_count_intersections(m.mesh[body], p, wp.vec3(0.5257311, 0.8506508, 0.0)) % 2
        votes += wp.mesh_query_ray_count_intersections(m.mesh[body], p, wp.vec3(0.0, 0.5257311, 0.8506508)) % 2
        if votes == 1:
            votes += wp.mesh_query_ray_count_intersections(m.mesh[body], p, wp.vec3(0.8506508, 0.0, 0.5257311)) % 2
        return votes >= 2

    @wp.func
    def contains(m: BodyArrays, outer: int, inner: int, r: M33, t: V3) -> bool:
        """Whether a piece of body ``inner`` lies inside closed body ``outer`` (x_outer = r x_inner + t),
        given that their surfaces do not cross: one point per piece decides, once the piece's
        extreme points are all in the outer body's box."""
        root = m.root[outer]
        for k in range(m.point_start[inner], m.point_start[inner] + m.point_count[inner]):
            inside = bool(True)
            for j in range(wp.static(PIECE_POINTS)):
                if inside and not in_box(m, root, r * m.points[PIECE_POINTS * k + j] + t):
                    inside = False
            if inside:
                p = r * m.points[PIECE_POINTS * k] + t
                if point_inside(m, outer, wp.vec3(wp.float32(p[0]), wp.float32(p[1]), wp.float32(p[2]))):
                    return True
        return False

    @wp.func
    def enclosed(m: BodyArrays, a: int, b: int, r: M33, t: V3) -> bool:
        """Whether either body contains a piece of the other (their surfaces being apart)."""
        rt = wp.transpose(r)
        return contains(m, b, a, rt, -(rt * t)) or contains(m, a, b, r, t)

    return enclosed
