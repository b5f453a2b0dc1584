"""A design sweep keeps each design's least clearances, never their series over time, so its frames
measure a mesh's clearance only where it is under the least so far (``CableOptions`` with
``frame_clearances`` False). That changes no figure a run reports, bit for bit: the least
clearance to every slot, when and where, the first contact, and all the rest. Only the
clearance series is not measured (NaN)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from rswarp import examples
from rswarp.kinematics.trajectory import random_trajectory
from rswarp.rsxml.documents import load_mechanism
from rswarp.sim.cable.solver import CableOptions
from rswarp.sim.cables import simulate_cables


@pytest.mark.parametrize("seed", [7, 11])
def test_a_sweep_that_keeps_only_the_least_clearances_changes_no_figure(seed):
    mech, _ = load_mechanism(str(examples.IRB2600_DRESSPACK))
    trajectory = random_trajectory(mech, 2.0, seed)
    whole, least = (simulate_cables(mech, [trajectory], 3, None, CableOptions(frame_clearances=fc)).cables[0]
                    for fc in (True, False))
    assert np.isfinite(whole.clearance).sum() > 10  # the hose comes near the links: the bound is at work
    assert np.isfinite(whole.gap.low).any() and np.isnan(least.gap.low).all()
    for f in dataclasses.fields(whole):
        a, b = getattr(least, f.name), getattr(whole, f.name)
        if isinstance(b, np.ndarray):
            assert np.array_equal(a, b, equal_nan=b.dtype.kind == "f"), f.name
    for name in ("tension", "bend", "torque"):
        for part in ("low", "median", "high"):
            assert np.array_equal(getattr(getattr(least, name), part), getattr(getattr(whole, name), part),
                                  equal_nan=True)
