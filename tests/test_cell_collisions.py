"""The robot against the cell's other bodies (``rswarp.sim.cell_check``): the posed-pair kernel's
verdicts checked against python-fcl (surface contact) plus a per-piece containment test of our own
(trimesh's ``contains`` on each closed shell), on seeded random states of the track cell and of the
positioner cell; the pairs left untested; hand-made states over, into and past the end of the
rail; and what ``rswarp sweep``, ``rswarp collisions`` and ``rswarp program`` report for a cell.
The RAPID modules are under tests/data/cell_collisions."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import fcl
import numpy as np
import pytest
import trimesh

from rswarp.kinematics.cell import CellKinematics
from rswarp.report.collisions import run_collisions
from rswarp.report.program import run_program
from rswarp.report.sweep import run_sweep
from rswarp.rsxml.cell import read_cell
from rswarp.sim.cell_check import CellChecker, body_poses, cell_pairs

from conftest import DATA

ROOT = Path(__file__).resolve().parents[1]
TRACK_CELL = ROOT / "examples" / "cells" / "track_cell.toml"
POSITIONER_CELL = ROOT / "examples" / "cells" / "positioner_cell.toml"
MODULES = DATA / "cell_collisions"
INTO_RAIL = MODULES / "wrist_into_rail.mod"
OVER_RAIL = MODULES / "wrist_over_rail.mod"

BASE_ON_CARRIAGE = 0.400  # m: the robot's base above the carriage's origin (track_cell.toml's frame)
TRAVEL = 4.0  # m: the track's eax_a range is 0 .. 4 m
RAIL_TOP = 0.200  # m: the rail's highest point (its two ribs, 225 to 275 mm either side of its middle)
BLOCK_TOP = 0.150  # m: the top of the rail's main block, between the ribs
RAIL_END = 4.300  # m: the rail's far end in x
ROBOT_LINKS = ("Base", "Link1", "Link2", "Link3", "Link4", "Link5", "Link6")


# -- the reference: fcl for surface contact, per-piece ray parity for containment ----------------
class Reference:
    """python-fcl's verdict on a pair (do the surfaces touch) and whether one body contains a
    vertex of the other (each closed shell of a body tested on its own: the carriage is a union of
    overlapping boxes, whose whole-mesh parity is wrong where they overlap)."""

    def __init__(self, bodies):
        self.bodies = bodies
        self.models = []
        self.pieces = []
        for b in bodies:
            m = fcl.BVHModel()
            m.beginModel(len(b.vertices), len(b.faces))
            m.addSubModel(np.asarray(b.vertices, float), np.asarray(b.faces, np.int64))
            m.endModel()
            self.models.append(m)
            mesh = trimesh.Trimesh(np.asarray(b.vertices, float), np.asarray(b.faces), process=False)
            self.pieces.append(mesh.split(only_watertight=False))

    def touch(self, i: int, j: int, poses: np.ndarray) -> bool:
        a = fcl.CollisionObject(self.models[i], fcl.Transform(poses[i][:3, :3], poses[i][:3, 3]))
        b = fcl.CollisionObject(self.models[j], fcl.Transform(poses[j][:3, :3], poses[j][:3, 3]))
        return fcl.collide(a, b, fcl.CollisionRequest(), fcl.CollisionResult()) > 0

    def inside(self, i: int, j: int, poses: np.ndarray) -> bool:
        """Whether some closed piece of body ``i`` contains a vertex of body ``j``."""
        rel = np.linalg.inv(poses[i]) @ poses[j]
        v = np.asarray(self.bodies[j].vertices, float) @ rel[:3, :3].T + rel[:3, 3]
        return any(piece.contains(v).any() for piece in self.pieces[i])

    def contained(self, i: int, j: int, poses: np.ndarray) -> bool:
        return self.inside(i, j, poses) or self.inside(j, i, poses)


@dataclass
class Cell:
    ck: CellKinematics
    found: object
    chk: CellChecker
    ref: Reference

    def index(self, a: str, b: str) -> int:
        return self.found.pair_names().index((a, b))


def _cell(path: Path) -> Cell:
    ck = CellKinematics(read_cell(str(path)))
    found = cell_pairs(ck)
    assert found is not None
    return Cell(ck, found, CellChecker(ck, found), Reference(found.bodies.bodies))


@pytest.fixture(scope="module")
def track() -> Cell:
    return _cell(TRACK_CELL)


@pytest.fixture(scope="module")
def positioner() -> Cell:
    return _cell(POSITIONER_CELL)


def agreement(cell: Cell, q: np.ndarray, ext: np.ndarray) -> dict:
    """The kernel's verdicts on every pair at every state against the reference's."""
    hits = cell.chk.hits(q, ext)
    poses = body_poses(cell.ck, cell.found, q, ext)
    names = cell.found.pair_names()
    touch = np.zeros_like(hits)
    missed, unexplained, contained = [], [], []
    for n in range(len(q)):
        for k, (i, j) in enumerate(cell.found.bodies.pairs):
            touch[n, k] = cell.ref.touch(i, j, poses[n])
            if touch[n, k] and not hits[n, k]:
                missed.append((n, names[k]))
            elif hits[n, k] and not touch[n, k]:
                (contained if cell.ref.contained(i, j, poses[n]) else unexplained).append((n, names[k]))
    return {"hits": hits, "touch": touch, "missed": missed, "unexplained": unexplained, "contained": contained}


def _check_agreement(cell: Cell, q: np.ndarray, ext: np.ndarray) -> dict:
    got = agreement(cell, q, ext)
    assert got["missed"] == [], f"fcl says these touch, the kernel says free: {got['missed'][:10]}"
    assert got["unexplained"] == [], \
        f"the kernel says collide, fcl says apart and neither contains the other: {got['unexplained'][:10]}"
    checked = cell.chk.checked
    hit = got["hits"][:, checked]
    # the sample is not trivial: colliding and free pairs both, and fcl finds contacts itself
    assert hit.sum() >= 20 and (~hit).sum() >= len(q), (hit.sum(), (~hit).sum())
    assert got["touch"][:, checked].sum() >= 20
    return got


# -- 1. the kernel against fcl on the track cell -------------------------------------------------
def test_track_poses_are_the_cell_frames(track):
    """The poses the comparison uses: the rail fixed, the carriage slid eax_a along x, the robot's
    base 400 mm above the carriage, each robot link its base times its own forward kinematics."""
    rng = np.random.default_rng(11)
    lo, hi = track.ck.robot.mech.bounds()
    q = rng.uniform(lo, hi, (20, 6))
    ext = rng.uniform(0.0, TRAVEL, (20, 1))
    poses = body_poses(track.ck, track.found, q, ext)
    names = [b.name for b in track.found.bodies.bodies]
    assert names == list(ROBOT_LINKS) + ["track.Rail", "track.Carriage"]
    carriage = np.broadcast_to(np.eye(4), (20, 4, 4)).copy()
    carriage[:, 0, 3] = ext[:, 0]
    base = carriage.copy()
    base[:, 2, 3] = BASE_ON_CARRIAGE
    np.testing.assert_allclose(poses[:, names.index("track.Rail")], np.broadcast_to(np.eye(4), (20, 4, 4)),
                               atol=1e-12)
    np.testing.assert_allclose(poses[:, names.index("track.Carriage")], carriage, atol=1e-12)
    np.testing.assert_allclose(poses[:, :7], base[:, None] @ track.ck.robot.fk64(q), atol=1e-12)


def test_track_kernel_agrees_with_fcl(track):
    rng = np.random.default_rng(20240611)
    lo, hi = track.ck.robot.mech.bounds()
    n = 1000
    q = rng.uniform(lo, hi, (n, 6))
    ext = rng.uniform(0.0, TRAVEL, (n, 1))
    got = _check_agreement(track, q, ext)
    # the arm reaches both bodies of the track: some link of it hits the rail and the carriage
    for other in ("track.Rail", "track.Carriage"):
        cols = [track.index(a, other) for a in ROBOT_LINKS[2:]]
        assert got["hits"][:, cols].any(), other


# -- 2. the pairs tested -------------------------------------------------------------------------
def test_only_base_on_carriage_is_untested(track, positioner):
    names = track.found.pair_names()
    assert names == [(a, b) for a in ROBOT_LINKS for b in ("track.Rail", "track.Carriage")]
    untested = [p for p, c in zip(names, track.chk.checked) if not c]
    assert untested == [("Base", "track.Carriage")]
    assert track.chk.checked.dtype == bool and track.chk.checked.shape == (len(names),)
    # fcl agrees at home: the base's underside lies on the carriage's top plate, nothing else touches
    home_q = track.ck.robot.mech.home_position()
    poses = body_poses(track.ck, track.found, home_q[None], track.ck.home()[None])[0]
    touching = [names[k] for k, (i, j) in enumerate(track.found.bodies.pairs) if track.ref.touch(i, j, poses)]
    assert touching == [("Base", "track.Carriage")]
    # the robot on the floor beside the positioner touches none of its links, nor the part on its face
    # plate, at home: all tested
    assert positioner.chk.checked.all() and len(positioner.chk.checked) == 7 * 4
    assert positioner.found.bodies.names[-1] == "weld_part"


# -- 3. hand-made states -------------------------------------------------------------------------
def _down(q2: float, q3: float) -> np.ndarray:
    """The arm in the x-z plane with the flange pointing straight down (q5 = pi/2 - q2 - q3)."""
    return np.array([[0.0, q2, q3, 0.0, np.pi / 2 - q2 - q3, 0.0]])


def _lowest(cell: Cell, q: np.ndarray, ext: np.ndarray, link: str) -> np.ndarray:
    """(3,) least world x, y, z of a robot link's vertices, and (3,) greatest."""
    b = ROBOT_LINKS.index(link)
    pose = body_poses(cell.ck, cell.found, q, ext)[0, b]
    v = np.asarray(cell.found.bodies.bodies[b].vertices, float) @ pose[:3, :3].T + pose[:3, 3]
    return v.min(axis=0), v.max(axis=0)


def test_arm_at_home_hits_nothing(track):
    q = track.ck.robot.mech.home_position()[None]
    for e in (0.0, 2.0, TRAVEL):
        ext = np.array([[e]])
        hits = track.chk.hits(q, ext)[0]
        assert not hits[track.chk.checked].any(), [p for p, h in zip(track.found.pair_names(), hits) if h]
        assert hits[track.index("Base", "track.Carriage")]  # the bolted pair: touching, and untested


def test_wrist_down_into_rail_hits_it(track):
    q, ext = _down(1.325, 0.4), np.array([[2.0]])
    lo, hi = _lowest(track, q, ext, "Link6")
    # over the rail's middle, and through its main block's top face: the surfaces cross
    assert lo[2] < BLOCK_TOP - 0.01 and hi[2] > BLOCK_TOP + 0.005 and abs(lo[1]) < 0.1 and 0.0 < lo[0] < RAIL_END
    hits = track.chk.hits(q, ext)[0]
    names = track.found.pair_names()
    k = track.index("Link6", "track.Rail")
    assert hits[k] and track.chk.checked[k]
    assert not hits[track.index("Link6", "track.Carriage")]
    i, j = track.found.bodies.pairs[k]
    assert track.ref.touch(i, j, body_poses(track.ck, track.found, q, ext)[0])
    # the arm raised (q2 1.2 rad, q3 0): the flange still straight down, over 250 mm up: clear of everything
    q_up = _down(1.2, 0.0)
    assert _lowest(track, q_up, ext, "Link6")[0][2] > RAIL_TOP + 0.05
    up = track.chk.hits(q_up, ext)[0]
    assert not up[track.chk.checked].any(), [p for p, h in zip(names, up) if h]


def test_wrist_past_rail_end_hits_nothing(track):
    """The same low pose with the carriage at the track's end: the wrist hangs past the rail's end."""
    q, ext = _down(1.4, 0.5), np.array([[TRAVEL]])
    for link in ("Link4", "Link5", "Link6"):
        assert _lowest(track, q, ext, link)[0][0] > RAIL_END + 0.01
    hits = track.chk.hits(q, ext)[0]
    assert not hits[track.chk.checked].any(), [p for p, h in zip(track.found.pair_names(), hits) if h]


def test_link_buried_in_rail_counts(track):
    """Link6 wholly inside the rail's middle block (no surface crossing: fcl says apart) collides."""
    q, ext = _down(1.4, 0.15), np.array([[2.0]])
    lo, hi = _lowest(track, q, ext, "Link6")
    assert 0.0 < lo[2] and hi[2] < BLOCK_TOP - 0.01 and max(abs(lo[1]), abs(hi[1])) < 0.2  # inside the block
    k = track.index("Link6", "track.Rail")
    i, j = track.found.bodies.pairs[k]
    poses = body_poses(track.ck, track.found, q, ext)[0]
    assert not track.ref.touch(i, j, poses) and track.ref.inside(j, i, poses)
    assert track.chk.hits(q, ext)[0, k]


# -- 4. the kernel against fcl on the positioner cell --------------------------------------------
def test_positioner_kernel_agrees_with_fcl(positioner):
    ck = positioner.ck
    assert [e.name for e in ck.cell.externals] == ["stn1"]
    e_lo, e_hi = ck.cell.externals[0].mechanism.bounds()
    np.testing.assert_allclose([e_lo[0], e_hi[0]], [-np.pi / 2, np.pi / 2])
    rng = np.random.default_rng(77)
    lo, hi = ck.robot.mech.bounds()
    n = 600
    q = rng.uniform(lo, hi, (n, 6))
    ext = np.column_stack([rng.uniform(-np.pi / 2, np.pi / 2, n), rng.uniform(-np.pi, np.pi, n)])
    got = _check_agreement(positioner, q, ext)
    for unit_link in ("stn1.Stand", "stn1.TiltFrame", "stn1.FacePlate"):
        cols = [positioner.index(a, unit_link) for a in ROBOT_LINKS]
        assert got["hits"][:, cols].any(), unit_link


# -- 5. rswarp sweep on a cell -------------------------------------------------------------------
def _own_box(folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """The robot's own flange box (its frame) from the voxel grid the sweep wrote."""
    with np.load(folder / "workspace.npz") as z:
        grid, origin, res = z["flange"], np.asarray(z["origin"], float), float(z["resolution"])
    report = json.loads((folder / "report.json").read_text())
    np.testing.assert_allclose(origin, report["voxel_origin"], atol=1e-12)
    assert res == pytest.approx(report["voxel_resolution"], abs=1e-12)
    k = np.argwhere(grid)
    assert len(k) > 100
    return origin + k.min(axis=0) * res, origin + (k.max(axis=0) + 1) * res


def test_sweep_track_cell_box_is_the_robot_box_over_the_travel(tmp_path):
    folder = tmp_path / "sweep"
    out = run_sweep(str(TRACK_CELL), str(folder), samples=5000)
    lo, hi = _own_box(folder)
    cell = json.loads((folder / "report.json").read_text())["cell"]
    assert cell == out.doc["cell"]
    assert cell["carrier"] == "track" and cell["travel"] == {"eax_a": [0.0, TRAVEL]}
    world_lo, world_hi = (np.asarray(v, float) for v in cell["flange_box_world"])
    np.testing.assert_allclose(world_lo, lo + [0.0, 0.0, BASE_ON_CARRIAGE], rtol=0, atol=1e-9)
    np.testing.assert_allclose(world_hi, hi + [TRAVEL, 0.0, BASE_ON_CARRIAGE], rtol=0, atol=1e-9)
    line = next(x for x in out.text.splitlines() if "in the cell" in x)
    assert line.startswith("  in the cell, on 'track' (eax_a 0 to 4000 mm): the flange reaches x ")
    m = [f"{round(v, 4):g}" for pair in zip(world_lo, world_hi) for v in pair]  # the robot file's metres
    assert f"x {m[0]} m to {m[1]} m, y {m[2]} m to {m[3]} m, z {m[4]} m to {m[5]} m in the world" in line
    assert "the floor and the cell's bodies not considered" in line


def test_sweep_positioner_cell_box_is_the_robot_box(tmp_path):
    folder = tmp_path / "sweep"
    out = run_sweep(str(POSITIONER_CELL), str(folder), samples=5000)
    lo, hi = _own_box(folder)
    cell = out.doc["cell"]
    assert cell["carrier"] is None and cell["travel"] is None
    np.testing.assert_allclose(cell["flange_box_world"], [lo, hi], rtol=0, atol=1e-9)
    assert any(x.startswith("  in the cell (the robot on the floor): the flange reaches x ")
               for x in out.text.splitlines())
    assert "on 'track'" not in out.text


# -- 6. rswarp collisions on a cell --------------------------------------------------------------
@pytest.fixture(scope="module")
def track_collisions(tmp_path_factory):
    """``rswarp collisions`` on the track cell, twice with the same seed."""
    return [run_collisions(str(TRACK_CELL), str(tmp_path_factory.mktemp("collisions")), samples=5000)
            for _ in range(2)]


def test_collisions_track_cell_report(track_collisions, track):
    out = track_collisions[0]
    cell = out.doc["cell"]
    assert json.loads(Path(out.doc["files"]["report"]).read_text())["cell"] == cell
    assert cell["samples"] == 5000 and cell["seed"] == 0
    pairs = {(p["body1"], p["body2"]): p for p in cell["pairs"]}
    assert list(pairs) == track.found.pair_names()
    base = pairs[("Base", "track.Carriage")]
    assert base["tested"] is False and base["collisions"] is None and base["rate"] is None
    tested = [p for p in cell["pairs"] if p["tested"]]
    assert len(tested) == 13
    for p in tested:
        assert 0 <= p["collisions"] <= 5000 and p["rate"] == pytest.approx(p["collisions"] / 5000, abs=1e-12)
        assert 0.0 <= p["rate"] <= 1.0
    colliding = [p for p in tested if p["collisions"] > 0]
    assert colliding and max(p["rate"] for p in tested) < 0.5
    # the base never reaches below the carriage, link 1 neither: those pairs are free in every state
    for key in (("Base", "track.Rail"), ("Link1", "track.Rail"), ("Link1", "track.Carriage")):
        assert pairs[key]["collisions"] == 0, key
    line = next(x for x in out.text.splitlines() if x.startswith("  in the cell ("))
    assert line == (f"  in the cell (5000 random states of the robot and its external axes): "
                    f"{len(colliding)} of 13 robot-cell pairs can collide")
    for p in colliding:
        assert f"    {p['body1']} - {p['body2']}: {100 * p['rate']:.1f} %" in out.text.splitlines()


def test_collisions_track_cell_rates_match_an_independent_draw(track_collisions, track):
    """Each pair's rate against our own Monte Carlo estimate (the robot's joints and eax_a uniform
    within their limits, a different seed), within five standard errors of the difference."""
    rng = np.random.default_rng(99)
    lo, hi = track.ck.robot.mech.bounds()
    n = 20000
    mine = track.chk.hits(rng.uniform(lo, hi, (n, 6)), rng.uniform(0.0, TRAVEL, (n, 1))).mean(axis=0)
    for p, k in zip(track_collisions[0].doc["cell"]["pairs"], range(len(mine))):
        if not p["tested"]:
            continue
        sd = np.sqrt(max(mine[k] * (1 - mine[k]), 1e-4) * (1 / 5000 + 1 / n))
        assert abs(p["rate"] - mine[k]) < 5 * sd + 1e-3, (p, mine[k])


def test_collisions_track_cell_is_deterministic(track_collisions):
    a, b = (out.doc["cell"] for out in track_collisions)
    assert a == b
    assert [p["collisions"] for p in a["pairs"]] == [p["collisions"] for p in b["pairs"]]


# -- 7. rswarp program on a cell -----------------------------------------------------------------
def _line_of(path: Path, text: str) -> int:
    lines = path.read_text().splitlines()
    return next(k + 1 for k, x in enumerate(lines) if x.strip().startswith(text))


def _collisions(out) -> list[dict]:
    return [f for f in out.doc["findings"] if f["kind"] == "collision"]


def test_program_wrist_into_rail_fails_on_the_rail(track):
    warnings: list[str] = []
    out = run_program(str(TRACK_CELL), [str(INTO_RAIL)], warn=warnings.append)
    assert out.code == 0  # findings are reported, not an error (docs/program.md)
    first, low = _line_of(INTO_RAIL, "MoveJ pAbove"), _line_of(INTO_RAIL, "MoveJ pLow")
    found = _collisions(out)
    assert found, out.text
    assert all(f["severity"] == "fail" for f in found)
    rail = [f for f in found if "track.Rail" in f["links"]]
    assert rail and all(tuple(f["links"])[1] == "track.Rail" for f in rail)
    at_low = {f["links"][0] for f in rail if f["line"] == low}
    assert "Link6" in at_low, [(f["line"], f["links"]) for f in found]
    assert not [f for f in found if f["line"] == first], "the first move stays 800 mm up"
    assert not [f for f in found if "Base" in f["links"]], "the base on its carriage is never reported"
    # the move's own record carries it, and its time lies within the move
    move = next(m for m in out.doc["moves"] if m["line"] == low)
    assert move["external_axes"] == {"eax_a": pytest.approx(0.8)}
    six = next(f for f in move["findings"] if f["kind"] == "collision" and f["links"] == ["Link6", "track.Rail"])
    assert move["start_s"] <= six["t_s"] <= move["end_s"]
    assert six["text"].startswith("Link6 hits track.Rail at t = ")
    assert f"line {low}: fail: Link6 hits track.Rail at t = {six['t_s']:.2f} s" in out.text
    # at the reported moment the wrist is really down at the rail: Link6 below the rail's top
    q = np.asarray(six["joints"], float)[None]
    pose = track.ck.robot.fk64(q)[0, ROBOT_LINKS.index("Link6")]
    v = np.asarray(track.found.bodies.bodies[ROBOT_LINKS.index("Link6")].vertices, float)
    z = (v @ pose[:3, :3].T + pose[:3, 3])[:, 2] + BASE_ON_CARRIAGE
    assert z.min() < RAIL_TOP
    assert ["Link6", "track.Rail"] in out.doc["collision_pairs_checked"]
    assert ["Base", "track.Carriage"] not in out.doc["collision_pairs_checked"]


def test_program_wrist_over_rail_has_no_collision():
    out = run_program(str(TRACK_CELL), [str(OVER_RAIL)])
    assert out.code == 0
    assert _collisions(out) == [], [f["text"] for f in _collisions(out)]
    assert all(not [f for f in m["findings"] if f["kind"] == "collision"] for m in out.doc["moves"])
    assert "hits" not in out.text
    # the two modules' targets differ only in pLow's z (-60 mm there, 800 mm here)
    into, over = ([x.strip() for x in m.read_text().splitlines() if "robtarget" in x] for m in (INTO_RAIL, OVER_RAIL))
    assert [a for a, b in zip(into, over) if a != b] == [
        "CONST robtarget pLow := [[1600, 0, -60], [0, 0, 1, 0], [0, 0, 0, 0], [800, 9E9, 9E9, 9E9, 9E9, 9E9]];"]
    assert over == [x.replace("[1600, 0, -60]", "[1600, 0, 800]") for x in into]
