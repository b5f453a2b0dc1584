"""A dress-pack verdict an engineer can sign: each cable's results in each environment held to the
hose's ratings (``Ratings``), every breach a finding record (``rswarp.findings``) with where along
the hose, when, the program line and the robot's joints then, by how much, and what to change;
PASS where no finding fails."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..config import MAX_STRAIN, MAX_TORSION_DEG
from ..findings import FAIL, WARN, Finding
from ..sim.cable.results import CableResult
from .cable_contact import rubs

STATIC_DIAMETERS = 5.0  # a hose's static (permanent-damage) bend radius: 5 diameters, as hose makers rate it
MAX_TORSION = math.radians(MAX_TORSION_DEG)  # rad/m: config's deg/m rating (180 deg/m: pi, exactly)
AT_REST = 1e-3  # rad/s (m/s): every joint slower than this is the robot at rest
STILL_FOR = 1.0  # s: the robot at rest this long is a hose at rest; until then its swing goes on
ORDER = ("crush", "pinch", "kink", "taut", "bend", "torsion", "clamp", "rub")  # the verdict's lines, worst kind first


@dataclass(frozen=True)
class Ratings:
    """What the hose is held to, SI: axial strain; static bend radius (None: 5 diameters; the
    dynamic one is the run's allowed bend radius); twist per metre; contact and clamp forces
    (None: reported, never a failure)."""

    max_strain: float = MAX_STRAIN
    static_bend_radius: float | None = None
    max_torsion: float = MAX_TORSION
    max_contact_force: float | None = None
    max_clamp_load: float | None = None

    def static(self, c: CableResult) -> float:
        return self.static_bend_radius if self.static_bend_radius is not None else STATIC_DIAMETERS * 2 * c.radius


@dataclass(frozen=True)
class Moment:
    """Where the robot was at a time of an environment's run: its joints, and the program line."""

    joints: tuple[float, ...] | None = None
    file: str | None = None
    line: int | None = None
    routine: str | None = None
    moving: bool = True


When = Callable[[int, float], Moment]  # (environment, t) -> the moment


def cable_findings(c: CableResult, weight: float, ratings: Ratings = Ratings(),
                   when: When | None = None) -> list[Finding]:
    """Every finding of cable ``c`` in every environment, in environment order."""
    at = when or (lambda e, t: Moment())
    out = []
    for e in range(c.envs):
        if c.status[e] != "ok":
            out.append(_make(c, e, at, "crush", FAIL, f"stopped: {c.status[e]}", c.failed_time[e], np.nan))
            continue
        out += _taut(c, e, at, ratings) + _bends(c, e, at, ratings) + _torsion(c, e, at, ratings)
        out += _pinch(c, e, at, weight) + _rubs(c, e, at, ratings) + _clamps(c, e, at, ratings)
    return out


def _make(c: CableResult, e: int, at: When, kind: str, severity: str, text: str, t: float, arc: float,
          **more) -> Finding:
    m = at(e, float(t)) if np.isfinite(t) else Moment()
    return Finding(kind, text, severity, m.file, m.line, m.routine, float(t) if np.isfinite(t) else None,
                   joints=m.joints, cable=c.name, env=e, at_m=float(arc) if np.isfinite(arc) else None, **more)


def _taut(c: CableResult, e: int, at: When, r: Ratings) -> list[Finding]:
    """Pulled, not hanging: its greatest axial strain past ``max_strain``. A taut hose carries one
    tension end to end, so it needs about strain x length more hose (at least what it stretched)."""
    strain = float(c.peak_tension[e]) / c.axial_stiffness if c.axial_stiffness > 0 else 0.0
    if not strain > r.max_strain:
        return []
    extra_mm = math.ceil(strain * c.length * 1000)
    # when it first went taut (the move that pulls it), where its strain peaked, and by how much
    t = c.taut_time[e] if np.isfinite(c.taut_time[e]) else c.peak_tension_time[e]
    return [_make(c, e, at, "taut", FAIL, f"pulled taut: strain {100 * strain:.2f} % over {100 * r.max_strain:.2f} %",
                  t, c.peak_tension_at[e], value=strain, limit=r.max_strain, unit="1",
                  advice=f"lengthen it by at least {extra_mm} mm (its stretch then), or bring its clamps closer "
                         "over this move")]


def _bends(c: CableResult, e: int, at: When, r: Ratings) -> list[Finding]:
    """Tighter than the static radius (a kink: damage), else than the dynamic one while moving."""
    radius = float(c.min_bend_radius[e])
    if not np.isfinite(radius):
        return []
    static, dynamic = r.static(c), c.allowed_bend_radius
    t, arc = c.min_bend_time[e], c.min_bend_at[e]
    if radius < static:
        return [_make(c, e, at, "kink", FAIL, f"bent to {radius * 1000:.0f} mm, under its static radius "
                      f"{static * 1000:.0f} mm", t, arc, value=radius, limit=static, unit="m",
                      advice=f"give it room to bend no tighter than {dynamic * 1000:.0f} mm there: more length, or "
                             "a clamp turned along its path")]
    if radius >= dynamic:
        return []
    moving = at(e, float(t)).moving if np.isfinite(t) else True
    return [_make(c, e, at, "bend", FAIL if moving else WARN, f"bent to {radius * 1000:.0f} mm, under its "
                  f"dynamic radius {dynamic * 1000:.0f} mm" + ("" if moving else " (at rest)"), t, arc, value=radius,
                  limit=dynamic, unit="m", advice=f"open the bend by {(dynamic - radius) * 1000:.0f} mm: more "
                                                  "length, or a clamp moved or turned along its path")]


def _torsion(c: CableResult, e: int, at: When, r: Ratings) -> list[Finding]:
    rate = float(c.max_twist_rate[e])
    if not rate > r.max_torsion:
        return []
    return [_make(c, e, at, "torsion", FAIL, f"twisted {np.degrees(rate):.0f} deg/m, over "
                  f"{np.degrees(r.max_torsion):.0f} deg/m", c.max_torque_time[e], c.max_torque_at[e], value=rate,
                  limit=r.max_torsion, unit="rad/m",
                  advice="let it turn in a swivel clamp, or lengthen the span that twists")]


def _pinch(c: CableResult, e: int, at: When, weight: float) -> list[Finding]:
    if not c.pinch[e] > weight:
        return []
    a, b = (c.links[k] for k in c.pinch_slots[e])
    return [_make(c, e, at, "pinch", FAIL, f"pinched between {a} and {b}: {c.pinch[e]:.3g} N across it",
                  c.pinch_time[e], c.pinch_at[e], links=tuple(dict.fromkeys((a, b))), value=float(c.pinch[e]),
                  limit=weight, unit="N", advice="route it out of the gap, or shorten the span that sags into it")]


def _rubs(c: CableResult, e: int, at: When, r: Ratings) -> list[Finding]:
    """Per slot it touched (``cable_contact.rubs``): of its segments that slid on it, the one
    pressed hardest (the rub's force, where along, its time in contact), the Archard wear on it
    (normal force x sliding distance); at the time the hose first touched it."""
    out = []
    for rub in rubs(c, e):
        name, force = rub["on"], rub["force_N"]
        slid = rub["segment"] is not None
        over = r.max_contact_force is not None and force > r.max_contact_force
        text = f"rubs on {name}: " + (f"{force:.3g} N, {rub['wear_J']:.3g} J of wear on it, "
                                      f"{rub['contact_time_s']:.2f} s in contact" if slid else
                                      "touches without sliding")
        out.append(_make(c, e, at, "rub", FAIL if over else WARN, text, rub["first_touch_s"],
                         np.nan if rub["at_m"] is None else rub["at_m"], links=(name,), value=force,
                         limit=r.max_contact_force, unit="N",
                         advice=f"keep it off {name}: a clamp or a guide" if slid else None))
    return out


def _clamps(c: CableResult, e: int, at: When, r: Ratings) -> list[Finding]:
    if r.max_clamp_load is None:
        return []
    out = []
    for a, name in enumerate(c.attachments):
        force = float(c.clamp_force[e, a])
        if force > r.max_clamp_load:
            out.append(_make(c, e, at, "clamp", FAIL, f"{name} pulled with {force:.3g} N, over "
                             f"{r.max_clamp_load:.3g} N (and turned by up to {c.clamp_moment[e, a]:.3g} N m)",
                             c.clamp_force_time[e, a], np.nan, value=force,
                             limit=r.max_clamp_load, unit="N", advice="more slack on either side of the clamp"))
    return out


def verdict(findings: list[Finding]) -> str:
    return "FAIL" if any(f.severity == FAIL for f in findings) else "PASS"


def verdict_lines(c: CableResult, findings: list[Finding]) -> list[str]:
    """The cable's verdict and, per kind, its worst finding and in how many environments."""
    mine = [f for f in findings if f.cable == c.name]
    kinds = sorted({f.kind for f in mine}, key=lambda k: ORDER.index(k) if k in ORDER else len(ORDER))
    fails = {f.env for f in mine if f.severity == FAIL}
    head = f"  verdict: {verdict(mine)}" + (f", failing in {len(fails)} of {c.envs} environment(s)" if fails else
                                            f" in {'every one of its' if c.envs > 1 else 'its'} {c.envs} "
                                            f"environment{'s' * (c.envs > 1)}")
    lines = [head]
    for kind in kinds:
        alike = [f for f in mine if f.kind == kind]
        worst = max(alike, key=_badness)
        envs = len({f.env for f in alike})
        where = [f"environment {worst.env}"] + ([f"t = {worst.t_s:.2f} s"] if worst.t_s is not None else []) + \
            ([f"line {worst.line}"] if worst.line else []) + ([f"{worst.at_m:.3f} m along"] if worst.at_m is not None
                                                              else [])
        text = f"  {worst.severity} {kind}: {worst.text} ({', '.join(where)}; in {envs} of {c.envs})"
        lines.append(text + (f"; {worst.advice}" if worst.advice and worst.severity == FAIL else ""))
    return lines


def _badness(f: Finding) -> tuple:
    """How far past its limit a finding goes, for the worst of a kind (fails first)."""
    if f.value is None or f.limit is None or not f.limit:
        return (f.severity == FAIL, f.value or 0.0)
    ratio = f.value / f.limit
    return (f.severity == FAIL, 1.0 / ratio if f.kind in ("kink", "bend") and ratio > 0 else ratio)


def moments(trajectories, assignment, moves=None) -> When:
    """``When`` of a run: each environment's trajectory (``assignment[e]``) interpolated at t, and
    with a program's ``moves`` (``plan.moves``) the move under way then. The hose is moving while
    the robot moves and for STILL_FOR after it stops (it swings on), past the trajectory's end too."""
    starts = np.array([m.start for m in moves]) if moves else None

    def at(e: int, t: float) -> Moment:
        tr = trajectories[assignment[e]]
        k = int(np.clip(np.searchsorted(tr.times, t), 1, len(tr.times) - 1)) if len(tr.times) > 1 else 0
        q = np.array([np.interp(t, tr.times, tr.q[:, j]) for j in range(tr.q.shape[1])])
        moving = True
        if len(tr.times) > 1:
            first = int(np.clip(np.searchsorted(tr.times, t - STILL_FOR), 1, k))
            steps = np.abs(np.diff(tr.q[first - 1:k + 1], axis=0)) / np.maximum(np.diff(tr.times[first - 1:k + 1]),
                                                                                1e-12)[:, None]
            moving = bool(steps.max() > AT_REST) and t - tr.times[-1] < STILL_FOR
        if starts is None:
            return Moment(tuple(float(v) for v in q), moving=moving)
        m = moves[max(int(np.searchsorted(starts, t, side="right")) - 1, 0)].motion
        return Moment(tuple(float(v) for v in q), m.file, m.line, m.routine, moving)

    return at
