"""RAPID's motion data as rswarp uses it, in SI: poses (RAPID: mm, quaternion [q1, q2, q3, q4] =
[w, x, y, z]), tools, work objects, robtargets, jointtargets, speeds and zones; the predefined
data every controller has (v5 ... v7000, vmax, z0 ... z200, fine, tool0, wobj0, load0); and the
check that a record has the shape of its type."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

NO_VALUE = 9e9  # RAPID's "not used" (extax, a jointtarget's unused axes)


@dataclass(frozen=True)
class Pose:
    """A RAPID pose in SI: translation (m) and unit quaternion (w, x, y, z)."""

    trans: tuple[float, float, float]
    quat: tuple[float, float, float, float]

    def matrix(self) -> np.ndarray:
        w, x, y, z = self.quat
        m = np.eye(4)
        m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
        m[:3, 3] = self.trans
        return m


IDENTITY = Pose((0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0))


@dataclass(frozen=True)
class Tool:
    robhold: bool
    tframe: Pose


@dataclass(frozen=True)
class WorkObject:
    robhold: bool
    ufprog: bool
    ufmec: str
    uframe: Pose
    oframe: Pose

    def matrix(self) -> np.ndarray:
        return self.uframe.matrix() @ self.oframe.matrix()


@dataclass(frozen=True)
class RobTarget:
    pose: Pose  # the TCP in the work object
    conf: tuple[int, int, int, int]  # cf1, cf4, cf6, cfx


@dataclass(frozen=True)
class JointTarget:
    robax: tuple[float, ...]  # degrees (rotational) or mm (linear), as RAPID writes them


@dataclass(frozen=True)
class Speed:
    v_tcp: float  # m/s
    v_ori: float  # rad/s


@dataclass(frozen=True)
class Zone:
    fine: bool
    pzone_tcp: float  # m


# -- shapes --------------------------------------------------------------------------------------

# Each record type: the shape of its aggregate. "n" a number, "b" a bool, "s" a string, an int k a
# list of k numbers, a tuple a nested record.
_POSE = (3, 4)
SHAPES = {
    "pose": _POSE,
    "tooldata": ("b", _POSE, ("n", 3, 4, "n", "n", "n")),
    "wobjdata": ("b", "b", "s", _POSE, _POSE),
    "robtarget": (3, 4, 4, 6),
    "jointtarget": (6, 6),
    "speeddata": 4,
    "zonedata": ("b", "n", "n", "n", "n", "n", "n"),
    "loaddata": ("n", 3, 4, "n", "n", "n"),
    "confdata": 4,
    "pos": 3,
    "orient": 4,
}
FIELDS = {
    "tooldata": "[robhold, tframe, tload]",
    "wobjdata": "[robhold, ufprog, ufmec, uframe, oframe]",
    "robtarget": "[trans, rot, robconf, extax]",
    "jointtarget": "[robax, extax]",
    "speeddata": "[v_tcp, v_ori, v_leax, v_reax]",
    "zonedata": "[finep, pzone_tcp, pzone_ori, pzone_eax, zone_ori, zone_leax, zone_reax]",
}


def mismatch(value, shape, where: str = "") -> str | None:
    """Why ``value`` does not have ``shape``, or None."""
    if shape == "n":
        return None if isinstance(value, float) else f"{where or 'the value'} must be a number"
    if shape == "b":
        return None if isinstance(value, bool) else f"{where or 'the value'} must be TRUE or FALSE"
    if shape == "s":
        return None if isinstance(value, str) else f"{where or 'the value'} must be a string"
    parts = ("n",) * shape if isinstance(shape, int) else shape
    if not isinstance(value, list) or len(value) != len(parts):
        return f"{where or 'the record'} must have {len(parts)} parts"
    for k, (v, s) in enumerate(zip(value, parts)):
        why = mismatch(v, s, f"{where or 'part'}[{k + 1}]" if where else f"part {k + 1}")
        if why:
            return why
    return None


# -- records from checked aggregates ----------------------------------------------------------------

def pose(value) -> Pose:
    (x, y, z), q = value
    q = np.asarray(q, float)
    norm = float(np.linalg.norm(q))
    unit = tuple(float(v) for v in q / norm) if norm > 0 else (1.0, 0.0, 0.0, 0.0)
    return Pose((float(x) / 1000.0, float(y) / 1000.0, float(z) / 1000.0), unit)


def quaternion_norm(value) -> float:
    """The norm of a record's quaternion (pose [trans, rot] or robtarget [trans, rot, ...])."""
    return float(np.linalg.norm(value[1]))


def tool(value) -> Tool:
    return Tool(value[0], pose(value[1]))


def work_object(value) -> WorkObject:
    return WorkObject(value[0], value[1], value[2], pose(value[3]), pose(value[4]))


def robtarget(value) -> RobTarget:
    return RobTarget(pose(value[:2]), tuple(int(round(c)) for c in value[2]))


def jointtarget(value) -> JointTarget:
    return JointTarget(tuple(value[0]))


def speed(value) -> Speed:
    return Speed(value[0] / 1000.0, float(np.radians(value[1])))


def zone(value) -> Zone:
    return Zone(value[0], value[1] / 1000.0)


# -- predefined data -----------------------------------------------------------------------------------

def predefined() -> dict[str, tuple[str, object]]:
    """Name -> (type, aggregate) of the data every controller predefines (RAPID reference:
    speeddata and zonedata tables; tool0, wobj0 and load0 are the flange, the world and no load)."""
    out: dict[str, tuple[str, object]] = {}
    for v in (5, 10, 20, 30, 40, 50, 60, 80, 100, 150, 200, 300, 400, 500, 600, 800, 1000, 1500, 2000, 2500, 3000,
              4000, 5000, 6000, 7000):
        out[f"v{v}"] = ("speeddata", [float(v), 500.0, 5000.0, 1000.0])
    out["vmax"] = ("speeddata", [5000.0, 500.0, 5000.0, 1000.0])
    out["fine"] = ("zonedata", [True, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    for z, (tcp, ori, eax, zori) in {0: (0.3, 0.3, 0.3, 0.03), 1: (1, 1, 1, 0.1), 5: (5, 8, 8, 0.8),
                                     10: (10, 15, 15, 1.5), 15: (15, 23, 23, 2.3), 20: (20, 30, 30, 3.0),
                                     30: (30, 45, 45, 4.5), 40: (40, 60, 60, 6.0), 50: (50, 75, 75, 7.5),
                                     60: (60, 90, 90, 9.0), 80: (80, 120, 120, 12.0), 100: (100, 150, 150, 15.0),
                                     150: (150, 225, 225, 23.0), 200: (200, 300, 300, 30.0)}.items():
        out[f"z{z}"] = ("zonedata", [False, float(tcp), float(ori), float(eax), float(zori), float(eax), float(zori)])
    origin = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]]
    load0 = [0.001, [0.0, 0.0, 0.001], [1.0, 0.0, 0.0, 0.0], 0.0, 0.0, 0.0]
    out["load0"] = ("loaddata", load0)
    out["tool0"] = ("tooldata", [True, origin, load0])
    out["wobj0"] = ("wobjdata", [False, True, "", origin, origin])
    return out
