"""A tool on the flange (issue "Robot data and outputs users trust", item 4): ``--tool`` as a mesh
with its mount, or as an RSXML Mechanism of type Tool, checked against every link but the one it
is on in collision sweeps, programs and cable runs, and drawn in videos; a tooldata's TCP checked
against it. Whether the tool touches a link is held against python-fcl, which rswarp does not use."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rswarp.errors import InputError, RsxmlError
from rswarp.examples import IRB2600, IRB2600_DRESSPACK
from rswarp.geometry.meshes import link_mesh
from rswarp.kinematics.kinematics import Kinematics
from rswarp.report.cables import run_cables
from rswarp.report.program import run_program
from rswarp.rsxml.documents import load_mechanism
from rswarp.sim.collisions import collisions
from rswarp.sim.tool import load_tool, tcp_gap, tool_body
from rswarp.sim.video import _Scene

from conftest import DATA

GRIPPER = DATA / "tool" / "gripper.stl"  # 80 mm square, 300 mm from the flange face along its z
GRIPPER_RSXML = DATA / "tool" / "gripper.rsxml"  # the same, with its TCP at its tip
FOLD = DATA / "rapid" / "tool_fold.mod"


def robot():
    return load_mechanism(IRB2600)[0]


@pytest.mark.parametrize("spec, message", [
    ("{g}@1,2,3", "give PATH or PATH@x,y,z,rx,ry,rz"),
    ("{g}@1,2,3,4,5,x", "give PATH or PATH@x,y,z,rx,ry,rz"),
    ("{g}@5000,0,0,0,0,0", "within"),
    ("{g}@0,0,0,1e7,0,0", r"angles within 5\.72958e\+06 deg \(100000 rad"),  # past the bound of every angle
    ("{g}@0,0,0,0,0,-1e7", "angles within"),
    ("{d}/tool/missing.stl", "missing.stl: cannot read it"),
])
def test_a_tool_given_wrong_is_a_one_line_error(spec, message):
    with pytest.raises(InputError, match=message):
        load_tool(robot(), spec.format(g=GRIPPER, d=DATA))


def test_a_robot_is_not_a_tool():
    with pytest.raises(RsxmlError, match="mechanism of type Tool; 'IRB2600_12_165__01' is a Robot"):
        load_tool(robot(), str(IRB2600))


def test_the_mount_places_the_mesh_in_the_flanges_frame():
    """@x,y,z,rx,ry,rz in the file's unit (m here) and degrees: turned 90 deg about y, the tool's
    300 mm run along the flange's x; moved 0.1 m along z, it starts 0.1 m out."""
    mech = robot()
    turned = load_tool(mech, f"{GRIPPER}@0,0,0.1,0,90,0")
    lo, hi = turned.vertices.min(axis=0), turned.vertices.max(axis=0)
    assert np.allclose(lo, [0.0, -0.04, 0.06]) and np.allclose(hi, [0.3, 0.04, 0.14])
    # on the robot: along the flange's z, which is world x at the zero position, from x = 1.03 m
    body = tool_body(mech, load_tool(mech, str(GRIPPER)))
    assert body.link == mech.graph.link_index("Link6") and body.tool
    assert np.allclose(body.vertices.min(axis=0), [1.03, -0.04, 1.22]) and np.isclose(body.vertices[:, 0].max(), 1.33)


def test_a_tool_mechanisms_tcp_and_the_gap_of_a_tooldatas():
    tool = load_tool(robot(), str(GRIPPER_RSXML))
    assert np.allclose(tool.tcp[:3, 3], [0.0, 0.0, 0.3])
    tip, far = np.eye(4), np.eye(4)
    tip[2, 3], far[2, 3] = 0.3, 0.55
    assert tcp_gap(tool, tip) == pytest.approx(0.0, abs=1e-6) and tcp_gap(tool, far) == pytest.approx(0.25)


def _fcl_touch(mech, tool, q) -> bool:
    """Whether Link4 and the tool intersect at ``q``, by python-fcl."""
    import fcl

    poses = Kinematics(mech).fk64(np.asarray(q, float)[None])[0]
    body = tool_body(mech, tool)
    objects = []
    for vertices, faces, pose in ((np.asarray(link_mesh(mech, "Link4").vertices), link_mesh(mech, "Link4").faces,
                                   poses[mech.graph.link_index("Link4")]),
                                  (body.vertices, body.faces, poses[body.link])):
        model = fcl.BVHModel()
        model.beginModel(len(vertices), len(faces))
        model.addSubModel(vertices, np.asarray(faces, np.int32))
        model.endModel()
        objects.append(fcl.CollisionObject(model, fcl.Transform(pose[:3, :3], pose[:3, 3])))
    return fcl.collide(*objects, fcl.CollisionRequest(), fcl.CollisionResult()) > 0


def test_a_program_finds_the_tool_in_the_arm_and_a_tooldata_that_misses_it():
    """Folding axis 5 to 120 deg swings the 300 mm gripper into Link4 (python-fcl agrees there,
    and not at 30 deg); the tooldata 250 mm beyond the tip is a finding, in both forms of --tool."""
    mech = robot()
    tool = load_tool(mech, str(GRIPPER))
    assert _fcl_touch(mech, tool, np.radians([0, 0, 0, 0, 120, 0]))
    assert not _fcl_touch(mech, tool, np.radians([0, 0, 0, 0, 30, 0]))
    plain = run_program(str(IRB2600), [str(FOLD)])
    assert not plain.doc["findings"]
    for given, gap in ((GRIPPER, "250 mm from gripper's body"), (GRIPPER_RSXML, "250.0 mm and 0.0 deg")):
        out = run_program(str(IRB2600), [str(FOLD)], tool=str(given))
        found = out.doc["findings"]
        hits = [f for f in found if f["kind"] == "collision"]
        assert hits and {tuple(f["links"]) for f in hits} == {("Link4", "tool gripper")}
        assert [f["line"] for f in hits] == [12, 13] and all(f["severity"] == "fail" for f in hits)
        off = [f for f in found if f["kind"] == "tool"]
        assert len(off) == 1 and off[0]["line"] == 13 and gap in off[0]["text"]
        assert off[0]["value"] == pytest.approx(0.25) and "tool:" in out.text


def test_a_sweep_checks_the_tool_against_every_link_but_its_own_and_keeps_it_out_of_the_srdf():
    mech = robot()
    tool = load_tool(mech, str(GRIPPER))
    c = collisions(mech, samples=4000, tool=tool)
    pairs = {(p.body1, p.body2): p for p in c.pairs if p.tool}
    assert {a for a, _ in pairs} == {"Base", "Link1", "Link2", "Link3", "Link4", "Link5"}
    assert pairs[("Link4", "tool gripper")].collisions > 0
    assert all("tool" not in a + b for a, b, _ in c.disabled())


def test_a_cable_run_measures_the_hose_against_the_tool_and_the_video_draws_it(tmp_path):
    out = run_cables(str(IRB2600_DRESSPACK), str(tmp_path / "run"), envs=1, random=True, seconds=0.5,
                     tool=str(GRIPPER))
    cable = json.loads((tmp_path / "run" / "report.json").read_text())["cables"][0]
    assert "tool gripper" in cable["slots"]
    assert 0 < cable["environments"][0]["clearance"]["tool gripper"]["min_clearance_m"] < 1.0
    assert "tool gripper: least clearance" in out.text
    mech = load_mechanism(IRB2600_DRESSPACK)[0]
    poses = np.repeat(np.eye(4)[None, None], len(mech.graph.links), axis=1)
    bare, tooled = _Scene(mech, poses, []), _Scene(mech, poses, [], load_tool(mech, str(GRIPPER)))
    assert len(tooled.faces) == len(bare.faces) + 12 and len(tooled.vertices(0)) == len(bare.vertices(0)) + 8
