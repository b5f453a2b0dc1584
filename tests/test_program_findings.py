"""Findings a robot programmer acts on (``rswarp program``): a target out of reach says by how much,
held against the wrist centre's distance from axis 2 computed here from the robot's joint points;
one reachable only outside the limits names the joint and the bound; each names where its data is
declared; findings and errors met on every pass of a loop are said once, counted; the table shows
where each move's expression puts its target."""

from __future__ import annotations

import re
from functools import lru_cache

import numpy as np
import pytest

import rswarp
from rswarp.examples import IRB2600
from rswarp.kernels.ik import NO_REACH
from rswarp.kinematics.kinematics import Kinematics
from rswarp.report.program import run_program

from conftest import DATA

RAPID = DATA / "rapid"
PALLET = RAPID / "pallet_reach"  # a 3 x 4 grid, Offs and RelTool of pPlace; its far row is out of reach
WOBJ = np.array([1.0, -0.6, 0.1])  # wPallet's uframe (PalletData.mod), no turn
TOOL_Z = 0.18  # tGripper's TCP along the flange's z


@lru_cache(maxsize=None)
def run(path: str, cycles: int = 1):
    return run_program(str(IRB2600), [str(path)], cycles=cycles)


def declared_line(path, text: str) -> int:
    return next(k for k, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def beyond_reach(target_m: list[float]) -> float:
    """How far the wrist centre of a target of the grid (in wPallet, the tool pointing down) is
    beyond the arm's reach from axis 2, from the RSXML's joint points alone (m)."""
    joints = {j.name: np.array(j.point1) for j in rswarp.load(IRB2600).active_joints}
    p2, p3, wrist0 = joints["J2"], joints["J3"], joints["J5"]  # axes 4, 5, 6 meet at J5's point
    flange_to_wrist = np.linalg.norm(joints["J6"] - wrist0)
    tcp = WOBJ + np.asarray(target_m)
    centre = tcp + [0.0, 0.0, TOOL_Z + flange_to_wrist]  # the tool points down: the flange and wrist above
    radial = np.hypot(centre[0], centre[1])  # axis 1 turned to face it: axis 2 is p2[0] out from it
    distance = np.hypot(radial - p2[0], centre[2] - p2[2])
    reach = np.linalg.norm(p3 - p2) + np.linalg.norm(wrist0 - p3)
    return float(distance - reach)


def test_out_of_reach_says_by_how_much_and_where_the_target_is_declared():
    out = run(PALLET, 3)
    skipped = [m for m in out.doc["moves"] if m.get("error")]
    assert out.code == 1 and len(skipped) == 3 * 4 * 3  # 3 moves to each of the far row's 4 places, 3 passes
    for m in skipped:
        (f,) = m["findings"]
        assert f["kind"] == "unreachable" and f["unit"] == "m" and f["severity"] == "fail"
        assert f["value"] - f["limit"] == pytest.approx(beyond_reach(m["target_m"]), abs=1e-9)
        assert f["advice"] == f"move the target {1000 * (f['value'] - f['limit']):.0f} mm closer to the robot's base"
        assert m["target_m"][0] == pytest.approx(0.66)  # the far row
    pdrop = declared_line(PALLET / "Pallet.mod", "VAR robtarget pDrop")
    pplace = declared_line(PALLET / "PalletData.mod", "robtarget pPlace")
    place = [m for m in skipped if m["target"].startswith("Offs(pPlace")]
    assert {m["declared"] for m in place} == {f"{PALLET / 'PalletData.mod'}:{pplace}"}
    assert {f["declared"] for m in place for f in m["findings"]} == {f"{PALLET / 'PalletData.mod'}:{pplace}"}
    assert place[0]["findings"][0]["chain"] == [f"main ({PALLET / 'Pallet.mod'}:14)"]
    worst = max(m["findings"][0]["value"] - m["findings"][0]["limit"] for m in place)
    least = min(m["findings"][0]["value"] - m["findings"][0]["limit"] for m in place)
    error = next(e for e in out.errors if "Offs(pPlace" in e)
    assert error.startswith(f"{PALLET / 'Pallet.mod'}:31: MoveL: 'Offs(pPlace,row*nPitchX,col*nPitchY,0)' is out of "
                            f"reach: the wrist centre is up to {1000 * worst:.0f} mm beyond the arm's reach from axis 2")
    assert error.endswith(f"; pPlace is declared at PalletData.mod:{pplace} (12 times, {1000 * least:.0f} to "
                          f"{1000 * worst:.0f} mm)")
    set_at = declared_line(PALLET / "Pallet.mod", "pDrop := Offs")  # a variable assigned at run time: that line
    assert pdrop < set_at and any(e.endswith(f"pDrop is set at Pallet.mod:{set_at} (12 times, 11 to 113 mm)")
                                  for e in out.errors)


def test_a_finding_met_on_every_pass_is_listed_once_with_a_count():
    """JSON keeps a record per move made; the top-level list one per line, kind and joint, with
    its count, all its times, the worst figure and the passes of the main loop in its text."""
    out = run(PALLET, 3)
    tops = [f for f in out.doc["findings"] if f["line"] == 31]
    assert len(tops) == 1 and tops[0]["count"] == 12 and len(tops[0]["times_s"]) == 12
    each = [f for m in out.doc["moves"] if m["line"] == 31 for f in m["findings"]]
    assert len(each) == 12 and tops[0]["value"] == max(f["value"] for f in each)
    assert sorted(tops[0]["times_s"]) == sorted(f["t_s"] for f in each)
    assert "(12 times, passes 1-3; " in tops[0]["text"] and tops[0]["text"].endswith(" mm, the worst shown)")
    machine = run(RAPID / "over_base.mod", 3)  # a MoveL over the robot's base, twice a pass
    lines = [line for line in machine.text.splitlines() if line.startswith("  line 13: fail: cannot follow its line")]
    assert len(lines) == 1 and lines[0].endswith("; pOutfeed is declared at over_base.mod:5 (6 times, passes 1-3)")
    (path,) = [f for f in machine.doc["findings"] if f["kind"] == "path"]
    assert path["count"] == 6 and path["joint"] == "J5" and path["unit"] == "rad"
    assert path["value"] > path["limit"] == pytest.approx(np.radians(120.0))
    assert path["advice"].startswith("J5 would need 120.05°, its limit is 120.00°: ")


def test_a_target_reachable_only_outside_the_limits_names_the_joint_and_its_bound():
    """pDeep (the tool down, 350 mm from axis 1, 400 mm up) needs J3 past 75°: of all the pose's
    solutions, the one needing the least past its limits is the one named."""
    out = run(RAPID / "over_base.mod", 3)
    (error,) = out.errors
    assert error.endswith(": MoveJ: 'pDeep' is reachable only outside the joint limits: J3 would need 85°, its limit "
                          "is 75°; pDeep is declared at over_base.mod:6 (3 times)")
    record = next(f for f in out.doc["findings"] if f["line"] == 15)
    assert record["kind"] == "joint_limit" and record["joint"] == "J3" and record["count"] == 3
    kin = Kinematics(rswarp.load(IRB2600))
    pose = np.eye(4)
    pose[:3, :3] = np.diag([-1.0, 1.0, -1.0])
    pose[:3, 3] = [0.35, 0.0, 0.4]
    sol = kin.solutions64(pose[None])  # tool0 in wobj0: the flange is the TCP
    lower, upper = kin.mech.bounds()
    past = np.maximum(np.maximum(lower - sol.q[0], sol.q[0] - upper), 0.0).max(axis=1)
    usable = np.isfinite(sol.q[0]).all(axis=1) & (sol.status[0] != NO_REACH)
    best = sol.q[0][usable][np.argmin(past[usable])]
    assert not (past[usable] == 0).any() and record["value"] == pytest.approx(best[2], abs=1e-9)
    assert record["limit"] == pytest.approx(upper[2])


def test_the_table_shows_each_moves_resolved_target():
    """The twelve places of RelTool(pDrop,0,0,-nApproach) told apart: x, y, z in wPallet, mm."""
    out = run(PALLET, 1)
    rows = [line for line in out.text.splitlines() if line.startswith("Pallet.mod:30 ")]
    assert len(rows) == 12 and all("RelTool(pDrop,0,0,-nApproach)" in r for r in rows)
    shown = [re.search(r"\[([-\d., ]+)\]", r).group(1) for r in rows]
    assert shown == [f"{330.0 * row:.1f}, {250.0 * col:.1f}, 150.0" for row in range(3) for col in range(4)]
    head = next(line for line in out.text.splitlines() if line.startswith("file:line"))
    assert head.split()[4:6] == ["resolved", "[mm]"]
    placed = next(m for m in out.doc["moves"] if m["line"] == 31 and not m.get("error"))  # fine: it ends there
    assert placed["tcp_m"] == pytest.approx(placed["target_m"], abs=1e-9)
