"""``rswarp program`` on a MultiMove cell (``[[robot]]``, once for each): every robot runs its own
motion task of the backup given, each planned alone on its robot, then put on one clock where the
tasks meet (``motion.multimove``: ``WaitSyncTask``, ``SyncMoveOn``/``Off``, the ``\\ID`` moves),
each checked as one robot's program is (its own links, its units, the cell's meshes), and the robots
checked against each other. One report: a table per robot, the meetings, the robots' clashes."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..config import BatchOptions, TaskOptions
from ..errors import InputError
from ..kinematics.kinematics import Kinematics
from ..motion.cells import cell_floor, with_cell_pairs, with_meshes
from ..motion.multimove import clashes, together
from ..motion.payload import load_scale
from ..motion.plan import plan_on
from ..motion.speeds import plan_speeds
from ..rapid.instructions import RUN_ALONE
from ..rapid.task import backup_tasks
from ..sim.program_check import check_program
from ..sim.tool import load_tool
from .output import Output, Warn, ignore, json_safe
from .program_doc import program_document
from .program_text import program_body

ONE_ROBOT = "give --task NAME to run one robot's task with it"


def member(cell, name: str):
    """The robot of a MultiMove ``cell`` whose task or name is ``name`` (``--task T_ROB2``), as a
    cell of its own; an InputError naming the robots where none is."""
    for c in cell.team:
        if name.strip().lower() in (c.robot.task.lower(), c.robot.name.lower()):
            return c
    have = ", ".join(f"{c.robot.name} ({c.robot.task})" for c in cell.team)
    raise InputError(f"{cell.path}: --task {name}: no robot of the cell runs it (its robots: {have})")


def refused(task: TaskOptions, csv, speed_plot, video) -> None:
    """An InputError for an option that is one robot's, given for the whole team."""
    for given, option in ((csv, "--csv"), (speed_plot, "--speed-plot"), (video, "--video"),
                          (task.tool, "--tool"), (task.payload, "--payload")):
        if given is not None:
            raise InputError(f"{option} is one robot's, and the cell has several: {ONE_ROBOT}")


def run_team(cell, programs: list[str], task: TaskOptions, batch: BatchOptions, disabled, floor: float | None,
             env, *, progress=None, warn: Warn = ignore) -> Output:
    """Every robot of ``cell`` on its task of the backup in ``programs``, on one clock, checked
    alone and against each other; ``floor`` (m, world) and ``env`` (``--env`` meshes, in the cell's
    world) as ``run_program`` takes them."""
    from ..sim.engine import cluster_for

    _tasks_there(cell, programs)
    for w in cell.warnings:
        warn(w)

    def said(w: str) -> None:  # run together here: the one-task note on meeting points is not this run's
        if RUN_ALONE not in w:
            warn(w)

    plans = [plan_on(c.robot.mechanism, replace(c, warnings=()), programs, replace(task, motion_task=c.robot.task),
                     device=batch.device, warn=said, strict=False)[1] for c in cell.team]
    names = [c.robot.name for c in cell.team]
    if any(p.errors for p in plans):  # a target a robot cannot take: no common clock, every error said
        docs = [_robot_doc(c, p, None, [], None, floor) for c, p in zip(cell.team, plans)]
        errors = tuple(str(d) for p in plans for d in p.errors)
        doc = _team_doc(cell, names, docs, None, (), ())
        return Output(json_safe(doc), team_text(doc), 1, errors)
    t = together(names, plans)
    mounted = load_tool(cell.robot.mechanism, cell.tool.spec(cell.robot.mechanism)) if cell.tool else None
    cluster = cluster_for(batch.ray, batch.device)
    docs = []
    for k, (c, p) in enumerate(zip(cell.team, t.plans)):
        tool = mounted if k == 0 else None
        mech = c.robot.mechanism
        tally, tools, tested = check_program(mech, p.q, (), disabled(mech), batch.device, cluster=cluster,
                                             progress=progress, tool=tool)
        pairs = tools.checker.bodies.pair_names() if tools.checker is not None else []
        here = with_meshes(c, env) if env else c
        tally, pairs, tested = with_cell_pairs(here, p, tally, pairs, tested, tool, batch.device)
        speeds = _Clocked(plan_speeds(Kinematics(mech), plans[k], load_scale(mech, None)), plans[k], p,
                          _slower(names, plans, k))
        docs.append(_robot_doc(c, p, tally, pairs, tested, floor, tools, tool, speeds))
    met = clashes(cell.team, t, batch.device, mounted)
    doc = _team_doc(cell, names, docs, t, t.meetings, met)
    errors = tuple(str(p.run.error) for p in plans if p.run.error is not None)
    return Output(json_safe(doc), team_text(doc), 1 if errors else 0, errors)


def _tasks_there(cell, programs) -> None:
    """Each robot's task is a task folder of the backup given; an InputError where not."""
    have = backup_tasks(programs)
    if not have:
        raise InputError(f"{cell.path}: a cell of {len(cell.team)} robots runs each robot's task of a backup (its "
                         f"RAPID/{cell.team[0].robot.task}, ...): give the backup's folder, or {ONE_ROBOT}")
    for c in cell.team:
        if c.robot.task.lower() not in (h.lower() for h in have):
            raise InputError(f"{cell.path}:{c.robot.line}: {c.robot.name} runs the task {c.robot.task}, which the "
                             f"backup lacks (it has {', '.join(have)}): give [[robot]] task = \"...\"")


def _robot_doc(c, p, tally, pairs, tested, floor, tools=None, tool=None, speeds=None) -> dict:
    """One robot's part of the report: the one-robot program's document, with its name, its task
    and, on the common clock, when its last move ends and how long it waits at the meetings."""
    mech = c.robot.mechanism
    below = -np.inf if floor is None else floor - cell_floor(c)
    doc = program_document(mech, p, tally, pairs, tested, None, below, tools, tool, None, speeds)
    moving = [m for m in p.moves if m.motion.kind != "wait"]
    # one robot's cycle is not the cell's: the cell's is the team's duration, on the common clock
    return {"name": c.robot.name, "task": c.robot.task} | doc | \
        {"last_move_end_s": max((m.end for m in moving), default=0.0), "cycle_s": None, "cycles_s": [],
         "cycle_pass": None}


def _slower(names, plans, k: int) -> dict[int, tuple[str, ...]]:
    """Robot ``k``'s synchronized moves (by index) -> the robots whose same move, planned alone,
    takes longest: the time all of them take on the common clock."""
    spans: dict[float, dict[str, float]] = {}
    for name, p in zip(names, plans):
        for m in p.moves:
            if m.motion.sync_id is not None:
                spans.setdefault(m.motion.sync_id, {})[name] = m.end - m.start
    out = {}
    for i, m in enumerate(plans[k].moves):
        if m.motion.sync_id is not None:
            took = spans[m.motion.sync_id]
            out[i] = tuple(n for n, v in took.items() if v >= max(took.values()) - 1e-9)
    return out


class _Clocked:
    """A robot's TCP speeds (``motion.speeds``) found on its plan alone, where the axes' limits
    hold, said on the common clock: a move's times moved to where it runs there, and a synchronized
    move another robot slows (evenly, to its own time) at the slower speed, held by that robot."""

    def __init__(self, speeds, alone, clocked, slower: dict[int, tuple[str, ...]]):
        self.speeds, self.alone, self.clocked, self.slower = speeds, alone, clocked, slower

    def record(self, k: int) -> tuple[dict | None, dict]:
        tcp, held = self.speeds.record(k)
        a, c = self.alone.moves[k], self.clocked.moves[k]
        own, span = a.end - a.start, c.end - c.start
        if tcp is None:
            return tcp, held
        tcp = dict(tcp, least_at_s=c.start + tcp["least_at_share"] * span)
        if span > own * (1 + 1e-6) + 1e-9 and k in self.slower:
            r = own / span  # the move's own profile, slowed evenly: every speed times r
            tcp = dict(tcp, mean_m_s=tcp["mean_m_s"] * r, least_m_s=tcp["least_m_s"] * r)
            held = {"limit": "synchronized", "ident": f"\\ID:={c.motion.sync_id:g}", "robots": list(self.slower[k]),
                    "ratio": 1.0, "alone": held}
        return tcp, held


def _team_doc(cell, names, docs, t, meetings, met) -> dict:
    """The team's report as data (SI): the robots' documents, the meetings and the clashes."""
    return {"cell": cell.path, "robots": docs, "duration_s": None if t is None else t.duration,
            "cycle_s": None if t is None else t.duration,
            "meetings": [{"ident": m.ident, "kind": m.kind, "time_s": m.time,
                          "waited_s": dict(zip(names, m.waited))} for m in meetings],
            "clashes": [{"first": c.first, "second": c.second, "time_s": c.time, "span_s": c.span} for c in met],
            "warnings": sorted({w for d in docs for w in d["warnings"]}),
            "errors": [e for d in docs for e in d["errors"]]}


KINDS = {"wait": "WaitSyncTask", "on": "SyncMoveOn", "off": "SyncMoveOff"}


def team_text(doc: dict) -> str:
    """What a programmer reads: each robot's table, then where the tasks met and what clashed."""
    robots = doc["robots"]
    lines = [f"{doc['cell']}: {len(robots)} robots (MultiMove)" +
             ("" if doc["duration_s"] is None else f", {doc['duration_s']:.2f} s in all, on one clock")]
    for r in robots:
        moves = sum(1 for m in r["moves"] if m["kind"] != "wait")
        lines += ["", f"{r['name']} ({r['task']}): {r['routine']}, {moves} move{'s' * (moves != 1)}, its last "
                      f"ending at {r['last_move_end_s']:.2f} s"]
        lines += program_body(r)
    meets = [m for m in doc["meetings"] if m["kind"] in KINDS]
    if meets:
        lines += ["", "meetings (each task waits there for the others):"]
        for m in meets:
            waits = ", ".join(f"{n} {w:.2f} s" for n, w in m["waited_s"].items() if w > 5e-4) or "none waited"
            lines.append(f"  {KINDS[m['kind']]} {m['ident']} at {m['time_s']:.2f} s: {waits}")
    synced = sorted({m["ident"] for m in doc["meetings"] if m["kind"] == "end"})
    if synced:
        lines.append(f"synchronized moves: {len(synced)} ({', '.join(synced)}), each at the slower robot's time")
    if doc["duration_s"] is not None:
        lines += [""] + _clash_lines(doc["clashes"])
    return "\n".join(lines)


def _clash_lines(met: list[dict]) -> list[str]:
    if not met:
        return ["robots against each other: no link of one meets a link of another"]
    out = [f"robots against each other: {len(met)} pair{'s' * (len(met) != 1)} of links meet"]
    out += [f"  {c['first']} and {c['second']}: from {c['time_s']:.2f} s, {c['span_s']:.2f} s in all" for c in met]
    return out
