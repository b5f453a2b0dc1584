"""The lines ``rswarp cable`` prints per cable: over the environments that ran to the end, the worst
of each answer a dress-pack designer asks (long enough? bent too tight? pulled how hard, and where?
what must each clamp hold? twisted? touching what, how hard, and where does it wear?), and which
environments stopped and why."""

from __future__ import annotations

import numpy as np

from ..sim.cable.rainflow import miner_passes
from ..sim.cable.results import CableResult
from ..sim.cable.solver import FATIGUE_EXPONENT
from .cable_contact import run_worst


def cable_lines(c: CableResult, weight: float, joints: tuple[tuple[str, bool], ...] = (), verdict: list[str] = (),
                passes: int = 1, rated: tuple[float, float] | None = None) -> list[str]:
    """The cable's ``verdict`` lines, then its answers; environments that stopped are reported as
    stopped, never as answers. A pinch harder than the cable's whole ``weight`` (N) is the robot's
    doing, and named with the ``joints`` (name, rotational) the robot was at. Fatigue is counted
    a pass of ``passes`` (with ``rated``: N cycles at bend radius R, the passes it lasts)."""
    lines = [f"{c.name}: {c.length:.3f} m, radius {c.radius * 1000:g} mm (E A {c.axial_stiffness:.3g} N, "
             f"E I {c.bending_stiffness:.3g} N m^2, G J {c.torsion_stiffness:.3g} N m^2)", *verdict]
    done = np.nonzero(c.status == "ok")[0]
    stopped = np.nonzero(c.status != "ok")[0]
    if len(done):
        lines += _answers(c, done)
        lines.append(fatigue_line(c, done, passes, rated))
        lines += _pinch_lines(c, done, weight, joints)
    else:
        lines.append(f"  no answers: every environment stopped before the end ({c.envs} of {c.envs})")
    for e in stopped[:5]:
        lines.append(f"  environment {e} {c.status[e]}")
    if len(stopped) > 5:
        lines.append(f"  ... and {len(stopped) - 5} more stopped")
    return lines


def _answers(c: CableResult, done: np.ndarray) -> list[str]:
    n = f"{len(done)}" + (f" (of {c.envs}; the others stopped)" if len(done) < c.envs else "")
    return [_bend_line(c, done, n), _tension_line(c, done), *_clamp_lines(c, done),
            _twist_line(c, done), *_contact_lines(c, done), *contact_lines(c, done)]


def _bend_line(c: CableResult, done: np.ndarray, n: str) -> str:
    bend = np.where(np.isfinite(c.min_bend_radius[done]), c.min_bend_radius[done], np.inf)
    e = int(done[np.argmin(bend)])
    tight = done[c.too_tight[done]]
    where = f" (environment {e}, t = {c.min_bend_time[e]:.2f} s, {c.min_bend_at[e]:.3f} m along)" \
        if np.isfinite(c.min_bend_radius[e]) else " (straight throughout)"
    return (f"  bend radius: least {c.min_bend_radius[e]:.3f} m{where}; allowed {c.allowed_bend_radius:.3f} m: "
            f"too tight in {len(tight)} of {n}")


def fatigue_line(c: CableResult, done: np.ndarray, passes: int, rated: tuple[float, float] | None) -> str:
    """The location that bends most often: its rainflow cycles a pass and, with ``rated`` (N
    cycles to failure at bend radius R, m), the passes it lasts by Miner's rule. Never summed over
    locations: each segment's count is its own."""
    if not len(done) or not c.fatigue_cycles[done].any():
        return "  fatigue: no bending cycle past a tenth of the allowed curvature"
    e, s = np.unravel_index(int(np.argmax(c.fatigue_cycles[done])), c.fatigue_cycles[done].shape)
    e = int(done[e])
    text = (f"  fatigue: {c.fatigue_cycles[e, s] / passes:.1f} bending cycles a pass at {c.segments[s]:.3f} m along "
            f"(environment {e}; rainflow, ASTM E1049)")
    if rated is not None:
        n, r = rated
        lasts = miner_passes(c.fatigue_sum[done], passes, n, 1.0 / r, FATIGUE_EXPONENT)
        k, j = np.unravel_index(int(np.argmin(lasts)), lasts.shape)
        text += (f"; lasts {lasts[k, j]:.3g} passes at {c.segments[j]:.3f} m along (environment {int(done[k])}; "
                 f"Miner, {n:g} cycles at {r:g} m, exponent {FATIGUE_EXPONENT:g})")
    return text


def _tension_line(c: CableResult, done: np.ndarray) -> str:
    e = int(done[np.argmax(c.peak_tension[done])])
    if not c.peak_tension[e] > 0:
        return "  tension: none (the cable is slack or pushed along its length throughout)"
    strain = c.peak_tension[e] / c.axial_stiffness
    return (f"  peak tension: {c.peak_tension[e]:.3g} N, the axial force (strain {strain:.2%}; environment {e}, t = "
            f"{c.peak_tension_time[e]:.2f} s, {c.peak_tension_at[e]:.3f} m along)")


def _clamp_lines(c: CableResult, done: np.ndarray) -> list[str]:
    out = []
    for a, name in enumerate(c.attachments):
        e = int(done[np.argmax(c.clamp_force[done, a])])
        m = int(done[np.argmax(c.clamp_moment[done, a])])
        out.append(f"  {name} holds up to {c.clamp_force[e, a]:.3g} N (environment {e}, t = "
                   f"{c.clamp_force_time[e, a]:.2f} s) and {c.clamp_moment[m, a]:.3g} N m (environment {m})")
    return out


def _twist_line(c: CableResult, done: np.ndarray) -> str:
    e = int(done[np.argmax(c.max_torque[done])])
    t = int(done[np.argmax(c.max_twist[done])])
    clamps = f"greatest {np.degrees(c.max_twist[t]):.1f} deg between the end clamps (environment {t}); " \
        if c.max_twist[t] > 0 else ""
    at = f", {c.max_torque_at[e]:.3f} m along" if np.isfinite(c.max_torque_at[e]) else ""
    return (f"  twist: {clamps}up to {np.degrees(c.max_twist_rate[done].max()):.1f} deg/m; torque up to "
            f"{c.max_torque[e]:.3g} N m (environment {e}{at})")


def _contact_lines(c: CableResult, done: np.ndarray) -> list[str]:
    out = []
    for j, name in enumerate(c.links):
        col = c.clearance[done, j]
        reached = col < np.inf  # -inf too: a link or floor the cable is wholly inside of
        if not reached.any():
            continue
        e = int(done[np.argmin(np.where(reached, col, np.inf))])
        touching = done[np.isfinite(c.contact_time[done, j])]
        label = "cables (itself, pi bend radii along it or more, and the others)" if name == "cables" else name
        text = f"  {label}: least clearance {c.clearance[e, j] * 1000:.1f} mm (environment {e}, " \
               f"t = {c.clearance_time[e, j]:.2f} s, {c.clearance_at[e, j]:.3f} m along)"
        if len(touching):
            first = touching[np.argmin(c.contact_time[touching, j])]
            text += f"; touches in {len(touching)} of {len(done)}, first environment {first} at t = " \
                    f"{c.contact_time[first, j]:.2f} s"
        if c.clearance[e, j] < -2 * c.radius - c.length / 4:  # deeper than any contact push leaves it
            text += " (carried inside by the robot: the trajectory goes through it)"
        out.append(text)
    return out or ["  clearance: nothing within reach of the cable"]


def contact_lines(c: CableResult, done: np.ndarray) -> list[str]:
    """The three contact figures (``cable_contact``), each the run's worst, its environment and time."""
    worst = run_worst(c, done)
    peak, rub, wear = worst["peak_force"], worst["worst_rub"], worst["worst_wear"]
    if peak is None and rub is None:
        return ["  contact: none"]
    out = []
    if peak is not None:
        out.append(f"  peak contact force: {peak['force_N']:.3g} N, the run's worst (environment "
                   f"{peak['environment']}, t = {peak['time_s']:.2f} s, {peak['at_m']:.3f} m along); sliding up to "
                   f"{c.max_sliding_speed[done].max():.3g} m/s")
    if rub is not None:
        slid = rub["segment"] is not None
        what = (f"{rub['force_N']:.3g} N on {rub['on']}, the run's worst (environment {rub['environment']}, first "
                f"touch t = {rub['first_touch_s']:.2f} s, {rub['at_m']:.3f} m along): {rub['wear_J']:.3g} J of wear "
                f"on it along the whole hose, {rub['contact_time_s']:.2f} s in contact there") if slid else \
            f"touches {rub['on']} without sliding (environment {rub['environment']}, t = {rub['first_touch_s']:.2f} s)"
        out.append(f"  worst rub: {what}")
    out.append("  worst wear: nothing slid while pressed" if wear is None else
               f"  worst wear: {wear['wear_J']:.3g} J (normal force x sliding) at one place, {wear['at_m']:.3f} m "
               f"along, mostly on {wear['on']}, the run's worst (environment {wear['environment']}"
               + (f", first touch t = {wear['first_touch_s']:.2f} s" if wear["first_touch_s"] is not None else "")
               + f"): {wear['contact_time_s']:.2f} s in contact")
    return out


def pinched(c: CableResult, weight: float) -> np.ndarray:
    """(envs,) whether something pressed the cable from opposite sides harder than its whole weight
    could: the robot pinching it against itself, the floor, a cable or the cell."""
    return c.pinch > weight


def _pinch_lines(c: CableResult, done: np.ndarray, weight: float, joints) -> list[str]:
    hard = done[pinched(c, weight)[done]]
    if not len(hard):
        most = c.pinch[done].max()
        return [f"  pinched: never (pressed from opposite sides at most {most:.3g} N, under its own weight "
                f"{weight:.3g} N)" if most > 0 else "  pinched: never"]
    e = int(hard[np.argmax(c.pinch[hard])])
    a, b = (c.links[k] for k in c.pinch_slots[e])
    what = f"between {a} and {b}" if a != b else f"in {a}"
    return [f"  pinched {what}: {c.pinch[e]:.3g} N across the hose (environment {e}, t = {c.pinch_time[e]:.2f} s, "
            f"{c.pinch_at[e]:.3f} m along, robot at {_joints(c.pinch_q[e], joints)}); pinched in {_envs(hard)}"]


def _joints(q: np.ndarray, joints) -> str:
    if not joints:
        return "its start"
    return ", ".join(f"{name} {np.degrees(v):.0f} deg" if rot else f"{name} {v * 1000:.0f} mm"
                     for v, (name, rot) in zip(q, joints))


def _envs(idx: np.ndarray) -> str:
    shown = ", ".join(str(i) for i in idx[:8])
    return f"environment(s) {shown}" + (f" and {len(idx) - 8} more" if len(idx) > 8 else "")
