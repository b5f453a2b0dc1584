"""Findings (``rswarp.findings``) of a program's trajectory as records: what the batch check
(``sim.program_check``) tallied per sample made into one record per move and kind, with the
links, the joint values, the time and the figures; the targets the robot could not take as
records too."""

from __future__ import annotations

import numpy as np

from ..findings import FAIL, Finding, at_time
from ..motion.misses import declared_words
from ..sim.program_check import SINGULAR, lowest_body
from ..sim.tool import TCP_GAP, tcp_gap

FLOOR_TOLERANCE = 1e-4  # m: a link this far below the floor counts as touching it


def move_findings(mech, p, move, tally, names, floor: float, tools=None) -> list[Finding]:
    """The planner's findings of ``move`` and those of the batch check over its samples."""
    a, b = move.rows
    out = list(move.findings)
    if tally is None or b <= a:
        return out
    rows = slice(a, b)
    m = move.motion
    if tally.outside[rows].any():
        out.append(_outside(mech, p, m, a + int(np.argmax(tally.outside[rows]))))
    hits = tally.hit[rows]
    step = _step(p.times[max(a - 1, 0):b])
    for k in np.nonzero(hits.any(axis=0))[0]:
        first = a + int(np.argmax(hits[:, k]))
        span = float(np.count_nonzero(hits[:, k])) * step
        out.append(at_time("collision", f"{names[k][0]} hits {names[k][1]} at t = {p.times[first]:.2f} s for "
                           f"{span:.2f} s", m, p.times[first], p.q[first], severity=FAIL, links=tuple(names[k]),
                           value=span, limit=0.0, unit="s",
                           advice="move the target or the path away, or check the collision matrix"))
    low = tally.low[rows]
    if np.nanmin(low) < floor - FLOOR_TOLERANCE:
        out.append(_below(mech, p, m, a + int(np.nanargmin(low)), float(np.nanmin(low)), floor, tools))
    linear = m.kind in ("linear", "circular")
    if p.q.shape[1] >= 6 and linear and not any(f.kind == "singularity" for f in out):
        q5 = np.abs(p.q[rows, 4])
        if q5.min() < SINGULAR:
            at = a + int(np.argmin(q5))
            out.append(at_time("singularity", f"passes {np.degrees(q5.min()):.2f} deg from the wrist singularity "
                               "(q5 = 0)", m, p.times[at], p.q[at], joint=mech.active_joints[4].name,
                               value=float(q5.min()), limit=float(SINGULAR), unit="rad"))
    return out


def _step(times: np.ndarray) -> float:
    """The time between samples (s), from a move's own (not the whole trajectory's)."""
    return float(np.median(np.diff(times))) if len(times) > 1 else 0.0


def _outside(mech, p, m, row: int) -> Finding:
    """The first sample of a move outside the joint limits: which joint, its value, the bound."""
    lower, upper = mech.bounds()
    q = p.q[row]
    over = np.maximum(lower - q, q - upper)
    j = int(np.argmax(over))
    joint = mech.active_joints[j]
    bound = float(lower[j] if q[j] < lower[j] else upper[j])
    f = mech.joint_factor(joint)
    unit = "rad" if joint.revolute else "m"
    shown = "mm" if unit == "m" else "deg"
    scale = 1000.0 if unit == "m" else np.degrees(1.0)
    return at_time("joint_limit", f"{joint.name} at {q[j] * scale:.2f} {shown}, outside its limit "
                   f"{bound * scale:.2f} {shown}, from t = {p.times[row]:.2f} s", m, p.times[row], q, severity=FAIL,
                   joint=joint.name, value=float(q[j]), limit=bound, unit=unit,
                   advice=f"keep {joint.name} within [{lower[j] / f:g}, {upper[j] / f:g}] (the file's unit)")


def _below(mech, p, m, row: int, low: float, floor: float, tools) -> Finding:
    """The lowest moment of a move that goes below the floor, and the link that does."""
    links = (lowest_body(tools, p.q[row]),) if tools is not None else ()
    who = f"{links[0]} " if links else ""
    return at_time("floor", f"{who}{1000 * (floor - low):.0f} mm below the floor at t = {p.times[row]:.2f} s", m,
                   p.times[row], p.q[row], severity=FAIL, links=links, value=low, limit=floor, unit="m",
                   advice=f"raise the target or the path by {1000 * (floor - low):.0f} mm")


ERROR_KINDS = (("out of reach", "unreachable"), ("reachable only outside", "joint_limit"),
               ("outside its limits", "joint_limit"), ("singularity", "singularity"))


def skipped_finding(move) -> Finding:
    """A move the robot could not make, as a ``fail`` record: how far beyond the reach or past
    which limit its target is, where it has a figure."""
    kind = next((k for words, k in ERROR_KINDS if words in move.error), "target")
    s = getattr(move, "shortfall", None)
    figures = {} if s is None else {"value": s.value, "limit": s.limit, "unit": s.unit, "joint": s.joint,
                                    "advice": s.advice()}
    return at_time(kind, f"{move.motion.instruction}: {move.error}; the move is skipped", move.motion, move.start,
                   severity=FAIL, **figures)


def grouped(found: list[tuple[dict, dict]]) -> list[dict]:
    """Records (each with its move's record) of one kind at one move line and its links or joint
    made one, in time order: the worst with ``count`` and ``times_s``, its text saying where the
    move's target is declared, how many times, in which passes of the main loop and, where the
    figures differ, from what to what."""
    groups: dict = {}
    for f, move in found:
        key = (f["file"], f["line"], f["kind"], f["severity"], tuple(f["links"]), f["joint"])
        groups.setdefault(key, []).append((f, move))
    out = []
    for members in groups.values():
        records = [f for f, _ in members]
        worst = max(records, key=_past)
        times = [f["t_s"] for f in records]
        where = worst.get("declared")
        where = f"set {where}" if where and worst.get("declared_by") == "assignment" else where
        text = worst["text"] + declared_words(members[0][1]["target"].split(", ")[-1], where)
        if len(records) > 1:
            text += f" ({_times(records, [m['cycle'] for _, m in members])})"
        out.append(dict(worst, text=text, count=len(records), times_s=times))
    return sorted(out, key=lambda f: min((t for t in f["times_s"] if t is not None), default=np.inf))


def _past(f: dict) -> float:
    """How far a record's figure is past its bound (0 where it has none)."""
    return abs(f["value"] - f["limit"]) if f["value"] is not None and f["limit"] is not None else 0.0


def _times(records: list[dict], cycles: list[int]) -> str:
    """``12 times, passes 1-3; 7 to 80 mm, the worst shown``: the count, the main loop's passes where there are
    several, and the spread of the figures where they differ (the worst is the one shown)."""
    text = f"{len(records)} times"
    passes = sorted({c + 1 for c in cycles})
    if len(passes) > 1:
        runs = passes[-1] - passes[0] + 1 == len(passes)
        text += f", passes {passes[0]}-{passes[-1]}" if runs else f", passes {', '.join(map(str, passes))}"
    figured = [_past(f) for f in records if f["value"] is not None and f["limit"] is not None]
    if figured:
        low, high = (_figure(v, records[0]["unit"]) for v in (min(figured), max(figured)))
        if low != high:
            text += f"; {low.split()[0] if low.split()[-1] == high.split()[-1] else low} to {high}, the worst shown"
    return text


def _figure(v: float, unit: str | None) -> str:
    """A figure in the words a programmer reads: mm, degrees, seconds."""
    if unit == "m":
        return f"{1000 * v:.0f} mm" if 1000 * v >= 9.95 else f"{1000 * v:.1f} mm"
    if unit == "rad":
        return f"{np.degrees(v):.1f}°"
    return f"{v:.2f} s" if unit == "s" else f"{v:.3g}"


TCP_MATCH = (1e-3, np.radians(1.0))  # m, rad: a tooldata this near a Tool mechanism's own TCP matches it


def tool_findings(p, tool) -> list[Finding]:
    """Each tooldata the task moved with (held by the robot, not tool0) checked against the tool
    on the flange: against a Tool mechanism's own TCP where it has one, else whether its TCP lies
    on or near the tool's body (within TCP_GAP)."""
    out, seen = [], set()
    for move in p.moves:
        data = move.motion.tool
        if tool is None or data is None or not data.robhold or data in seen:
            continue
        seen.add(data)
        tframe = data.tframe.matrix()
        if np.allclose(tframe, np.eye(4)):
            continue
        if tool.tcp is not None:
            off = float(np.linalg.norm(tframe[:3, 3] - tool.tcp[:3, 3]))
            turn = float(np.arccos(np.clip((np.trace(tool.tcp[:3, :3].T @ tframe[:3, :3]) - 1) / 2, -1, 1)))
            if off > TCP_MATCH[0] or turn > TCP_MATCH[1]:
                out.append(at_time("tool", f"its tooldata's TCP is {1000 * off:.1f} mm and {np.degrees(turn):.1f} deg "
                                   f"from {tool.name}'s own TCP", move.motion, move.start, value=off,
                                   limit=TCP_MATCH[0], unit="m", links=(f"tool {tool.name}",),
                                   advice="measure the TCP again, or correct the tooldata or the tool's file"))
            continue
        gap = tcp_gap(tool, tframe)
        if gap > TCP_GAP:
            out.append(at_time("tool", f"its tooldata's TCP is {1000 * gap:.0f} mm from {tool.name}'s body: the "
                               "tooldata or the --tool mesh and its mount is off", move.motion, move.start, value=gap,
                               limit=TCP_GAP, unit="m", links=(f"tool {tool.name}",),
                               advice="check the tooldata's tframe against the tool's drawing, and --tool's offset"))
    return out
