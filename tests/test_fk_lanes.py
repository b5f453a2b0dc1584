"""FK eight configurations a thread (``kernels/fk_lanes``): the same poses as the float64 kernels,
whatever a configuration's place in its block, the 3x4 form equal to the 4x4's top rows, and a huge
angle or NaN handled as the one-a-thread kernels handle them."""

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.kernels import fk_lanes
from rswarp.kinematics.kinematics import Kinematics

from conftest import DATA


@pytest.fixture(scope="module")
def irb2600():
    return Kinematics(rswarp.load(examples.IRB2600))


def _q(kin, n, seed=0):
    lo, hi = kin.mech.bounds()
    return np.random.default_rng(seed).uniform(lo, hi, (n, kin.dof)).astype(np.float32)


def test_arms_take_the_lanes_and_loops_do_not(irb2600):
    assert irb2600._lanes() is not None
    assert Kinematics(rswarp.load(DATA / "branching.rsxml"))._lanes() is not None  # a tree with a slider
    loops = sorted((DATA / "loops").glob("*.rsxml"))
    assert loops and all(not fk_lanes.lanes_fit(Kinematics(rswarp.load(p)).chain) for p in loops[:2])


def test_poses_match_float64_within_a_micrometre(irb2600):
    q = _q(irb2600, 1003)  # not a multiple of the lanes: the last block is partial
    ref = irb2600.fk64(q.astype(np.float64))
    for rows in (4, 3):
        got = irb2600.fk(q, rows=rows)
        assert got.shape == (1003, 7, rows, 4)
        assert np.abs(got[..., :3, 3] - ref[..., :3, 3]).max() < 1e-6
        assert np.abs(got[..., :3, :3] - ref[..., :3, :3]).max() < 1e-6
    assert np.array_equal(irb2600.fk(q, rows=3), irb2600.fk(q)[:, :, :3])
    link, m = irb2600.flange_frame()
    assert np.abs(irb2600.flange(q) - (ref[:, link] @ m)).max() < 1e-6


def test_a_pose_does_not_depend_on_its_lane(irb2600):
    """Shifted by one, three and five, each configuration sits in another lane and block (and a
    batch of one runs as a recorded launch): the poses stay the same, bit for bit."""
    q = _q(irb2600, 200, seed=1)
    whole = irb2600.fk(q)
    for shift in (1, 3, 5):
        assert np.array_equal(irb2600.fk(q[shift:]), whole[shift:])
    assert np.array_equal(irb2600.fk(q[17:18]), whole[17:18])
    assert np.array_equal(irb2600.flange(q[3:]), irb2600.flange(q)[3:])


def test_huge_angles_and_nan(irb2600):
    """An angle past the float32 reduction's range takes libm's sine and cosine for its block; a
    NaN joint makes NaN every link it moves, and only those."""
    q = _q(irb2600, 16, seed=2)
    q[5, 5] = 1.0e5  # J6 turned 16 000 times: as float32 it is exactly 100000.0
    q[9, 1] = np.nan
    got = irb2600.fk(q)
    ref = irb2600.fk64(q.astype(np.float64))
    fine = np.ones(16, bool)
    fine[9] = False
    assert np.abs(got[fine, :, :3] - ref[fine, :, :3]).max() < 1e-6
    moved = np.isnan(got[9]).any(axis=(1, 2))
    assert moved.tolist() == np.isnan(ref[9]).any(axis=(1, 2)).tolist() == [False, False] + [True] * 5


def test_bad_rows_are_refused(irb2600):
    with pytest.raises(ValueError, match="rows must be 3 or 4"):
        irb2600.fk(np.zeros((1, 6)), rows=2)
    with pytest.raises(ValueError, match="out must be"):
        irb2600.fk(np.zeros((2, 6)), rows=3, out=np.zeros((2, 7, 4, 4), np.float32))


def test_transforms_are_the_poses_as_position_and_quaternion(irb2600):
    """``fk_transforms`` (Newton's body_q form): the position of each link and a unit quaternion
    of its turn, against float64 matrices (scipy's conversion of the quaternion back)."""
    from scipy.spatial.transform import Rotation

    q = _q(irb2600, 203, seed=3)
    got = irb2600.fk_transforms(q)
    ref = irb2600.fk64(q.astype(np.float64))
    assert got.shape == (203, 7, 7)
    assert np.abs(got[..., :3] - ref[..., :3, 3]).max() < 1e-6
    assert np.abs(np.linalg.norm(got[..., 3:], axis=-1) - 1).max() < 1e-6
    turned = Rotation.from_quat(got[..., 3:].reshape(-1, 4).astype(np.float64)).as_matrix().reshape(203, 7, 3, 3)
    assert np.abs(turned - ref[..., :3, :3]).max() < 1e-6
    loops = Kinematics(rswarp.load(sorted((DATA / "loops").glob("*.rsxml"))[0]))  # no lanes: from the matrices
    qs = np.zeros((2, loops.dof))
    assert np.abs(loops.fk_transforms(qs)[..., :3] - loops.fk(qs)[..., :3, 3]).max() == 0


def test_transforms_stay_within_their_tolerance_and_their_lane(irb2600):
    """Position and quaternion take the half angles' sines alone, the rotation from them by the
    double-angle rules: positions within 2e-6 m of float64 over many configurations, and a configuration's numbers the same in any lane, bit for bit."""
    q = _q(irb2600, 20_000, seed=4)
    got = irb2600.fk_transforms(q)
    ref = irb2600.fk64(q.astype(np.float64))
    assert np.abs(got[..., :3] - ref[..., :3, 3]).max() < 2e-6
    for shift in (1, 5):
        assert np.array_equal(irb2600.fk_transforms(q[shift:300]), got[shift:300])


def test_a_launcher_of_its_own_chunk_takes_wide_chunks_only_where_no_scratch_is_kept():
    """Left to choose, a launcher hands a kernel with no scratch four chunks a thread up to
    WIDE_CHUNK (each launch is set up in Python); a chunk given, or scratch, keeps the chunk."""
    from rswarp.launch import DEFAULT_CHUNK, WIDE_CHUNK, Launcher

    def spans(launcher, n, wide):
        got = []
        launcher._spread(n, lambda lo, hi: got.append(hi - lo), wide=wide)
        return got

    free, given = Launcher("cpu", threads=1), Launcher("cpu", chunk=1000, threads=1)
    assert spans(free, 1_000_000, True) == [250_000] * 4
    assert max(spans(free, 10 * WIDE_CHUNK, True)) == WIDE_CHUNK
    assert max(spans(free, 1_000_000, False)) == DEFAULT_CHUNK
    assert max(spans(given, 1_000_000, given._wide)) == 1000
    kin, small = Kinematics(rswarp.load(examples.IRB2600)), Kinematics(rswarp.load(examples.IRB2600), chunk=7)
    q = _q(kin, 5000, seed=5)
    assert np.array_equal(kin.fk_transforms(q), small.fk_transforms(q))
    assert np.array_equal(kin.fk(q), small.fk(q))


def test_a_block_reads_its_rows_whatever_their_layout(irb2600):
    """The block's rows are read whole where a row's numbers sit side by side, number by number
    where they do not: the lanes kernel launched on a column-major view gives the same poses."""
    import warp as wp

    q = _q(irb2600, 1001, seed=6)
    want = irb2600.fk_transforms(q)
    columns = np.asfortranarray(q)
    view = wp.array(ptr=columns.ctypes.data, dtype=wp.float32, shape=q.shape, strides=columns.strides, device="cpu")
    assert view.strides[1] != 4
    out = wp.empty((len(q), want.shape[1]), dtype=wp.transformf, device="cpu")
    wp.launch(irb2600._lanes()[0][7], dim=-(-len(q) // fk_lanes.LANES), inputs=[view], outputs=[out], device="cpu")
    assert np.array_equal(out.numpy().reshape(want.shape), want)
