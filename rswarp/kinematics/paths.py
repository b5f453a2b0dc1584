"""The paths a linear or circular RAPID move takes between two poses: the TCP on its line or on
the circle through three points, the orientation slerped, in NumPy (a quaternion at a time costs
less than SciPy's rotation objects, which a move would build thousands of)."""

from __future__ import annotations

import math

import numpy as np


def path(start: np.ndarray, end: np.ndarray, circle: np.ndarray | None = None):
    """``at(u)`` poses (N, 4, 4) along the straight line (or the circle through ``circle``) from
    ``start`` to ``end``, orientation slerped; the path's length (m) and turn (rad). ValueError
    for a circle whose points are on one line."""
    q0, q1 = quaternion(start[:3, :3]), quaternion(end[:3, :3])
    if q0 @ q1 < 0:
        q1 = -q1
    turn = float(2.0 * np.arccos(min(1.0, abs(float(q0 @ q1)))))
    p0, p1 = start[:3, 3], end[:3, 3]
    if circle is None:
        length = float(np.linalg.norm(p1 - p0))

        def point(u):
            return p0 + np.outer(u, p1 - p0)
    else:
        point, length = _arc(p0, circle[:3, 3], p1)

    def at(u):
        u = np.atleast_1d(u)
        out = np.zeros((len(u), 4, 4))
        out[:, :3, :3] = rotations(slerp(q0, q1, u, turn / 2))
        out[:, :3, 3] = point(u)
        out[:, 3, 3] = 1.0
        return out

    return at, length, turn


def quaternion(m: np.ndarray) -> np.ndarray:
    """The unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method)."""
    (a, b, c), (d, e, f), (g, h, i) = m[:3, :3].tolist()
    tr = a + e + i
    if tr >= max(a, e, i):
        r = 2.0 * math.sqrt(tr + 1.0)
        q = (0.25 * r, (h - f) / r, (c - g) / r, (d - b) / r)
    elif a >= e and a >= i:
        r = 2.0 * math.sqrt(1.0 + a - e - i)
        q = ((h - f) / r, 0.25 * r, (b + d) / r, (c + g) / r)
    elif e >= i:
        r = 2.0 * math.sqrt(1.0 + e - a - i)
        q = ((c - g) / r, (b + d) / r, 0.25 * r, (f + h) / r)
    else:
        r = 2.0 * math.sqrt(1.0 + i - a - e)
        q = ((d - b) / r, (c + g) / r, (f + h) / r, 0.25 * r)
    n = math.sqrt(sum(v * v for v in q))
    return np.array(q) / n


def slerp(q0: np.ndarray, q1: np.ndarray, u: np.ndarray, half: float) -> np.ndarray:
    """Quaternions (N, 4) a share ``u`` of the way from q0 to q1 (``half``: half the angle between)."""
    if half < 1e-9:
        out = q0 + np.outer(u, q1 - q0)
    else:
        s = np.sin(half)
        out = np.outer(np.sin((1 - u) * half) / s, q0) + np.outer(np.sin(u * half) / s, q1)
    return out / np.linalg.norm(out, axis=1, keepdims=True)


def rotations(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (N, 3, 3) of unit quaternions (N, 4), (w, x, y, z)."""
    w, x, y, z = q.T
    xx, yy, zz, xy, xz, yz, wx, wy, wz = x * x, y * y, z * z, x * y, x * z, y * z, w * x, w * y, w * z
    return np.column_stack([1 - 2 * (yy + zz), 2 * (xy - wz), 2 * (xz + wy),
                            2 * (xy + wz), 1 - 2 * (xx + zz), 2 * (yz - wx),
                            2 * (xz - wy), 2 * (yz + wx), 1 - 2 * (xx + yy)]).reshape(-1, 3, 3)


def turn_between(a: np.ndarray, b: np.ndarray) -> float:
    """The angle (rad) of the rotation from matrix ``a`` to ``b``."""
    c = (np.trace(a.T @ b) - 1.0) / 2.0
    return float(np.arccos(np.clip(c, -1.0, 1.0)))


def _arc(a: np.ndarray, b: np.ndarray, c: np.ndarray):
    """(point(u), length) of the circle arc from a through b to c."""
    ab, ac = b - a, c - a
    n = np.cross(ab, ac)
    scale = max(np.linalg.norm(ab), np.linalg.norm(ac), 1e-9)
    if np.linalg.norm(n) < 1e-6 * scale * scale or min(np.linalg.norm(ab), np.linalg.norm(ac),
                                                        np.linalg.norm(c - b)) < 1e-6:
        raise ValueError("the start, the circle point and the end of a circle are on one line (or two coincide)")
    centre = a + (np.cross(n, ab) * (ac @ ac) + np.cross(ac, n) * (ab @ ab)) / (2 * (n @ n))
    r = float(np.linalg.norm(a - centre))
    e1 = (a - centre) / r
    e2 = np.cross(n / np.linalg.norm(n), e1)
    angle = lambda p: np.mod(np.arctan2((p - centre) @ e2, (p - centre) @ e1), 2 * np.pi)  # noqa: E731
    sweep = angle(c)

    def point(u):
        t = np.asarray(u) * sweep
        return centre + r * (np.outer(np.cos(t), e1) + np.outer(np.sin(t), e2))

    return point, r * sweep
