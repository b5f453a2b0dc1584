"""Poses shown to people: ZYX Euler angles read back to the same rotation, gimbal lock included."""

import math

import numpy as np

from rswarp.transforms import euler_zyx_matrix
from rswarp.transforms import matrix_euler_zyx as euler_zyx


def test_euler_round_trip():
    rng = np.random.default_rng(0)
    for _ in range(500):
        e = rng.uniform(-math.pi, math.pi, 3)
        e[1] = rng.uniform(-math.pi / 2, math.pi / 2)
        assert np.allclose(euler_zyx_matrix(*euler_zyx(euler_zyx_matrix(*e))), euler_zyx_matrix(*e), atol=1e-12)


def test_gimbal_lock_is_exact_for_float32_input():
    r = euler_zyx_matrix(0.3, math.pi / 2, -0.2).astype(np.float32).astype(np.float64)
    rx, ry, rz = euler_zyx(r)
    assert abs(ry - math.pi / 2) < 1e-6  # atan2: no sqrt blow-up of float32 rounding near 90 degrees
    assert np.allclose(euler_zyx_matrix(rx, ry, rz), r, atol=1e-6)
