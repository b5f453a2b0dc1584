"""``program_plan``: a RAPID task on a robot or a cell, from its module files to a timed plan. The
task is read (``rapid.task``) and run by the interpreter over the planner (``motion.planner``, or
``motion.cell_plan`` over a cell), which resolves, follows and times every move; the loads it
carries lower the accelerations (``motion.payload``). The public ``rswarp.program``."""

from __future__ import annotations

from pathlib import Path

from ..config import TaskOptions, routed
from ..errors import Diagnostic, InputError, RsxmlError, Warn, ignore
from ..kinematics.kinematics import Kinematics
from ..rapid.eio import add_configuration
from ..rapid.interpret import MAX_CYCLES, Interpreter
from ..rapid.task import load_task
from ..rsxml.robot_data import axis_limits, robot_data
from .cells import cell_planner, robot_of
from .payload import carried_loads, load_factors, load_scale, read_payload
from .planner import Planner


def program_plan(path: str, programs, task: TaskOptions | None = None, *, device: str = "cpu", warn: Warn = ignore,
                 strict: bool = True, **changes):
    """(mechanism, plan) of the RAPID task in ``programs`` (module files, folders, .pgf files) on
    the robot or cell at ``path``, run as ``task`` says (``TaskOptions``; ``changes`` replace its
    fields: ``routine="other"``, ``io={"diStart": 1}``); with ``strict`` an RsxmlError lists every
    target the robot cannot take. The payload is carried on top of each move's tool and GripLoad
    loads, which lower the accelerations (docs/payload-timing.md)."""
    task = checked_cycles(routed(changes, task=task or TaskOptions())["task"])
    mech, cell = robot_of(path)
    return plan_on(mech, cell, programs, task, device=device, warn=warn, strict=strict)


def checked_cycles(task: TaskOptions) -> TaskOptions:
    """``task``, its ``--cycles`` within what a run takes; an InputError where not."""
    if not 1 <= int(task.cycles) <= MAX_CYCLES:
        raise InputError(f"--cycles must be 1 to {MAX_CYCLES}, not {task.cycles}")
    return task


def plan_on(mech, cell, programs, task: TaskOptions, *, device: str = "cpu", warn: Warn = ignore,
            strict: bool = True):
    """``program_plan`` on a robot (``mech``) or a cell already read (``cell``, its robot
    ``mech``; None for the robot alone): each robot of a MultiMove cell is planned so."""
    load = read_payload(task.payload, mech) if isinstance(task.payload, str) else task.payload
    name = task.motion_task or (cell.robot.task if cell is not None else None)  # a MultiMove robot's own task
    modules = load_task([programs] if isinstance(programs, (str, Path)) else list(programs), name)
    if cell is not None and cell.eio is not None:  # the cell's backup's signals, as its task folder's would be
        add_configuration(modules, cell.eio)
    limits, scale = axis_limits(mech, task.limits), load_scale(mech, load)
    if cell is not None:
        for w in cell.warnings:
            warn(w)
        planner = cell_planner(cell, device, task.external_axes, limits, scale)
    else:
        planner = Planner(Kinematics(mech, device), external_axes=task.external_axes, limits=limits, load_scale=scale)
    run = Interpreter(modules, planner, dict(task.io), int(task.cycles), {k: list(v) for k, v in task.inputs.items()},
                      task.assume_missing).run(task.routine, keep=True)
    plan = planner.finish(run)
    for w in (*run.warnings, *planner.notes):
        warn(str(w))
    carried = carried_loads(mech, plan, load)
    if carried and load_factors(mech).arm is None:
        warn(load_factors(mech).warning)
    _over_rated(mech, carried, warn)
    if run.stopped is not None:
        warn(str(run.stopped))
    if strict and (plan.errors or run.error is not None):
        raise RsxmlError([d for d in (run.error,) if d is not None] + list(plan.errors))
    return mech, plan


def _over_rated(mech, carried: list[dict], warn: Warn) -> None:
    """A warning for each load heavier than the robot data's rated payload: the timing takes it,
    the robot is not made for it."""
    data = robot_data(mech)
    rated = data.payload if data is not None else None
    for found in carried:
        if rated is not None and found["mass"] > rated * (1 + 1e-9):
            warn(f"{mech.path or mech.name}: warning: a load of {found['mass']:g} kg ({found['source']}) is over the "
                 f"robot's rated {rated:g} kg ({Path(data.path).name}): timed as given, beyond what the robot is "
                 "made to carry")


def moved_before_stop(plan) -> None:
    """An InputError where a task stopped for a live input before it made any move: a hose run
    or a design sweep over it would run over nothing; the stop line says what to give."""
    stopped = plan.run.stopped
    if stopped is not None and not float(plan.times[-1]) > 0:
        raise RsxmlError(Diagnostic(stopped.file, stopped.line, f"{stopped.message} (the task stops before its first "
                                                                "move: nothing to run the hoses over)"))


