"""Poses for people: joint values typed in a file's units, 4x4 matrices shown as position + ZYX
Euler angles in those units, and checks of joint values against limits (``rswarp fk``)."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..kinematics.kinematics import Kinematics
from ..rsxml.documents import load_mechanism
from ..rsxml.model import Mechanism
from ..rsxml.parse import number
from ..rsxml.units import BOUNDS, format_number
from ..transforms import matrix_euler_zyx
from .output import Output, Warn, ignore, json_safe


def run_fk(path: str, q: str, device: str = "cpu", warn: Warn = ignore) -> Output:
    """``rswarp fk``: every link's and flange's pose for joint values typed in the file's units
    (values outside their limits are a warning, not an error)."""
    mech, _ = load_mechanism(path)
    values = joint_values(mech, q)
    for warning in limit_warnings(mech, values):
        warn(warning)
    return Output(*fk_report(mech, values, device=device))


def pose_dict(m: np.ndarray) -> dict:
    return {"matrix": [[round(float(v), 7) for v in row] for row in m],
            "position": [round(float(v), 7) for v in m[:3, 3]]}


def rounded(v: float, factor: float, resolution: float) -> str:
    """``v`` (SI) in file units, to the decimals that ``resolution`` (SI) needs: float32 noise off."""
    digits = max(0, math.ceil(-math.log10(resolution / factor)))
    text = f"{v / factor:.{digits}f}"
    text = text.rstrip("0").rstrip(".") if "." in text else text
    return "0" if text in ("-0", "") else text


def pose_text(mech: Mechanism, links: list[tuple[str, np.ndarray]], flanges: list[tuple[str, np.ndarray]]) -> str:
    lf, af = mech.length_factor, mech.angle_factor
    lu, au = mech.length_unit or "m", mech.angle_unit or "rad"
    rows = [["frame", f"x [{lu}]", f"y [{lu}]", f"z [{lu}]", f"rx [{au}]", f"ry [{au}]", f"rz [{au}]"]]
    for kind, items in (("link", links), ("flange", flanges)):
        for name, m in items:
            e = matrix_euler_zyx(m[:3, :3].astype(np.float64)) if np.isfinite(m).all() else np.full(3, np.nan)
            rows.append([f"{kind} {name}", *(rounded(float(v), lf, 1e-6) for v in m[:3, 3]),
                         *(rounded(a, af, 1e-5) for a in e)])
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in enumerate(zip(r, widths)))
                     for r in rows)


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
    """Every link's and flange's pose for one set of joint values (SI): a JSON-ready dict and text.
    Where a loop cannot close (past a dead point) the links it moves are NaN, ``closes`` is False
    and the text says so on its last line."""
    kin = Kinematics(mech, device=device)
    links = kin.fk(q[None])[0]
    flanges = {f.name: kin.flange(q[None], f.name)[0] for f in mech.flanges}
    # poses past a dead point are NaN whole, and only there: the flag without a second solve
    closes = bool(np.isfinite(links).all() and all(np.isfinite(m).all() for m in flanges.values()))
    doc = {"q": q.tolist(), "closes": closes, "links": {n: pose_dict(m) for n, m in zip(kin.links, links)},
           "flanges": {n: pose_dict(m) for n, m in flanges.items()}}
    text = pose_text(mech, list(zip(kin.links, links)), list(flanges.items()))
    if not closes:
        doc = json_safe(doc)  # JSON has no NaN: the poses a loop cannot give are null
        text += ("\nunreachable: a loop cannot close at these joint values (past a dead point); the links it "
                 "moves have no pose (nan)")
    return doc, text
