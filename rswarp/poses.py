"""Poses for people: 4x4 matrices as position + ZYX Euler angles in a file's units, and checks of
joint values against limits (used by ``rswarp fk``)."""

from __future__ import annotations

import math

import numpy as np

from .model import Mechanism
from .units import format_number


def euler_zyx(r: np.ndarray) -> tuple[float, float, float]:
    """(rx, ry, rz) with R = Rz(rz) Ry(ry) Rx(rx), the RSXML ``euler`` convention."""
    cy = math.hypot(r[0, 0], r[1, 0])
    ry = math.atan2(-r[2, 0], cy)  # atan2, not asin: well conditioned near +-90 degrees
    if cy > 1e-6:
        return math.atan2(r[2, 1], r[2, 2]), ry, math.atan2(r[1, 0], r[0, 0])
    return 0.0, ry, math.atan2(-r[0, 1], r[1, 1])  # gimbal lock: put it all in rz


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
            e = euler_zyx(m[:3, :3].astype(np.float64))
            rows.append([f"{kind} {name}", *(rounded(float(v), lf, 1e-6) for v in m[:3, 3]),
                         *(rounded(a, af, 1e-5) for a in e)])
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in enumerate(zip(r, widths))) for r in rows)


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
