"""``--video`` for ``rswarp cable`` and ``rswarp program``: the run's worst environment (or the
one asked for) with its hose coloured by bend radius or wear, and a program's motion with the
links in collision in red; at most ``VIDEO_FPS`` frames a second of the run's time."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..kinematics.kinematics import Kinematics
from ..outputs import claim, record
from ..sim.video import BEND_COLOURS, GREY, RED, Tube, bend_colours, render_frames, wear_colours, write_video

VIDEO_FPS = 30.0
VIDEO_SIZE = 512
COLOURINGS = ("bend", "wear")


def claim_video(path: str | None, made: str | Path | None = None) -> None:
    """Refuse, before any work, a video path that cannot be written or would replace a file rswarp
    did not write (``made``: the run's output folder, which the video may go into)."""
    if path is not None:
        from ..sim.video import check_video_path

        made = None if made is None else Path(made)
        claim(check_video_path(path, made), made)


def _saved(path: str | Path, frames: np.ndarray, fps: float) -> dict:
    path = Path(path)
    write_video(path, frames, fps)
    record(path.parent if str(path.parent) else Path("."), [path.name])
    return {"path": str(path), "frames": int(len(frames)), "fps": fps, "size": int(frames.shape[1])}


def worst_environment(run, colouring: str) -> int:
    """The environment with the least bend radius (``bend``) or the most wear (``wear``)."""
    cable = run.cables[0]
    ok = np.array([s == "ok" for s in cable.status])
    if colouring == "wear":
        return int(np.argmax(np.where(ok, cable.wear.sum(axis=(1, 2)), -1.0)))
    return int(np.argmin(np.where(ok & np.isfinite(cable.min_bend_radius), cable.min_bend_radius, np.inf)))


def cable_video(mech, run, trajectories, path: str, env: int | None = None, colouring: str = "bend",
                size: int = VIDEO_SIZE) -> dict:
    """Environment ``env`` (default: the worst) of a cable run again, its shapes kept, rendered."""
    from ..sim.cables import simulate_cables

    if colouring not in COLOURINGS:
        raise InputError(f"--video-color must be one of {', '.join(COLOURINGS)}")
    envs = run.envs
    env = worst_environment(run, colouring) if env is None else env
    if not 0 <= env < envs:
        raise InputError(f"--video-env must be 0 to {envs - 1}")
    options = dataclasses.replace(run.options, record=0)
    again = simulate_cables(mech, [trajectories[run.assignment[env]]], 1, float(run.times[-1]), options)
    step = max(1, int(round(options.frame_rate / VIDEO_FPS)))
    stride = again.cables[0].stride
    keep = max(1, step // stride)
    q = again.q[::keep]
    tubes, legend = [], []
    for k, c in enumerate(again.cables):
        pts = c.recorded[::keep]
        if colouring == "wear":
            colours = wear_colours(run.cables[k].wear[env].sum(axis=1), len(pts))
            legend = [(GREY, "no wear"), ((0.55, 0.05, 0.05), "most wear (Archard)")]
        else:
            colours = bend_colours(pts, c.allowed_bend_radius)
            legend = [(BEND_COLOURS[0], f"bend radius >= {c.allowed_bend_radius:.2f} m"),
                      (BEND_COLOURS[1], "tighter than allowed"), (BEND_COLOURS[2], "tighter than half of it")]
        tubes.append(Tube(pts, colours, c.radius))
    n = min(len(q), *(len(t.points) for t in tubes))
    poses = Kinematics(mech).fk64(q[:n])
    tubes = [Tube(t.points[:n], t.colours[:n], t.radius) for t in tubes]
    frames = render_frames(mech, poses, tubes, size, legend=[(GREY, f"environment {env}"), *legend])
    return {**_saved(path, frames, options.frame_rate / (keep * stride)), "environment": env, "colour": colouring}


def program_video(mech, plan, tally, names, path: str, size: int = VIDEO_SIZE) -> dict:
    """A program's motion at ``VIDEO_FPS``, the links of a colliding pair red while they touch."""
    times = np.arange(0.0, float(plan.times[-1]) + 1e-9, 1.0 / VIDEO_FPS)
    rows = np.clip(np.searchsorted(plan.times, times), 0, len(plan.times) - 1)
    poses = Kinematics(mech).fk64(plan.q[rows])
    graph = mech.graph
    marked = []
    for r in rows:
        hit = tally.hit[r] if tally.hit.shape[1] else np.zeros(0, bool)
        marked.append({graph.link_index(n) for k in np.nonzero(hit)[0] for n in names[k] if n in graph.links})
    frames = render_frames(mech, poses, [], size, marked=marked,
                           legend=[(GREY, f"{Path(plan.run.files[0]).stem}.{plan.run.routine}"), (RED, "in collision")])
    return _saved(path, frames, VIDEO_FPS)
