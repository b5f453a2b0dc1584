"""Twist that acts (issue "Cables as Cosserat rods"): a clamped rod twisted carries G J Phi / L and
stays straight below Greenhill's threshold; twisted past it and slackened, it writhes out of its
plane, its link (twist plus writhe, Calugareanu) kept at what the clamps imposed."""

from __future__ import annotations

import numpy as np
import pytest
from rods import ribbon_link, rod, run

GJ = 5e8 / 3 * np.pi * 0.01 ** 4 / 2  # twist.rsxml: G = E / 3 at Poisson 0.5


def test_twisted_rod_carries_gj_phi_over_l_and_stays_straight():
    """The head turned a quarter turn about the rod's axis: the rod carries G J Phi / L within 2 %
    (its greatest torque and each clamp's moment about the axis), twists Phi / L per metre, and
    twist alone, below Greenhill's threshold, bends it not at all."""
    _, solver, state = rod("twist", damping=5.0)
    phi = np.pi / 2
    run(solver, state, 2.0, joints=lambda t: np.array([[0.0, phi * min(t, 1.0)]]))
    stats = solver.statistics(state)[0]
    want = GJ * phi / 0.5
    assert stats["torque"][0] == pytest.approx(want, rel=0.02)
    assert np.abs(stats["clamp_moment"][0, :, 2]) == pytest.approx([want, want], rel=0.02)
    assert stats["twist"][0] == pytest.approx(phi, rel=1e-6)
    assert stats["twist_rate"][0] == pytest.approx(phi / 0.5, rel=0.01)
    assert np.abs(solver.points(state, 0, 0)[:, :2]).max() < 1e-9 and stats["bend_radius"][0] > 1e6


def writhed(turns: int):
    """writhe.rsxml turned ``turns`` in 3 s, then slackened 100 mm in 4 s: (centreline nodes, the
    material axis d1 at each node, the last statistics)."""
    _, solver, state = rod("writhe", damping=2.0)
    run(solver, state, 8.0,
        joints=lambda t: np.array([[-0.1 * np.clip((t - 3) / 4, 0, 1), 2 * np.pi * turns * min(t / 3, 1)]]))
    nodes, (_, frames) = solver.points(state, 0, 0), solver.frames(state, 0, 0)
    d1 = frames[:, :, 0]
    d1 = np.vstack([d1[:1], d1[1:] + d1[:-1], d1[-1:]])
    return nodes, d1 / np.linalg.norm(d1, axis=1, keepdims=True), solver.statistics(state)[0]


def test_twisted_past_greenhill_then_slackened_writhes():
    """Untwisted and slackened, the rod bows in its plane (x z) exactly. Twisted three turns, past
    Greenhill's 2.15 (M L / EI = 8.99 for clamped ends), then slackened, it leaves that plane by
    centimetres; the ribbon's linking number with its centreline stays within 0.05 turns of three."""
    flat, d1_flat, stats = writhed(0)
    assert stats["status"][0] == 0 and np.abs(flat[:, 0]).max() > 0.05 and np.abs(flat[:, 1]).max() < 1e-9
    assert abs(ribbon_link(flat, d1_flat, np.array([0.0, 0.0, 1.0]), 0.005)) < 0.05
    coiled, d1, stats = writhed(3)
    assert stats["status"][0] == 0 and np.abs(coiled[:, 1]).max() > 0.03
    thickness = np.linalg.svd(coiled - coiled.mean(axis=0), compute_uv=False)[-1] / np.sqrt(len(coiled))
    assert thickness > 0.01  # m: no plane holds it
    assert ribbon_link(coiled, d1, np.array([0.0, 0.0, 1.0]), 0.005) == pytest.approx(3.0, abs=0.05)
