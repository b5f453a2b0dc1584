"""Generic forward kinematics kernel: one thread per joint configuration walks the link tree.

Each mechanism also gets kernels of its own (``fk_codegen``), several times faster; this one
serves any subset of links with any offsets.

Inputs are plain arrays compiled from a mechanism (see ``rswarp.compile``). Links are in
topological order (a parent before its children) and every link's frame is the world frame at the
zero position, so a link's pose is its parent's pose times its joint's screw motion (product of
exponentials). ``poses`` is per-thread scratch, one row per configuration.
"""

import warp as wp

wp.set_module_options({"enable_backward": False})  # forward only: halves the compile time

REVOLUTE = wp.constant(0)
PRISMATIC = wp.constant(1)
FIXED = wp.constant(2)


@wp.func
def screw(jtype: int, axis: wp.vec3, point: wp.vec3, theta: float) -> wp.transform:
    """The rigid motion of a joint by ``theta`` about/along a world axis through ``point``."""
    if jtype == REVOLUTE:
        r = wp.quat_from_axis_angle(axis, theta)
        return wp.transform(point - wp.quat_rotate(r, point), r)
    if jtype == PRISMATIC:
        return wp.transform(axis * theta, wp.quat_identity())
    return wp.transform_identity()


@wp.func
def walk(q: wp.array2d(dtype=wp.float32), i: int, parent: wp.array(dtype=wp.int32),
         jtype: wp.array(dtype=wp.int32), qidx: wp.array(dtype=wp.int32), axis: wp.array(dtype=wp.vec3),
         point: wp.array(dtype=wp.vec3), base: wp.transform, poses: wp.array2d(dtype=wp.transform)):
    """Fill ``poses[i, :]`` with every link's world pose for configuration ``i``."""
    for k in range(parent.shape[0]):
        p = parent[k]
        if p < 0:
            poses[i, k] = base
        else:
            theta = float(0.0)
            if qidx[k] >= 0:
                theta = q[i, qidx[k]]
            poses[i, k] = wp.transform_multiply(poses[i, p], screw(jtype[k], axis[k], point[k], theta))


@wp.func
def to_mat44(t: wp.transform) -> wp.mat44:
    r = wp.quat_to_matrix(wp.transform_get_rotation(t))
    p = wp.transform_get_translation(t)
    return wp.mat44(r[0, 0], r[0, 1], r[0, 2], p[0],
                    r[1, 0], r[1, 1], r[1, 2], p[1],
                    r[2, 0], r[2, 1], r[2, 2], p[2],
                    0.0, 0.0, 0.0, 1.0)


@wp.kernel
def fk_frames(q: wp.array2d(dtype=wp.float32), parent: wp.array(dtype=wp.int32), jtype: wp.array(dtype=wp.int32),
              qidx: wp.array(dtype=wp.int32), axis: wp.array(dtype=wp.vec3), point: wp.array(dtype=wp.vec3),
              base: wp.transform, out_link: wp.array(dtype=wp.int32), out_offset: wp.array(dtype=wp.transform),
              poses: wp.array2d(dtype=wp.transform), out: wp.array2d(dtype=wp.mat44)):
    """``out[i, j]`` = pose of link ``out_link[j]`` times ``out_offset[j]``, as a 4x4 matrix."""
    i = wp.tid()
    walk(q, i, parent, jtype, qidx, axis, point, base, poses)
    for j in range(out_link.shape[0]):
        out[i, j] = to_mat44(wp.transform_multiply(poses[i, out_link[j]], out_offset[j]))
