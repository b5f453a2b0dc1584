"""A timing report a programmer reads (issue 59, item 4): per move the TCP's mean and least speed
against the programmed one, where it is least and which limit holds it (``rswarp program
--json``: ``tcp_speed``, ``limited_by``), and ``--speed-plot`` (``rswarp.motion.speeds``). The
TCP's speed is checked here against the robot's own forward kinematics, apart from the module."""

from __future__ import annotations

import json
from functools import lru_cache

import numpy as np
import pytest

import rswarp
from rswarp.cli import main
from rswarp.errors import InputError
from rswarp.examples import IRB2600
from rswarp.kinematics.kinematics import Kinematics
from rswarp.motion.plan import program_plan
from rswarp.motion.speeds import plan_speeds
from rswarp.motion.tcp import frames
from rswarp.report.program import run_program

from conftest import DATA

RAPID = DATA / "rapid"
PNG = b"\x89PNG\r\n\x1a\n"
TCP_SPEED_KEYS = {"programmed_m_s", "mean_m_s", "least_m_s", "least_at_s", "least_at_share"}
LIMITS = {"velocity", "acceleration", "jerk", "tcp_speed", "orientation_speed", "zone", "time", "none"}


@lru_cache(maxsize=None)
def speeds_of(name: str):
    """(plan, its Speeds) of a module of tests/data/rapid on the IRB 2600."""
    mech, p = program_plan(str(IRB2600), [str(RAPID / name)])
    return p, plan_speeds(Kinematics(mech), p)


@lru_cache(maxsize=None)
def report(name: str):
    return run_program(str(IRB2600), [str(RAPID / name)])


def fk_speeds(p, k: int) -> np.ndarray:
    """The TCP's speed (m/s) over each sample interval of move ``k``, by the robot's FK apart."""
    kin = Kinematics(rswarp.load(IRB2600))
    m = p.moves[k]
    a, b = m.rows
    link, offset = kin.flange_frame()
    tcp = frames(kin.mech, m.motion.tool, m.motion.wobj).relative(kin.fk64(p.q[a - 1:b])[:, link] @ offset)
    return np.linalg.norm(np.diff(tcp[:, :3, 3], axis=0), axis=1) / np.diff(p.times[a - 1:b])


def test_a_movel_at_v100_keeps_100_mm_s_and_is_held_by_its_speed():
    """A 200 mm MoveL at v100 far from any singularity: between its ramps the TCP goes 100 mm/s
    (the robot's FK says so too), its least speed there is 100 mm/s, and v100 holds it."""
    p, s = speeds_of("speed_v100.mod")
    k = 1
    ts, held = s.record(k)
    assert ts["programmed_m_s"] == pytest.approx(0.1)
    assert ts["least_m_s"] == pytest.approx(0.1, rel=0.01)
    assert 0.95 * 0.1 < ts["mean_m_s"] < 0.1  # the ramps from and to rest cost a little
    mv = p.moves[k]
    assert mv.start < ts["least_at_s"] < mv.end and 0 <= ts["least_at_share"] <= 1
    own = fk_speeds(p, k)
    middle = own[len(own) // 4: 3 * len(own) // 4]
    assert np.allclose(middle, 0.1, rtol=1e-3)
    a, b = mv.rows
    assert np.allclose(s.tcp[a:b], own, rtol=1e-6, atol=1e-9)
    assert held["limit"] == "tcp_speed" and held["ratio"] == pytest.approx(1.0, abs=0.01)


def test_the_speed_is_the_tcps_in_its_work_object():
    """A MoveL at v200 that turns a long tilted tool 30 deg in a turned work object, and one at
    v100 with a stationary tool: between the ramps each TCP keeps its programmed speed, which
    the flange (its own speed 5 % off) does not."""
    p, s = speeds_of("speed_tools.mod")
    kin = Kinematics(rswarp.load(IRB2600))
    link, offset = kin.flange_frame()
    for k, v in ((1, 0.2), (3, 0.1)):
        a, b = p.moves[k].rows
        middle = slice(a + (b - a) // 4, a + 3 * (b - a) // 4)
        assert np.allclose(s.tcp[middle], v, rtol=1e-3)
        assert np.allclose(s.tcp[a:b], fk_speeds(p, k), rtol=1e-6, atol=1e-9)
        assert s.record(k)[1]["limit"] == "tcp_speed"
    a, b = p.moves[1].rows
    flange = (kin.fk64(p.q[a - 1:b])[:, link] @ offset)[:, :3, 3]
    speed = np.linalg.norm(np.diff(flange, axis=0), axis=1) / np.diff(p.times[a - 1:b])
    assert abs(speed[(b - a) // 2] - 0.2) > 0.005


def test_a_movel_by_the_wrist_singularity_is_held_by_a_wrist_axis():
    """The 0.5 m MoveL that passes 2 deg from q5 = 0, at v1000: the TCP drops far below 1000 mm/s
    in the middle, where axis 4 or 6 is at its top speed or acceleration, and the text says so."""
    p, s = speeds_of("wrist_speed.mod")
    ts, held = s.record(1)
    assert ts["least_m_s"] < 0.5 * ts["programmed_m_s"]
    assert 0.3 < ts["least_at_share"] < 0.7
    assert held["limit"] in ("velocity", "acceleration") and held["axis"] in ("J4", "J6")
    assert held["ratio"] == pytest.approx(1.0, abs=0.05)
    own = fk_speeds(p, 1)
    assert own[len(own) // 4: 3 * len(own) // 4].min() == pytest.approx(ts["least_m_s"], rel=1e-6)
    text = report("wrist_speed.mod").text
    slow = [line for line in text.splitlines() if line.startswith("  line 10: MoveL")]
    assert slow and f"{held['axis']}'s" in slow[0], text


def test_the_json_gives_every_move_its_speed_and_what_holds_it(capsys):
    assert main(["program", str(IRB2600), str(RAPID / "speed_v100.mod"), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    moves = doc["moves"]
    assert [m["kind"] for m in moves] == ["joint", "linear", "wait"]
    for m in moves:
        assert {"tcp_speed", "limited_by", "file", "line", "start_s", "end_s", "findings"} <= set(m)
        assert m["limited_by"]["limit"] in LIMITS
    assert set(moves[1]["tcp_speed"]) == TCP_SPEED_KEYS
    assert moves[1]["limited_by"]["limit"] == "tcp_speed"
    assert moves[2]["tcp_speed"] is None and moves[2]["limited_by"] == {"limit": "none"}
    assert doc["speed_plot"] is None


def test_speed_plot_is_a_png_and_a_users_file_is_never_replaced(tmp_path, capsys):
    plot = tmp_path / "speed.png"
    argv = ["program", str(IRB2600), str(RAPID / "speed_v100.mod"), "--speed-plot", str(plot)]
    assert main(argv) == 0
    assert f"speed plot: {plot}" in capsys.readouterr().out
    data = plot.read_bytes()
    assert data.startswith(PNG) and len(data) > 5000
    assert main(argv + ["--json"]) == 0  # rswarp's own file: written again
    assert json.loads(capsys.readouterr().out)["speed_plot"] == str(plot)
    mine = tmp_path / "mine.png"
    mine.write_bytes(b"the user's")
    with pytest.raises(InputError, match="mine.png"):  # refused before any work: the task is not even read
        run_program(str(IRB2600), [str(tmp_path / "absent.mod")], speed_plot=str(mine))
    assert mine.read_bytes() == b"the user's"
    assert main(["program", str(IRB2600), str(RAPID / "speed_v100.mod"), "--speed-plot",
                 str(tmp_path / "no" / "such" / "folder.png")]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("rswarp: ") and "does not exist" in err and "\n" not in err
