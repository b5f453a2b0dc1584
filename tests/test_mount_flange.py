"""Mounting flanges, one rule (issue "Hardening the cell surfaces"): what rides a unit is placed
in the unit's RSXML Flange, its ``frame`` relative to it. A track written as RobotStudio writes it,
its carriage's mount flange 250 mm up and the robot's frame at zero: every move of a program ends
on its target, and the MoveL with the carriage moving keeps its line."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from rswarp import examples
from rswarp.cli import main
from rswarp.errors import RsxmlError
from rswarp.kinematics.cell import CellKinematics
from rswarp.motion.plan import program_plan
from rswarp.rsxml.cell import read_cell

MODULE = examples.CELLS / "track_transfer.mod"


def _track(tmp_path, flanges: str) -> str:
    """A copy of the bundled track with ``flanges`` for its Flanges element, and a cell on it."""
    folder = tmp_path / "track"
    shutil.copytree(examples.TRACK.parent, folder)
    rsxml = folder / examples.TRACK.name
    text = rsxml.read_text()
    start, end = text.index("<Flanges>"), text.index("</Flanges>") + len("</Flanges>")
    rsxml.write_text(text[:start] + flanges + text[end:])
    cell = tmp_path / "cell.toml"
    cell.write_text(f'[robot]\nrsxml = "{examples.IRB2600.resolve().as_posix()}"\non = "track"\n'
                    f'frame = [0, 0, 0, 0, 0, 0]\n\n[[external]]\nname = "track"\nrsxml = "{rsxml.as_posix()}"\n'
                    'axes = ["eax_a"]\n')
    return str(cell)


MOUNT_250 = '<Flanges><Flange name="mount" link="Carriage" x="1, 0, 0" y="0, 1, 0" z="0, 0, 1" t="0, 0, 250"/></Flanges>'


def test_the_robot_stands_on_the_tracks_flange_and_every_move_ends_on_its_target(tmp_path, capsys):
    cell = _track(tmp_path, MOUNT_250)
    ck = CellKinematics(read_cell(cell))
    base = ck.robot_base(ck.split(ck.home()[None]))[0]
    assert np.allclose(base[:3, 3], [0.0, 0.0, 0.25], atol=1e-12)  # the flange, not the carriage link
    assert main(["program", cell, str(MODULE), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    moves = [m for m in doc["moves"] if m["kind"] != "wait"]
    off = [(m["target"], np.linalg.norm(np.subtract(m["tcp_m"], m["target_m"]))) for m in moves]
    fine = ("pInfeed", "pOutfeed", "Offs(pNow,0,0,200)")  # the stops; the others end in their corner's zone
    assert len(moves) == 7 and all(v < 0.5e-3 for t, v in off if t in fine)
    assert all(v <= 0.1 + 1e-6 for _, v in off)  # a blended move ends within its zone (z50, z100) of its target


def test_the_movel_with_the_carriage_moving_keeps_its_line(tmp_path):
    cell = _track(tmp_path, MOUNT_250)
    _, plan = program_plan(cell, [str(MODULE)])
    ck = CellKinematics(read_cell(cell))
    carry = next(m for m in plan.moves if m.target == "pCarry")
    rows = slice(carry.rows[0], carry.rows[1])
    ext = plan.ext[rows]
    assert np.ptp(ext[:, 0]) > 1.0  # the carriage runs 1.5 m under this move
    tool = carry.motion.tool.tframe.matrix()
    tcp = (ck.flange(plan.q[rows], ck.split(ext)) @ tool)[:, :3, 3]
    start, end = np.array([0.9, -0.6, 0.9]), np.array([2.4, -0.3, 1.0])  # pInfeedApp to pCarry, in the world
    d = (end - start) / np.linalg.norm(end - start)
    along = (tcp - start) @ d
    off = np.linalg.norm((tcp - start) - np.outer(along, d), axis=1)
    inside = off[(along > 0.05) & (along < np.linalg.norm(end - start) - 0.1)]  # out of the z50 and z100 zones
    assert inside.size and inside.max() < 0.5e-3


def test_a_unit_with_several_flanges_names_the_one_riders_mount_on(tmp_path):
    two = ('<Flanges><Flange name="low" link="Carriage" x="1, 0, 0" y="0, 1, 0" z="0, 0, 1" t="0, 0, 100"/>'
           '<Flange name="high" link="Carriage" x="1, 0, 0" y="0, 1, 0" z="0, 0, 1" t="0, 0, 300"/></Flanges>')
    cell = _track(tmp_path, two)
    with pytest.raises(RsxmlError, match="has 2 flanges \\(low, high\\): give flange"):
        read_cell(cell)
    with open(cell, "a") as fh:
        fh.write('flange = "high"\n')
    ck = CellKinematics(read_cell(cell))
    assert np.allclose(ck.robot_base(ck.split(ck.home()[None]))[0, :3, 3], [0.0, 0.0, 0.3], atol=1e-12)
