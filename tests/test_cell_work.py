"""The work on a positioner (an ``[[environment]]`` mesh ``on`` a unit): it stands in the unit's
flange frame and turns and tilts with the face plate, in the collision checks and the video alike."""

from __future__ import annotations

import numpy as np
import pytest

from rswarp import examples
from rswarp.errors import RsxmlError
from rswarp.kinematics.cell import CellKinematics
from rswarp.report.program import run_program
from rswarp.rsxml.cell import read_cell
from rswarp.sim.cell_check import body_poses, cell_pairs

from conftest import DATA

CELL = examples.CELLS / "positioner_cell.toml"


def _rx(deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def test_the_part_turns_and_tilts_with_the_face_plate():
    """The part's pose is the face plate's: by hand, the plate's centre 0.8 m up at zero, tilted
    about the axis 0.9 m up, the positioner 1.1 m along x turned -90 deg (its x along the world's -y)."""
    ck = CellKinematics(read_cell(str(CELL)))
    found = cell_pairs(ck)
    k = found.bodies.names.index("weld_part")
    tilt, turn = 30.0, 60.0
    poses = body_poses(ck, found, ck.robot.mech.home_position()[None], np.radians([[tilt, turn]]))
    place = np.array([[0, 1, 0, 1.1], [-1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
    up, down = np.eye(4), np.eye(4)
    up[2, 3], down[2, 3] = 0.9, -0.9
    rz = np.eye(4)
    rz[:2, :2] = [[np.cos(np.radians(turn)), -np.sin(np.radians(turn))],
                  [np.sin(np.radians(turn)), np.cos(np.radians(turn))]]
    plate = np.eye(4)
    plate[2, 3] = 0.8
    expected = place @ up @ _rx(tilt) @ down @ plate @ rz
    assert np.allclose(poses[0, k], expected, atol=1e-9)


def test_a_flange_driven_into_the_turning_part_hits_it():
    out = run_program(str(CELL), [str(DATA / "cell_work" / "into_part.mod")])
    text = out.text
    assert "hits weld_part" in text
    hits = [f for m in out.doc["moves"] for f in m["findings"] if "weld_part" in f.get("text", "")]
    assert hits and all(m["line"] in (11, 12) for m in out.doc["moves"] if any(
        "weld_part" in f.get("text", "") for f in m["findings"]))


def test_the_bundled_weld_touches_nothing():
    out = run_program(str(CELL), [str(examples.CELLS / "positioner_weld.mod")])
    assert out.code == 0 and "findings: none" in out.text


def test_a_mesh_on_a_unit_the_cell_lacks_is_an_error_at_its_line(tmp_path):
    bad = tmp_path / "cell.toml"
    bad.write_text(CELL.read_text().replace('on = "stn1"', 'on = "stn2"').replace(
        "../", str(examples.CELLS.parent) + "/").replace('"weld_part.stl"', f'"{examples.CELLS / "weld_part.stl"}"'))
    with pytest.raises(RsxmlError) as exc:
        read_cell(str(bad))
    line = next(k for k, t in enumerate(bad.read_text().splitlines(), 1) if t.startswith("on ="))
    assert str(exc.value).startswith(f"{bad}:{line}: [[environment]] 1 on = 'stn2' names no [[external]]; "
                                     "did you mean 'stn1'?")
