"""The Cosserat rod in motion (issue "Cables as Cosserat rods"): Coulomb friction with a static
regime on an accelerating plate, energy that never grows when nothing drives or damps the rods,
and attachments that follow a turning link."""

from __future__ import annotations

import numpy as np
import pytest
from rods import FRAME, WEIGHT, energy, rod, run

MU, G = 0.4, 9.81  # the default friction coefficient


@pytest.mark.parametrize("ratio", [0.5, 2.0])
def test_hose_on_an_accelerating_plate(ratio):
    """A loose hose lies on a plate that accelerates along x at a = ratio mu g for 0.4 s. Below mu g
    it rides with the plate (within a millimetre: the static regime creeps under 1 mm/s); above
    it, it slides back over the plate by (a - mu g) t^2 / 2 within 3 %, resisted by mu times its
    weight."""
    a, seconds = ratio * MU * G, 0.4
    _, solver, state = rod("friction", damping=0.0)
    t = run(solver, state, 0.5)
    start = solver.points(state, 0, 0).mean(axis=0)
    assert solver.statistics(state)[0]["normal_force"][0] > 0
    plate = 0.5 * a * seconds ** 2
    run(solver, state, seconds, joints=lambda s: np.array([[0.5 * a * (s - t) ** 2]]), t0=t)
    moved = solver.points(state, 0, 0).mean(axis=0) - start
    behind = plate - moved[0]
    if ratio < 1:
        assert abs(behind) < 1e-3
    else:
        assert behind == pytest.approx(0.5 * (a - MU * G) * seconds ** 2, rel=0.03)
        assert solver.statistics(state)[0]["sliding_speed"][0] == pytest.approx((a - MU * G) * seconds, rel=0.05)
    assert abs(moved[2]) < 1e-3  # still on the plate


def test_energy_never_grows_undriven_and_undamped():
    """Both hoses of catenary.rsxml, thrown with random velocities and spins, no damping, no floor,
    the joints still: their kinetic, gravitational and elastic energy falls or holds every frame
    (implicit Euler only ever takes energy out)."""
    _, solver, state = rod("catenary", damping=0.0, floor=None)
    rng = np.random.default_rng(1)
    state.v.numpy()[:] = rng.normal(0.0, 0.5, (*state.v.shape, 3))  # on the CPU, views of the state
    state.w.numpy()[:] = rng.normal(0.0, 5.0, (*state.w.shape, 3))
    energies = [energy(solver, state)]
    run(solver, state, 2.0, each=lambda t: energies.append(energy(solver, state)))
    steps = np.diff(energies)
    assert steps.max() <= 1e-12 * energies[0] and energies[-1] < 0.95 * energies[0]


def test_attached_points_follow_a_turning_link():
    """The hose on the arm's tip, J1 turning 90 degrees a second each way in two environments: its
    attached end stays on the arm within 0.1 mm at every frame's end, and its free end swings
    along."""
    _, solver, state = rod("catenary", envs=2)
    rate = np.radians(90.0)
    for f in range(60):
        t = (f + 1) * FRAME
        run(solver, state, FRAME, joints=lambda s: np.array([[rate * s], [-rate * s]]), t0=f * FRAME)
        for e, sign in enumerate((1, -1)):
            a = sign * rate * t
            assert np.linalg.norm(solver.points(state, 1, e)[0] - [0.4 * np.cos(a), 0.4 * np.sin(a), 0.5]) < 1e-4
    ends = solver.points(state, 1)[:, -1]
    assert np.isfinite(ends).all() and ends[0, 1] > 0.1 > -0.1 > ends[1, 1]


def test_a_hose_pinched_between_a_link_and_the_plate():
    """A block lowers onto a hose lying on a plate: resting on the plate, or with the block 2 mm
    above it, nothing presses the hose from opposite sides (pinch 0: its contacts all push one
    way); lowered 3 mm into it, the hose is pinched between the block and the plate, harder than
    its own weight, under the block."""
    _, solver, state = rod("pinch", envs=3)
    depth = np.array([0.0, 0.028, 0.033])  # m the block is lowered: its bottom meets the hose at 0.030
    t = run(solver, state, 0.3)
    run(solver, state, 0.5, joints=lambda s: (depth * min((s - t) / 0.4, 1.0))[:, None], t0=t)
    s = solver.statistics(state)[0]
    assert np.all(s["status"] == 0)
    assert s["pinch"][0] == 0.0 and s["pinch"][1] == 0.0
    assert s["normal_force"][0] > 0  # it does rest on the plate
    weight = WEIGHT * np.pi * 0.01 ** 2 * 0.3
    assert s["pinch"][2] > weight
    assert {solver.slots[k] for k in s["pinch_slots"][2]} == {"Press", "Base"}
    assert 0.05 <= s["pinch_at"][2] <= 0.25  # under the block (x = 400..600 mm; the hose starts at 350)
