"""What ``rswarp cable`` leaves in its output folder and prints: ``report.json`` (per environment
and cable: tension, bend radius, clearance and contact per link, whether the cable is long enough,
twist, final points), plots over time (``tension.png``, ``bend_radius.png``, ``clearance.png``)
and, when asked, ``playback.usdc``: robot and cables over time for usdview."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from ..files import atomic_write
from ..kinematics.kinematics import Kinematics
from ..kinematics.trajectory import RANDOM_SECONDS, run_trajectories
from ..options import checked
from ..outputs import atomic_folder, check_replaceable
from ..rsxml.documents import load_mechanism
from ..rsxml.model import Mechanism
from ..sim.cable_results import CableResult
from ..sim.cable_solver import DENSITY, FRAME_RATE, SUBSTEPS, CableOptions, link_meshes
from ..sim.cables import CableRun, run_frames, simulate_cables
from ..sim.engine import cluster_for
from .output import Output, Warn, ignore, json_bytes, json_safe

CABLE_FILES = ("report.json", "tension.png", "bend_radius.png", "clearance.png", "playback.usdc")
TAUT = 0.999  # attachments this share of the cable length apart: pulled straight, no slack left


def run_cables(path: str, out: str, envs: int = 16, trajectory: list[str] | None = None, random: bool = False,
               seconds: float | None = None, seed: int = 0, usd: bool = False, min_bend_radius: float | None = None,
               floor: float | None = 0.0, density: float = DENSITY, frame_rate: float = FRAME_RATE,
               substeps: int = SUBSTEPS, cable_model: str = "chain", device: str = "cpu", ray: str | None = None,
               progress: Callable[[float, float], None] | None = None, warn: Warn = ignore) -> Output:
    """``rswarp cable``: every cable of ``path`` over the ``trajectory`` CSV files (or ``random``
    ones), written into ``out``; ``min_bend_radius`` and ``floor`` (None: none) in the file's length
    unit."""
    mech, _ = load_mechanism(path)
    check_cable_folder(out)
    options = CableOptions(frame_rate=frame_rate, substeps=substeps, density=density, cable_model=cable_model,
                           min_bend_radius=mech.si_length(min_bend_radius), floor=mech.si_length(floor),
                           record=0 if usd else -1, device=device)
    checked("envs", envs)
    if seconds is not None or random:  # bounded before any trajectory is made
        run_frames(seconds or RANDOM_SECONDS, options)
    trajectories = run_trajectories(mech, trajectory, random, envs, seconds, seed)
    run = simulate_cables(mech, trajectories, envs, seconds, options, progress=progress,
                          cluster=cluster_for(ray, device))
    for w in run.warnings:
        warn(w)
    doc = write_cables(run, mech, out, usd=usd)
    return Output(doc, cables_text(run, doc["files"]))


def check_cable_folder(out: str | Path) -> None:
    """Refuse an output folder the run could not replace, before anything is simulated."""
    check_replaceable(Path(out), CABLE_FILES)


def write_cables(run: CableRun, mech: Mechanism, out: str | Path, usd: bool = False) -> dict:
    """Write the run's files into ``out`` as one set (an interrupted run leaves the old set). The
    report as a dict, its files under ``files``."""
    out = Path(out)
    names = {"report": "report.json", "tension_plot": "tension.png", "bend_plot": "bend_radius.png",
             "clearance_plot": "clearance.png"} | ({"playback": "playback.usdc"} if usd else {})
    doc = cable_report(run) | {"files": {k: str(out / v) for k, v in names.items()}}
    with atomic_folder(out, CABLE_FILES) as tmp:
        for key, png in zip(("tension_plot", "bend_plot", "clearance_plot"), _plots(run)):
            atomic_write(tmp / names[key], png)
        if usd:
            _playback(run, mech, tmp / names["playback"])
        atomic_write(tmp / names["report"], json_bytes(doc))
    return doc


def cable_report(run: CableRun) -> dict:
    """The run as JSON-ready data (SI units; null where a quantity never occurred)."""
    o = run.options
    return json_safe({
        "mechanism": run.mechanism, "environments": run.envs, "seconds": float(run.times[-1]),
        "frame_rate": o.frame_rate, "substeps": o.substeps, "cable_model": o.cable_model,
        "trajectories": list(run.trajectories),
        "floor_z_m": o.floor, "warnings": list(run.warnings),
        "cables": [_cable_dict(c, run) for c in run.cables]})


def _cable_dict(c: CableResult, run: CableRun) -> dict:
    return {"name": c.name, "length_m": c.length, "radius_m": c.radius, "allowed_bend_radius_m": c.allowed_bend_radius,
            "torsion_stiffness_Nm2": c.torsion_stiffness, "summary": _summary(c),
            "environments": [_env_dict(c, e, run) for e in range(c.envs)]}


def _summary(c: CableResult) -> dict:
    """The answers over the environments that ran to the end (None where none did)."""
    ok = c.status == "ok"
    done = np.nonzero(ok)[0]
    most = (lambda a: float(np.max(a[done])) if len(done) else None)  # noqa: E731
    return {"stopped": int((~ok).sum()), "finished": int(ok.sum()), "too_tight": int(c.too_tight[ok].sum()),
            "taut": int((c.stretch[ok] >= TAUT).sum()), "touching": int(c.touching[ok].sum()),
            "least_bend_radius_m": _least(c.min_bend_radius[ok]), "peak_tension_N": most(c.peak_tension),
            "greatest_twist_rad": most(c.max_twist)}


def _env_dict(c: CableResult, e: int, run: CableRun) -> dict:
    links = {}
    for j, name in enumerate(c.links):
        if np.isfinite(c.clearance[e, j]):
            links[name] = {"min_clearance_m": c.clearance[e, j], "time_s": c.clearance_time[e, j],
                           "at_m": c.clearance_at[e, j], "contact_time_s": c.contact_time[e, j],
                           "contact_at_m": c.contact_at[e, j]}
    return {"environment": e, "trajectory": run.trajectories[run.assignment[e]], "status": str(c.status[e]),
            "peak_tension_N": c.peak_tension[e], "peak_tension_time_s": c.peak_tension_time[e],
            "taut": bool(c.stretch[e] >= TAUT), "max_attachment_distance_ratio": c.stretch[e],
            "max_attachment_distance_time_s": c.stretch_time[e],
            "min_bend_radius_m": c.min_bend_radius[e], "min_bend_time_s": c.min_bend_time[e],
            "min_bend_at_m": c.min_bend_at[e], "bend_ok": bool(not c.too_tight[e]),
            "max_twist_rad": c.max_twist[e], "max_torque_Nm": c.torsion_stiffness * c.max_twist[e] / c.length,
            "clearance": links, "final_points": np.round(c.final_points[e], 6).tolist()}


def _least(values: np.ndarray) -> float | None:
    finite = values[np.isfinite(values)]
    return float(finite.min()) if len(finite) else None


def cables_text(run: CableRun, files: dict) -> str:
    """The summary a user reads: per cable, the worst environment for each question."""
    lines = [f"{run.mechanism}: {len(run.cables)} cable(s), {run.envs} environment(s), "
             f"{run.times[-1]:g} s at {run.options.frame_rate:g} frames/s"]
    for c in run.cables:
        lines += _cable_lines(c)
    lines += [f"{k}: {v}" for k, v in files.items()]
    return "\n".join(lines)


def _cable_lines(c: CableResult) -> list[str]:
    """The cable's answers over the environments that ran to the end; those that stopped are
    reported as stopped, never as answers."""
    lines = [f"{c.name}: {c.length:.3f} m, radius {c.radius * 1000:g} mm"]
    done = np.nonzero(c.status == "ok")[0]
    stopped = np.nonzero(c.status != "ok")[0]
    if len(done):
        lines += _answer_lines(c, done)
    else:
        lines.append(f"  no answers: every environment stopped before the end ({c.envs} of {c.envs})")
    for e in stopped[:5]:
        lines.append(f"  environment {e} {c.status[e]}")
    if len(stopped) > 5:
        lines.append(f"  ... and {len(stopped) - 5} more stopped")
    return lines


def _answer_lines(c: CableResult, done: np.ndarray) -> list[str]:
    """Long enough, bend radius, tension, contact and twist over the environments ``done``."""
    n = f"{len(done)}" + (f" (of {c.envs}; the others stopped)" if len(done) < c.envs else "")
    taut = done[c.stretch[done] >= TAUT]
    most = c.stretch[done].max()
    lines = [f"  long enough: {len(done) - len(taut)} of {n}" + (
        f"; pulled straight in {_envs(taut)} (attachments {most:.1%} of the length apart)" if len(taut) else
        f" (attachments at most {most:.1%} of the length apart)")]
    bend = np.where(np.isfinite(c.min_bend_radius[done]), c.min_bend_radius[done], np.inf)
    e = int(done[np.argmin(bend)])
    tight = done[c.too_tight[done]]
    where = f" (environment {e}, t = {c.min_bend_time[e]:.2f} s, {c.min_bend_at[e]:.3f} m along)" \
        if np.isfinite(c.min_bend_radius[e]) else " (straight throughout)"
    lines.append(f"  bend radius: least {c.min_bend_radius[e]:.3f} m{where}; allowed {c.allowed_bend_radius:.3f} m: "
                 f"too tight in {len(tight)} of {n}")
    e = int(done[np.argmax(c.peak_tension[done])])
    lines.append(f"  peak tension: {c.peak_tension[e]:.3g} N (environment {e}, t = {c.peak_tension_time[e]:.2f} s)"
                 + ("; taut runs: the tension is the solver's, an inextensible cable has no stiffness to bound it"
                    if len(taut) else ""))
    lines += _contact_lines(c, done)
    e = int(done[np.argmax(c.max_twist[done])])
    lines.append(f"  twist: greatest {np.degrees(c.max_twist[e]):.1f} deg between the clamps (environment {e}; "
                 f"torque {c.torsion_stiffness * c.max_twist[e] / c.length:.3g} N m)")
    return lines


def _contact_lines(c: CableResult, done: np.ndarray) -> list[str]:
    out = []
    for j, name in enumerate(c.links):
        col = c.clearance[done, j]
        reached = col < np.inf  # -inf too: a link or floor the cable is wholly inside of
        if not reached.any():
            continue
        e = int(done[np.argmin(np.where(reached, col, np.inf))])
        touching = done[np.isfinite(c.contact_time[done, j])]
        text = f"  {name}: least clearance {c.clearance[e, j] * 1000:.1f} mm (environment {e}, " \
               f"t = {c.clearance_time[e, j]:.2f} s, {c.clearance_at[e, j]:.3f} m along)"
        if len(touching):
            first = touching[np.argmin(c.contact_time[touching, j])]
            text += f"; touches in {len(touching)} of {len(done)}, first environment {first} at t = " \
                    f"{c.contact_time[first, j]:.2f} s"
        if c.clearance[e, j] < -2 * c.radius - c.length / 4:  # deeper than any contact push leaves it
            text += " (carried inside by the robot: the trajectory goes through it)"
        out.append(text)
    return out or ["  clearance: nothing within reach of the cable"]


def _envs(idx: np.ndarray) -> str:
    shown = ", ".join(str(i) for i in idx[:8])
    return f"environment(s) {shown}" + (f" and {len(idx) - 8} more" if len(idx) > 8 else "")


def _plots(run: CableRun) -> list[bytes]:
    """Tension, bend radius and clearance over time: per cable, the median across environments and
    the band from least to greatest."""
    from .figures import figure_png

    t = run.times
    out = []
    for key, title, unit, scale in (("tension", "Tension", "N", 1.0), ("bend", "Least bend radius", "mm", 1000.0),
                                    ("gap", "Least clearance", "mm", 1000.0)):
        def draw(ax, key=key, scale=scale):
            for c in run.cables:
                s = getattr(c, key)
                line, = ax.plot(t, s.median * scale, label=f"{c.name} (median)")
                ax.fill_between(t, s.low * scale, s.high * scale, color=line.get_color(), alpha=0.25, lw=0,
                                label=f"{c.name} (least to greatest)")
                if key == "bend":
                    ax.set_yscale("log")
                    ax.axhline(c.allowed_bend_radius * scale, color=line.get_color(), ls="--",
                               label=f"{c.name} allowed")
            if key == "gap":
                ax.axhline(0.0, color="k", lw=0.8)
        out.append(figure_png(draw, f"{title} over {run.envs} environment(s)", "time (s)", f"{title.lower()} ({unit})"))
    return out


def _playback(run: CableRun, mech: Mechanism, path: Path) -> None:
    """The recorded environment's robot and cables, sampled per frame (every stride-th when long)."""
    from ..export.playback import PlaybackCable, PlaybackLink, write_playback

    stride = run.cables[0].stride
    q = run.q[::stride]
    poses = Kinematics(mech).fk(q)
    links = [PlaybackLink(name, m[0], m[1], (0.85, 0.85, 0.85), poses[:, j])
             for j, (name, m) in enumerate(zip(mech.graph.links, link_meshes(mech).meshes)) if m is not None]
    cables = [PlaybackCable(c.name, c.recorded, c.radius, _color(mech, c.name)) for c in run.cables]
    write_playback(path, mech.name, links, cables, run.options.frame_rate / stride)


def _color(mech: Mechanism, name: str) -> tuple[float, float, float]:
    cable = next(c for c in mech.cables if c.name == name)
    return tuple(v / 255 for v in cable.color) if cable.color else (0.1, 0.1, 0.1)
