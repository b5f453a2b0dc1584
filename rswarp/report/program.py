"""``rswarp program``: a RAPID routine run through the robot model. Every target resolved (joints,
configuration, margins), the trajectory built and checked in one batch, a table of the moves with
their findings, and the trajectory as the CSV that ``rswarp cable --trajectory`` reads."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from ..files import atomic_write
from ..kinematics.kinematics import Kinematics
from ..kinematics.program import Plan, plan
from ..kinematics.trajectory import Trajectory
from ..outputs import claim, record
from ..rapid.module import read_module
from ..rsxml.documents import load_mechanism
from ..sim.bodies import placed_environments
from ..sim.program_check import SINGULAR, check_program
from .output import Output, Warn, ignore, json_safe

FLOOR_TOLERANCE = 1e-4  # m: a link this far below the floor counts as touching it


def program_plan(path: str, module: str, routine: str = "main", device: str = "cpu", warn: Warn = ignore):
    """(mechanism, plan) of ``routine`` in ``module`` on the robot at ``path``."""
    mech, _ = load_mechanism(path)
    mod = read_module(module, routine)
    for w in mod.warnings:
        warn(str(w))
    return mech, plan(Kinematics(mech, device), mod)


def program_trajectory(path: str, module: str, routine: str = "main", warn: Warn = ignore) -> Trajectory:
    """The routine's joint trajectory, for a cable run (``rswarp cable --program``)."""
    _, p = program_plan(path, module, routine, warn=warn)
    return Trajectory(str(module), p.times, p.q)


def run_program(path: str, module: str, routine: str = "main", csv: str | None = None,
                environment: list[str] | None = None, collision_matrix: str | None = None, floor: float = 0.0,
                video: str | None = None, video_size: int = 512, device: str = "cpu", ray: str | None = None,
                progress=None, warn: Warn = ignore) -> Output:
    """``rswarp program``: resolve, build, check and report; ``csv`` writes the trajectory."""
    from ..export.srdf import read_srdf
    from ..sim.engine import cluster_for

    mech, p = program_plan(path, module, routine, device, warn)
    if csv is not None:
        claim(Path(csv))  # a file of the user's is never replaced: refused before any work
    if video is not None:
        from .videos import claim_video

        claim_video(video)
    env = placed_environments(mech, environment or [])
    disabled = read_srdf(collision_matrix, mech.link_names) if collision_matrix else ()
    tally, tools, checked = check_program(mech, p.q, env, disabled, device, cluster=cluster_for(ray, device),
                                          progress=progress)
    names = tools.checker.bodies.pair_names() if tools.checker is not None else []
    moves = [_findings(mech, p, m, tally, names, mech.si_length(floor)) for m in p.moves]
    if csv is not None:
        atomic_write(csv, trajectory_csv(mech, p).encode())
        record(Path(csv).parent if str(Path(csv).parent) else Path("."), [Path(csv).name])
    doc = {"robot": mech.name, "module": p.module.name, "routine": p.module.routine,
           "duration_s": float(p.times[-1]), "samples": len(p.times),
           "targets": [{"name": t.name, "line": t.line, "joints": t.joints, "conf": t.conf,
                        "limit_margin": t.limit_margin, "reach_margin_m": t.reach_margin} for t in p.targets],
           "moves": moves, "skipped": [str(w) for w in p.module.warnings], "csv": csv,
           "collision_pairs_checked": [list(n) for n, c in zip(names, [] if checked is None else checked) if c]}
    if video is not None:
        from .videos import program_video

        doc["video"] = program_video(mech, p, tally, names, video, video_size)
    return Output(json_safe(doc), program_text(mech, doc))


def _findings(mech, p: Plan, move, tally, names, floor: float) -> dict:
    a, b = move.rows
    out = list(move.findings)
    if b > a:
        rows = slice(a, b)
        if tally.outside[rows].any():
            out.append(f"outside the joint limits from t = {p.times[a + np.argmax(tally.outside[rows])]:.2f} s")
        hits = tally.hit[rows]
        for k in np.nonzero(hits.any(axis=0))[0]:
            first = a + int(np.argmax(hits[:, k]))
            out.append(f"{names[k][0]} hits {names[k][1]} at t = {p.times[first]:.2f} s")
        low = tally.low[rows]
        if np.nanmin(low) < floor - FLOOR_TOLERANCE:
            at = a + int(np.nanargmin(low))
            out.append(f"{1000 * (floor - np.nanmin(low)):.0f} mm below the floor at t = {p.times[at]:.2f} s")
        q5 = np.abs(p.q[rows, 4]) if p.q.shape[1] >= 6 else None
        if q5 is not None and q5.min() < SINGULAR and not any("singularity" in f for f in out):
            out.append(f"passes {np.degrees(q5.min()):.2f} deg from the wrist singularity (q5 = 0)")
    return {"line": move.line, "instruction": move.instruction, "target": move.target, "start_s": move.start,
            "end_s": move.end, "findings": out}


def trajectory_csv(mech, p: Plan) -> str:
    """``time,<joints>`` in the file's units, one row per sample (what ``--trajectory`` reads)."""
    joints = mech.active_joints
    buf = io.StringIO()
    buf.write(",".join(["time"] + [j.name for j in joints]) + "\n")
    factors = [mech.joint_factor(j) for j in joints]
    for t, q in zip(p.times, p.q):
        buf.write(",".join([f"{t:.6f}"] + [_fixed(v / f) for v, f in zip(q, factors)]) + "\n")
    return buf.getvalue()


def _fixed(v: float) -> str:
    """Six decimals of the file's unit (1e-6 deg or mm), trailing zeros off."""
    text = f"{v:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def program_text(mech, doc: dict) -> str:
    """The table a robot programmer reads: one row per move, its findings under it."""
    lines = [f"{doc['robot']}: {doc['module']}.{doc['routine']}, {len(doc['moves'])} steps, "
             f"{doc['duration_s']:.2f} s (every move stops at its point: zones are not blended)"]
    rows = [["line", "instruction", "target", "start [s]", "duration [s]", "findings"]]
    for m in doc["moves"]:
        rows.append([str(m["line"]), m["instruction"], m["target"], f"{m['start_s']:.2f}",
                     f"{m['end_s'] - m['start_s']:.2f}", str(len(m["findings"])) if m["findings"] else "-"])
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines += ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]
    found = [(m["line"], f) for m in doc["moves"] for f in m["findings"]]
    lines.append(f"findings: {len(found)}" if found else "findings: none")
    lines += [f"  line {line}: {f}" for line, f in found]
    if doc["csv"]:
        lines.append(f"trajectory: {doc['csv']}")
    if doc.get("video"):
        lines.append(f"video: {doc['video']['path']} ({doc['video']['frames']} frames)")
    return "\n".join(lines)
