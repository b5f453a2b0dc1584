"""Fatigue of a hose per location (issue "Dress-pack verdicts an engineer signs", item 2): rainflow
counting (ASTM E1049-85, 5.4.4) of each segment's curvature, streamed over many series at once,
held against the standard's worked example and against a plain one-series count written here from
its steps; Miner's sum against its arithmetic; and a cable run's count per location."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rswarp.examples import IRB2600_DRESSPACK, IRB2600_PROGRAM
from rswarp.report.cables import run_cables
from rswarp.sim.cable.rainflow import Rainflow, count, miner_passes


def test_astm_e1049_worked_example():
    """ASTM E1049-85 (2017), Fig. 6 and its table: the history -2, 1, -3, 5, -1, 3, -4, 4, -2."""
    assert count([-2, 1, -3, 5, -1, 3, -4, 4, -2]) == [(3.0, 0.5), (4.0, 1.5), (6.0, 0.5), (8.0, 1.0), (9.0, 0.5)]


def _reference(history: list[float]) -> list[tuple[float, float]]:
    """ASTM E1049's steps, one series, lists: reversals, then the rule, the residue as halves."""
    points = [history[0]]
    for a, b in zip(history[1:-1], history[2:]):
        if (a - points[-1]) * (b - a) < 0:
            points.append(a)
    if history[-1] != points[-1]:
        points.append(history[-1])
    stack, out = [], []
    for p in points:
        stack.append(p)
        while len(stack) >= 3:
            x, y = abs(stack[-1] - stack[-2]), abs(stack[-2] - stack[-3])
            if x < y:
                break
            if len(stack) == 3:
                out.append((y, 0.5))
                stack.pop(0)
            else:
                out.append((y, 1.0))
                del stack[-3:-1]
    out += [(abs(b - a), 0.5) for a, b in zip(stack, stack[1:])]
    return out


def test_many_series_at_once_count_as_each_alone():
    rng = np.random.default_rng(7)
    histories = np.cumsum(rng.normal(size=(40, 300)), axis=1)  # random walks: deep nesting
    histories[3] = 1.0  # a series that never moves
    flow = Rainflow(40, 3.0, floor=0.5)
    for column in histories.T:
        flow.add(column)
    cycles, damage = flow.finish()
    for k, h in enumerate(histories):
        ref = _reference(list(h)) if k != 3 else []
        assert cycles[k] == pytest.approx(sum(n for r, n in ref if r >= 0.5))
        assert damage[k] == pytest.approx(sum(n * r ** 3 for r, n in ref))


def test_the_stacks_stay_bounded():
    """A history whose ranges only grow nests without end: with a stack of 8 the oldest ranges
    are counted as halves as they leave it, and nothing is lost from the count."""
    grow = [(-1) ** k * k for k in range(200)]
    flow = Rainflow(1, 1.0, depth=8)
    for v in grow:
        flow.add(np.array([float(v)]))
    cycles, _ = flow.finish()
    assert flow.stack.shape == (1, 8) and cycles[0] == pytest.approx(sum(n for _, n in _reference(grow)))


def test_miners_rule():
    """1e6 cycles to failure at 0.3 m; a pass of 10 cycles to 0.6 m (half the curvature range):
    each does (1/2)^4 of a rated one's damage, so it lasts 1e6 / (10 / 16) = 1.6e6 passes."""
    rng_rated = 1 / 0.3
    damage_sum = 10 * (1 / 0.6) ** 4
    assert miner_passes(np.array([damage_sum]), 1, 1e6, rng_rated, 4.0)[0] == pytest.approx(1.6e6)
    assert miner_passes(np.array([0.0]), 1, 1e6, rng_rated, 4.0)[0] == np.inf


def test_a_cable_run_counts_its_fatigue_per_location(tmp_path):
    out = run_cables(str(IRB2600_DRESSPACK), str(tmp_path / "run"), program=[str(IRB2600_PROGRAM)],
                     rated_cycles="1e6@0.3")
    env = json.loads((tmp_path / "run" / "report.json").read_text())["cables"][0]["environments"][0]
    cycles = np.array(env["fatigue"]["rainflow_cycles"])
    assert cycles.shape == (len(env["wear"]["contact_time_s"]),) and cycles.max() >= 1
    line = next(x for x in out.text.splitlines() if x.strip().startswith("fatigue:"))
    assert f"{cycles.max():.1f} bending cycles a pass" in line and "Miner, 1e+06 cycles at 0.3 m" in line
