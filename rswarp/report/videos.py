"""``--video`` for ``rswarp cable`` and ``rswarp program``: the run's worst environment (or the
one asked for) with its hose coloured by bend radius or wear, and a program's motion with the
links in collision in red; at most ``VIDEO_FPS`` frames a second of the run's time. Each frame
says its time and, for a RAPID program, the file, line and instruction of the move under way.

``FRAME_PROGRESS`` holds the progress callback a video's frames report to when the caller passes
none: the command line sets it to a bar on stderr (not under --json). ``FRAME_RATE`` holds the
frames a second of the run's time a video shows (``VIDEO_FPS``; the demo sets fewer, with
``frame_rate``)."""

from __future__ import annotations

import contextlib
import dataclasses
from contextvars import ContextVar
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from ..errors import InputError
from ..kinematics.kinematics import Kinematics
from ..outputs import claim, record
from ..rsxml.units import length_text
from ..sim.video import BEND_COLOURS, GREY, RED, Tube, bend_colours, render_frames, wear_colours, write_video

VIDEO_FPS = 30.0
VIDEO_SIZE = 512
COLOURINGS = ("bend", "wear")
FRAME_PROGRESS: ContextVar[Callable[[int, int], None] | None] = ContextVar("rswarp_frame_progress", default=None)
FRAME_RATE: ContextVar[float] = ContextVar("rswarp_video_frame_rate", default=VIDEO_FPS)


@contextlib.contextmanager
def frame_rate(fps: float):
    """Within the block, videos show ``fps`` frames a second of the run's time (at most the run's
    own frame rate)."""
    token = FRAME_RATE.set(float(fps))
    try:
        yield
    finally:
        FRAME_RATE.reset(token)


@contextlib.contextmanager
def frame_progress(progress: Callable[[int, int], None] | None):
    """Within the block, videos report their frames to ``progress(done, total)`` unless their
    caller passes its own."""
    token = FRAME_PROGRESS.set(progress)
    try:
        yield
    finally:
        FRAME_PROGRESS.reset(token)


def time_caption(t: float) -> str:
    return f"t = {t:.2f} s"


def move_captions(times: np.ndarray, moves: Sequence) -> list[str]:
    """For each time (s), the move under way then as ``file:line  instruction target`` (a RAPID
    plan's ``moves``: each with ``start``, ``end``, ``target`` and ``motion.file``, ``.line``,
    ``.instruction``): the first whose end is past the time, else the last; a move of no duration
    is never under way."""
    if not moves:
        return ["" for _ in times]
    ends = np.array([m.end for m in moves], float)
    out = []
    for t in np.asarray(times, float):
        m = moves[min(int(np.searchsorted(ends, t, side="right")), len(moves) - 1)]
        out.append(f"{Path(m.motion.file).name}:{m.motion.line}  {m.motion.instruction} {m.target}".rstrip())
    return out


def captions(times: np.ndarray, moves: Sequence | None = None) -> list[str]:
    """Each frame's text: its time, and under it the program's line when there are ``moves``."""
    lines = move_captions(times, moves) if moves is not None else None
    return [time_caption(t) + ("" if lines is None else "\n" + lines[k]) for k, t in enumerate(times)]


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
                size: int = VIDEO_SIZE, moves: Sequence | None = None,
                progress: Callable[[int, int], None] | None = None, label: str | None = None) -> dict:
    """Environment ``env`` (default: the worst) of a cable run again, its shapes kept, rendered on
    the run's floor (none: under the robot). ``moves``: the RAPID plan's moves the trajectory
    came from (``plan.moves``), for each frame's program line; ``progress(done, total)`` counts
    frames (default ``FRAME_PROGRESS``'s); ``label``: the legend's name for what is shown (default
    "environment K"). ``mech`` is the robot and hose the run simulated (a design's, for a sweep's
    design)."""
    from ..sim.cables import simulate_cables

    if colouring not in COLOURINGS:
        raise InputError(f"--video-color must be one of {', '.join(COLOURINGS)}")
    envs = run.envs
    env = worst_environment(run, colouring) if env is None else env
    if not 0 <= env < envs:
        raise InputError(f"--video-env must be 0 to {envs - 1}")
    options = dataclasses.replace(run.options, record=0)
    again = simulate_cables(mech, [trajectories[run.assignment[env]]], 1, float(run.times[-1]), options)
    step = max(1, int(round(options.frame_rate / FRAME_RATE.get())))
    stride = again.cables[0].stride  # the hose's shapes are kept every stride-th frame, the joints every frame
    keep = max(1, step // stride)
    tubes, legend = [], []
    for k, c in enumerate(again.cables):
        pts = c.recorded[::keep]
        if colouring == "wear":
            colours = wear_colours(run.cables[k].wear[env].sum(axis=1), len(pts))
            legend = [(GREY, "no wear"), ((0.55, 0.05, 0.05), "most wear (Archard)")]
        else:
            colours = bend_colours(pts, c.allowed_bend_radius)
            legend = [(BEND_COLOURS[0], f"bend radius >= {length_text(c.allowed_bend_radius, *_unit(mech))}"),
                      (BEND_COLOURS[1], "tighter than allowed"), (BEND_COLOURS[2], "tighter than half of it")]
        tubes.append(Tube(pts, colours, c.radius))
    rows = np.arange(0, len(again.q), keep * stride)  # the frames whose shapes were kept
    n = min(len(rows), *(len(t.points) for t in tubes))
    rows = rows[:n]
    poses = Kinematics(mech).fk64(again.q[rows])
    base = trajectories[run.assignment[env]].base_at(again.times[rows])
    if base is not None:  # the robot carried along its track, as the hose was run
        poses[..., :3, 3] += base[:, None, :]
    tubes = [Tube(t.points[:n], t.colours[:n], t.radius) for t in tubes]
    frames = render_frames(mech, poses, tubes, size, legend=[(GREY, label or f"environment {env}"), *legend],
                           captions=captions(again.times[rows], moves), floor=options.floor, length=_unit(mech),
                           tool=options.tool,
                           progress=progress if progress is not None else FRAME_PROGRESS.get())
    return {**_saved(path, frames, options.frame_rate / (keep * stride)), "environment": env, "colour": colouring}


def program_video(mech, plan, tally, names, path: str, size: int = VIDEO_SIZE, floor: float | None = None,
                  tool=None, progress: Callable[[int, int], None] | None = None, cell=None) -> dict:
    """A program's motion at ``FRAME_RATE`` (``VIDEO_FPS``), the links of a colliding pair red while they touch,
    each frame with its time and the move under way (file:line and instruction), on a floor grid
    at ``floor`` (m; None: under the robot). ``progress(done, total)`` counts frames (default
    ``FRAME_PROGRESS``'s). With a ``cell`` the whole cell, in the world: the robot where its
    carrier puts it, the units' links where the external axes put them, its meshes."""
    fps = FRAME_RATE.get()
    times = np.arange(0.0, float(plan.times[-1]) + 1e-9, 1.0 / fps)
    rows = np.clip(np.searchsorted(plan.times, times), 0, len(plan.times) - 1)
    poses = Kinematics(mech).fk64(plan.q[rows])
    extra = ()
    if cell is not None:
        from ..motion.cells import cell_bodies

        poses, extra = cell_bodies(cell, plan, rows, poses)
    marked = []
    for r in rows:
        hit = tally.hit[r] if tally.hit.shape[1] else np.zeros(0, bool)
        marked.append({n for k in np.nonzero(hit)[0] for n in names[k]})
    frames = render_frames(mech, poses, [], size, marked=marked,
                           legend=[(GREY, f"{Path(plan.run.files[0]).stem}.{plan.run.routine}"), (RED, "in collision")],
                           captions=captions(times, plan.moves), floor=floor, length=_unit(mech), tool=tool,
                           progress=progress if progress is not None else FRAME_PROGRESS.get(), extra=extra)
    return _saved(path, frames, fps)


def _unit(mech) -> tuple[float, str]:
    return mech.length_factor, mech.length_unit or "m"
