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


def test_quick_calls_give_the_batch_s_numbers_and_leave_the_rest_to_it(kin):
    """One to QUICK poses a call (``kinematics.quick``): every branch, link pose and flange as the
    batch gives them, bit for bit, from poses and joints as a script holds them; anything else
    goes the batch's way, which still says what is wrong."""
    from rswarp.errors import InputError
    from rswarp.kinematics.quick import QUICK

    q = np.random.default_rng(3).uniform(-2, 2, (40, 6))
    links, flanges = kin.fk64(q), kin.flange(q)
    link, m = kin.flange_frame()
    poses = links[:, link] @ m
    sol = kin.ik64(poses)
    for k in range(len(q)):
        one = kin.ik64(poses[k])  # (4, 4)
        assert all(np.array_equal(a[0], b[k], equal_nan=True)
                   for a, b in ((one.q, sol.q), (one.conf, sol.conf), (one.status, sol.status)))
        assert np.array_equal(kin.fk64(q[k]), links[k:k + 1])
        assert np.array_equal(kin.flange(q[k:k + 1]), flanges[k:k + 1])
    for n in (2, QUICK, QUICK + 1):
        part = kin.ik64(poses[:n].copy())
        assert np.array_equal(part.q, sol.q[:n], equal_nan=True) and np.array_equal(part.conf, sol.conf[:n])
    assert kin._quick.ik64(poses[0].astype(np.float32)) is None  # another type: the batch's way
    assert kin._quick.ik64(poses[:, :3]) is None
    bad = poses[0].copy()
    bad[0, 3] = np.nan
    assert kin._quick.ik64(bad) is None
    with pytest.raises(InputError, match="finite"):
        kin.ik64(bad)
    sheared = poses[0].copy()
    sheared[0, 1] += 0.3
    with pytest.raises(InputError, match="pose 0 of 1 has a rotation that is not orthonormal"):
        kin.ik64(sheared)


def test_quick_calls_from_threads_each_get_their_own_answer(kin):
    """The recorded arrays are shared: calls from several threads at once are each their own."""
    from concurrent.futures import ThreadPoolExecutor

    q = np.random.default_rng(4).uniform(-2, 2, (400, 6))
    whole = kin.fk64(q)
    with ThreadPoolExecutor(4) as pool:
        got = list(pool.map(lambda k: kin.fk64(q[k]), range(len(q))))
    assert all(np.array_equal(g, whole[k:k + 1]) for k, g in enumerate(got))


def test_a_quick_collision_check_of_one_state_is_the_batch_s(kin):
    """``Checker.verdicts`` of one to a few states (float32 or float64, as a script holds them)
    gives the batch's verdicts and gaps bit for bit; a NaN state is still reported colliding."""
    from rswarp.sim.bodies import collision_bodies
    from rswarp.sim.collisions import Checker

    mech = kin.mech
    checker = Checker(mech, collision_bodies(mech), threads=1)
    q = np.random.default_rng(5).uniform(*mech.bounds(), (300, 6))
    hit, gap = checker.verdicts(q)
    assert hit.any() and not hit.all()  # both kinds of state among them
    for k in range(0, len(q), 7):
        h1, g1 = checker.verdicts(q[k])
        h2, g2 = checker.verdicts(q[k:k + 3].astype(np.float32))
        assert np.array_equal(h1, hit[k:k + 1]) and np.array_equal(g1, gap[k:k + 1], equal_nan=True)
        assert np.array_equal(h2, hit[k:k + 3]) and np.array_equal(g2, gap[k:k + 3], equal_nan=True)
    bad = q[0].copy()
    bad[2] = np.nan
    assert checker.verdicts(bad)[0].all()


def test_a_command_s_end_stops_every_launcher_s_workers():
    """``launch.stop_workers`` (a command's last step) ends every pool's workers, so that none is
    left for Python to wait on at exit however a Ctrl-C cut a launch short."""
    from rswarp.launch import MIN_SPLIT, stop_workers

    launcher = Launcher("cpu", threads=2)
    launcher.load(_scaled_add)
    n = 4 * MIN_SPLIT  # chunks for both threads: the pool is made
    out = np.zeros(n, np.float32)
    launcher.launch(_scaled_add, n, params=[1.0], inputs=[np.ones(n, np.float32)], outputs=[out])
    assert (out == 1.0).all() and launcher._pool is not None
    workers = list(launcher._pool._threads)
    assert workers
    stop_workers()
    for t in workers:
        t.join(timeout=10)
    assert not any(t.is_alive() for t in workers)
    launcher.launch(_scaled_add, n, params=[1.0], inputs=[np.ones(n, np.float32)], outputs=[out])
    assert (out == 2.0).all()  # used again: a new pool
