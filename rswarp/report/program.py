"""``rswarp program``: a RAPID task run through the robot model. Its modules read and run as the
controller runs them (``rswarp.rapid``), planned (``motion.plan``: every target resolved, the
trajectory built and timed) and checked in one batch, a table of the moves with their findings, and
the trajectory as the CSV that ``rswarp cable --trajectory`` reads."""

from __future__ import annotations

import io as _io
import math
from dataclasses import replace
from pathlib import Path

from ..config import BatchOptions, TaskOptions, VideoOptions, routed
from ..errors import InputError
from ..files import atomic_write
from ..kinematics.kinematics import Kinematics
from ..motion.cells import (
    cell_floor,
    csv_columns,
    robot_of,
    tool_spec,
    with_cell_pairs,
    with_meshes,
)
from ..motion.payload import load_scale, read_payload
from ..motion.plan import checked_cycles, plan_on
from ..motion.planner import Plan
from ..motion.speeds import plan_speeds
from ..options import checked
from ..outputs import claim, record
from ..sim.bodies import placed_environments
from ..sim.program_check import check_program
from ..sim.tool import load_tool
from .multimove import member, refused, run_team
from .output import Output, Warn, ignore, json_safe
from .program_doc import program_document
from .program_text import program_text


def run_program(path: str, programs: list[str], task: TaskOptions | None = None, batch: BatchOptions | None = None,
                video: VideoOptions | None = None, *, csv: str | None = None, speed_plot: str | None = None,
                progress=None, warn: Warn = ignore, **changes) -> Output:
    """``rswarp program``: run, resolve, build, check and report; ``csv`` writes the trajectory,
    ``speed_plot`` a PNG of the TCP's speed over time; ``changes`` replace fields of the options
    (``cycles=3``, ``tool="gripper.stl"``). Targets the robot cannot take are all reported (exit 1),
    with the rest of the report."""
    from ..export.srdf import read_srdf
    from ..sim.engine import cluster_for

    o = routed(changes, task=task or TaskOptions(), batch=batch or BatchOptions(), video=video or VideoOptions())
    task, batch, video = o["task"], o["batch"], o["video"]
    _claim_outputs(csv, speed_plot, video.video)  # a file of the user's is never replaced: refused before any work
    robot, cell = robot_of(path)  # every option and input checked before any work
    task = checked_cycles(task)
    if cell is not None and cell.team and task.motion_task:  # one robot of a MultiMove cell
        cell = member(cell, task.motion_task)
        task = replace(task, motion_task=cell.robot.task)
    elif cell is not None and cell.team:
        return _team(cell, programs, task, batch, video, csv, speed_plot, progress, warn)
    tool = tool_spec(cell, task.tool)
    world_floor, floor = _floors(task, robot, cell)
    env = placed_environments(robot, task.environment)
    if cell is not None and env:  # --env meshes stand in the cell's world, checked with its own
        cell, env = with_meshes(cell, env), ()
    mounted = load_tool(robot, tool)
    load = read_payload(task.payload, robot) if isinstance(task.payload, str) else task.payload
    disabled = read_srdf(task.collision_matrix, robot.link_names) if task.collision_matrix else ()
    mech, p = plan_on(robot, cell, [programs] if isinstance(programs, str) else programs, replace(task, payload=load),
                      device=batch.device, warn=warn, strict=False)
    speeds = plan_speeds(Kinematics(mech), p, load_scale(mech, load))
    if p.errors:
        for given, option in ((csv, "--csv"), (speed_plot, "--speed-plot"), (video.video, "--video")):
            if given is not None:
                warn(f"{option}: nothing written, the task has targets the robot cannot take (below)")
        doc = program_document(mech, p, None, [], None, csv=None, payload=load, speeds=speeds)
        return Output(json_safe(doc), program_text(mech, doc), 1, tuple(str(d) for d in p.errors))
    tally, tools, tested = check_program(mech, p.q, env, disabled, batch.device,
                                         cluster=cluster_for(batch.ray, batch.device), progress=progress, tool=mounted)
    names = tools.checker.bodies.pair_names() if tools.checker is not None else []
    if cell is not None:  # the robot against the units' links and the cell's meshes, where the axes put them
        tally, names, tested = with_cell_pairs(cell, p, tally, names, tested, mounted, batch.device)
    _write_files(mech, p, csv, speed_plot, speeds)
    doc = program_document(mech, p, tally, names, tested, csv, floor, tools, mounted, load, speeds) | \
        {"speed_plot": speed_plot}
    if video.video is not None:
        from .videos import program_video

        doc["video"] = program_video(mech, p, tally, names, video.video, video.video_size, tool=mounted, cell=cell,
                                     floor=world_floor)
    if p.run.error is not None:  # the task stopped at a run-time error: reported whole, exit 1
        return Output(json_safe(doc), program_text(mech, doc), 1, (str(p.run.error),))
    return Output(json_safe(doc), program_text(mech, doc))


def _team(cell, programs, task, batch, video, csv, speed_plot, progress, warn) -> Output:
    """``run_program`` on a MultiMove cell: every robot on its task, on one clock."""
    from ..export.srdf import read_srdf

    refused(task, csv, speed_plot, video.video)
    robot = cell.robot.mechanism
    floor = None if task.floor is None else checked("floor", robot.si_length(task.floor))
    env = placed_environments(robot, task.environment)
    disabled = (lambda mech: read_srdf(task.collision_matrix, mech.link_names)) if task.collision_matrix else \
        (lambda mech: ())
    return run_team(cell, [programs] if isinstance(programs, str) else programs, task, batch, disabled, floor, env,
                    progress=progress, warn=warn)


def _floors(task: TaskOptions, robot, cell) -> tuple[float | None, float]:
    """(the floor's height in the world, m, or None; its height in the robot's frame): no floor,
    nothing is below it, and a video draws one under the robot."""
    if task.floor is None:
        return None, -math.inf
    world = checked("floor", robot.si_length(task.floor))
    return world, world - (cell_floor(cell) if cell is not None else 0.0)


def _claim_outputs(csv: str | None, speed_plot: str | None, video: str | None = None) -> None:
    """The CSV, the speed plot and the video, checked free to write before any work: named, each
    rswarp's or new, in a folder it can write in, a PNG for the plot, not one file for both."""
    if video is not None:
        from .videos import claim_video

        claim_video(video)
    for out, option in ((csv, "--csv"), (speed_plot, "--speed-plot")):
        if out is not None:
            if not str(out).strip():
                raise InputError(f"{option}: the file name is empty")
            claim(Path(out))
    if speed_plot is not None and Path(speed_plot).suffix.lower() != ".png":
        raise InputError(f"{speed_plot}: --speed-plot writes a PNG image: name a .png file")
    if csv is not None and speed_plot is not None and Path(csv).resolve() == Path(speed_plot).resolve():
        raise InputError(f"{csv}: --csv and --speed-plot name the same file")


def _write_files(mech, p: Plan, csv: str | None, speed_plot: str | None, speeds) -> None:
    """The trajectory's CSV and the TCP's speed plot, where asked for, each noted as rswarp's."""
    if csv is not None:
        atomic_write(csv, trajectory_csv(mech, p).encode())
        record(Path(csv).parent if str(Path(csv).parent) else Path("."), [Path(csv).name])
    if speed_plot is not None:
        from .speed_plot import write_speed_plot

        write_speed_plot(speed_plot, p, speeds, f"{mech.name}: {p.run.routine}, TCP speed")


def trajectory_csv(mech, p: Plan) -> str:
    """``time,<joints>`` in the file's units, one row per sample (what ``--trajectory`` reads); the time to
    the nanosecond, so its differences keep the samples' speeds and accelerations."""
    joints = mech.active_joints
    names, ext = csv_columns(p)
    buf = _io.StringIO()
    buf.write(",".join(["time"] + [j.name for j in joints] + names) + "\n")
    factors = [mech.joint_factor(j) for j in joints]
    for t, q, e in zip(p.times, p.q, ext):
        buf.write(",".join([f"{t:.9f}"] + [_fixed(v / f) for v, f in zip(q, factors)] + [_fixed(v) for v in e]) + "\n")
    return buf.getvalue()


def _fixed(v: float) -> str:
    """Six decimals of the file's unit (1e-6 deg or mm), trailing zeros off."""
    text = f"{v:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text
