"""The planner's misses told by how much (``shortfall``): a target it could not take, each time,
and once in ``errors`` for every line and reason with a count and the worst figure; a linear or
circular move's path finding where it stops. Each names where its target's data is declared."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..errors import Diagnostic
from . import shortfall as sf
from .tcp import Frames

FIGURED = (("out of reach", False), ("reachable only outside the joint limits", True))  # (words, a limit's)
_BASE = re.compile(r"^(?:[A-Za-z_]\w*\()*([A-Za-z_]\w*)")


def declared(motion) -> str | None:
    """``file:line`` of the data the move's (end) target is or is built from, or None."""
    where = getattr(motion, "declared", ())
    return where[-1] or None if where else None


def declared_words(name: str, where: str | None) -> str:
    """``; pPlace is declared at PalletData.mod:6`` (the data ``Offs(pPlace, ...)`` is built from)."""
    if not where:
        return ""
    verb = "set" if where.startswith("set ") else "declared"
    file, _, line = where.removeprefix("set ").rpartition(":")
    base = _BASE.match(name)
    return f"; {base.group(1) if base else 'its data'} is {verb} at {Path(file).name}:{line}"


def target_flange(planner, m) -> np.ndarray | None:
    """The flange pose a robtarget move asks for, where its frames are known."""
    fr = planner.frames.get((m.tool, m.wobj))
    if not isinstance(fr, Frames) or not m.targets:
        return None
    return fr.flange(m.targets[-1].pose.matrix()[None])[0]


def figured(planner, flange: np.ndarray, why: str) -> str:
    """``why`` a pose cannot be taken, with by how much where it is out of reach or past a limit."""
    limit = next((lim for words, lim in FIGURED if why.endswith(words)), None)
    s = sf.shortfalls(planner.kin, flange[None], limit)[0] if limit is not None else None
    return why if s is None else f"{why}: {s.words()}"


def explained(planner) -> tuple[tuple, tuple[Diagnostic, ...]]:
    """The planner's moves, each it skipped for reach or a limit with its shortfall (and its error
    saying it); its errors once per line and reason, with the count and the worst figure."""
    moves = list(planner.moves)
    rows, flanges, limits = [], [], []
    for k, mv in enumerate(moves):
        why = next((lim for words, lim in FIGURED if mv.error and mv.error.endswith(words)), None)
        flange = planner.target_flange(mv.motion) if why is not None else None
        if flange is not None:
            rows.append(k)
            flanges.append(flange)
            limits.append(why)
    found = sf.shortfalls(planner.kin, np.array(flanges), limits) if rows else []
    groups: dict = {}
    for k, mv in enumerate(moves):
        if mv.error is not None:
            groups.setdefault((mv.motion.file, mv.motion.line, f"{mv.instruction}: {mv.error}"), []).append(k)
    for k, s in zip(rows, found):
        if s is not None:
            moves[k] = replace(moves[k], error=f"{moves[k].error}: {s.words()}", shortfall=s)
    errors = []
    for e in planner.errors:
        group = groups.get((e.file, e.line, e.message), [])
        errors.append(_error(e, [moves[k] for k in group]))
    return tuple(moves), tuple(errors)


def _error(e: Diagnostic, moves: list) -> Diagnostic:
    """One error for every move its line and reason skipped: the worst figure, the target's
    declaration, how many times and, where the figures differ, from what to what."""
    if not moves:
        return e
    figured = [mv.shortfall for mv in moves if mv.shortfall is not None]
    message = e.message
    if figured:
        worst = max(figured, key=lambda s: s.excess)
        low = min(s.excess for s in figured)
        differ = _shown(worst, low) != _shown(worst, worst.excess)
        message += f": {worst.words(up_to=differ)}"
    message += declared_words(moves[0].motion.names[-1], declared(moves[0].motion))
    if len(moves) > 1:
        spread = f", {_shown(worst, low).split()[0]} to {_shown(worst, worst.excess)}" if figured and differ else ""
        message += f" ({len(moves)} times{spread})"
    return Diagnostic(e.file, e.line, message, e.severity, e.repeats)


def _shown(s: sf.Shortfall, excess: float) -> str:
    """An excess as the words show it: mm, or degrees (mm) of a joint."""
    if s.unit == "m" and s.kind != sf.LIMIT or not s.revolute:
        return f"{sf.mm(excess)} mm"
    return f"{np.degrees(excess):.1f}°"


def path_findings(planner, step) -> list:
    """A linear or circular move's findings, the one of a path it cannot follow told by how much
    beyond the reach or past which limit it would go where it stops."""
    out = []
    for f in step.findings:
        if f.kind == "path" and f.unit == "1" and ("out of reach" in f.text or "a joint limit" in f.text):
            f = _path_shortfall(planner, step, f)
        out.append(f)
    return out


def _path_shortfall(planner, step, f):
    from .plan_steps import probe_path

    m = step.motion
    fr = planner.frames.get((m.tool, m.wobj))
    if not isinstance(fr, Frames) or f.value is None:
        return f
    made = probe_path(fr, m, planner.flange_at(step.q0))
    if made is None:
        return f
    u, _, _, flanges = made
    k = int(np.argmin(np.abs(u - f.value)))
    last = step.q[-1] if step.q is not None and len(step.q) else step.q0
    rest = flanges[k:]  # the worst of the rest of the path, not the edge where it stopped (a circle point far out)
    found = [x for x in sf.shortfalls(planner.kin, rest, True, np.repeat(last[None], len(rest), axis=0))
             if x is not None]
    reach = [x for x in found if x.kind != sf.LIMIT]
    # beyond the reach: its worst; past a limit: where it stops (the branch beyond is no path the robot takes)
    s = max(reach, key=lambda x: x.excess) if reach else found[0] if found else None
    if s is None:
        return f
    text = f.text
    if s.kind == sf.LIMIT:
        text = text.replace("out of reach", "reachable only outside the joint limits")
    else:
        text = text.replace("a joint limit", "out of reach")
    words = f"{text}: {s.words(up_to=len(reach) > 1)}{_via(m)}"
    return replace(f, text=words, value=s.value, limit=s.limit, unit=s.unit, joint=s.joint,
                   advice=s.advice())


def _via(m) -> str:
    """For a circle, the point it passes through, which draws the circle out of reach."""
    if m.kind != "circular" or len(m.names) < 2:
        return ""
    where = getattr(m, "declared", ())
    file, _, line = where[0].removeprefix("set ").rpartition(":") if where and where[0] else ("", "", "")
    at = f" (declared at {Path(file).name}:{line})" if file else ""
    return f"; the circle passes through '{m.names[0]}'{at}"
