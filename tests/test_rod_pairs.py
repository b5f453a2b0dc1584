"""A cable's clearance to the cables (itself and the others), frame by frame, equals a search over
every pair of capsules made here in NumPy, under the kernel's rules: neighbours along a cable are
never a pair, nor for a clearance two capsules within pi allowed bend radii along one, and only
pairs within reach count. So the kernel's skips (a far pair's chain bound, a hose's straightness,
after which the search goes on to the next cable) leave out no pair within reach."""

from __future__ import annotations

import numpy as np
import pytest
from rods import rod, run

from rswarp.kernels.rod.gather import NEIGHBOURS
from rswarp.kernels.rod.slots import CABLES_NAME
from rswarp.kernels.rod.types import MAX_CONTACTS
from rswarp.sim.cable.solver import REACH


def _closest(p1, q1, p2, q2):
    """The closest points' parameters (s, t) of two segments (Ericson, Real-Time Collision
    Detection 5.1.9), in NumPy."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f, c, b = d1 @ d1, d2 @ d2, d2 @ r, d1 @ r, d1 @ d2
    den = a * e - b * b
    s = np.clip((b * f - c * e) / den, 0.0, 1.0) if den > 1e-12 * a * e else 0.0
    t = (b * s + f) / e
    if t < 0.0:
        t, s = 0.0, np.clip(-c / a, 0.0, 1.0)
    elif t > 1.0:
        t, s = 1.0, np.clip((b - c) / a, 0.0, 1.0)
    return s, t


def _brute_force(solver, state) -> np.ndarray:
    """Per cable, its least gap to any capsule within reach (inf: none), over every pair."""
    lay = solver.layout
    x, q = state.x.numpy()[0], state.q.numpy()[0]
    qx, qy, qz, qw = q.T
    axis = np.stack([2 * (qx * qz + qy * qw), 2 * (qy * qz - qx * qw), 1 - 2 * (qx * qx + qy * qy)], -1)
    h, r, arc, cab = lay.half, lay.radius, lay.arc, lay.cable
    fold = np.pi * np.array([c.allowed_bend_radius for c in solver.cables])
    least = np.full(len(lay.cables), np.inf)
    for i in range(lay.bodies):
        for j in range(i + 1, lay.bodies):
            if cab[i] == cab[j]:
                along = arc[j] - arc[i]
                if along - h[i] + h[j] < h[i] + h[j] + NEIGHBOURS * (r[i] + r[j]) or along + 2 * h[j] < fold[cab[i]]:
                    continue
            if np.linalg.norm(x[j] - x[i]) >= h[i] + h[j] + r[i] + r[j] + REACH:
                continue
            ai, aj = axis[i] * h[i], axis[j] * h[j]
            s, t = _closest(x[i] - ai, x[i] + ai, x[j] - aj, x[j] + aj)
            gap = np.linalg.norm((x[i] - ai + 2 * s * ai) - (x[j] - aj + 2 * t * aj)) - r[i] - r[j]
            if cab[i] != cab[j] or abs(arc[j] + 2 * t * h[j] - arc[i] - 2 * s * h[i]) >= fold[cab[i]]:
                least[cab[i]] = min(least[cab[i]], gap)
                least[cab[j]] = min(least[cab[j]], gap)
    return least


def _frame_end(solver, state) -> np.ndarray:
    """Each cable's clearances (cables, slots) at the state as it is: a frame of no substeps, so only
    the frame's end searches (a substep's contact search notes its own gaps too)."""
    envs, bodies = state.x.shape
    poses = solver._poses(state.joints, np.zeros((envs, 0, solver.dof)))  # the frame's start alone
    solver.launcher.launch(solver.kernel, envs, params=[solver.params, 1 / 60, solver.options.iterations],
                           inputs=[poses, state.design], scratch=(bodies, bodies, bodies * MAX_CONTACTS, bodies),
                           outputs=list(state.groups))
    return np.stack([c["clearance"][0] for c in solver.statistics(state)])


@pytest.mark.parametrize("name, cables", [("coil", 1), ("side_by_side", 2)])
def test_every_pair_within_reach_is_found(name, cables):
    """The coil's chain advances along its axis throughout, its turns a few millimetres apart: the
    straightness bound skips only pairs several turns apart. Of the straight hoses side by side, each
    skips its own far pairs at once, and the search goes on to the other's."""
    _, solver, state = rod(name, floor=None, min_bend_radius=0.02)
    slot = solver.slots.index(CABLES_NAME)
    found = []
    for _ in range(6):
        run(solver, state, 1 / 60)
        want = _brute_force(solver, state)
        got = _frame_end(solver, state)[:, slot]
        assert np.isfinite(want).all() and len(want) == cables
        assert got == pytest.approx(want, abs=1e-9)
        found.append(want)
    assert np.max(found) < 0.03  # turns, and hoses, a few centimetres apart at most
