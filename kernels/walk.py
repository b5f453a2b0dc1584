"""The generic tree walk: forward kinematics that reads the chain from arrays, for chains longer
than ``fk.MAX_UNROLLED_LINKS`` and for arbitrary subsets of links. One module serves every chain
length, so a 1000-axis chain does not compile a 1000-link unrolled kernel."""

import warp as wp

from .cache import cached, module_name
from .closed_forms import closed_function
from .fk import pose_functions, wrist_centre
from .specs import SPEC
from .types import REVOLUTE, types_of


@cached
def generic_walk(scalar=wp.float32):
    """(Tree struct, walk): the chain as device arrays, and a wp.func that writes every link's pose
    into ``poses[i]``, parents first."""
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    S = scalar
    _, to_mat34, apply, _ = pose_functions(scalar)
    closed_value = closed_function(scalar)

    @wp.struct
    class Tree:
        parent: wp.array(dtype=wp.int32)
        jtype: wp.array(dtype=wp.int32)
        qidx: wp.array(dtype=wp.int32)
        axis: wp.array(dtype=V3)
        point: wp.array(dtype=V3)
        order: wp.array(dtype=wp.int32)
        follows: wp.array(dtype=wp.int32)  # 1: a passive joint of a solved loop (mimic or closed rows)
        mimic: wp.array2d(dtype=S)
        closed_form: wp.array(dtype=wp.types.vector(SPEC, S))
        closed_input: wp.array2d(dtype=S)

    @wp.func
    def walk(tree: Tree, q: wp.array2d(dtype=S), i: int, poses: wp.array2d(dtype=M34)):
        for o in range(tree.order.shape[0]):
            k = tree.order[o]
            p = tree.parent[k]
            if p < 0:
                poses[i, k] = to_mat34(wp.identity(n=3, dtype=S), V3())
                continue
            th = S(0.0)
            if tree.qidx[k] >= 0:
                th = q[i, tree.qidx[k]]
            elif tree.follows[k] != 0:  # a passive joint of a solved loop
                arm = S(0.0)
                for c in range(q.shape[1]):
                    th += tree.mimic[k, c] * q[i, c]
                    arm += tree.closed_input[k, c] * q[i, c]
                if tree.closed_form[k][0] != S(0.0):
                    th = closed_value(tree.closed_form[k], arm)
            a = tree.axis[k]
            r = wp.identity(n=3, dtype=S)
            t = th * a
            if tree.jtype[k] == REVOLUTE:
                r = wp.quat_to_matrix(wp.quat_from_axis_angle(a, th))
                t = tree.point[k] - r * tree.point[k]
            if wp.isnan(th):  # past a dead point: no pose at all
                r = r * S(wp.nan)
                t = t * S(wp.nan)
            m = poses[i, p]
            rp = M33(m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2])
            poses[i, k] = to_mat34(rp * r, apply(m, t))

    return Tree, walk


@cached
def generic_kernels(scalar=wp.float32):
    """(Tree struct, frames kernel, wrist_flange kernel) reading the chain from arrays.

    ``frames``: ``frames_out[i, j]`` = pose of link ``links[j]`` times ``offsets[j]``.
    ``wrist_flange``: flange position and wrist centre from link indices and constants. ``poses``
    is a per-configuration scratch array of every link's pose."""
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    S = scalar
    _, _, apply, rotate = pose_functions(scalar)
    centre = wrist_centre(scalar)
    Tree, walk = generic_walk(scalar)
    module = module_name("fk_walk", scalar)

    @wp.kernel(enable_backward=False, module=module)
    def frames(
        # Model:
        tree: Tree,
        links: wp.array(dtype=wp.int32),
        offsets: wp.array(dtype=M44),
        # In:
        q: wp.array2d(dtype=S),
        # Scratch:
        poses: wp.array2d(dtype=M34),
        # Out:
        frames_out: wp.array2d(dtype=M44),
    ):
        i = wp.tid()
        walk(tree, q, i, poses)
        for j in range(links.shape[0]):
            m = poses[i, links[j]]
            full = M44(m[0, 0], m[0, 1], m[0, 2], m[0, 3], m[1, 0], m[1, 1], m[1, 2], m[1, 3],
                       m[2, 0], m[2, 1], m[2, 2], m[2, 3], S(0.0), S(0.0), S(0.0), S(1.0))
            frames_out[i, j] = full * offsets[j]

    @wp.kernel(enable_backward=False, module=module)
    def wrist_flange(
        # Model: links = (flange link, J4's link, J5's link); consts = (flange offset, p4, a4, p5, a5)
        tree: Tree,
        links: wp.array(dtype=wp.int32),
        consts: wp.array(dtype=V3),
        # In:
        q: wp.array2d(dtype=S),
        # Scratch:
        poses: wp.array2d(dtype=M34),
        # Out:
        wrist_out: wp.array(dtype=V3),
        flange_out: wp.array(dtype=V3),
    ):
        i = wp.tid()
        walk(tree, q, i, poses)
        flange_out[i] = apply(poses[i, links[0]], consts[0])
        if links.shape[0] < 3:
            wrist_out[i] = V3()
            return
        m4 = poses[i, links[1]]
        m5 = poses[i, links[2]]
        wrist_out[i] = centre(apply(m4, consts[1]), rotate(m4, consts[2]), apply(m5, consts[3]), rotate(m5, consts[4]))

    return Tree, frames, wrist_flange
