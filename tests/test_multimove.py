"""MultiMove (issue "Real programs in real cells"): the tasks of a two-robot backup
(``tests/data/rapid/wild/multimove``: T_ROB1 carries, T_ROB2 welds) planned each on its robot and
put on one clock as the controller runs them (RAPID reference, WaitSyncTask: "each program task
waits until all program tasks have reached the named synchronization point"; SyncMoveOn: the
moves with the same ``\\ID`` start and end together), then checked against each other."""

from __future__ import annotations

import numpy as np
import pytest

import rswarp
from rswarp.errors import RsxmlError
from rswarp.examples import IRB2600
from rswarp.motion.multimove import clashes, together
from rswarp.motion.plan import program_plan
from rswarp.rsxml.cell import Cell, PlacedRobot

from conftest import DATA

BACKUP = DATA / "rapid" / "wild" / "multimove"


def plans():
    return [program_plan(str(IRB2600), [str(BACKUP)], motion_task=name, strict=False)[1] for name in ("T_ROB1", "T_ROB2")]


def test_the_tasks_meet_and_their_synchronized_moves_start_and_end_together():
    alone = plans()
    t = together(["ROB_1", "ROB_2"], alone)
    rob1, rob2 = t.plans
    sync = [[m for m in p.moves if m.motion.sync_id is not None] for p in t.plans]
    for a, b in zip(*sync):  # \ID 10, 20, 30
        assert a.motion.sync_id == b.motion.sync_id
        assert a.start == pytest.approx(b.start, abs=1e-9) and a.end == pytest.approx(b.end, abs=1e-9)
        # each takes the slower one's time, alone
        took = [mv.end - mv.start for p in alone for mv in p.moves if mv.motion.sync_id == a.motion.sync_id]
        assert a.end - a.start == pytest.approx(max(took), abs=1e-9)
    wait = t.meetings[0]  # WaitSyncTask sync1: T_ROB2 waits while T_ROB1 goes home
    assert (wait.ident, wait.kind) == ("sync1", "wait")
    assert wait.waited[0] == 0.0 and wait.waited[1] == pytest.approx(alone[0].moves[0].end, abs=1e-9)
    assert np.array_equal(rob1.times, rob2.times) and rob1.times[-1] == pytest.approx(t.duration)
    # ROB_2 holds still while it waits, then moves: its joints at the clock's start and at the meeting are its home
    k = int(np.searchsorted(rob2.times, wait.time)) - 1
    assert np.allclose(rob2.q[k], rob2.q[0])
    # on the clock each robot ends where it ended alone, and holds there once its task is done
    assert np.allclose(rob1.q[-1], alone[0].q[-1], atol=1e-9) and np.allclose(rob2.q[-1], alone[1].q[-1], atol=1e-9)

def test_tasks_that_meet_at_different_points_are_an_error_at_the_first(tmp_path):
    p1, p2 = plans()
    cut = type(p2)(**{**p2.__dict__, "moves": p2.moves[1:]})  # T_ROB2 without its WaitSyncTask
    with pytest.raises(RsxmlError, match="the tasks do not meet at the same points: ROB_1 at sync1 .* ROB_2 at sync2"):
        together(["ROB_1", "ROB_2"], [p1, cut])


def test_robots_standing_close_are_found_to_hit_each_other_and_far_apart_not():
    t = together(["ROB_1", "ROB_2"], plans())
    mech = rswarp.load(IRB2600)
    facing = np.diag([-1.0, -1.0, 1.0, 1.0])
    far, near = facing.copy(), facing.copy()
    far[0, 3], near[0, 3] = 3.2, 2.2
    assert clashes([_cell("ROB_1", mech, np.eye(4)), _cell("ROB_2", mech, far)], t) == ()
    met = clashes([_cell("ROB_1", mech, np.eye(4)), _cell("ROB_2", mech, near)], t)
    assert met and all(c.first.startswith("ROB_1.") and c.second.startswith("ROB_2.") for c in met)
    assert 0.0 < met[0].time < t.duration and met[0].span > 0.0


def _cell(name, mech, frame):
    """One robot's cell of a two-robot team: the robot alone, at ``frame`` in the world."""
    return Cell(str(IRB2600), PlacedRobot(str(IRB2600), mech, frame, name=name, task=f"T_{name}"))
