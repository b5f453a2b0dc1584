"""The arm's IK takes its twenty angles eight at a time (``trig.atan2_lanes``): the lanes' atan2
against the scalar one bit for bit, a wrist that is not orthogonal (the Paden-Kahan branches no
bundled robot takes) against a product of exponentials written here, and the stretched arm, where
acos amplifies rounding."""

from __future__ import annotations

import numpy as np
import pytest
from ptx import ptx_of

import rswarp
from rswarp.examples import IRB2600
from rswarp.kernels.cache import FINITE_MATH, cpu_flags
from rswarp.kernels.ik import _folded, arm_ik_kernel
from rswarp.kernels.trig import V8D, atan2_lanes, trig_funcs
from rswarp.kinematics import ik as ikm
from rswarp.kinematics.kinematics import Kinematics
from rswarp.launch import Launcher, init_warp

wp = init_warp()


def _atan2_pair(flags: str):
    """A kernel giving the scalar atan2 and the lanes' of the same (N, 8) inputs, compiled with ``flags``."""
    scalar = trig_funcs(wp.float64).atan2

    @wp.kernel(enable_backward=False, module="unique")
    def both(y: wp.array2d(dtype=wp.float64), x: wp.array2d(dtype=wp.float64), one_out: wp.array2d(dtype=wp.float64),
             lanes_out: wp.array2d(dtype=wp.float64)):
        i = wp.tid()
        yv = V8D()
        xv = V8D()
        for ln in range(8):
            yv[ln] = y[i, ln]
            xv[ln] = x[i, ln]
            one_out[i, ln] = scalar(y[i, ln], x[i, ln])
        r = atan2_lanes(yv, xv)
        for ln in range(8):
            lanes_out[i, ln] = r[ln]

    if flags:
        cpu_flags(both.module, flags)
    return both


@pytest.mark.parametrize("flags", ["", FINITE_MATH, "-DRSW_LANES_LOOP"], ids=["plain", "finite-math", "loop"])
def test_the_lanes_atan2_is_the_scalar_atan2_bit_for_bit(flags):
    """Random magnitudes over ten decades, the axes, both signs, 1e-300 and 45 degrees: the same
    bits from the lanes as from the scalar function, vectorized or looped (any compiler but clang)."""
    rng = np.random.default_rng(3)
    y, x = rng.normal(size=(2, 40_000)) * 10.0 ** rng.integers(-6, 4, (2, 40_000))
    edges = np.array([0.0, 1.0, -1.0, 1e-300, -1e-300, 3.0, -3.0, 2.5])
    ey, ex = (a.ravel() for a in np.meshgrid(edges, edges))
    y = np.concatenate([y, ey]).reshape(-1, 8)
    x = np.concatenate([x, ex]).reshape(-1, 8)
    arrays = [wp.array(a, dtype=wp.float64, device="cpu") for a in (y, x)]
    outs = [wp.zeros(y.shape, dtype=wp.float64, device="cpu") for _ in range(2)]
    wp.launch(_atan2_pair(flags), len(y), inputs=arrays, outputs=outs, device="cpu")
    one, lanes = (o.numpy() for o in outs)
    assert np.array_equal(one, lanes)
    assert np.abs(one - np.arctan2(y, x)).max() < 1e-15 * np.pi


def _rodrigues(w: np.ndarray, q: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations about the unit axis w by the angles q."""
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    s, c = np.sin(q)[:, None, None], np.cos(q)[:, None, None]
    return np.eye(3) + s * k + (1 - c) * (k @ k)


def _poe(arm: ikm.ArmConstants, q: np.ndarray) -> np.ndarray:
    """(N, 4, 4) flange poses of the arm at q by the product of exponentials of its zero-position
    axes: each joint turns everything after it about its axis through its point."""
    w3 = arm.s3 * np.asarray(arm.w2)
    axes = [(arm.w1, arm.p1), (arm.w2, arm.p2), (w3, arm.p3), (arm.w4, arm.c0), (arm.w5, arm.c0), (arm.w6, arm.c0)]
    n = len(q)
    rot = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    pos = np.zeros((n, 3))
    for j, (w, p) in enumerate(axes):
        r = _rodrigues(np.asarray(w, float), q[:, j])
        p = np.asarray(p, float)
        pos = pos + np.einsum("nij,nj->ni", rot, p - r @ p)  # the joint's translation, in the frame so far
        rot = rot @ r
    rm = np.asarray(arm.rm, float).reshape(3, 3)
    out = np.zeros((n, 4, 4))
    out[:, :3, :3] = rot @ rm
    out[:, :3, 3] = pos + np.einsum("nij,j->ni", rot, np.asarray(arm.c0) - rm @ np.asarray(arm.cf))
    out[:, 3, 3] = 1.0
    return out


def _tilted_wrist() -> ikm.ArmConstants:
    """The IRB 2600's arm with axis 5 tilted 20 degrees towards axis 4: a spherical wrist that is
    not orthogonal, solved by Paden-Kahan subproblems 2 and 1."""
    arm = Kinematics(rswarp.load(IRB2600))._ik_form()
    w4, w5 = np.asarray(arm.w4, float), np.asarray(arm.w5, float)
    t = np.radians(20.0)
    w5 = np.cos(t) * w5 + np.sin(t) * w4
    return arm._replace(w5=tuple(w5 / np.linalg.norm(w5)), lo=(-np.pi,) * 6, hi=(np.pi,) * 6)


def test_a_wrist_that_is_not_orthogonal_meets_every_pose():
    """Every branch within the limits meets its pose within 1e-9 by the product of exponentials
    (float32 within 1e-3, its singular band), the configuration the pose came from is among them,
    and a straight wrist gives one solution. Folded back (q5 = pi) this wrist is not singular: its
    axis 6 is then off axis 4, and q4 must still turn it."""
    arm = _tilted_wrist()
    assert not _folded(arm, wp.float64).FLIP
    q = np.random.default_rng(5).uniform(-np.pi, np.pi, (4000, 6))
    q[:20, 4] = 0.0  # the wrist straight
    q[20:40, 4] = np.pi  # folded back
    poses = _poe(arm, q)
    for dtype, tol in ((np.float64, 1e-9), (np.float32, 1e-3)):  # float32: its singular band, 1e-3
        sol = ikm.closed_form(Launcher("cpu", threads=1), arm, poses.astype(dtype), dtype)
        rows = np.nonzero(sol.status == ikm.OK)
        got = _poe(arm, sol.q[rows].astype(np.float64))
        assert np.abs(got - poses[rows[0]]).max() < tol, dtype
    sol = ikm.closed_form(Launcher("cpu", threads=1), arm, poses, np.float64)
    near = np.abs(np.angle(np.exp(1j * (sol.q - q[:, None])))).max(axis=-1) < 1e-6
    assert (near & (sol.status != ikm.NO_REACH)).any(axis=1)[20:].all()
    assert (sol.status[:20, 1::2] == ikm.SAME).any(axis=1).all()  # a singular wrist's twin is the same pose


def test_a_wrist_folded_back_is_met_not_straightened():
    """The IRB 2600's orthogonal wrist with axis 5 free to turn (-pi, pi], poses at q5 = pi (axis 6
    folded back onto axis 4) and within float32's singular band of it: every branch within the
    limits meets its pose, in both precisions. The singular wrist's q5 is pi there, not 0."""
    kin = Kinematics(rswarp.load(IRB2600))
    arm = kin._ik_form()
    arm = arm._replace(lo=arm.lo[:4] + (-np.pi,) + arm.lo[5:], hi=arm.hi[:4] + (np.pi,) + arm.hi[5:])
    lo, hi = kin.mech.bounds()
    q = np.random.default_rng(12).uniform(lo, hi, (2000, 6))
    q[:, 4] = np.pi - np.random.default_rng(13).uniform(0.0, 5e-4, len(q)) * (np.arange(len(q)) % 2)
    link, off = kin.flange_frame()
    poses = kin.fk64(q)[:, link] @ off
    for dtype, tol in ((np.float64, 1e-9), (np.float32, 1e-3)):
        sol = ikm.closed_form(Launcher("cpu", threads=1), arm, poses.astype(dtype), dtype)
        rows = np.nonzero(sol.status == ikm.OK)
        got = kin.fk64(sol.q[rows].astype(np.float64))[:, link] @ off
        assert len(rows[0]) >= len(q)
        assert np.abs(got - poses[rows[0]]).max() < tol, dtype


def test_a_stretched_arm_keeps_its_digits():
    """Configurations within 1e-7 rad of the straight elbow, where acos amplifies rounding: every
    branch within the limits still meets its pose within 1e-14 m, as anywhere else (2e-15 m seen)."""
    kin = Kinematics(rswarp.load(IRB2600))
    arm = kin._ik_form()
    k = _folded(arm, wp.float64)
    straight = float(np.angle(np.exp(1j * arm.s3 * float(k.TURN0))))
    lo, hi = kin.mech.bounds()
    q = np.random.default_rng(9).uniform(lo, hi, (20_000, 6))
    q[:, 2] = straight + np.random.default_rng(10).uniform(-1e-7, 1e-7, len(q))
    q[:, 4] = np.where(np.abs(q[:, 4]) < 0.05, 0.05, q[:, 4])
    link, off = kin.flange_frame()
    poses = kin.fk64(q)[:, link] @ off
    sol = kin.ik64(poses)
    rows = np.nonzero(sol.ok)
    got = kin.fk64(sol.q[rows])[:, link] @ off
    assert len(rows[0]) > len(q)
    assert np.abs(got[:, :3, 3] - poses[rows[0], :3, 3]).max() < 1e-14


def test_the_benchmarks_count_eight_scalar_atan2_for_a_lanes_call():
    """``benchmarks/limits.py`` cannot read a native snippet; what it charges ``atan2_lanes`` is
    eight times what it counts for the scalar atan2 of a kernel (the IK's printed arithmetic)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).parents[1] / "benchmarks" / "limits.py"
    spec = importlib.util.spec_from_file_location("rswarp_bench_limits", path)
    limits = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(limits)
    scalar = trig_funcs(wp.float64).atan2

    @wp.kernel(enable_backward=False, module="unique")
    def one(y: wp.array(dtype=wp.float64), a_out: wp.array(dtype=wp.float64)):
        i = wp.tid()
        a_out[i] = scalar(y[i], y[i])

    a = wp.zeros(4, dtype=wp.float64, device="cpu")
    wp.launch(one, 4, inputs=[a], outputs=[a], device="cpu")
    assert limits.kernel_flops(limits.module_dir(one), "test_the_benchmarks") * 8 == limits.NATIVE_FLOPS["atan2_lanes"]


@pytest.mark.parametrize("scalar", ["float64", "float32"])
def test_the_lanes_kernel_compiles_for_cuda(scalar, tmp_path):
    """No GPU is here to run it, but NVRTC is: the IK kernel with its native lanes (the looped
    path, the one any compiler but the CPU's clang takes) compiles to PTX for sm_90, for an
    orthogonal wrist and a tilted one."""
    kin = Kinematics(rswarp.load(IRB2600))
    for arm in (kin._ik_form(), _tilted_wrist()):
        kernel = arm_ik_kernel(arm, getattr(wp, scalar))
        assert ".entry" in ptx_of(kernel.module, tmp_path)  # the kernel, its lanes inlined
