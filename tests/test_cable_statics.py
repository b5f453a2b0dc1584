"""The Cosserat rod against analytic statics (issue "Cables as Cosserat rods"): the catenary, a
clamped hose pulled (E A strain), and the self-weight cantilever in large deflection (the elastica,
Wang 1986). Each settles with damping, which leaves the static answer as it is."""

from __future__ import annotations

import numpy as np
import pytest
from rods import WEIGHT, rod, run
from scipy.optimize import brentq


def test_catenary_sag_and_end_tension():
    """A thin wire 1.2 m long hung from points 1 m apart: sag c (cosh(D / 2c) - 1), with S = 2c
    sinh(D / 2c), within 1 %; each support pulled with w c cosh(D / 2c) within 2 %, as the clamp
    load and as the wire's own greatest axial force."""
    _, solver, state = rod("catenary", damping=3.0)
    run(solver, state, 6.0)
    c = brentq(lambda c: 2 * c * np.sinh(0.5 / c) - 1.2, 0.05, 10.0)
    points, stats = solver.points(state, 0, 0), solver.statistics(state)[0]
    assert 1.0 - points[:, 2].min() == pytest.approx(c * (np.cosh(0.5 / c) - 1), rel=0.01)
    end = WEIGHT * np.pi * 0.002 ** 2 * c * np.cosh(0.5 / c)
    assert np.linalg.norm(stats["clamp_force"][0], axis=1) == pytest.approx([end, end], rel=0.02)
    assert stats["tension"][0] == pytest.approx(end, rel=0.02)
    assert stats["tension_at"][0] < 0.05 or stats["tension_at"][0] > 1.15  # at a support


def test_clamped_hose_carries_ea_strain():
    """The issue's hose (1 m, r 25 mm, E 5e7 Pa), clamped straight at both ends. At rest it carries
    only what gravity gives: its clamps hold its weight, and its tension is E A times the stretch of
    its sag (a few newtons). Pulled 2 mm it carries E A delta / L = 196 N within 2 % and stays
    straight (a bend radius of metres)."""
    _, solver, state = rod("stretch", damping=5.0)
    t = run(solver, state, 3.0)
    stats, points = solver.statistics(state)[0], solver.points(state, 0, 0)
    ea, weight = 5e7 * np.pi * 0.025 ** 2, WEIGHT * np.pi * 0.025 ** 2
    assert -stats["clamp_force"][0, :, 2].sum() == pytest.approx(weight, rel=0.005)
    sagged = np.linalg.norm(np.diff(points, axis=0), axis=1).sum() - 1.0
    assert stats["tension"][0] == pytest.approx(ea * sagged, rel=0.1) and stats["tension"][0] < 0.2 * weight
    run(solver, state, 2.0, joints=lambda s: np.array([[0.002 * min(s - t, 1.0)]]), t0=t)
    stats = solver.statistics(state)[0]
    assert stats["tension"][0] == pytest.approx(ea * 0.002, rel=0.02)
    assert stats["clamp_force"][0, 1, 0] == pytest.approx(-ea * 0.002, rel=0.02)  # the slide is pulled back
    assert stats["bend_radius"][0] > 5.0


@pytest.mark.parametrize("beta, drop", [(1, 0.12347), (5, 0.49591)])
def test_self_weight_cantilever_elastica(tmp_path, beta, drop):
    """A hose clamped level at one end, free at the other, bent by its own weight with q L^3 / EI
    = beta: the tip drops by the elastica's 0.12347 L (beta 1) and 0.49591 L (beta 5) within 2 %.
    Bending alone makes no twist: the hose carries no torque."""
    youngs = 5.885e7 / beta
    _, solver, state = rod("cantilever", text={'youngsModulus="5.885e7"': f'youngsModulus="{youngs}"'}, tmp=tmp_path,
                           damping=5.0)
    run(solver, state, 4.0)
    tip = solver.points(state, 0, 0)[-1]
    assert (1.0 - tip[2]) / 0.5 == pytest.approx(drop, rel=0.02)
    stats = solver.statistics(state)[0]
    assert stats["twist_rate"][0] < 1e-9 and stats["torque"][0] < 1e-9
