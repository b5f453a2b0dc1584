"""Rotations and rigid transforms in NumPy (float64): the one place where Euler angles, quaternions
and 4x4 matrices are converted. Matrices act on column vectors; quaternions are (w, x, y, z)."""

from __future__ import annotations

import math

import numpy as np


def euler_zyx_matrix(rx: float, ry: float, rz: float) -> np.ndarray:
    """R = Rz(rz) @ Ry(ry) @ Rx(rx): ZYX Euler angles as RobotStudio (and URDF's rpy) write them."""
    cx, sx, cy, sy, cz, sz = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    return np.array([
        [cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
        [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
        [-sy, cy * sx, cy * cx],
    ])


def matrix_euler_zyx(r: np.ndarray) -> tuple[float, float, float]:
    """(rx, ry, rz) with R = Rz(rz) Ry(ry) Rx(rx); at gimbal lock the whole turn goes into rz."""
    cy = math.hypot(r[0, 0], r[1, 0])
    ry = math.atan2(-r[2, 0], cy)  # atan2, not asin: well conditioned near +-90 degrees
    if cy > 1e-6:
        return math.atan2(r[2, 1], r[2, 2]), ry, math.atan2(r[1, 0], r[0, 0])
    return 0.0, ry, math.atan2(-r[0, 1], r[1, 1])


def quat_matrix(q) -> np.ndarray:
    """Rotation matrix of a quaternion (w, x, y, z), normalized first."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def matrix_quat(r: np.ndarray) -> tuple[float, float, float, float]:
    """Unit quaternion (w, x, y, z) with w >= 0 of a rotation matrix (Shepperd's method)."""
    r = np.asarray(r, float)
    tr = np.trace(r)
    if tr > 0:
        s = 2.0 * math.sqrt(1.0 + tr)
        q = (0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s)
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        q = ((r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s)
    elif r[1, 1] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        q = ((r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        q = ((r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s)
    q = np.asarray(q) / np.linalg.norm(q)
    return tuple(float(v) for v in (q if q[0] >= 0 else -q))


def quat_x_to(axis) -> tuple[float, float, float, float]:
    """The shortest rotation (w, x, y, z) taking +X onto ``axis``: a joint frame whose X is the axis."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    c = float(a[0])
    if c > 1 - 1e-12:
        return (1.0, 0.0, 0.0, 0.0)
    if c < -1 + 1e-12:
        return (0.0, 0.0, 0.0, 1.0)  # 180 degrees about z
    v = np.cross([1.0, 0.0, 0.0], a)
    w = 1.0 + c
    n = math.sqrt(w * w + float(v @ v))
    return (w / n, *(float(t / n) for t in v))


def translated(m: np.ndarray, origin) -> np.ndarray:
    """``m`` seen from a world-aligned frame at ``origin``: the translation less the origin."""
    rel = np.array(m, float)
    rel[:3, 3] -= np.asarray(origin, float)
    return rel
