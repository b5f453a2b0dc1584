"""Inverse kinematics (issue "Robot programs", part 1): every branch of every pose against the
mechanism's own forward kinematics, ABB configuration data, the palletizer's closed form, the
numerical fallback, and what a pose out of reach or at the wrist singularity gives."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

import rswarp
from rswarp.examples import IRB1300, IRB2600, IRB2600ID, PALLETIZER
from rswarp.kinematics import ik as ikm
from rswarp.kinematics.kinematics import Kinematics

from conftest import DATA

ARMS = [IRB1300, IRB2600, IRB2600ID, DATA / "ik" / "reversed_j3.rsxml"]
CHUNK = 20_000  # poses checked at once: their 8 branches' link poses stay under 150 MB


@lru_cache(maxsize=None)
def kinematics(path) -> Kinematics:
    return Kinematics(rswarp.load(path))


def configurations(kin: Kinematics, n: int, seed: int = 0) -> np.ndarray:
    lo, hi = kin.mech.bounds()
    return np.random.default_rng(seed).uniform(np.maximum(lo, -2 * np.pi), np.minimum(hi, 2 * np.pi), (n, kin.dof))


def flange(kin: Kinematics, q: np.ndarray) -> np.ndarray:
    link, m = kin.flange_frame()
    return kin.fk64(q)[:, link] @ m


def mismatch(kin: Kinematics, q: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Per row, the larger of the position error (m) and the rotation error (rad, from the matrix
    difference: both are small)."""
    got = flange(kin, q)
    pos = np.abs(got[:, :3, 3] - poses[:, :3, 3]).max(axis=1)
    rot = np.abs(got[:, :3, :3] - poses[:, :3, :3]).max(axis=(1, 2))
    return np.maximum(pos, rot)


def same_angles(a: np.ndarray, b: np.ndarray, tol: float) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * (a - b)))).max(axis=-1) < tol


@pytest.mark.parametrize("path", ARMS, ids=lambda p: p.stem)
def test_every_branch_of_a_million_poses_meets_its_pose(path):
    """10^6 random configurations within the limits: every valid branch of every pose meets the
    pose within 1e-9 (m and rad) in float64, and the configuration it came from is among them."""
    kin = kinematics(path)
    assert kin.ik_method == "arm"
    q = configurations(kin, 1_000_000)
    for lo in range(0, len(q), CHUNK):
        part = q[lo:lo + CHUNK]
        poses = flange(kin, part)
        sol = kin.ik64(poses)
        rows = np.nonzero(sol.ok)
        assert mismatch(kin, sol.q[rows], poses[rows[0]]).max() < 1e-9
        found = (same_angles(sol.q, part[:, None], 1e-6) & sol.ok).any(axis=1)
        assert found.all(), part[~found][:3]


@pytest.mark.parametrize("path", ARMS, ids=lambda p: p.stem)
def test_confdata_picks_the_solution_that_has_it(path):
    """The solution ik picks for a configuration's confdata is that configuration (turns of axes 4
    and 6 included), and its confdata is the one asked for."""
    kin = kinematics(path)
    q = configurations(kin, 20_000, seed=1)
    conf = kin.confdata(q)
    got, found = kin.ik64(flange(kin, q), conf=conf)
    assert found.all()
    assert np.abs(got - q).max() < 1e-8
    assert (kin.confdata(got) == conf).all()


def test_confdata_follows_abb_quadrants():
    """cf1, cf4, cf6: quadrant k holds [k 90, (k + 1) 90) deg, negative ones from -1; cfx at the
    zero position is 0 (wrist in front of axis 1 and of the lower arm, q5 not negative)."""
    kin = kinematics(IRB2600)
    q = np.radians([[0, 0, 0, 0, 30, 0], [95, 0, 0, -1, 30, 270], [-90, 0, 0, 359, -30, -91],
                    [180, 0, 0, 0, 30, 0], [0, 0, -170, 0, 30, 0]])
    conf = kin.confdata(q)
    assert conf[:, :3].tolist() == [[0, 0, 0], [1, -1, 3], [-1, 3, -2], [2, 0, 0], [0, 0, 0]]
    assert conf[0, 3] == 0 and conf[2, 3] == 1
    assert conf[3, 3] == 0  # axis 1 turned half a turn carries the arm's direction with it
    assert conf[4, 3] == 6  # J3 folded back: the wrist centre behind the lower arm and behind axis 1


def test_the_eight_branches_have_eight_configurations():
    """A pose well inside the workspace has all eight branches, each with its own cfx."""
    kin = kinematics(IRB2600)
    poses = flange(kin, np.radians([[10, 20, -30, 40, 50, 60]]))
    sol = kin.ik64(poses)
    valid = sol.conf[0][sol.ok[0]]
    assert len({tuple(c) for c in valid[:, [0, 3]].tolist()}) == sol.ok[0].sum()
    assert set(valid[:, 3].tolist()) <= set(range(8))


def test_float32_meets_the_pose_within_1e_5_away_from_the_wrist_singularity():
    kin = kinematics(IRB2600)
    q = configurations(kin, 100_000, seed=2)
    poses = flange(kin, q)
    sol = kin.ik(poses.astype(np.float32))
    keep = sol.ok & (np.abs(sol.q[..., 4]) > np.radians(2))
    rows = np.nonzero(keep)
    assert mismatch(kin, sol.q[rows].astype(np.float64), poses[rows[0]]).max() < 1e-5


def test_a_pose_out_of_reach_is_flagged_never_answered():
    kin = kinematics(IRB2600)
    pose = flange(kin, np.zeros((1, 6)))
    pose[0, 0, 3] += 2.0  # two metres beyond the stretched arm
    sol = kin.ik64(pose)
    assert not sol.ok.any()
    assert set(sol.status.ravel().tolist()) == {ikm.NO_REACH}
    q, found = kin.ik64(pose, conf=[0, 0, 0, 0])
    assert not found[0] and np.isnan(q).all()


def test_a_pose_reached_only_outside_the_limits_is_flagged():
    """J2 at 160 deg (its limit is 155): the pose exists, no solution within the limits has it."""
    kin = kinematics(IRB2600)
    q = np.radians([[0, 160, -60, 0, 30, 0]])
    sol = kin.ik64(flange(kin, q))
    near = same_angles(sol.q[0], q, 1e-6)
    assert near.any() and sol.status[0][near][0] == ikm.NO_LIMITS


def test_wrist_singularity_gives_one_solution_holding_q4_at_zero():
    """q5 = 0: axes 4 and 6 in line. One solution per arm branch, q4 = 0, q6 takes q4 + q6; its
    flip is marked the same pose."""
    kin = kinematics(IRB2600)
    q = np.radians([[20, 10, 5, 35, 0, 25]])
    poses = flange(kin, q)
    sol = kin.ik64(poses)
    arm = np.nonzero(same_angles(sol.q[0, :, :3], q[:, :3], 1e-9))[0]  # the branch pair of q's arm
    assert len(arm) == 2 and arm[0] % 2 == 0
    first, twin = arm
    assert sol.status[0, first] == ikm.OK and sol.status[0, twin] == ikm.SAME
    assert sol.q[0, first, 3] == 0.0 and sol.q[0, first, 4] == 0.0
    assert np.isclose(sol.q[0, first, 5], np.radians(60))
    assert mismatch(kin, sol.q[0, [first]], poses).max() < 1e-9


@pytest.mark.parametrize("path", ARMS, ids=lambda p: p.stem)
def test_near_the_wrist_singularity_rounded_poses_are_met_by_every_branch(path):
    """float32 flange poses (``kin.flange``, rounded to 1e-7) with |q5| < 1e-3, solved in float64:
    where the rounding sets q4, q6 makes up the rest of the turn, so every valid branch meets the
    pose within its rounding (a new user's first flow once met it 0.08 rad off)."""
    kin = kinematics(path)
    q = configurations(kin, 5000, seed=3)
    q[:, 4] = np.random.default_rng(4).uniform(-1e-3, 1e-3, len(q))
    poses = kin.flange(q).astype(np.float64)
    sol = kin.ik64(poses)
    rows = np.nonzero(sol.ok)
    assert len(rows[0]) >= len(q)
    assert mismatch(kin, sol.q[rows], poses[rows[0]]).max() < 1e-5


def test_the_palletizer_closed_form_through_its_loops():
    """10^6 configurations of the IRB 9460 (its parallel rods solved as loops): every branch meets
    its pose, the configuration is among them, and its confdata picks it."""
    kin = kinematics(PALLETIZER)
    assert kin.ik_method == "palletizer"
    q = configurations(kin, 1_000_000, seed=3)
    for lo in range(0, len(q), 2 * CHUNK):
        part = q[lo:lo + 2 * CHUNK]
        poses = flange(kin, part)
        sol = kin.ik64(poses)
        rows = np.nonzero(sol.ok)
        assert mismatch(kin, sol.q[rows], poses[rows[0]]).max() < 1e-9
        assert (same_angles(sol.q, part[:, None], 1e-6) & sol.ok).any(axis=1).all()
        if lo == 0:
            got, found = kin.ik64(poses, conf=kin.confdata(part))
            assert found.all() and np.abs(got - part).max() < 1e-8


def test_a_palletizer_cannot_tilt_its_flange():
    kin = kinematics(PALLETIZER)
    pose = flange(kin, np.zeros((1, kin.dof)))
    c, s = np.cos(0.1), np.sin(0.1)
    pose[0, :3, :3] = pose[0, :3, :3] @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    assert not kin.ik64(pose).ok.any()


def test_other_mechanisms_are_solved_numerically_and_say_so():
    """J6 off the wrist centre: no closed form; damped least squares from several starts finds the
    pose within 1e-9 and is flagged numerical."""
    kin = kinematics(DATA / "ik" / "offset_wrist.rsxml")
    assert kin.ik_method == "numerical"
    q = configurations(kin, 40, seed=4)
    poses = flange(kin, q)
    sol = kin.ik64(poses)
    assert sol.numerical
    assert sol.ok.any(axis=1).mean() > 0.9
    rows = np.nonzero(sol.ok)
    assert mismatch(kin, sol.q[rows], poses[rows[0]]).max() < 1e-9


def test_every_solution_goes_into_the_arrays_given_as_out():
    """``ik64``/``ik`` with ``out=`` fill the caller's arrays with the same numbers as fresh ones,
    and refuse arrays of another shape or type, ``conf`` beside them, and a robot with no arm's
    closed form."""
    kin = kinematics(IRB2600)
    poses = flange(kin, configurations(kin, 500, seed=9))
    for solve, dtype in ((kin.ik64, np.float64), (kin.ik, np.float32)):
        fresh = solve(poses)
        out = ikm.IKSolutions(np.full((500, 8, 6), 7.0, dtype), np.zeros((500, 8, 4), np.int8),
                              np.zeros((500, 8), np.int8))
        assert solve(poses, out=out) is out
        for a, b in ((out.q, fresh.q), (out.conf, fresh.conf), (out.status, fresh.status)):
            assert np.array_equal(a, b, equal_nan=True)
        with pytest.raises(ValueError, match="out.q must be a C-contiguous"):
            solve(poses[:499], out=out)
    with pytest.raises(ValueError, match="not taken with conf"):
        kin.ik64(poses, conf=(0, 0, 0, 0), out=out)
    pal = kinematics(PALLETIZER)
    with pytest.raises(ValueError, match="arm's closed form"):
        pal.ik64(flange(pal, configurations(pal, 3)), out=out)
