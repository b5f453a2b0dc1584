"""Poses for people: joint values typed in a file's units, each link's and flange's frame shown
as its origin, ZYX Euler angles in those units and a quaternion, and checks of joint values
against limits (``rswarp fk``)."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..kinematics.kinematics import Kinematics
from ..rsxml.documents import load_mechanism
from ..rsxml.model import Mechanism
from ..rsxml.parse import number
from ..rsxml.units import BOUNDS, format_number
from ..transforms import matrix_euler_zyx, matrix_quat
from .output import Output, Warn, ignore, json_safe


def run_fk(path: str, q: str, device: str = "cpu", warn: Warn = ignore) -> Output:
    """``rswarp fk``: every link's and flange's pose for joint values typed in the file's units
    (values outside their limits are a warning, not an error)."""
    mech, _ = load_mechanism(path)
    values = joint_values(mech, q)
    for warning in limit_warnings(mech, values):
        warn(warning)
    return Output(*fk_report(mech, values, device=device))


FRAMES = ("a link's frame has its origin on the axis of the joint that moves it (the base's at the world origin) and "
          "the world's axes at the zero position, as the USD and URDF exports place it; a flange is its own frame")


def link_frames(mech: Mechanism, names, displacements: np.ndarray) -> np.ndarray:
    """(links, 4, 4): each link's frame at the joint values whose displacements ``kin.fk`` gave
    (``displacements[k]`` takes a point of link k at the zero position to where it is now)."""
    from ..geometry.frames import link_origins

    origins = link_origins(mech)
    out = np.array(displacements, np.float64)
    for k, name in enumerate(names):
        out[k, :3, 3] = out[k, :3, :3] @ origins.get(name, np.zeros(3)) + out[k, :3, 3]
    return out


def rotation_of(m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(ZYX Euler angles rx, ry, rz in rad, quaternion w, x, y, z) of a pose's rotation; NaN where
    the pose is (a loop that cannot close)."""
    if not np.isfinite(m).all():
        return np.full(3, np.nan), np.full(4, np.nan)
    r = np.asarray(m[:3, :3], np.float64)
    return np.array(matrix_euler_zyx(r)), np.array(matrix_quat(r))


def pose_dict(m: np.ndarray) -> dict:
    """A frame in JSON: its origin (m), rotation as a quaternion (w, x, y, z) and as ZYX Euler angles
    (rx, ry, rz; rad), and the 4x4 matrix (world from frame)."""
    euler, quat = rotation_of(m)
    return {"position": _json(m[:3, 3]), "quaternion": _json(quat), "euler_zyx": _json(euler),
            "matrix": [_json(row) for row in m]}


def _json(values) -> list[float]:
    return [round(float(v), 7) + 0.0 for v in values]  # + 0.0: never -0.0


def rounded(v: float, factor: float, resolution: float) -> str:
    """``v`` (SI) in file units, to the decimals that ``resolution`` (SI) needs: float32 noise off."""
    digits = max(0, math.ceil(-math.log10(resolution / factor)))
    text = f"{v / factor:.{digits}f}"
    text = text.rstrip("0").rstrip(".") if "." in text else text
    return "0" if text in ("-0", "") else text


def pose_text(mech: Mechanism, links: list[tuple[str, np.ndarray]], flanges: list[tuple[str, np.ndarray]]) -> str:
    """The frames as a table under two lines that say what it holds: a header naming each column
    and its unit (the file's), and what a link's frame is."""
    lf, af = mech.length_factor, mech.angle_factor
    lu, au = mech.length_unit or "m", mech.angle_unit or "rad"
    lines = [f"each link's and flange's frame in the world: origin x, y, z in {lu}; rotation as ZYX Euler angles "
             f"rx, ry, rz in {au} (R = Rz Ry Rx) and as the quaternion q1..q4 (w, x, y, z, as RAPID's orient)", FRAMES]
    rows = [["frame", f"x [{lu}]", f"y [{lu}]", f"z [{lu}]", f"rx [{au}]", f"ry [{au}]", f"rz [{au}]",
             "q1", "q2", "q3", "q4"]]
    for kind, items in (("link", links), ("flange", flanges)):
        for name, m in items:
            euler, quat = rotation_of(m)
            rows.append([f"{kind} {name}", *(rounded(float(v), lf, 1e-6) for v in m[:3, 3]),
                         *(rounded(float(a), af, 1e-5) for a in euler), *(rounded(float(v), 1.0, 1e-6) for v in quat)])
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join(lines + ["  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in enumerate(zip(r, widths)))
                              for r in rows])


def limit_warnings(mech: Mechanism, q: np.ndarray) -> list[str]:
    """One line per joint value outside its limits, in the file's units."""
    out = []
    for j, v in zip(mech.active_joints, q):
        lim = mech.limit(j.name)
        if lim is not None and not lim.min - 1e-12 <= v <= lim.max + 1e-12:
            f = mech.joint_factor(j)
            out.append(f"rswarp: warning: {j.name} = {format_number(v, f)} is outside its limits "
                       f"[{format_number(lim.min, f)}, {format_number(lim.max, f)}]")
    return out


def joint_values(mech: Mechanism, text: str) -> np.ndarray:
    """Active-joint values typed in the file's units (``"0, 0, 0, 0, 30, 0"``) as SI: plain ASCII
    decimals, each within what a joint can do (``BOUNDS``)."""
    names = [j.name for j in mech.active_joints]
    try:
        values = [number(v) for v in text.replace(",", " ").split()]
    except ValueError as exc:
        raise InputError(f"--q: '{text}' has {exc}") from None
    if len(values) != len(names):
        raise InputError(f"--q needs {len(names)} values ({', '.join(names)}), got '{text}'")
    si = [v * mech.joint_factor(j) for v, j in zip(values, mech.active_joints)]
    for v, s, j in zip(values, si, mech.active_joints):
        bound, what = BOUNDS["angle" if j.revolute else "length"][0], "rad" if j.revolute else "m"
        if abs(s) > bound:
            raise InputError(f"--q: {j.name} = {v:g} is beyond what a joint can do ({bound:g} {what})")
    return np.array(si)


def fk_report(mech: Mechanism, q: np.ndarray, device: str = "cpu") -> tuple[dict, str]:
    """Every link's and flange's frame for one set of joint values (SI): a JSON-ready dict and text.
    A link's JSON keeps ``displacement`` too: what ``kin.fk`` gives, the motion of the link from
    the zero position (its points' world coordinates there to here). Where a loop cannot close
    (past a dead point) the links it moves are NaN, ``closes`` is False and the text says so on
    its last line."""
    kin = Kinematics(mech, device=device)
    moved = kin.fk(q[None])[0]
    links = link_frames(mech, kin.links, moved)
    flanges = {f.name: kin.flange(q[None], f.name)[0] for f in mech.flanges}
    # poses past a dead point are NaN whole, and only there: the flag without a second solve
    closes = bool(np.isfinite(links).all() and all(np.isfinite(m).all() for m in flanges.values()))
    doc = {"q": q.tolist(), "closes": closes, "frames": FRAMES,
           "links": {n: pose_dict(m) | {"displacement": [_json(row) for row in d]}
                     for n, m, d in zip(kin.links, links, moved)},
           "flanges": {n: pose_dict(m) for n, m in flanges.items()}}
    text = pose_text(mech, list(zip(kin.links, links)), list(flanges.items()))
    if not closes:
        doc = json_safe(doc)  # JSON has no NaN: the poses a loop cannot give are null
        text += ("\nunreachable: a loop cannot close at these joint values (past a dead point); the links it "
                 "moves have no pose (nan)")
    return doc, text
