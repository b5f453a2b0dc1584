"""The paths a linear or circular RAPID move takes between two poses: the TCP on its line or on
the circle through three points, the orientation slerped, in NumPy (a quaternion at a time costs
less than SciPy's rotation objects, which a move would build thousands of). ``lines`` and
``poses_along`` do for many straight moves at once what ``path`` does for one, in the same
arithmetic, so their probes are the same to the bit."""

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


def angles(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The angle (N,) of the rotation from each of ``a`` to each of ``b`` (N, 3, 3), exact when small."""
    r = np.swapaxes(a, -1, -2) @ b
    cos = 0.5 * (np.trace(r, axis1=1, axis2=2) - 1.0)
    sin = 0.5 * np.linalg.norm(np.stack([r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0],
                                         r[:, 1, 0] - r[:, 0, 1]], axis=1), axis=1)
    return np.arctan2(sin, cos)


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


def quaternions(m: np.ndarray) -> np.ndarray:
    """``quaternion`` of rotation matrices (N, 3+, 3+) at once, the same arithmetic row by row."""
    (a, b, c), (d, e, f), (g, h, i) = (m[:, r, :3].T for r in range(3))
    tr = a + e + i
    first = tr >= np.maximum(np.maximum(a, e), i)
    second = ~first & (a >= e) & (a >= i)
    third = ~first & ~second & (e >= i)
    q = np.empty((len(m), 4))
    for rows, root, parts in ((first, lambda k: tr[k] + 1.0, _q_trace),
                              (second, lambda k: 1.0 + a[k] - e[k] - i[k], _q_x),
                              (third, lambda k: 1.0 + e[k] - a[k] - i[k], _q_y),
                              (~(first | second | third), lambda k: 1.0 + i[k] - a[k] - e[k], _q_z)):
        k = np.flatnonzero(rows)
        if len(k):
            r = 2.0 * np.sqrt(root(k))
            q[k] = np.column_stack(parts(r, *(v[k] for v in (a, b, c, d, e, f, g, h, i))))
    n = np.sqrt(q[:, 0] * q[:, 0] + q[:, 1] * q[:, 1] + q[:, 2] * q[:, 2] + q[:, 3] * q[:, 3])
    return q / n[:, None]


def _q_trace(r, a, b, c, d, e, f, g, h, i):
    return 0.25 * r, (h - f) / r, (c - g) / r, (d - b) / r


def _q_x(r, a, b, c, d, e, f, g, h, i):
    return (h - f) / r, 0.25 * r, (b + d) / r, (c + g) / r


def _q_y(r, a, b, c, d, e, f, g, h, i):
    return (c - g) / r, (b + d) / r, 0.25 * r, (f + h) / r


def _q_z(r, a, b, c, d, e, f, g, h, i):
    return (d - b) / r, (c + g) / r, (f + h) / r, 0.25 * r


def lines(start: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``path``'s measures of straight moves from poses ``start`` to ``end`` (N, 4, 4) at once:
    (length (N,), turn (N,), q0, q1 (N, 4), q1 on q0's side)."""
    q0, q1 = quaternions(start), quaternions(end)
    dot = np.array([a @ b for a, b in zip(q0, q1)])  # as ``path`` takes it: the turn's arccos magnifies its rounding
    q1 = np.where((dot < 0)[:, None], -q1, q1)
    turn = 2.0 * np.arccos(np.minimum(1.0, np.abs(dot)))
    length = np.array([np.linalg.norm(v) for v in end[:, :3, 3] - start[:, :3, 3]])
    return length, turn, q0, q1


def poses_along(u: np.ndarray, q0: np.ndarray, q1: np.ndarray, half: np.ndarray, p0: np.ndarray,
                p1: np.ndarray) -> np.ndarray:
    """Poses (N, 4, 4) at shares ``u`` (N,) of straight moves, each row its own move's start and
    end (``q0``, ``q1``, ``p0``, ``p1``, rows of (N, 4) and (N, 3), ``half`` its half turn): the
    TCP on its line, the orientation slerped, as ``path``'s ``at`` computes each."""
    out = np.zeros((len(u), 4, 4))
    _rotations_into(slerps(q0, q1, u, half), out)
    out[:, :3, 3] = p0 + u[:, None] * (p1 - p0)
    out[:, 3, 3] = 1.0
    return out


def _rotations_into(q: np.ndarray, out: np.ndarray) -> None:
    """``rotations`` of quaternions (N, 4) written into ``out[:, :3, :3]``."""
    w, x, y, z = q.T
    xx, yy, zz, xy, xz, yz, wx, wy, wz = x * x, y * y, z * z, x * y, x * z, y * z, w * x, w * y, w * z
    for (r, c), v in zip(((0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (1, 2), (2, 0), (2, 1), (2, 2)),
                         (1 - 2 * (yy + zz), 2 * (xy - wz), 2 * (xz + wy), 2 * (xy + wz), 1 - 2 * (xx + zz),
                          2 * (yz - wx), 2 * (xz - wy), 2 * (yz + wx), 1 - 2 * (xx + yy))):
        out[:, r, c] = v


def slerps(q0: np.ndarray, q1: np.ndarray, u: np.ndarray, half: np.ndarray) -> np.ndarray:
    """``slerp`` row by row: quaternion rows ``q0``, ``q1`` (N, 4), shares ``u`` and half angles ``half`` (N,)."""
    near = half < 1e-9
    s = np.sin(half)
    with np.errstate(divide="ignore", invalid="ignore"):  # rows near no turn are taken linearly
        out = (np.sin((1 - u) * half) / s)[:, None] * q0 + (np.sin(u * half) / s)[:, None] * q1
    if near.any():
        k = np.flatnonzero(near)
        out[k] = q0[k] + u[k, None] * (q1[k] - q0[k])
    w, x, y, z = out.T
    return out / np.sqrt(w * w + x * x + y * y + z * z)[:, None]  # ``np.linalg.norm``'s sum, in its order
