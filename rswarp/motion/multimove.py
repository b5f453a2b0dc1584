"""MultiMove: the tasks of several robots run together, as the controller runs them. Each task is
planned on its own robot (``planner``); then the tasks meet: at a ``WaitSyncTask`` or
``SyncMoveOn``/``SyncMoveOff`` every task waits until the last one comes to the same meeting
point, and the moves of a synchronized stretch (``\\ID``) start together and end together, the
slower one's time for both (the faster is slowed evenly to it). The plans are put on one clock:
each robot holds still while it waits, and the trajectories are sampled together."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..errors import Diagnostic, RsxmlError
from .planner import Plan
from .timing import RATE


@dataclass(frozen=True)
class Meeting:
    """Where the tasks met: the syncident (or a synchronized move's ``\\ID``), its kind, the time on
    the common clock, and how long each task waited there (s)."""

    ident: str
    kind: str
    time: float
    waited: tuple[float, ...]


@dataclass(frozen=True)
class Together:
    """The tasks on one clock: the robots' names, each one's plan with its times, samples and moves
    on that clock (``plans``), and the meetings."""

    names: tuple[str, ...]
    plans: tuple[Plan, ...]
    meetings: tuple[Meeting, ...]

    @property
    def duration(self) -> float:
        return float(self.plans[0].times[-1])


def together(names, plans, rate: float = RATE) -> Together:
    """``plans`` (one per robot, each planned alone) put on one clock where their tasks meet."""
    items = [_items(p) for p in plans]
    _same_order(names, items)
    maps = [[(0.0, 0.0)] for _ in plans]
    fixed: list[dict] = [{} for _ in plans]  # move index -> (start, end) on the clock, where a meeting sets it
    meetings = []
    for j in range(len(items[0])):
        row = [it[j] for it in items]
        kind, ident = row[0][0], row[0][1]
        if kind == "end":  # a synchronized move ends together: the slower one's time for both
            began = [m[-1] for m in maps]
            span = max(old - b[0] for (_, _, old, _, _), b in zip(row, began))
            at = max(b[1] for b in began) + span
            for (_, _, old, _, k), m, f in zip(row, maps, fixed):
                m.append((old, at))
                f[k] = (f[k][0], at)
            meetings.append(Meeting(ident, kind, at, tuple(0.0 for _ in row)))
            continue
        now = [_forward(old, m) for (_, _, old, _, _), m in zip(row, maps)]
        at = max(now)
        for (_, _, old, _, k), m, t, f in zip(row, maps, now, fixed):
            m += [(old, t), (old, at)]
            f[k] = (at, at)
        meetings.append(Meeting(ident, kind, at, tuple(at - t for t in now)))
    ends = [_forward(float(p.times[-1]), m) for p, m in zip(plans, maps)]
    clock = np.linspace(0.0, max(ends), max(int(np.ceil(max(ends) * rate)), 1) + 1)
    out = tuple(_on_clock(p, m, f, clock) for p, m, f in zip(plans, maps, fixed))
    return Together(tuple(names), out, tuple(meetings))


def _items(p: Plan) -> list:
    """A task's meeting points in order: (kind, ident, time, the move's place) for each sync point
    (kind wait, on, off) and the start and end of each synchronized move (kind start, end)."""
    out = []
    for k, m in enumerate(p.moves):
        mo = m.motion
        if mo.sync is not None:
            out.append((mo.sync_kind, mo.sync.lower(), m.start, (mo.file, mo.line), k))
        elif mo.sync_id is not None:
            out.append(("start", f"\\ID:={mo.sync_id:g}", m.start, (mo.file, mo.line), k))
            out.append(("end", f"\\ID:={mo.sync_id:g}", m.end, (mo.file, mo.line), k))
    return out


def _same_order(names, items) -> None:
    """The tasks meet at the same points in the same order, as the controller requires; an error
    at the first place they differ."""
    for j in range(max(len(it) for it in items)):
        here = [it[j] if j < len(it) else None for it in items]
        if any(h is None or h[:2] != here[0][:2] for h in here if here[0] is not None) or here[0] is None:
            said = [f"{n} at {h[1]} ({h[3][0]}:{h[3][1]})" if h else f"{n} has no more" for n, h in zip(names, here)]
            first = next(h for h in here if h is not None)
            raise RsxmlError(Diagnostic(first[3][0], first[3][1], "the tasks do not meet at the same points: "
                                                                   + "; ".join(said)))


def _forward(old: float, m: list, before: bool = False) -> float:
    """A task's own time ``old`` on the common clock: after the meeting points at it (``before``:
    ahead of them, where a move ending there arrives)."""
    olds = [a for a, _ in m]
    k = max(int(np.searchsorted(olds, old, side="left" if before else "right")) - 1, 0)
    a, b = m[k]
    if k + 1 < len(m) and m[k + 1][0] > a:  # a stretch slowed to another task's time
        a1, b1 = m[k + 1]
        return b + (old - a) * (b1 - b) / (a1 - a)
    return b + (old - a)


def _on_clock(p: Plan, m: list, fixed: dict, clock: np.ndarray) -> Plan:
    """The plan sampled on the common clock: its own time there for each instant (held while it
    waits), its joints there, its moves' start and end there."""
    olds, news = np.array([a for a, _ in m] + [m[-1][0] + 1e9]), np.array([b for _, b in m] + [m[-1][1] + 1e9])
    own = np.interp(clock, news, olds)
    own = np.minimum(own, float(p.times[-1]))
    q, ext = _resampled(own, p.times, p.q), None if p.ext is None else _resampled(own, p.times, p.ext)
    moves = []
    for k, mv in enumerate(p.moves):
        start, end = fixed.get(k, (_forward(mv.start, m), _forward(mv.end, m, before=True)))
        rows = (int(np.searchsorted(clock, start, side="right")), int(np.searchsorted(clock, end, side="right")))
        moves.append(replace(mv, start=start, end=end, rows=rows))
    return replace(p, times=clock, q=q, ext=ext, moves=tuple(moves), cycles=())


def _resampled(at: np.ndarray, times: np.ndarray, values: np.ndarray) -> np.ndarray:
    """``values`` (samples, columns; none for a cell without units) at the times ``at``."""
    out = np.empty((len(at), values.shape[1]))
    for k in range(values.shape[1]):
        out[:, k] = np.interp(at, times, values[:, k])
    return out


@dataclass(frozen=True)
class Clash:
    """Two robots' links that meet on the common clock: the links (``ROB_1.link_3``,
    ``ROB_2.link_5``), when first and for how long (s)."""

    first: str
    second: str
    time: float
    span: float


def clashes(cells, t: Together, device: str = "cpu", tool=None) -> tuple[Clash, ...]:
    """Every pair of robots' links that collide at a sample of the common clock (``cells``: each
    robot's cell, ``rsxml.cell.Cell``, its base on the floor or on its units where the plan's
    external axes put them; ``tool``: the first robot's), a pair touching with every robot and
    unit at home left out as a build that touches (as a cell's pairs are)."""
    out = []
    step = float(t.plans[0].times[1] - t.plans[0].times[0]) if len(t.plans[0].times) > 1 else 0.0
    for i in range(len(cells)):
        for j in range(i + 1, len(cells)):
            hit, names = _pair_hits(cells[i], cells[j], t.plans[i], t.plans[j], device, tool if i == 0 else None)
            for k in np.flatnonzero(hit.any(axis=0)):
                first = int(np.argmax(hit[:, k]))
                out.append(Clash(f"{cells[i].robot.name}.{names[k][0]}", names[k][1], float(t.plans[i].times[first]),
                                 float(hit[:, k].sum()) * step))
    return tuple(sorted(out, key=lambda c: c.time))


def _pair_hits(a, b, pa: Plan, pb: Plan, device: str, tool) -> tuple[np.ndarray, list]:
    """(samples, pairs) whether robot ``a``'s links (and ``tool``) meet robot ``b``'s, each where
    its own cell puts it, and the pairs' names (``ROB_2.link_5`` for b's)."""
    from ..kinematics.cell import CellKinematics
    from ..rsxml.cell import LOGICAL_AXES, Cell, External
    from ..sim.cell_check import CellChecker, cell_pairs
    from ..sim.tool import tool_body

    mb = b.robot.mechanism
    other = External(b.robot.name, b.robot.rsxml, mb, np.eye(4), LOGICAL_AXES[:mb.dof],
                     tuple(x.name for x in mb.active_joints))
    pair_ck = CellKinematics(Cell(a.path, replace(a.robot, on=None), (other,)), device)
    found = cell_pairs(pair_ck, tool_body(pair_ck.robot.mech, tool) if tool is not None else None)
    if found is None:
        return np.zeros((len(pa.times), 0), bool), []
    cka, ckb = CellKinematics(a, device), CellKinematics(b, device)
    wa, wb = len(cka.home()), mb.dof

    def poses(q, rest):  # rest: a's external joints, b's joints, b's external joints
        la = cka.robot_links(q, cka.split(rest[:, :wa]))
        lb = ckb.robot_links(rest[:, wa:wa + wb], ckb.split(rest[:, wa + wb:]))
        return np.stack([la[:, w[0]] if who == "robot" else lb[:, w[1]] for who, *w in found.owner], axis=1)

    home = (a.robot.mechanism.home_position(), np.concatenate([cka.home(), mb.home_position(), ckb.home()]))
    checker = CellChecker(pair_ck, found, device, poses=poses, home=home)
    rest = np.hstack([_ext(pa, wa), pb.q, _ext(pb, len(ckb.home()))])
    return checker.hits(pa.q, rest) & checker.checked, found.pair_names()


def _ext(p: Plan, width: int) -> np.ndarray:
    """A plan's external joints (samples, width); none where its robot drives no unit."""
    return p.ext if p.ext is not None else np.zeros((len(p.times), width))
