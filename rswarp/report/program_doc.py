"""The document of one robot's ``rswarp program`` run (SI): its moves with their findings, limits,
speeds and targets, the loads it carries, its warnings and errors, as ``--json`` writes it and the
text is made from. A MultiMove report holds one per robot."""

from __future__ import annotations

import numpy as np

from ..kinematics.kinematics import Kinematics
from ..motion import timing
from ..motion.cells import external_values
from ..motion.payload import carried_loads, load_scale
from ..motion.planner import Plan
from ..motion.targets import joint_values
from ..motion.tcp import frames
from .findings import grouped, move_findings, skipped_finding, tool_findings


def program_document(mech, p: Plan, tally, names, checked, csv, floor: float = 0.0, tools=None, tool=None,
              payload=None, speeds=None) -> dict:
    """The run as data (SI): its moves with their findings as records (a target it could not take
    among them) and their speeds (``motion.speeds``), every finding once per move line, kind and
    links, counted, in time order, and the loads the moves carry with what each does to the
    accelerations."""
    run = p.run
    kin = Kinematics(mech)
    ends = _move_ends(kin, p)
    moves = [_move(mech, p, m, tally, names, floor, ends[k] + (_target_m(kin, m.motion, p, m.rows[1] - 1),), tools)
             for k, m in enumerate(p.moves)]
    scale, made = load_scale(mech, payload), {}
    for k, (said, move) in enumerate(zip(moves, p.moves)):  # limits made once per setting a move runs under
        if speeds is not None:
            said["tcp_speed"], said["limited_by"] = speeds.record(k)
        m = move.motion
        key = (m.kind == "wait", m.override, m.accel, m.ramp, m.held_loads)
        if key not in made:
            made[key] = _move_limits(p.limits, m, scale)
        if made[key] is not None:
            said["limits"] = made[key]
    for f in tool_findings(p, tool):  # the tooldata against the tool, at the first move that used it
        next(m for m in moves if (m["file"], m["line"]) == (f.file, f.line))["findings"].append(f.record())
    found = grouped([(f, m) for m in moves for f in m["findings"]])
    cycle = run.cycle
    return {"robot": mech.name, "files": list(run.files), "routine": run.routine,
            "duration_s": float(p.times[-1]), "cycle_s": p.cycle_s, "cycles_s": list(p.cycles),
            "cycle_pass": None if p.cycle_pass is None else p.cycle_pass + 1, "into_next_pass_s": p.into_next,
            "main_loop": f"{cycle.file}:{cycle.line}" if cycle is not None and cycle.endless else None,
            "samples": len(p.times), "statements": run.statements, "axis_limits": _limits_dict(p.limits),
            "targets": [{"name": t.name, "file": t.file, "line": t.line, "joints": t.joints, "conf": t.conf,
                         "limit_margin": t.limit_margin, "reach_margin_m": t.reach_margin,
                         "ignored": t.ignored} for t in p.targets],
            "tool": None if tool is None else {"name": tool.name, "given": tool.source},
            "external_axes": {axis or f"{unit}.{joint}": "rotational" if revolute else "linear"
                              for axis, unit, joint, revolute in p.ext_axes},
            "loads": carried_loads(mech, p, payload),
            "moves": moves, "findings": found,
            "warnings": [str(w) for w in run.warnings], "errors": [str(e) for e in p.errors], "csv": csv,
            "speed_plot": None,
            "stopped": str(run.stopped) if run.stopped is not None else None, "needs_input": run.needs_input,
            "error": _run_error(run), "assumed": _assumed(run, moves),
            "collision_pairs_checked": [list(n) for n, c in zip(names, [] if checked is None else checked) if c]}


def _run_error(run) -> dict | None:
    """The run-time error the task stopped at (every move before it planned, timed and checked):
    its line and the calls that led there; None where it ran to its end."""
    e = run.error
    return None if e is None else {"file": e.file, "line": e.line, "message": e.message, "text": str(e),
                                   "chain": list(run.error_chain)}


def _assumed(run, moves: list[dict]) -> list[dict]:
    """``--assume-missing``'s stand-ins, each once: its name, type, value, the line that first uses
    it; and each move (and its findings) that uses one says which."""
    from ..rapid.interpret import STAND_IN

    at: dict = {}
    for a in run.assumed:
        for use in a.uses:
            at.setdefault(use, []).append(a.name)
    for m in moves:
        names = sorted(at.get((m["file"], m["line"]), ()))
        if names:
            m["assumed"] = names
            for f in m["findings"]:
                f["assumed"] = names
    return [{"name": a.name, "type": a.type, "value": STAND_IN.get(a.type, "0"), "file": a.file, "line": a.line,
             "uses": len(a.uses)} for a in sorted(run.assumed, key=lambda a: (a.file, a.line, a.name))]


def _move_limits(limits, motion, scale) -> dict | None:
    """A move's own axis limits (SI) where VelSet, AccSet or the load it carries make them differ
    from the robot's (``axis_limits``); None where they do not, or for a wait."""
    if motion.kind == "wait" or limits is None:
        return None
    factor = scale(*motion.held_loads) if scale is not None else None
    if factor is not None:  # a cell's external axes after the robot's
        factor = timing.widened(factor, len(limits.velocity))
    v, a, j = timing.move_limits([motion], limits, None if factor is None else factor[None])
    if np.array_equal(v[0], limits.velocity) and np.array_equal(a[0], limits.acceleration) and \
            np.array_equal(j[0], limits.jerks()):
        return None
    return {"velocity": v[0], "acceleration": a[0], "jerk": j[0]}


def _limits_dict(limits) -> dict:
    """The axis limits the timing used (SI), where they come from, and that line in words; ``axes``
    per axis with each quantity's source and which are estimates, so a move's time can be redone."""
    return {"source": limits.source, "assumed": limits.assumed, "accelerations_assumed": limits.accel_assumed,
            "velocity": limits.velocity, "acceleration": limits.acceleration, "jerk": limits.jerks(),
            "axes": limits.rows(), "summary": limits.summary()}


def _move_ends(kin, p: Plan) -> list:
    """Each move's end: its joints, and its TCP in its work object (m), or None."""
    out = []
    for m in p.moves:
        row = m.rows[1] - 1
        mo = m.motion
        if m.error or mo.kind == "wait" or mo.tool is None:
            out.append((p.q[row] if m.error is None else None, None, None))
            continue
        fr = frames(kin.mech, mo.tool, mo.wobj) if p.framer is None else p.framer(mo.tool, mo.wobj, p.ext[row])
        link, offset = kin.flange_frame()
        flange = kin.fk64(p.q[row][None])[:, link] @ offset
        out.append((p.q[row], fr.relative(flange)[0, :3, 3], fr.world(flange)[0, :3, 3]))
    return out


def _move(mech, p: Plan, move, tally, names, floor: float, end, tools) -> dict:
    m = move.motion
    out = {"file": m.file, "line": m.line, "routine": m.routine, "chain": list(m.chain), "instruction": m.instruction,
           "kind": m.kind, "target": move.target, "start_s": move.start, "end_s": move.end, "cycle": m.cycle,
           "joints": end[0], "tcp_m": end[1], "tcp_world_m": end[2], "target_m": end[3],
           "external_axes": external_values(p, None if move.error else move.rows[1] - 1),
           "target_extax": list(m.targets[-1].extax) if p.ext is not None and m.targets else None,
           "declared": (m.declared[-1].removeprefix("set ") or None) if m.declared else None,
           "findings": [f.record() for f in move_findings(mech, p, move, tally, names, floor, tools)]}
    if move.error:
        out["error"] = move.error
        out["findings"].append(skipped_finding(move).record())
    return out


def _target_m(kin, m, p: Plan, row: int) -> list[float] | None:
    """A move's target as resolved: a robtarget's position in the move's work object (m), or where
    a jointtarget puts the TCP in it (in a cell, with the external axes where the move leaves
    them); None for a wait or a jointtarget the robot cannot take."""
    if m.kind == "wait" or not m.targets:
        return None
    if m.kind != "absolute":
        return [float(v) for v in m.targets[-1].pose.trans]
    q, why = joint_values(kin.mech, m.targets[0], m.names[0])
    if q is None or why is not None or m.tool is None:
        return None
    try:
        fr = frames(kin.mech, m.tool, m.wobj) if p.framer is None else p.framer(m.tool, m.wobj, p.ext[row])
    except ValueError:
        return None
    link, offset = kin.flange_frame()
    return [float(v) for v in fr.relative(kin.fk64(q[None])[:, link] @ offset)[0, :3, 3]]
