"""``rswarp place ROBOT_OR_CELL PROGRAM... --vary ... --out DIR``: the task run once for its poses,
every candidate base solved against every pose in one batch, the bases that reach them all checked
for collisions at each pose, the best ``--top`` (by their singularity margin) run through the whole
program as ``rswarp program`` runs it and ordered by cycle time; ``best.toml`` the fastest that runs
clean. The figures a designer reads, and the files (``files``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...config import BatchOptions, PlaceOptions, TaskOptions, routed
from ...errors import InputError, RsxmlError
from ...findings import FAIL
from ...kinematics.kinematics import Kinematics
from ...motion.cells import is_cell, robot_of
from ...motion.plan import checked_cycles, plan_on
from ...outputs import atomic_folder, check_replaceable
from ...sim.engine import cluster_for, run_batch
from ...transforms import matrix_euler_zyx
from ..output import Output, Warn, ignore, json_safe
from .candidates import base_frames, candidates, parse_vary
from .clear import Clearance
from .files import candidates_csv, cell_toml, limiting_csv, map_png
from .job import PlaceJob
from .poses import program_poses


@dataclass(frozen=True)
class Timed:
    """A base run through the whole program: its candidate, cycle time (s; None where it did not
    run clean), the failing findings and the errors."""

    index: int
    cycle_s: float | None
    fails: int
    errors: int


def run_place(path: str, programs: list[str], task: TaskOptions | None = None, batch: BatchOptions | None = None,
              place: PlaceOptions | None = None, *, out: str = "rswarp-place", progress=None, warn: Warn = ignore,
              **changes) -> Output:
    """``rswarp place``: the bases ``place`` varies, each scored over every pose of the task in
    ``programs`` on the robot or cell at ``path``; the files written into ``out``."""
    o = routed(changes, task=task or TaskOptions(), batch=batch or BatchOptions(), place=place or PlaceOptions())
    task, batch, place = checked_cycles(o["task"]), o["batch"], o["place"]
    varies = parse_vary(place.vary)  # every option checked before any work
    check_replaceable(Path(out))
    mech, cell = robot_of(path)
    _placeable(path, cell)
    now = _placed_frame(mech, cell)
    current = np.array([*(now[:3, 3] * 1000.0), math.degrees(matrix_euler_zyx(now[:3, :3])[2])])
    tilt = tuple(math.degrees(a) for a in matrix_euler_zyx(now[:3, :3])[:2])
    values = candidates(varies, place.samples, current, batch.seed)
    meshes, tool, clearance = _checker(mech, cell, task, batch.device)  # the meshes and the tool loaded first
    _, plan = plan_on(mech, cell, programs, task, device=batch.device, warn=warn, strict=False)
    poses = program_poses(plan, mech, now, _mounts(cell, plan))
    job = PlaceJob(base_frames(values, tilt), poses, meshes, tool, cell.robot.rsxml if cell is not None else mech.path)
    tally = run_batch(job, mech, tools=(Kinematics(mech, batch.device), clearance), device=batch.device,
                      cluster=cluster_for(batch.ray, batch.device), progress=progress)
    found, clear = tally.reach, tally.clear
    feasible = (found.reached == len(poses.world)) & clear.free
    order = sorted(np.flatnonzero(feasible), key=lambda k: (-found.score[k], k))[:place.top]
    with atomic_folder(out) as tmp:
        timed = [_timed(path, programs, task, batch, tmp, rank, k, values[k], tilt) for rank, k in enumerate(order, 1)]
        now_run = _run(path, programs, task, batch, -1)  # the current base, as it stands
        best = _best(timed)
        if best is not None:
            (tmp / "best.toml").write_bytes((tmp / f"rank-{order.index(best.index) + 1}.toml").read_bytes())
        cycles = {t.index: t.cycle_s for t in timed}
        (tmp / "candidates.csv").write_text(candidates_csv(values, found.reached, len(poses.world), feasible,
                                                           found.singular, cycles))
        (tmp / "limiting.csv").write_text(limiting_csv(poses, found.ruled_out, found.beyond, clear.hits, clear.pair))
        share = found.reached / len(poses.world)
        (tmp / "map.png").write_bytes(map_png(values, share, poses.tcp, None if best is None else best.index,
                                              current, f"{mech.name}: where it reaches the program's poses"))
    doc = _document(path, out, values, poses, found, feasible, timed, best, now_run, current)
    return Output(json_safe(doc), place_text(doc), 0 if best is not None else 1)


def _placed_frame(mech, cell) -> np.ndarray:
    """The frame a candidate replaces, where it is now: the robot's base (its RSXML BaseFrame, or a
    cell's ``[robot] frame``), or, where a unit carries the robot, that unit's ``frame``."""
    if cell is None:
        return mech.base_frame.matrix() if mech.base_frame else np.eye(4)
    return cell.carrier.frame if cell.carrier is not None else cell.robot.frame


def _mounts(cell, plan):
    """Where a unit carries the robot: row -> its base in the carrier's frame at that row of the
    plan (a track's carriage where the move put it); None for a robot on the floor."""
    if cell is None or cell.carrier is None:
        return None
    from ...kinematics.cell import CellKinematics

    ck = CellKinematics(cell)
    frame = np.linalg.inv(cell.carrier.frame)
    return lambda row: frame @ ck.robot_base(ck.split(plan.ext[row:row + 1]))[0]


def _placeable(path: str, cell) -> None:
    """An InputError for a cell whose robot is not placed by its own frame (yet)."""
    if cell is None:
        return
    if cell.team:
        raise InputError(f"{path}: a MultiMove cell: place one robot, in a cell of its own")
    if cell.carrier is not None and cell.robot.on is None:
        raise InputError(f"{path}: the robot rides a unit the cell file does not name")


def _checker(mech, cell, task, device) -> tuple:
    """(the meshes checked at every pose, the tool, their checkers with the robot's): the cell's
    meshes that stand still and ``--env``'s, the cell's ``[tool]`` or ``--tool``; a mesh that does
    not load stops here, before any work."""
    from ...motion.cells import tool_spec
    from ...rsxml.cell import CellMesh
    from ...sim.bodies import placed_environments
    from ...sim.tool import load_tool

    meshes = tuple(m for m in (cell.environment if cell is not None else ()) if m.on is None)
    meshes += tuple(CellMesh(e.name, e.path, e.pose) for e in placed_environments(mech, task.environment))
    tool = load_tool(mech, tool_spec(cell, task.tool))
    rsxml = cell.robot.rsxml if cell is not None else mech.path
    return meshes, tool, Clearance(mech, meshes, tool, device, rsxml)


def _timed(path, programs, task, batch, folder: Path, rank: int, k: int, value: np.ndarray, tilt) -> Timed:
    """Candidate ``k`` written as ``rank-R.toml`` and run through the whole program."""
    frame = [float(round(v, 6)) + 0.0 for v in (*value[:3], *tilt, value[3])]  # + 0.0: no -0.0 in the file
    name = folder / f"rank-{rank}.toml"
    # the folder is written beside the output folder it becomes: its paths hold in both
    name.write_text(cell_toml(path, is_cell(path), frame, folder,
                              f"rswarp place: candidate {k}, rank {rank} by its singularity margin"))
    return _run(str(name), programs, task, batch, k)


def _run(cell: str, programs, task, batch, k: int) -> Timed:
    """The cycle time of one placement, as ``rswarp program`` gives it (None where it errs)."""
    from ..program import run_program

    try:
        result = run_program(cell, programs, task, batch)
    except RsxmlError:
        return Timed(k, None, 0, 1)
    doc = result.doc
    fails = sum(1 for m in doc["moves"] for f in m["findings"] if f.get("severity") == FAIL)
    clean = result.code == 0 and not doc["errors"] and not fails
    return Timed(k, doc["cycle_s"] if clean else None, fails, len(doc["errors"]))


def _best(timed: list[Timed]) -> Timed | None:
    clean = [t for t in timed if t.cycle_s is not None]
    return min(clean, key=lambda t: (t.cycle_s, t.index)) if clean else None


def _document(path, out, values, poses, found, feasible, timed, best, now_run, current) -> dict:
    """The placement as data: the counts, the bases timed, the best against the current one."""
    every = int((found.reached == len(poses.world)).sum())
    row = lambda k: {"x_mm": values[k, 0], "y_mm": values[k, 1], "z_mm": values[k, 2], "yaw_deg": values[k, 3]}  # noqa: E731
    return {"path": path, "out": out, "candidates": len(values), "poses": len(poses.world), "moves": poses.moves,
            "reach_every_pose": every, "feasible": int(feasible.sum()), "conf_rules_out": int(found.conf_missed.sum()),
            "timed": [row(t.index) | {"cycle_s": t.cycle_s, "fails": t.fails, "errors": t.errors} for t in timed],
            "best": None if best is None else row(best.index) | {"cycle_s": best.cycle_s},
            "current": {"x_mm": current[0], "y_mm": current[1], "z_mm": current[2], "yaw_deg": current[3],
                        "cycle_s": now_run.cycle_s}}


def place_text(doc: dict) -> str:
    """What a cell designer reads: how many bases reach every pose, the bases timed, the best."""
    lines = [f"{doc['path']}: {doc['candidates']} bases tried against {doc['poses']} poses of {doc['moves']} moves; "
             f"{doc['reach_every_pose']} reach every pose, {doc['feasible']} of them free of collisions"]
    for t in doc["timed"]:
        said = f"{t['cycle_s']:.2f} s" if t["cycle_s"] is not None else \
            f"does not run clean ({t['errors']} errors, {t['fails']} failing findings)"
        lines.append(f"  base x {t['x_mm']:.0f} mm, y {t['y_mm']:.0f} mm, z {t['z_mm']:.0f} mm, yaw {t['yaw_deg']:.1f} "
                     f"deg: {said}")
    b, c = doc["best"], doc["current"]
    now = f"{c['cycle_s']:.2f} s" if c["cycle_s"] is not None else "does not run clean"
    if b is None:
        lines.append(f"best: none of the bases tried runs the program clean (the current base: {now})")
    else:
        change = 100.0 * (b["cycle_s"] / c["cycle_s"] - 1.0) if c["cycle_s"] else None
        vs = "" if change is None else ", the same to 0.1 %" if abs(change) < 0.05 else f", {change:+.1f} %"
        lines.append(f"best: x {b['x_mm']:.0f} mm, y {b['y_mm']:.0f} mm, z {b['z_mm']:.0f} mm, "
                     f"yaw {b['yaw_deg']:.1f} deg, cycle {b['cycle_s']:.2f} s against the current base's "
                     f"{now}{vs} -> {doc['out']}/best.toml")
    if doc["conf_rules_out"]:
        lines.append(f"confdata: {doc['conf_rules_out']} bases reach some pose only in another configuration than "
                     "the program's (ConfJ/ConfL on): its confdata was taught where the robot stands now")
    lines.append(f"files: {doc['out']}/candidates.csv, limiting.csv, map.png")
    return "\n".join(lines)


def place(path: str, programs, task: TaskOptions | None = None, batch: BatchOptions | None = None,
          place: PlaceOptions | None = None, *, out: str = "rswarp-place", **changes) -> dict:
    """``rswarp.place``: ``run_place`` from Python; the placement as data (``--json``'s), the files
    in ``out``; keywords are the options' fields (``vary=("x=-500:500:11",)``, ``top=4``)."""
    return run_place(path, [programs] if isinstance(programs, (str, Path)) else list(programs), task, batch, place,
                     out=str(out), **changes).doc
