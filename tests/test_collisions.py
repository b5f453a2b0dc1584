"""Self-collision sweeps and the collision matrix: exact verdicts against analytic fixtures and
python-fcl (plus containment, which FCL misses, confirmed with trimesh), MoveIt's rules, the
files written, determinism, bounded memory, and the matrix in exports."""

from __future__ import annotations

import dataclasses
import json
import math
import tracemalloc

import numpy as np
import pytest

import rswarp
from rswarp.cli import main
from rswarp.geometry.bvh import PIECE_POINTS, build_bvh, component_points, quad_slots
from rswarp.kernels import types as kernel_types
from rswarp.kinematics.chain import chain_of
from rswarp.sim.bodies import collision_bodies
from rswarp.sim.collisions import CHUNK, Checker, collisions
from rswarp.sim.witness import pair_columns

from conftest import DATA

IRB = DATA.parent.parent / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
FIX = DATA / "collisions"


def load(name: str):
    return rswarp.load(str(FIX / name))


@pytest.fixture(scope="module")
def irb():
    mech = rswarp.load(str(IRB))
    bodies = collision_bodies(mech)
    return mech, bodies, Checker(mech, bodies)


# -- exact verdicts on analytic fixtures --------------------------------------------------------------


def fold_angles() -> tuple[float, float]:
    """Where the arm's lowest corner (0.4 m out, 0.02 m below its hinge axis, 0.4 m above the slab)
    touches the slab: 0.4 sin(t) + 0.02 cos(t) = 0.4, and its mirror image about 90 degrees."""
    r, phi = math.hypot(0.4, 0.02), math.atan2(0.02, 0.4)
    first = math.asin(0.4 / r) - phi
    return first, math.pi - first


def test_arm_folds_onto_its_grandparent_at_the_known_angle():
    mech = load("fold.rsxml")
    bodies = collision_bodies(mech)
    assert bodies.pair_names() == [("Base", "Link2")]  # Link1 is adjacent to both
    lo, hi = fold_angles()
    theta = np.radians(np.linspace(0, 120, 1201))
    theta = theta[(np.abs(theta - lo) > 1e-3) & (np.abs(theta - hi) > 1e-3)]  # clear of the touching angles
    for j1 in (0.0, math.radians(7)):  # the slab is wide enough: turning J1 changes nothing
        q = np.stack([np.full_like(theta, j1), theta], axis=1)
        hit = Checker(mech, bodies).verdicts(q)[0][:, 0]
        np.testing.assert_array_equal(hit, (theta > lo) & (theta < hi))


def test_padding_widens_the_verdict():
    mech = load("fold.rsxml")
    checker = Checker(mech, collision_bodies(mech), padding=0.005)
    # the arm's lowest corner, over the slab from 74 degrees on, is 0.4 - 0.4 sin t - 0.02 cos t above it
    theta = np.radians(np.array([76.0, 77.0, 78.0, 80.0]))
    gap = 0.4 - 0.4 * np.sin(theta) - 0.02 * np.cos(theta)
    hit = checker.verdicts(np.stack([np.zeros(4), theta], axis=1))[0][:, 0]
    np.testing.assert_array_equal(hit, gap <= 0.005)
    assert hit.any() and not hit.all()


def test_ball_inside_a_box_collides():
    """Containment is a collision: inside (x < 0.4), crossing the wall (to 0.6), free beyond."""
    mech = load("ball.rsxml")
    checker = Checker(mech, collision_bodies(mech))
    x = np.array([0.0, 0.1, 0.3, 0.38, 0.45, 0.5, 0.55, 0.62, 0.8, 1.0])
    hit = checker.verdicts(np.stack([x, np.full_like(x, 0.3)], axis=1))[0][:, 0]
    np.testing.assert_array_equal(hit, x < 0.6)


def test_open_meshes_judge_inside_by_winding_number():
    """Closed meshes are judged by ray parity, open ones by the winding number: the same verdicts."""
    mech = load("ball.rsxml")
    bodies = collision_bodies(mech)
    opened = dataclasses.replace(bodies, bodies=tuple(dataclasses.replace(b, watertight=False) for b in bodies.bodies))
    x = np.linspace(0.0, 1.0, 41)
    q = np.stack([x, np.full_like(x, 0.3)], axis=1)
    closed_hit = Checker(mech, bodies).verdicts(q)[0]
    np.testing.assert_array_equal(closed_hit, Checker(mech, opened).verdicts(q)[0])
    np.testing.assert_array_equal(closed_hit[:, 0], x < 0.6)


def test_exact_distance_of_the_fold():
    mech = load("fold.rsxml")
    checker = Checker(mech, collision_bodies(mech))
    theta = np.radians(np.array([76.0, 80.0, 84.0]))  # the corner over the slab
    d = checker.distances(np.stack([np.zeros(3), theta], axis=1), np.zeros(3, np.int32))
    np.testing.assert_allclose(d, 0.4 - 0.4 * np.sin(theta) - 0.02 * np.cos(theta), atol=1e-7)  # STL: float32


# -- agreement with python-fcl on the IRB 2600 ----------------------------------------------------------


def fcl_verdicts(bodies, poses: np.ndarray) -> np.ndarray:
    """python-fcl's verdicts for every state and pair (surfaces only)."""
    fcl = pytest.importorskip("fcl")
    objs = []
    for b in bodies.bodies:
        model = fcl.BVHModel()
        model.beginModel(len(b.vertices), len(b.faces))
        model.addSubModel(b.vertices, b.faces.astype(np.int32))
        model.endModel()
        objs.append(fcl.CollisionObject(model, fcl.Transform()))
    out = np.zeros((len(poses), len(bodies.pairs)), bool)
    request = fcl.CollisionRequest()
    for i in range(len(poses)):
        for obj, b in zip(objs, bodies.bodies):
            m = poses[i, b.link]
            obj.setTransform(fcl.Transform(m[:3, :3], m[:3, 3]))
        for p, (a, b) in enumerate(bodies.pairs):
            out[i, p] = fcl.collide(objs[a], objs[b], request, fcl.CollisionResult()) > 0
    return out


def contained(bodies, poses: np.ndarray, i: int, p: int) -> bool:
    """Whether one body of pair p contains the other at state i (trimesh's ray tests on every vertex;
    with surfaces apart, as FCL says, a closed mesh is inside or out as a whole, so nearly all its
    vertices must agree: ray tests misjudge a vertex now and then): our independent confirmation
    of what FCL misses."""
    import trimesh

    a, b = (bodies.bodies[k] for k in bodies.pairs[p])

    def posed(body):
        m = poses[i, body.link]
        return body.vertices @ m[:3, :3].T + m[:3, 3]

    va, vb = posed(a), posed(b)
    return bool(trimesh.Trimesh(vb, b.faces).contains(va).mean() > 0.95
                or trimesh.Trimesh(va, a.faces).contains(vb).mean() > 0.95)


def test_verdicts_agree_with_fcl_and_containment(irb):
    mech, bodies, checker = irb
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(7).random((10_000, len(lower)))
    ours = checker.verdicts(q)[0]
    ref = fcl_verdicts(bodies, rswarp.Kinematics(mech).fk64(q))
    assert len(bodies.pairs) == 15
    assert not (ref & ~ours).any(), "FCL found a collision we did not"
    extra = np.argwhere(ours & ~ref)
    assert len(extra) > 0  # Link5/Link6 inside the Base happen in about 1 of 400 states
    poses = rswarp.Kinematics(mech).fk64(q)
    for i, p in extra:
        assert contained(bodies, poses, i, p), f"state {i}, pair {bodies.pair_names()[p]}: ours only, not containment"
    assert ref[:, bodies.pair_names().index(("Link4", "Link6"))].all()


# -- MoveIt's rules -------------------------------------------------------------------------------------


def test_link_without_geometry_is_contracted_away():
    mech = load("fold_bare.rsxml")
    bodies = collision_bodies(mech)
    assert frozenset(("Base", "Link2")) in bodies.adjacent
    c = collisions(mech, samples=10)  # no pair is left to test
    assert c.pairs == () and c.disabled() == [("Base", "Link2", "Adjacent")] and c.free_fraction == 1.0


def test_default_always_never():
    home = collisions(load("fold_home.rsxml"), samples=2000)
    assert [(p.body1, p.body2, p.reason) for p in home.pairs] == [("Base", "Link2", "Default")]
    always = collisions(load("fold_always.rsxml"), samples=2000)
    assert always.pairs[0].reason == "Always" and always.always_rounds == 2
    free = collisions(load("fold.rsxml"), samples=2000)
    assert free.pairs[0].reason is None  # collides in about 9.5 % of samples: checked
    assert free.pairs[0].collisions == pytest.approx(2000 * (fold_angles()[1] - fold_angles()[0]) / math.radians(120),
                                                     rel=0.2)
    assert free.disabled() == [("Base", "Link1", "Adjacent"), ("Link1", "Link2", "Adjacent")]


def test_never_pairs_report_their_clearance(irb):
    mech, bodies, _ = irb
    c = collisions(mech, samples=3000, seed=1)
    never = {(p.body1, p.body2): p for p in c.pairs if p.reason == "Never"}
    assert set(never) >= {("Link2", "Link4"), ("Link3", "Link5"), ("Link3", "Link6")}
    for p in never.values():
        assert 0 <= p.clearance_floor <= p.clearance < 1.0 and p.collisions == 0
    # the clearance is a true distance, met again at the configuration reported
    p = never[("Link3", "Link5")]
    k = bodies.pair_names().index(("Link3", "Link5"))
    assert Checker(mech, bodies).distances(np.array([p.clearance_q]), np.array([k]))[0] == pytest.approx(p.clearance)
    assert [(p.body1, p.body2) for p in c.pairs if p.reason == "Default"] == [("Link4", "Link6")]


def test_environment_meshes(tmp_path):
    import trimesh

    floor = trimesh.creation.box(extents=[4, 4, 0.1])
    floor.apply_translation([0, 0, -0.05])
    floor.export(tmp_path / "floor.stl")
    mech = rswarp.load(str(IRB))
    from rswarp.sim.bodies import placed_environments

    env = placed_environments(mech, [f"{tmp_path / 'floor.stl'}@0,0,0.001"])
    c = collisions(mech, samples=2000, environment=env)
    floor_pairs = {p.body1: p for p in c.pairs if p.environment}
    assert set(floor_pairs) == set(c.links)
    assert floor_pairs["Base"].reason == "Default"  # the base stands 1 mm into the floor
    assert floor_pairs["Link6"].collisions > 0  # the wrist reaches the floor
    assert floor_pairs["Link1"].reason == "Never"


# -- what only speeds the verdicts up -------------------------------------------------------------


def test_oriented_boxes_hold_their_triangles():
    """Every node's box (oriented, a proper rotation) holds every vertex of the triangles below it."""
    import trimesh

    mesh = trimesh.load(str(IRB.parent / "link_3.stl"))
    tree = build_bvh(mesh.vertices, mesh.faces)
    assert np.allclose(np.linalg.det(tree.axes), 1.0)
    assert not np.allclose(tree.axes, np.eye(3))  # some boxes are turned to fit
    first = np.zeros(len(tree.left), np.int64)
    count = np.zeros(len(tree.left), np.int64)
    for k in range(len(tree.left) - 1, -1, -1):  # children come after their parent
        if tree.left[k] < 0:
            first[k], count[k] = -1 - tree.left[k], tree.right[k]
        else:
            first[k] = first[tree.left[k]]
            count[k] = count[tree.left[k]] + count[tree.right[k]]
    for k in range(len(tree.left)):
        local = (tree.triangles[first[k]:first[k] + count[k]].reshape(-1, 3) - tree.center[k]) @ tree.axes[k]
        assert (np.abs(local) <= tree.half[k] + 1e-12).all()
    assert PIECE_POINTS == kernel_types.PIECE_POINTS
    assert component_points(mesh.vertices, mesh.faces).shape == (1, PIECE_POINTS, 3)


def test_quad_slots_cover_each_node_two_levels_down():
    """The crossing walk's four boxes of a node are the nodes two levels below it (a leaf above that
    stands for itself): each appears once, and together they hold exactly the node's triangles."""
    import trimesh

    mesh = trimesh.load(str(IRB.parent / "link_3.stl"))
    tree = build_bvh(mesh.vertices, mesh.faces)
    record, slots = quad_slots(tree.left, tree.right, kernel_types.QUAD)
    inner = np.flatnonzero(tree.left >= 0)
    assert (record[inner] == np.arange(len(inner))).all() and (record[tree.left < 0] == -1).all()

    def below(k, levels):
        if tree.left[k] < 0 or levels == 0:
            return [k]
        return below(tree.left[k], levels - 1) + below(tree.right[k], levels - 1)

    def leaves(k):
        return [k] if tree.left[k] < 0 else leaves(tree.left[k]) + leaves(tree.right[k])

    for k in inner:
        got = [s for s in slots[record[k]] if s >= 0]
        assert sorted(got) == sorted(below(k, 2))
        assert sorted(sum((leaves(s) for s in got), [])) == sorted(leaves(k))


def test_pair_columns_are_the_joints_between_the_bodies(irb):
    mech, bodies, _ = irb
    cols = dict(zip(bodies.pair_names(), pair_columns(chain_of(mech.graph), bodies)))
    assert cols[("Base", "Link2")] == (0, 1)
    assert cols[("Link4", "Link6")] == (4, 5)
    assert cols[("Base", "Link6")] == (0, 1, 2, 3, 4, 5)


def test_witness_grids_change_no_verdict(irb):
    """The witnesses only spare walks: with and without them, the same verdicts and gaps; and the
    pair that always collides (Link4/Link6) has witnesses in nearly every cell."""
    mech, bodies, checker = irb
    p = bodies.pair_names().index(("Link4", "Link6"))
    grid = checker.witnesses
    cells = grid.witness.reshape(-1, kernel_types.WITNESSES, 2)[grid.start[p]:grid.start[p] + 32 * 32]
    assert (cells[:, 0, 0] >= 0).mean() > 0.95
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(11).random((3000, len(lower)))
    hit, gap = checker.verdicts(q)
    bare_hit, bare_gap = Checker(mech, bodies, witnesses=False).verdicts(q)
    np.testing.assert_array_equal(hit, bare_hit)
    np.testing.assert_array_equal(gap, bare_gap)
    assert hit[:, p].all()


def test_the_verdicts_do_not_depend_on_the_leaf_size(irb, monkeypatch):
    """The walk's leaves of one triangle (the tree's: its triangle carried across once for the leaves
    beside it) and leaves of several (``tree``'s leaf test): the same verdicts and gaps."""
    import functools

    from rswarp.sim import bodies as sim_bodies

    mech, bodies, checker = irb
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(12).random((3000, len(lower)))
    hit, gap = checker.verdicts(q)
    monkeypatch.setattr(sim_bodies, "build_bvh", functools.partial(build_bvh, leaf=3))
    coarse = Checker(mech, bodies, witnesses=False)
    assert (coarse._device.tree.right[coarse._device.tree.left < 0] > 1).any()
    coarse_hit, coarse_gap = coarse.verdicts(q)
    assert hit.any()
    np.testing.assert_array_equal(coarse_hit, hit)
    np.testing.assert_array_equal(coarse_gap, gap)


# -- sweep properties ---------------------------------------------------------------------------------


def test_same_numbers_on_one_core_or_many(irb):
    mech = irb[0]
    one = collisions(mech, samples=3000, seed=3, threads=1).report()
    many = collisions(mech, samples=3000, seed=3, threads=2).report()
    assert one == many


def test_a_configuration_without_a_pose_is_never_cleared(irb):
    """A row with a NaN or an infinity is reported colliding in every pair (gaps NaN), the other
    rows as they are without it; a q of the wrong shape is refused before any launch."""
    mech, bodies, checker = irb
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(5).random((9, len(lower)))
    hit, gap = checker.verdicts(q)
    bad = q.copy()
    bad[2, 3], bad[6, 0] = np.nan, np.inf
    bad_hit, bad_gap = checker.verdicts(bad)
    assert bad_hit[[2, 6]].all() and np.isnan(bad_gap[[2, 6]]).all()
    keep = [0, 1, 3, 4, 5, 7, 8]
    np.testing.assert_array_equal(bad_hit[keep], hit[keep])
    np.testing.assert_array_equal(bad_gap[keep], gap[keep])
    np.testing.assert_array_equal(checker.verdicts(q[4])[0], hit[4:5])  # one configuration, one row
    for shape in ((3, len(lower) - 1), (3, len(lower) + 1), (2, 3, len(lower))):
        with pytest.raises(ValueError, match="q must have shape"):
            checker.verdicts(np.zeros(shape))


def test_memory_is_bounded():
    mech = load("fold.rsxml")

    def peak(n):
        tracemalloc.start()
        collisions(mech, samples=n)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        return peak

    small, large = peak(2 * CHUNK), peak(8 * CHUNK)
    assert large < 1.5 * small + (1 << 20)


# -- command line and files ------------------------------------------------------------------------------


def test_cli_writes_srdf_json_and_heatmap(tmp_path, capsys):
    out = tmp_path / "c"
    assert main(["collisions", str(IRB), "--samples", "2000", "--out", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["samples"] == 2000 and 0 < doc["collision_free_fraction"] < 1
    from lxml import etree

    root = etree.parse(str(out / "collision_matrix.srdf")).getroot()
    pairs = {(e.get("link1"), e.get("link2")): e.get("reason") for e in root.iter("disable_collisions")}
    assert pairs[("Base", "Link1")] == "Adjacent" and pairs[("Link4", "Link6")] == "Default"
    assert set(pairs.values()) <= {"Adjacent", "Default", "Always", "Never"}
    assert (out / "heatmap.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert json.loads((out / "report.json").read_text())["disabled"] == doc["disabled"]


def test_cli_bad_environment(tmp_path, capsys):
    code = main(["collisions", str(IRB), "--samples", "10", "--out", str(tmp_path / "c"), "--env", "floor.stl@1,2"])
    assert code == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "MESH@x,y,z" in err
    assert not (tmp_path / "c").exists()


# -- the matrix in exports --------------------------------------------------------------------------------


def test_matrix_extends_export_filters(tmp_path):
    from pxr import Usd, UsdPhysics

    out = tmp_path / "c"
    assert main(["collisions", str(IRB), "--samples", "2000", "--out", str(out)]) == 0
    srdf = out / "collision_matrix.srdf"
    assert main(["export", str(IRB), "-o", str(tmp_path / "r.usda"), "--collision-matrix", str(srdf)]) == 0
    stage = Usd.Stage.Open(str(tmp_path / "r.usda"))
    root = "/IRB2600_12_165__01"
    targets = UsdPhysics.FilteredPairsAPI(stage.GetPrimAtPath(f"{root}/Link2")).GetFilteredPairsRel().GetTargets()
    assert {str(t) for t in targets} >= {f"{root}/Link4", f"{root}/Link5", f"{root}/Link6"}
    assert main(["export", str(IRB), "-o", str(tmp_path / "r.urdf"), "--collision-matrix", str(srdf)]) == 0
    text = (tmp_path / "r.srdf").read_text()
    assert 'link1="Link3" link2="Link5" reason="Never"' in text


def test_bad_collision_matrix(tmp_path, capsys):
    bad = tmp_path / "bad.srdf"
    bad.write_text('<robot name="x">\n  <disable_collisions link1="Base" link2="Nope" reason="Never"/>\n</robot>\n')
    assert main(["export", str(IRB), "-o", str(tmp_path / "r.usda"), "--collision-matrix", str(bad)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{bad}:2: link 'Nope'") and err.count("\n") == 1
    assert not (tmp_path / "r.usda").exists()


def test_newton_finds_no_contact_between_filtered_pairs_at_home(tmp_path):
    """The exported USD in Newton's own collision pipeline: at home, no contact joins two links the
    export filters (adjacent, touching at home, or disabled by the matrix)."""
    newton = pytest.importorskip("newton")
    from rswarp.export import export

    mech = rswarp.load(str(IRB))
    c = collisions(mech, samples=2000)
    result = export(mech, tmp_path / "r.usda", disabled=tuple(c.disabled()))
    filtered = {frozenset((a, b)) for a, b, _ in result.physics.filtered}
    builder = newton.ModelBuilder()
    builder.add_usd(str(tmp_path / "r.usda"))
    model = builder.finalize(device="cpu")
    state = model.state()
    newton.eval_fk(model, state.joint_q, state.joint_qd, state)
    contacts = model.contacts()
    model.collide(state, contacts)
    n = int(contacts.rigid_contact_count.numpy()[0])
    body = model.shape_body.numpy()
    labels = model.body_label if hasattr(model, "body_label") else model.body_key
    s0, s1 = contacts.rigid_contact_shape0.numpy()[:n], contacts.rigid_contact_shape1.numpy()[:n]
    touching = {frozenset((labels[body[a]].rsplit("/", 1)[-1], labels[body[b]].rsplit("/", 1)[-1]))
                for a, b in zip(s0, s1) if a >= 0 and b >= 0 and body[a] >= 0 and body[b] >= 0}
    assert not (touching & filtered)
    assert frozenset(("Link4", "Link6")) in filtered


def test_heat_map_never_rounds_a_collision_to_zero():
    from rswarp.report.collisions import _percent

    assert _percent(0.0) == "0.0%"
    assert _percent(1e-6) == "<0.1%"
    assert _percent(0.03018) == "3.0%"
