"""What ``rswarp info`` shows of a cell file: the robot and where it stands, each external unit
with its frame and the logical axes that drive its joints, the tool and the environment, in the
cell file's own units (mm, degrees) and as SI data for ``--json``."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..rsxml.cell import Cell
from ..transforms import matrix_euler_zyx
from .output import Output, Warn, ignore


def _frame(m: np.ndarray) -> str:
    """A 4x4 (m) as the cell file writes it: x, y, z in mm, then rx, ry, rz in degrees."""
    rx, ry, rz = np.degrees(matrix_euler_zyx(m[:3, :3]))
    return ", ".join(f"{v + 0.0:g}" for v in (*np.round(m[:3, 3] * 1e3, 3), *np.round((rx, ry, rz), 3)))


def cell_dict(cell: Cell) -> dict:
    """The cell as data (SI: frames as 4x4 in metres); a MultiMove cell's robots each with theirs."""
    if cell.team:
        return {"path": cell.path, "kind": "Cell", "robots": [cell_dict(c) | {"name": c.robot.name,
                                                                              "task": c.robot.task}
                                                              for c in cell.team], "warnings": list(cell.warnings)}
    r = cell.robot
    return {"path": cell.path, "kind": "Cell",
            "robot": {"rsxml": r.rsxml, "name": r.mechanism.name, "on": r.on, "frame": r.frame.tolist()},
            "externals": [{"name": e.name, "rsxml": e.rsxml, "model": e.mechanism.model_name,
                           "frame": e.frame.tolist(), "axes": dict(zip(e.axes, e.joints)),
                           "carrier_link": e.carrier_link, "joints": _unit_axes(e)} for e in cell.externals],
            "tool": None if cell.tool is None else {"path": cell.tool.path, "mount": cell.tool.mount.tolist()},
            "environment": [{"mesh": m.path, "pose": m.pose.tolist(), "on": m.on} for m in cell.environment],
            "warnings": list(cell.warnings)}


def _unit_axes(e) -> list[dict]:
    """Each joint of a unit with its logical axis, its travel and its limits (SI: m or rad, m/s or
    rad/s, ...) and where the limits come from (its robot-data file, or rswarp's default)."""
    from ..rsxml.robot_data import axis_limits

    mech = e.mechanism
    lo, hi = mech.bounds()
    limits = axis_limits(mech)
    names = [j.name for j in mech.active_joints]
    by_joint = dict(zip(e.joints, e.axes))
    out = []
    for k, j in enumerate(mech.active_joints):
        jerk = None if limits.jerk is None else float(limits.jerk[k])
        out.append({"name": names[k], "axis": by_joint.get(names[k]), "type": "rotational" if j.revolute else "linear",
                    "travel": [float(lo[k]), float(hi[k])], "velocity": float(limits.velocity[k]),
                    "acceleration": float(limits.acceleration[k]), "jerk": jerk, "source": limits.source})
    return out


def cell_text(cell: Cell) -> str:
    """The cell in the file's units, a line per thing it places (each robot's, MultiMove)."""
    if cell.team:
        head = f"{cell.path}: a MultiMove cell of {len(cell.team)} robots, each running its own task"
        return "\n\n".join([head] + [f"{c.robot.name} (task {c.robot.task}):\n" +
                                       cell_text(c).split("\n", 1)[1] for c in cell.team])
    r = cell.robot
    lines = [f"{cell.path}: a cell of {1 + len(cell.externals)} mechanism{'s' if cell.externals else ''}",
             f"robot {r.mechanism.name} ({Path(r.rsxml).name}) {_riding(cell, r.on)}, frame [{_frame(r.frame)}]"
             + _at_home(cell)]
    for e in cell.externals:
        axes = ", ".join(f"{a} -> {j} ({_range(e.mechanism, j)})" for a, j in zip(e.axes, e.joints))
        lines.append(f"external {e.name}: {e.mechanism.model_name} ({Path(e.rsxml).name}), frame [{_frame(e.frame)}], "
                     f"{axes}, carries on {e.carrier_link}")
    if cell.tool is not None:
        lines.append(f"tool {Path(cell.tool.path).name}, mounted [{_frame(cell.tool.mount)}] on the flange")
    lines += [f"environment {Path(m.path).name} " + (f"{_riding(cell, m.on)}, frame [{_frame(m.pose)}]" if m.on else
                                                     f"at [{_frame(m.pose)}]") for m in cell.environment]
    return "\n".join(lines)


def _riding(cell: Cell, on: str | None) -> str:
    """Where a thing rides: on the floor, or on a unit's mounting flange (its frame is there)."""
    if on is None:
        return "on the floor"
    unit = cell.external(on)
    flange = f"flange '{unit.mount.name}' ({unit.carrier_link})" if unit.mount is not None else unit.carrier_link
    return f"on {on}'s {flange}"


def _at_home(cell: Cell) -> str:
    """Where a carried robot's base sits in the world with every unit at home."""
    if cell.carrier is None:
        return ""
    from ..kinematics.cell import CellKinematics

    ck = CellKinematics(cell)
    return f"; at home its base at [{_frame(ck.robot_base(ck.split(ck.home()[None]))[0])}] in the world"


def _range(mech, joint: str) -> str:
    """A joint's travel as RAPID gives its axis: ``0 .. 4000 mm`` or ``-90 .. 90 deg``."""
    j = mech.joint(joint)
    lo, hi = (float(v[[x.name for x in mech.active_joints].index(joint)]) for v in mech.bounds())
    f, unit = (np.degrees(1.0), "deg") if j.revolute else (1000.0, "mm")
    return f"{lo * f:g} .. {hi * f:g} {unit}"


def cell_output(cell: Cell, warn: Warn = ignore) -> Output:
    """``rswarp info CELL.toml``: its warnings to ``warn``, the cell as text and data."""
    for w in cell.warnings:
        warn(w)
    return Output(cell_dict(cell), cell_text(cell))
