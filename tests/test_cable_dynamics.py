"""Cable dynamics kernels against analytic statics (issue "Cable dynamics in parallel
environments", in progress): the inextensible catenary, a clamped cantilever, attachments that
follow a turning link."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import rswarp
from rswarp.sim.cable_chain import ParticleChain
from rswarp.sim.cable_solver import CableOptions

from conftest import DATA

FRAME = 1 / 60


def settle(mech, cable, seconds: float, envs: int = 1, damping: float = 3.0, qs=None):
    chain = ParticleChain(mech, cable, CableOptions(substeps=20, iterations=2, damping=damping))
    state = chain.state(envs)
    zero = np.zeros((envs, chain.substeps, mech.dof), np.float32)
    for f in range(int(round(seconds / FRAME))):
        chain.step(state, zero if qs is None else qs(f), FRAME)
    return chain.arrays, state.x.numpy(), state.v.numpy()


def test_hanging_hose_sags_like_the_inextensible_catenary():
    """Span 1 m, length 1.2 m: sag c (cosh(D / 2c) - 1) with S = 2c sinh(D / 2c), within 1 %; no
    segment longer than its rest length by 0.1 % (inextensible)."""
    mech = rswarp.load(DATA / "cables" / "catenary.rsxml")
    model, x, _ = settle(mech, mech.cables[0], seconds=8.0)
    c = brentq(lambda c: 2 * c * np.sinh(0.5 / c) - 1.2, 0.05, 10.0)
    sag = c * (np.cosh(0.5 / c) - 1)
    assert 1.0 - x[0, :, 2].min() == pytest.approx(sag, rel=0.01)
    strain = np.linalg.norm(np.diff(x[0], axis=0), axis=1) / model.rest - 1
    assert np.abs(strain).max() < 1e-3


def cantilever_error(tmp_path, segment_mm: str) -> float:
    """The clamped cantilever's tip drop, relative to w L^4 / (8 EI), minus one."""
    text = (DATA / "cables" / "cantilever.rsxml").read_text()
    (tmp_path / f"c{segment_mm}.rsxml").write_text(text.replace('maxSegmentLength="6.25"',
                                                                f'maxSegmentLength="{segment_mm}"'))
    mech = rswarp.load(tmp_path / f"c{segment_mm}.rsxml")
    model, x, _ = settle(mech, mech.cables[0], seconds=10.0, damping=5.0)
    ei = 5e8 * np.pi * 0.01 ** 4 / 4
    w = 1200 * 9.81 * np.pi * 0.01 ** 2
    return float((1.0 - x[0, model.cable][-1][2]) / (w * 0.5 ** 4 / (8 * ei)) - 1)


def test_clamped_cantilever_tip_drops_by_beam_theory(tmp_path):
    """Tip deflection w L^4 / (8 EI) within 3 % with 80 segments (the clamp's ghost particle puts
    the root at the control point), and the error halves when the segments do (40: 4.7 %, 80:
    2.2 %): the discretization converges to the beam."""
    coarse, fine = cantilever_error(tmp_path, "12.5"), cantilever_error(tmp_path, "6.25")
    assert 0 < fine < 0.03 and 0.04 < coarse < 0.055 and 0.015 < fine < 0.03
    assert coarse / fine == pytest.approx(2.0, rel=0.25)


def test_attached_points_follow_a_turning_link():
    """The hose on the arm's tip, with J1 turning 90 degrees a second: its attached point stays on
    the arm within 0.1 mm at every frame's end."""
    mech = rswarp.load(DATA / "cables" / "catenary.rsxml")
    carried = mech.cables[1]
    chain = ParticleChain(mech, carried, CableOptions(substeps=10, iterations=2))
    state = chain.state(2)
    x = state.x.numpy()  # on the CPU, a view of the state the kernel updates
    rate = np.radians(90.0)
    for f in range(60):
        t = (f * 10 + np.arange(1, 11)) * FRAME / 10
        qs = np.stack([rate * t, -rate * t])[:, :, None]  # two environments turning opposite ways
        chain.step(state, qs, FRAME)
        for e, sign in enumerate((1, -1)):
            a = sign * rate * (f + 1) * FRAME
            want = np.array([0.4 * np.cos(a), 0.4 * np.sin(a), 0.5])
            assert np.linalg.norm(x[e, 0] - want) < 1e-4
    assert np.isfinite(x).all() and x[0, -1, 1] > 0.1 > -0.1 > x[1, -1, 1]  # the free ends swing along


def test_with_nothing_driven_energy_never_increases():
    """The catenary hose released from its V-shaped rest shape with no damping: kinetic plus
    gravitational energy (its bending energy is negligible) never grows from frame to frame."""
    mech = rswarp.load(DATA / "cables" / "catenary.rsxml")
    chain = ParticleChain(mech, mech.cables[0], CableOptions(substeps=20, iterations=2, damping=0.0))
    model = chain.arrays
    state = chain.state(1)
    x, v = state.x.numpy(), state.v.numpy()  # views of the state on the CPU
    mass = np.where(model.inv_mass > 0, 1 / np.where(model.inv_mass > 0, model.inv_mass, 1), 0.0)
    zero = np.zeros((1, chain.substeps, mech.dof), np.float32)
    energy = []
    for _ in range(120):
        chain.step(state, zero, FRAME)
        energy.append(float(np.sum(mass * (0.5 * np.sum(v[0] ** 2, axis=1) + 9.81 * x[0, :, 2]))))
    assert np.diff(energy).max() <= 1e-6 * abs(energy[0])
    assert energy[-1] < energy[0]  # it moved, and lost energy to the projections
