"""Where a self-collision sweep's time goes, stage by stage: the sweep kernel rebuilt with its
stages cut after each one (forward kinematics; bounding spheres; certified and witness cells; root boxes;
convex hulls; containment; the walk for crossing triangles), each timed on one thread over the same states,
once a round in each of several rounds, its best kept. The
difference between two rows is the later stage's cost; the fractions say how many pair tests
reach each stage. For ``bench_collisions.py``."""


import time
from typing import Any

import numpy as np

STAGES = ("forward kinematics", "bounding spheres", "certified and witness cells", "root boxes", "convex hulls",
          "containment", "tree walks")


def _pair_test(stage: int):
    """``test(m, poses, q, i, p) -> uint8`` of pair p, the sweep's pair verdict cut after
    ``stage``: 3 where it passed the spheres and was cut there, 2 where it reached the walk (and
    was cut there or walked to nothing), 1 where it collides, 0 where a stage found it free."""
    from rswarp.kernels import collide
    from rswarp.kernels.types import bodies_struct, types_of
    from rswarp.kernels.witness import APART, CROSSING, certified_function, witness_functions
    from rswarp.launch import init_warp

    wp = init_warp()
    S, V3, _, _, _ = types_of(wp.float32)
    arrays = bodies_struct(wp.float32)
    body_pose, body_centre = collide._body_pose(wp.float32)
    rotation, relative = collide.pose_helpers(wp.float32)
    witness_cell, witness_hit = witness_functions(wp.float32)
    certified = certified_function(wp.float32)
    after_cells = _after_cells(stage)

    @wp.func
    def test(m: arrays, poses: Any, centres: Any, q: wp.array2d(dtype=S), i: int, p: int) -> wp.uint8:
        a = m.pair_a[p]
        b = m.pair_b[p]
        if wp.static(stage < 1):
            return wp.uint8(0)
        if wp.length(centres[a] - centres[b]) - m.radius[a] - m.radius[b] > m.padding:
            return wp.uint8(0)
        if wp.static(stage < 2):
            return wp.uint8(3)
        rel = relative(body_pose(m, poses, a), body_pose(m, poses, b))
        r = rotation(rel)
        t = V3(rel[0, 3], rel[1, 3], rel[2, 3])
        cert = certified(m, p, q, i)
        if cert == APART:
            return wp.uint8(0)
        if cert == CROSSING:
            return wp.uint8(1)
        cell = witness_cell(m, p, q, i)
        if cell >= 0 and witness_hit(m, cell, r, t):
            return wp.uint8(1)
        return after_cells(m, p, r, t)

    return test


def _after_cells(stage: int):
    """``after_cells(m, p, r, t) -> uint8``: the stages after the cells (root boxes, hulls,
    containment, the usual crossings and the walk), cut after ``stage``, codes as ``_pair_test``'s."""
    from rswarp.kernels.contain import containment_functions
    from rswarp.kernels.hull import hull_function
    from rswarp.kernels.quad import quad_walk
    from rswarp.kernels.tree import traversal_functions
    from rswarp.kernels.types import bodies_struct, types_of
    from rswarp.kernels.witness import witness_functions
    from rswarp.launch import init_warp

    wp = init_warp()
    _, V3, M33, _, _ = types_of(wp.float32)
    arrays = bodies_struct(wp.float32)
    node_gap, _ = traversal_functions(wp.float32)
    meshes_cross = quad_walk(wp.float32)
    enclosed = containment_functions(wp.float32)
    _, witness_hit = witness_functions(wp.float32)
    hulls_apart = hull_function(wp.float32)

    @wp.func
    def after_cells(m: arrays, p: int, r: M33, t: V3) -> wp.uint8:
        a = m.pair_a[p]
        b = m.pair_b[p]
        if wp.static(stage >= 3):
            if node_gap(m, m.root[a], m.root[b], r, t) > m.padding:
                return wp.uint8(0)
        if wp.static(stage >= 4):
            if hulls_apart(m, a, b, r, t, m.padding):
                return wp.uint8(0)
        if wp.static(stage >= 5):
            if enclosed(m, a, b, r, t):
                return wp.uint8(1)
        if wp.static(stage >= 6):
            if m.usual[p] >= 0:  # the pair's usual crossings, then the walk
                if witness_hit(m, m.usual[p], r, t):
                    return wp.uint8(1)
            if meshes_cross(m, a, b, r, t):
                return wp.uint8(1)
        return wp.uint8(2)

    return after_cells


def _kernel(checker, bodies, stage: int):
    """The sweep kernel cut after ``stage`` (``_pair_test``'s codes per pair)."""
    from rswarp.kernels import collide
    from rswarp.kernels.cache import cpu_flags
    from rswarp.kernels.collide import SWEEP_FLAGS
    from rswarp.kernels.fk import emit_local, tree_fk
    from rswarp.kernels.types import bodies_struct, types_of
    from rswarp.launch import init_warp

    wp = init_warp()
    S, _, _, M34, _ = types_of(wp.float32)
    arrays = bodies_struct(wp.float32)
    chain = checker.chain
    fk = tree_fk(chain, set(int(k) for k in bodies.links), emit_local(wp.float32), wp.float32)
    test = _pair_test(stage)
    body_pose, body_centre = collide._body_pose(wp.float32)
    n = len(chain.parent)
    nb = len(bodies.bodies)

    @wp.kernel(enable_backward=False, module=f"bench_collision_stage_{stage}")
    def staged(m: arrays, q: wp.array2d(dtype=S), hit_out: wp.array2d(dtype=wp.uint8)):
        i = wp.tid()
        poses = wp.zeros(shape=n, dtype=M34)
        fk(q, i, poses)
        centres = wp.zeros(shape=nb, dtype=wp.vec3)
        if wp.static(stage > 0):
            for k in range(nb):
                centres[k] = body_centre(m, poses, k)
        for p in range(m.pair_a.shape[0]):
            hit_out[i, p] = test(m, poses, centres, q, i, p)
        if wp.static(stage == 0):  # the poses used, so the compiler keeps the forward kinematics
            far = S(0.0)
            for k in range(n):
                far = far + wp.abs(poses[k][0, 3])
            if far > S(1.0e30):
                hit_out[i, 0] = wp.uint8(9)

    cpu_flags(staged.module, SWEEP_FLAGS)  # as the sweep's kernel is compiled
    return staged


def stage_table(checker, bodies, q: np.ndarray, repeats: int = 9) -> list[tuple[str, float, float]]:
    """Rows (stage, microseconds a state up to and with it, share of pair tests it passes on to the
    next stage; at the last, the share that collide), one thread."""
    from rswarp.launch import Launcher, init_warp

    wp = init_warp()
    launcher = Launcher("cpu", chunk=8192, threads=1)
    q = np.ascontiguousarray(q, np.float32)
    hit = np.empty((len(q), len(bodies.pairs)), np.uint8)
    struct = checker._device.struct(wp.float32)
    kernels = [_kernel(checker, bodies, stage) for stage in range(len(STAGES))]
    shares = []
    for stage, kernel in enumerate(kernels):
        launcher.load(kernel)
        launcher.launch(kernel, len(q), params=[struct], inputs=[q], outputs=[hit])
        # the share of pair tests this stage leaves to the next (at the last: those that collide)
        passed = hit == 3 if stage == 1 else hit == 1 if stage == len(STAGES) - 1 else hit == 2
        shares.append(1.0 if stage == 0 else float(passed.mean()))
    best = [np.inf] * len(kernels)
    for _ in range(repeats):  # rounds, every stage once a round: a noisy spell meets them all
        for stage, kernel in enumerate(kernels):
            t = time.perf_counter()
            launcher.launch(kernel, len(q), params=[struct], inputs=[q], outputs=[hit])
            best[stage] = min(best[stage], time.perf_counter() - t)
    return [(name, b / len(q) * 1e6, share) for name, b, share in zip(STAGES, best, shares)]
