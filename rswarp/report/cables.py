"""What ``rswarp cable`` leaves in its output folder and prints: ``report.json`` (per cable and
environment: tension and where, bend radius, clearance and contact per slot, whether the cable is
long enough, twist and torque, what each clamp holds, the wear map, final points), the plots
(``cable_plots``) and, when asked, ``playback.usdc``: robot and cables over time for usdview."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Callable

import numpy as np

from ..config import BatchOptions, HoseOptions, TaskOptions, VideoOptions, routed
from ..errors import InputError
from ..files import atomic_write
from ..kinematics.kinematics import Kinematics
from ..kinematics.trajectory import RANDOM_SECONDS, Trajectory, run_trajectories
from ..motion.cells import base_offsets, carried, floor_in_robot, is_cell
from ..motion.payload import task_payload
from ..options import checked
from ..outputs import atomic_folder, check_replaceable
from ..rsxml.cell import read_cell
from ..rsxml.documents import load_mechanism
from ..rsxml.model import Mechanism
from ..sim.cable.results import CableResult
from ..sim.cable.solver import CableOptions, contact_meshes
from ..sim.cables import CableRun, run_frames, simulate_cables
from ..sim.engine import cluster_for
from .cable_contact import contact, run_worst, shown_slots
from .cable_lines import cable_lines, pinched
from .cable_plots import cable_plots
from .dresspack_options import cable_options, ratings_of
from .output import Output, Warn, ignore, json_bytes, json_safe
from .verdicts import Ratings, cable_findings, moments, verdict, verdict_lines

TAUT = 0.999  # attachments this share of the cable length apart: pulled straight, no slack left


def run_cables(path: str, out: str, task: TaskOptions | None = None, hose: HoseOptions | None = None,
               batch: BatchOptions | None = None, video: VideoOptions | None = None, *, envs: int | None = None,
               trajectory: list[str] | None = None, random: bool = False, seconds: float | None = None,
               usd: bool = False, program: list[str] | None = None,
               progress: Callable[[float, float], None] | None = None, warn: Warn = ignore, **changes) -> Output:
    """``rswarp cable``: every cable of ``path`` over the ``trajectory`` CSV files (or ``random``
    ones, or a RAPID ``program``'s routine, run as ``task`` says), written into ``out``; the hose
    held to ``hose``'s ratings; ``task``'s floor (None: none) and environment meshes' places
    (MESH@x,y,z) and ``hose``'s bend radii in the file's length unit. ``changes`` replace fields of
    the options (``frame_rate=30.0``, ``tool="gripper.stl"``, ``seed=4``)."""
    o = routed(changes, task=task or TaskOptions(), hose=hose or HoseOptions(), batch=batch or BatchOptions(),
               video=video or VideoOptions())
    task, hose, batch, video = o["task"], o["hose"], o["batch"], o["video"]
    said, told = [], warn  # every warning is also in report.json's warnings, as the command printed it

    def warn(line) -> None:
        said.append(str(line))
        told(line)

    envs = default_envs(envs, program)
    cell = read_cell(path) if is_cell(path) else None
    mech, report = load_mechanism(cell.robot.rsxml if cell is not None else path)
    _say_no_slack(report, warn)
    placed = replace(task, floor=floor_in_robot(cell, mech, task.floor))  # the floor in the robot's frame
    ratings = ratings_of(mech, hose)
    rated = rated_fatigue(hose.rated_cycles, mech)
    check_cable_folder(out)
    check_video_options(video.video, video.video_env, video.video_color, envs, out)
    options = cable_options(mech, placed, hose, batch.device, record=0 if usd else -1)
    checked("envs", envs)
    if not mech.cables:  # before any trajectory is made
        raise InputError(f"{mech.path or mech.name}: the mechanism has no Cable to simulate")
    if seconds is not None or random:  # bounded before any trajectory is made
        run_frames(seconds or RANDOM_SECONDS, options)
    plan = None
    if program is None:
        _say_unused(task, warn)
    else:
        from ..motion.plan import moved_before_stop, program_plan

        _, plan = program_plan(path, program, task, warn=warn)
        moved_before_stop(plan)
    trajectories = _trajectories(mech, options, plan, trajectory, random, envs, seconds, batch.seed, warn,
                                 base_offsets(cell, plan) if plan is not None else None)
    trajectories = [carried(cell, t) for t in trajectories]  # a CSV's external axes carry the robot
    run = simulate_cables(mech, trajectories, envs, seconds, options, progress=progress,
                          cluster=cluster_for(batch.ray, batch.device))
    for w in run.warnings:
        warn(w)
    doc, text = _reported(run, mech, out, usd, trajectories, plan, ratings, rated, said)
    if video.video is not None:
        from .videos import cable_video

        moves = plan.moves if plan is not None else None
        doc["video"] = cable_video(mech, run, trajectories, video.video, video.video_env, video.video_color,
                                   video.video_size, moves)
        text += f"\nvideo: {video.video} (environment {doc['video']['environment']}, {doc['video']['frames']} frames)"
    return Output(doc, text)


# the task options only a --program reads, and their flags
PROGRAM_ONLY = {"routine": "--routine", "io": "--io", "inputs": "--input", "cycles": "--cycles",
                "external_axes": "--external-axes", "limits": "--limits", "payload": "--payload"}


def _say_unused(task: TaskOptions, warn: Warn) -> None:
    """One warning naming the task's options given without ``--program``: only a program reads them."""
    default = TaskOptions()
    given = [flag for key, flag in PROGRAM_ONLY.items() if getattr(task, key) != getattr(default, key)]
    if given:
        warn(f"rswarp cable: warning: {', '.join(given)} ignored: only a --program runs a task (--trajectory and "
             "--random follow joint values)")


def default_envs(envs: int | None, program) -> int:
    """``--envs`` as given, else 1 over a ``--program`` (its environments would be alike), else 16."""
    return envs if envs is not None else 1 if program is not None else 16


def _say_no_slack(report, warn: Warn) -> None:
    """A hose with no slack: the run's answers depend on it, so the run says so, as check does."""
    for d in report.diagnostics:
        if d.severity == "warning" and "desiredLength" in d.message:
            warn(str(d))


def _trajectories(mech, options: CableOptions, plan, trajectory, random: bool, envs: int, seconds, seed: int,
                  warn: Warn, base=None) -> list:
    """What the environments follow: the program's ``plan`` (its robot carried by ``base``, a
    track's travel), random programs, or CSV files."""
    if plan is not None:
        trajectories = [Trajectory(", ".join(plan.run.files), plan.times, plan.q, base=base)]
        if seconds is not None and seconds < trajectories[0].duration:
            warn(f"rswarp: warning: --seconds {seconds:g}: the task takes {trajectories[0].duration:.2f} s; the run "
                 f"covers its first {seconds:g} s")
    elif random:  # random programs: free of the floor (at the run's floor) and of the robot itself
        from ..sim.random_program import random_programs

        return random_programs(mech, envs, seconds or RANDOM_SECONDS, seed,
                               0.0 if options.floor is None else options.floor, options)
    else:
        trajectories = run_trajectories(mech, trajectory, False, envs, seconds, seed)
    if 0 < len(trajectories) < envs:
        many = f"{len(trajectories)} trajectories" if len(trajectories) > 1 else "one trajectory"
        warn(f"rswarp: warning: --envs {envs}: {many} for {envs} environments; those that follow the same one "
             f"are alike")
    return trajectories


def _reported(run: CableRun, mech, out: str, usd: bool, trajectories, plan, ratings: Ratings, rated, said=()):
    """(report, text) of a run: its verdicts and findings, written into ``out`` with its plots;
    over a program, each finding's line, the fatigue a pass and the payload it carries."""
    load = task_payload(plan) if plan is not None else None
    found = run_findings(run, trajectories, plan.moves if plan is not None else None, ratings)
    stopped = plan.run.stopped if plan is not None else None
    doc = write_cables(run, mech, out, usd=usd, ratings=ratings, more={
        "payload": None if load is None else {"mass": load.mass, "cog": load.cog, "source": load.source},
        "program_stopped": None if stopped is None else str(stopped),
        "needs_input": None if stopped is None else plan.run.needs_input, **verdict_data(run, found),
        "warnings": list(dict.fromkeys([*run.warnings, *said]))})
    passes = max(len(plan.cycles), 1) if plan is not None else 1
    text = cables_text(run, doc["files"], found, passes, rated)
    if stopped is not None:  # the verdict is of the moves before the stop, and says so
        text += (f"\nprogram stopped: {stopped}; the hoses were run over the {plan.times[-1]:.2f} s of moves before "
                 "it, not the whole program")
    if load is not None:  # the joints are the plan's: a load changes no hose figure, and is said so
        text += (f"\npayload: {load.mass:g} kg ({load.source}); the robot follows its planned joints, which no "
                 "load changes here")
    return doc, text


def rated_fatigue(spec: str | None, mech) -> tuple[float, float] | None:
    """``--rated-cycles N@R``: N bending cycles to failure at bend radius R (the file's length
    unit), as (N, R in m); None without it."""
    if spec is None:
        return None
    n, at, r = spec.partition("@")
    try:
        cycles, radius = float(n), mech.si_length(float(r))
    except ValueError:
        cycles = radius = float("nan")
    if not at or not 1 <= cycles < 1e15 or not 0 < radius < 1e3:
        raise InputError(f"--rated-cycles '{spec}': give N@R, the cycles a hose lasts bent to radius R (the file's "
                         "length unit), e.g. 1e7@" + f"{0.3 / mech.length_factor:g}" + " for 300 mm")
    return cycles, radius


def run_findings(run: CableRun, trajectories, moves=None, ratings: Ratings = Ratings()) -> list:
    """Every finding of a run's cables (``report.verdicts``), each at its environment's moment."""
    when = moments(trajectories, run.assignment, moves)
    return [f for c, w in zip(run.cables, run.weights) for f in cable_findings(c, w, ratings, when)]


def verdict_data(run: CableRun, found: list) -> dict:
    """The verdict of each cable and every finding, for the report."""
    return {"verdicts": {c.name: verdict([f for f in found if f.cable == c.name]) for c in run.cables},
            "findings": [f.record() for f in found]}


def check_video_options(video: str | None, env: int | None, colour: str, envs: int, out) -> None:
    """``--video``, ``--video-env`` and ``--video-color`` refused before any work where they cannot
    be honoured."""
    from .videos import COLOURINGS, claim_video

    if video is None:
        if env is not None:
            raise InputError("--video-env needs --video (the file to render the environment into)")
        return
    claim_video(video, out)
    if colour not in COLOURINGS:
        raise InputError(f"--video-color must be one of {', '.join(COLOURINGS)}")
    if env is not None and not 0 <= env < envs:
        raise InputError(f"--video-env must be 0 to {envs - 1} (the run has {envs} environments), not {env}")


def check_cable_folder(out: str | Path) -> None:
    """Refuse an output folder the run could not replace, before anything is simulated."""
    check_replaceable(Path(out))


def write_cables(run: CableRun, mech: Mechanism, out: str | Path, usd: bool = False, more: dict | None = None,
                 ratings: Ratings = Ratings()) -> dict:
    """Write the run's files into ``out`` as one set (an interrupted run leaves the old set). The
    report (with ``more`` in it) as a dict, its files under ``files``; the plots draw the
    ``ratings``' limits."""
    out = Path(out)
    plots = cable_plots(run, ratings)
    names = {"report": "report.json"} | {Path(f).stem + "_plot": f for f in plots} | (
        {"playback": "playback.usdc"} if usd else {})
    doc = cable_report(run) | json_safe(more or {}) | {"files": {k: str(out / v) for k, v in names.items()}}
    with atomic_folder(out) as tmp:
        for name, png in plots.items():
            atomic_write(tmp / name, png)
        if usd:
            _playback(run, mech, tmp / names["playback"])
        atomic_write(tmp / names["report"], json_bytes(doc))
    return doc


def cable_report(run: CableRun) -> dict:
    """The run as JSON-ready data (SI units; null where a quantity never occurred)."""
    o = run.options
    return json_safe({
        "mechanism": run.mechanism, "environments": run.envs, "seconds": float(run.times[-1]),
        "frame_rate": o.frame_rate, "substeps": o.substeps, "iterations": o.iterations, "cable_model": o.cable_model,
        "density_kg_m3": o.density, "poisson": o.poisson, "friction": o.friction, "damping_per_s": o.damping,
        "trajectories": list(run.trajectories), "floor_z_m": o.floor,
        "environment": [e.name for e in o.environment], "warnings": list(run.warnings),
        "cables": [_cable_dict(c, w, run) for c, w in zip(run.cables, run.weights)]})


def _cable_dict(c: CableResult, weight: float, run: CableRun) -> dict:
    return {"name": c.name, "length_m": c.length, "radius_m": c.radius, "allowed_bend_radius_m": c.allowed_bend_radius,
            "axial_stiffness_N": c.axial_stiffness, "bending_stiffness_Nm2": c.bending_stiffness,
            "torsion_stiffness_Nm2": c.torsion_stiffness, "slots": [c.links[j] for j in _slots(c, run)],
            "attachments": list(c.attachments),
            "segments_at_m": c.segments, "weight_N": weight, "summary": _summary(c, weight, run),
            "environments": [_env_dict(c, e, run) for e in range(c.envs)]}


def _slots(c: CableResult, run: CableRun) -> list[int]:
    """The slots the report names: no floor's in a run with none (``--no-floor``)."""
    return shown_slots(c, run.options.floor is not None)


def _summary(c: CableResult, weight: float, run: CableRun) -> dict:
    """The answers over the environments that ran to the end (None where none did); ``contact``:
    the run's worst of each contact figure (``cable_contact``), with its environment."""
    ok = c.status == "ok"
    done = np.nonzero(ok)[0]
    most = (lambda a: float(np.max(a[done])) if len(done) else None)  # noqa: E731
    return {"stopped": int((~ok).sum()), "finished": int(ok.sum()), "too_tight": int(c.too_tight[ok].sum()),
            "straight_between_clamps": int((c.stretch[ok] >= TAUT).sum()), "touching": int(c.touching[ok].sum()),
            "least_bend_radius_m": _least(c.min_bend_radius[ok]), "peak_tension_N": most(c.peak_tension),
            "greatest_twist_rad": most(c.max_twist), "greatest_torque_Nm": most(c.max_torque),
            "contact": run_worst(c, done), "pinched": int(pinched(c, weight)[ok].sum()),
            "greatest_pinch_N": most(c.pinch),
            "clamp_force_N": [most(c.clamp_force[:, a]) for a in range(len(c.attachments))],
            "clamp_moment_Nm": [most(c.clamp_moment[:, a]) for a in range(len(c.attachments))]}


def _env_dict(c: CableResult, e: int, run: CableRun) -> dict:
    links = {}
    for j in _slots(c, run):
        name = c.links[j]
        if np.isfinite(c.clearance[e, j]):
            links[name] = {"min_clearance_m": c.clearance[e, j], "time_s": c.clearance_time[e, j],
                           "at_m": c.clearance_at[e, j], "contact_time_s": c.contact_time[e, j],
                           "contact_at_m": c.contact_at[e, j]}
    clamps = [{"attachment": name, "peak_force_N": c.clamp_force[e, a], "peak_force_time_s": c.clamp_force_time[e, a],
               "peak_moment_Nm": c.clamp_moment[e, a], "peak_moment_time_s": c.clamp_moment_time[e, a],
               "final_force_N": c.final_clamp_force[e, a], "final_moment_Nm": c.final_clamp_moment[e, a]}
              for a, name in enumerate(c.attachments)]
    return {"environment": e, "trajectory": run.trajectories[run.assignment[e]], "status": str(c.status[e]),
            "peak_tension_N": c.peak_tension[e], "peak_tension_time_s": c.peak_tension_time[e],
            "peak_tension_at_m": c.peak_tension_at[e],
            "straight_between_clamps": bool(c.stretch[e] >= TAUT), "max_attachment_distance_ratio": c.stretch[e],
            "fatigue": {"rainflow_cycles": c.fatigue_cycles[e], "miner_sum_per_m4": c.fatigue_sum[e]},
            "max_attachment_distance_time_s": c.stretch_time[e],
            "min_bend_radius_m": c.min_bend_radius[e], "min_bend_time_s": c.min_bend_time[e],
            "min_bend_at_m": c.min_bend_at[e], "bend_ok": bool(not c.too_tight[e]),
            "max_twist_rad": c.max_twist[e], "max_twist_rate_rad_per_m": c.max_twist_rate[e],
            "max_torque_Nm": c.max_torque[e], "max_torque_time_s": c.max_torque_time[e],
            "max_torque_at_m": c.max_torque_at[e], "contact": contact(c, e),
            "max_sliding_speed_m_s": c.max_sliding_speed[e], "pinch": _pinch_dict(c, e, run), "clamps": clamps,
            "wear": {"contact_time_s": c.wear_contact_time[e], "peak_force_N": c.wear_peak_normal[e],
                     "archard_J": c.segment_wear[e], "bend_cycles": c.bend_cycles[e],
                     "archard_by_slot_J": {c.links[j]: c.wear[e, :, j] for j in _slots(c, run)
                                           if np.any(c.wear[e, :, j] > 0)}},
            "clearance": links, "final_points": np.round(c.final_points[e], 6).tolist()}


def _pinch_dict(c: CableResult, e: int, run: CableRun) -> dict | None:
    """The hardest the cable was pressed from opposite sides, by what, and where the robot was."""
    if not c.pinch[e] > 0:
        return None
    return {"force_N": c.pinch[e], "time_s": c.pinch_time[e], "at_m": c.pinch_at[e],
            "between": [c.links[k] for k in c.pinch_slots[e]],
            "joints": {name: c.pinch_q[e, i] for i, (name, _) in enumerate(run.joints)}}


def _least(values: np.ndarray) -> float | None:
    finite = values[np.isfinite(values)]
    return float(finite.min()) if len(finite) else None


def cables_text(run: CableRun, files: dict, findings=(), passes: int = 1,
                rated: tuple[float, float] | None = None) -> str:
    """The summary a user reads: per cable, its verdict and the worst of each finding, then the
    worst environment for each question, and its fatigue a pass of ``passes``."""
    lines = [f"{run.mechanism}: {len(run.cables)} cable(s), {run.envs} environment(s), "
             f"{run.times[-1]:g} s at {run.options.frame_rate:g} frames/s"]
    for c, weight in zip(run.cables, run.weights):
        lines += cable_lines(c, weight, run.joints, verdict_lines(c, list(findings)), passes, rated)
    lines += [f"{k}: {v}" for k, v in files.items()]
    return "\n".join(lines)


def _playback(run: CableRun, mech: Mechanism, path: Path) -> None:
    """The recorded environment's robot and cables, sampled per frame (every stride-th when long)."""
    from ..export.playback import PlaybackCable, PlaybackLink, write_playback

    stride = run.cables[0].stride
    q = run.q[::stride]
    poses = Kinematics(mech).fk(q)
    meshes = contact_meshes(mech, tool=run.options.tool)
    links = [PlaybackLink(name, m[0], m[1], (0.85, 0.85, 0.85), poses[:, j])
             for j, (name, m) in enumerate(zip(mech.graph.links, meshes.links)) if m is not None]
    links += [PlaybackLink(name, v, f, (0.55, 0.6, 0.7), poses[:, j]) for name, j, v, f in meshes.tool]
    cables = [PlaybackCable(c.name, c.recorded, c.radius, _color(mech, c.name)) for c in run.cables]
    write_playback(path, mech.name, links, cables, run.options.frame_rate / stride)


def _color(mech: Mechanism, name: str) -> tuple[float, float, float]:
    cable = next(c for c in mech.cables if c.name == name)
    return tuple(v / 255 for v in cable.color) if cable.color else (0.1, 0.1, 0.1)
