"""RAPID's motion data as rswarp uses it, in SI, from the interpreter's records: poses (RAPID: mm,
quaternion [q1, q2, q3, q4] = [w, x, y, z]), tools, work objects, robtargets, jointtargets,
speeds and zones; each checked as the controller checks it before a move (a quaternion normalized
within 0.1, numbers finite, speeds positive), a ``Mismatch`` saying what is wrong otherwise."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .values import Mismatch, Rec

NO_VALUE = 9e9  # RAPID's "not used" (extax, a jointtarget's unused axes)
UNUSED = (8.9e9, 9.1e9)  # a value in this band is "not used" (9E9 as written); beyond it, a number too large
MAX_MM = 1e6  # 1 km, the bound of every length rswarp reads
MAX_AXIS = 1e5  # degrees or mm of a joint value
QUAT_SLACK = 0.1  # |q1²+q2²+q3²+q4² - 1| the controller normalizes; beyond, it refuses the orientation
MAX_SPEED = 1e5  # mm/s or deg/s
TOP_TCP_SPEED = 7000.0  # mm/s: the controller runs a faster v_tcp at the robot's top speed (v7000, ABB's largest)


@dataclass(frozen=True)
class Pose:
    """A RAPID pose in SI: translation (m) and unit quaternion (w, x, y, z)."""

    trans: tuple[float, float, float]
    quat: tuple[float, float, float, float]

    def matrix(self) -> np.ndarray:
        """The 4x4 transform (a new array each call; the first is kept)."""
        cached = self.__dict__.get("_matrix")
        if cached is None:
            cached = self._compute()
            self.__dict__["_matrix"] = cached
        return cached.copy()

    def _compute(self) -> np.ndarray:
        w, x, y, z = self.quat
        m = np.eye(4)
        m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
        m[:3, 3] = self.trans
        return m


IDENTITY = Pose((0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0))


@dataclass(frozen=True)
class Load:
    mass: float  # kg
    cog: tuple[float, float, float]  # m, in the tool's frame
    inertia: tuple[float, float, float]  # kg m², about the axes of moment
    aom: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)  # the axes of moment (w, x, y, z) in the tool's frame


@dataclass(frozen=True)
class Tool:
    robhold: bool
    tframe: Pose
    load: Load | None = None


@dataclass(frozen=True)
class WorkObject:
    robhold: bool
    ufprog: bool
    ufmec: str
    uframe: Pose
    oframe: Pose

    def matrix(self) -> np.ndarray:
        return self.uframe.matrix() @ self.oframe.matrix()

    @property
    def coordinated(self) -> bool:
        """Moved by a mechanical unit (ufprog FALSE): its frame follows axes rswarp does not have."""
        return not self.ufprog


@dataclass(frozen=True)
class RobTarget:
    pose: Pose  # the TCP in the work object
    conf: tuple[int, int, int, int]  # cf1, cf4, cf6, cfx
    extax: tuple[float | None, ...] = (None,) * 6  # mm or degrees; None: not used


@dataclass(frozen=True)
class JointTarget:
    robax: tuple[float | None, ...]  # degrees (rotational) or mm (linear), as RAPID writes them; None: 9E9
    extax: tuple[float | None, ...] = (None,) * 6


@dataclass(frozen=True)
class Speed:
    v_tcp: float  # m/s
    v_ori: float  # rad/s
    v_leax: float = math.inf  # m/s: a linear external axis's (a track's) top speed; inf: none given
    v_reax: float = math.inf  # rad/s: a rotating external axis's (a positioner's)


@dataclass(frozen=True)
class Zone:
    fine: bool
    pzone_tcp: float  # m
    pzone_ori: float = 0.0  # m
    zone_ori: float = 0.0  # rad


def _numbers(values, what: str, bound: float) -> tuple[float, ...]:
    out = tuple(float(v) for v in values)
    for v in out:
        if not math.isfinite(v):
            raise Mismatch(f"{what} holds {v}: every number must be finite")
        if abs(v) > bound:
            raise Mismatch(f"{what} holds {v:g}, beyond {bound:g}")
    return out


def quaternion(value: Rec, what: str) -> tuple[float, float, float, float]:
    """A unit quaternion from an orient, normalized as the controller does; ``Mismatch`` when its
    squares sum farther than ``QUAT_SLACK`` from 1."""
    q = _numbers(value.vals, f"the quaternion of {what}", 1e3)
    n2 = sum(c * c for c in q)
    if abs(n2 - 1.0) > QUAT_SLACK:
        raise Mismatch(f"the quaternion of {what} is not normalized: q1²+q2²+q3²+q4² = {n2:.4g} (the controller "
                       f"accepts 1 ± {QUAT_SLACK:g})")
    n = math.sqrt(n2)
    return tuple(c / n for c in q)


def pose(value: Rec, what: str) -> Pose:
    """A pose from a record whose first two components are a pos and an orient."""
    x, y, z = _numbers(value.vals[0].vals, f"the position of {what}", MAX_MM)
    return Pose((x / 1000.0, y / 1000.0, z / 1000.0), quaternion(value.vals[1], what))


def axes(value: Rec, what: str, bound: float) -> tuple[float | None, ...]:
    """Axis values (mm or degrees), None for 9E9."""
    out = []
    for v in value.vals:
        v = float(v)
        if not math.isfinite(v):
            raise Mismatch(f"{what} holds {v}: every number must be finite")
        out.append(None if UNUSED[0] <= abs(v) <= UNUSED[1] else v)
        if out[-1] is not None and abs(v) > bound:
            raise Mismatch(f"{what} holds {v:g}, beyond {bound:g}")
    return tuple(out)


def robtarget(value: Rec, what: str) -> RobTarget:
    conf = []
    for c in _numbers(value.vals[2].vals, f"the confdata of {what}", 1e3):
        if c != round(c):
            raise Mismatch(f"the confdata of {what} holds {c:g}: cf1, cf4, cf6 and cfx are whole numbers")
        conf.append(int(round(c)))
    return RobTarget(pose(value, what), tuple(conf), axes(value.vals[3], f"the extax of {what}", MAX_MM))


def jointtarget(value: Rec, what: str) -> JointTarget:
    return JointTarget(axes(value.vals[0], f"the robax of {what}", MAX_AXIS),
                       axes(value.vals[1], f"the extax of {what}", MAX_MM))


def load(value: Rec, what: str) -> Load:
    mass, ix, iy, iz = _numbers((value.vals[0],) + value.vals[3:], f"the load of {what}", 1e6)
    cog = _numbers(value.vals[1].vals, f"the load's centre of gravity of {what}", MAX_MM)
    if mass < 0 or min(ix, iy, iz) < 0:
        raise Mismatch(f"the load of {what} has a negative mass or inertia")
    aom = quaternion(value.vals[2], f"the load's axes of moment of {what}")
    return Load(mass, tuple(c / 1000.0 for c in cog), (ix, iy, iz), aom)


def tool(value: Rec, what: str) -> Tool:
    return Tool(bool(value.vals[0]), pose(value.vals[1], what), load(value.vals[2], what))


def work_object(value: Rec, what: str) -> WorkObject:
    return WorkObject(bool(value.vals[0]), bool(value.vals[1]), str(value.vals[2]),
                      pose(value.vals[3], f"{what}.uframe"), pose(value.vals[4], f"{what}.oframe"))


def speed(value: Rec, what: str) -> Speed:
    v_tcp, v_ori, v_leax, v_reax = _numbers(value.vals, what, 1e30)  # the controller caps, never refuses, a speed
    if not v_tcp > 0 or not v_ori > 0:
        raise Mismatch(f"{what} has v_tcp {v_tcp:g} mm/s and v_ori {v_ori:g} deg/s: both must be above 0")
    if v_leax < 0 or v_reax < 0:
        raise Mismatch(f"{what} has a negative speed for external axes")
    return Speed(v_tcp / 1000.0, math.radians(v_ori), v_leax / 1000.0 if v_leax > 0 else math.inf,
                 math.radians(v_reax) if v_reax > 0 else math.inf)


def zone(value: Rec, what: str) -> Zone:
    sizes = _numbers(value.vals[1:], what, 1e30)  # the controller cuts a zone to half its move, never refuses it
    if min(sizes) < 0:
        raise Mismatch(f"{what} has a negative zone size")
    return Zone(bool(value.vals[0]), sizes[0] / 1000.0, sizes[1] / 1000.0, math.radians(sizes[3]))


FINE = Zone(True, 0.0)
