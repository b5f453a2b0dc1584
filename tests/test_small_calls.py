"""Small batches run as recorded launches (``launch._Recorded``): the same numbers as a batch's,
bit for bit, whatever the size, after the model's parameters change, after the cache drops a
launch, and where a kernel reads the output it updates."""

from __future__ import annotations

import numpy as np
import pytest
import warp as wp

from rswarp import examples
from rswarp.kinematics.kinematics import Kinematics
from rswarp.launch import RECORDED, SMALL, Launcher, init_warp
from rswarp.rsxml.documents import load_mechanism

init_warp()


@wp.kernel
def _scaled_add(scale: float, x: wp.array(dtype=float), out: wp.array(dtype=float)):
    i = wp.tid()
    out[i] = out[i] + scale * x[i]  # reads what it updates


@pytest.fixture(scope="module")
def kin():
    return Kinematics(load_mechanism(str(examples.IRB2600))[0])


def test_small_batches_give_the_batch_s_numbers(kin):
    q = np.random.default_rng(0).uniform(-2, 2, (SMALL + 600, 6))
    whole = kin.fk64(q)  # the threaded path: over SMALL items
    poses = kin.flange(q)
    sol = kin.ik64(poses.astype(np.float64))
    for n in (1, 2, 7, SMALL):
        assert np.array_equal(kin.fk64(q[:n]), whole[:n])
        part = kin.ik64(poses[:n].astype(np.float64))
        assert np.array_equal(part.q, sol.q[:n], equal_nan=True) and np.array_equal(part.status, sol.status[:n])
    again = kin.fk64(q[3:4])  # a recorded launch run again on other inputs
    assert np.array_equal(again, whole[3:4])


def test_a_changed_parameter_is_used_and_an_updated_output_read():
    launcher = Launcher("cpu")
    launcher.load(_scaled_add)
    x = np.arange(4, dtype=np.float32)
    out = np.ones(4, np.float32)
    launcher.launch(_scaled_add, 4, params=[2.0], inputs=[x], outputs=[out])
    assert out.tolist() == [1.0, 3.0, 5.0, 7.0]
    launcher.launch(_scaled_add, 4, params=[3.0], inputs=[x], outputs=[out])
    assert out.tolist() == [1.0, 6.0, 11.0, 16.0]  # the new scale, added to what the caller's array held


def test_the_cache_keeps_its_size_and_its_answers():
    launcher = Launcher("cpu")
    launcher.load(_scaled_add)
    for n in range(1, RECORDED + 10):
        x = np.full(n, 2.0, np.float32)
        out = np.zeros(n, np.float32)
        launcher.launch(_scaled_add, n, params=[1.5], inputs=[x], outputs=[out])
        assert (out == 3.0).all()
    assert len(launcher._records) == RECORDED


def test_stacked_trajectories_are_each_trajectory_bit_for_bit():
    """A cable run's random programs evaluated all at once give each one's own joints exactly,
    before its start, between its knots, on them and past its end."""
    from rswarp.kinematics.trajectory import Stacked, random_trajectory

    mech = load_mechanism(str(examples.IRB2600))[0]
    trajs = [random_trajectory(mech, 3.0 + k, k) for k in range(5)]
    stacked = Stacked.of(trajs)
    t = np.concatenate([[-1.0, 0.0], np.linspace(0.0, 12.0, 997), trajs[2].times])
    got = stacked.at(t)
    for k, tr in enumerate(trajs):
        assert np.array_equal(got[k], tr.at(t))
