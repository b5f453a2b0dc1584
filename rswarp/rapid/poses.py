"""RAPID's pose arithmetic on its own records, in its own units (mm, quaternions [q1, q2, q3, q4]
= [w, x, y, z], angles in degrees): Offs, RelTool, OrientZYX, EulerZYX, PoseMult, PoseInv,
PoseVect, NOrient, DefFrame and the vector functions, in plain Python (a statement computes one
pose; NumPy's call costs more than the arithmetic)."""

from __future__ import annotations

import math

from .values import Rec

Quat = tuple[float, float, float, float]
Vec = tuple[float, float, float]


def qmul(a: Quat, b: Quat) -> Quat:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def qconj(q: Quat) -> Quat:
    return (q[0], -q[1], -q[2], -q[3])


def qnorm(q: Quat) -> Quat:
    n = math.sqrt(sum(c * c for c in q))
    return tuple(c / n for c in q) if n > 0 else (1.0, 0.0, 0.0, 0.0)


def rotate(q: Quat, v: Vec) -> Vec:
    w, x, y, z = q
    vx, vy, vz = v
    # v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
    cx, cy, cz = y * vz - z * vy, z * vx - x * vz, x * vy - y * vx
    return (vx + 2 * (w * cx + y * cz - z * cy), vy + 2 * (w * cy + z * cx - x * cz),
            vz + 2 * (w * cz + x * cy - y * cx))


def axis_angle(axis: int, degrees: float) -> Quat:
    h = math.radians(degrees) / 2
    q = [math.cos(h), 0.0, 0.0, 0.0]
    q[1 + axis] = math.sin(h)
    return tuple(q)


def pos(v: Vec) -> Rec:
    return Rec("pos", tuple(float(c) for c in v))


def orient(q: Quat) -> Rec:
    return Rec("orient", tuple(float(c) for c in q))


def pose(trans: Vec, rot: Quat) -> Rec:
    return Rec("pose", (pos(trans), orient(rot)))


def frame(value: Rec) -> tuple[Vec, Quat]:
    """(translation, quaternion) of a pose or robtarget record."""
    return value.vals[0].vals, value.vals[1].vals


def compose(a: tuple[Vec, Quat], b: tuple[Vec, Quat]) -> tuple[Vec, Quat]:
    (ta, qa), (tb, qb) = a, b
    r = rotate(qa, tb)
    return (ta[0] + r[0], ta[1] + r[1], ta[2] + r[2]), qnorm(qmul(qa, qb))


def invert(a: tuple[Vec, Quat]) -> tuple[Vec, Quat]:
    t, q = a
    c = qconj(q)
    r = rotate(c, t)
    return (-r[0], -r[1], -r[2]), c


def offs(target: Rec, dx: float, dy: float, dz: float) -> Rec:
    """Offs: the robtarget displaced in its work object (mm)."""
    x, y, z = target.vals[0].vals
    return Rec(target.type, (pos((x + dx, y + dy, z + dz)),) + target.vals[1:])


def reltool(target: Rec, dx: float, dy: float, dz: float, rx: float = 0.0, ry: float = 0.0, rz: float = 0.0) -> Rec:
    """RelTool: displaced in the target's own tool frame (mm), then turned about its x, then the
    new y, then the new z (degrees)."""
    t, q = frame(target)
    turn = qmul(qmul(axis_angle(0, rx), axis_angle(1, ry)), axis_angle(2, rz))
    t2, q2 = compose((t, q), ((dx, dy, dz), turn))
    return Rec(target.type, (pos(t2), orient(q2)) + target.vals[2:])


def orient_zyx(z: float, y: float, x: float) -> Rec:
    """OrientZYX: the orientation turned about z, then the new y, then the new x (degrees)."""
    return orient(qmul(qmul(axis_angle(2, z), axis_angle(1, y)), axis_angle(0, x)))


def euler_zyx(q: Quat, which: str) -> float:
    """EulerZYX: one angle (degrees) of the orientation's z-y-x Euler angles."""
    w, x, y, z = qnorm(q)
    if which == "x":
        return math.degrees(math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)))
    if which == "y":
        return math.degrees(math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x)))))
    return math.degrees(math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))


def pose_mult(a: Rec, b: Rec) -> Rec:
    return pose(*compose(frame(a), frame(b)))


def pose_inv(a: Rec) -> Rec:
    return pose(*invert(frame(a)))


def pose_vect(a: Rec, p: Rec) -> Rec:
    t, q = frame(a)
    r = rotate(q, p.vals)
    return pos((t[0] + r[0], t[1] + r[1], t[2] + r[2]))


def def_frame(p1: Vec, p2: Vec, p3: Vec, origin: int = 1) -> Rec | None:
    """DefFrame: x from p1 towards p2, y towards p3 in their plane; origin at p1 (\\Origin 1, the
    default), at p2 (2), or on the line through p1 and p2 where p3 is on the y axis (3). None
    where the points are on one line."""
    x = _unit(_sub(p2, p1))
    v = _sub(p3, p1)
    z = _cross(x, v) if x else None
    if not x or not z or _length(z) < 1e-9:
        return None
    z = _unit(z)
    y = _cross(z, x)
    o = p2 if origin == 2 else tuple(a + b * sum(c * d for c, d in zip(v, x)) for a, b in zip(p1, x)) \
        if origin == 3 else p1
    return pose(o, matrix_quat((x, y, z)))


def matrix_quat(cols) -> Quat:
    """The unit quaternion of a rotation given by its columns (x, y, z axes)."""
    (m00, m10, m20), (m01, m11, m21), (m02, m12, m22) = cols
    tr = m00 + m11 + m22
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = (0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s)
    elif m00 > m11 and m00 > m22:
        s = math.sqrt(1.0 + m00 - m11 - m22) * 2
        q = ((m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s)
    elif m11 > m22:
        s = math.sqrt(1.0 + m11 - m00 - m22) * 2
        q = ((m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s)
    else:
        s = math.sqrt(1.0 + m22 - m00 - m11) * 2
        q = ((m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s)
    return qnorm(q)


def _sub(a: Vec, b: Vec) -> Vec:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _cross(a: Vec, b: Vec) -> Vec:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _length(a: Vec) -> float:
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


def _unit(a: Vec) -> Vec | None:
    n = _length(a)
    return tuple(c / n for c in a) if n > 1e-12 else None


def distance(a: Vec, b: Vec) -> float:
    return _length(_sub(a, b))


def cross(a: Vec, b: Vec) -> Vec:
    """The vector product (CrossProd, and RAPID's ``pos * pos``)."""
    return _cross(a, b)


def mir_pos(target: Rec, plane: Rec, mir_y: bool = False) -> Rec:
    """MirPos: the robtarget mirrored in the xy-plane of the work object's frame (uframe then
    oframe); the tool's x axis turned back (its y axis with \\MirY), so the frame stays right-handed."""
    f = compose(frame(plane.vals[3]), frame(plane.vals[4]))
    t, q = compose(invert(f), frame(target))
    cols = [rotate(q, e) for e in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))]
    cols = [(c[0], c[1], -c[2]) for c in cols]  # every axis mirrored in the plane
    flip = 1 if mir_y else 0
    cols[flip] = tuple(-c for c in cols[flip])
    t2, q2 = compose(f, ((t[0], t[1], -t[2]), matrix_quat(cols)))
    return Rec(target.type, (pos(t2), orient(q2)) + target.vals[2:])
