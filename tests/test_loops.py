"""Kinematic loops and their kinds (parallelogram, four-bar, slider, general), asked of the graph."""

from __future__ import annotations

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.kinematics.loops import FOUR_BAR, GENERAL, PARALLELOGRAM, SLIDER, classify, loops
from rswarp.report.info import SHOWN_LOOPS, mechanism_text
from rswarp.rsxml.model import Joint, Mechanism, Part

from conftest import DATA


def test_parallel_rod_is_a_parallelogram_with_coaxial_active_joints():
    (loop,) = loops(rswarp.load(DATA / "parallel_rod.rsxml").graph)
    assert loop.kind == PARALLELOGRAM and loop.closing.name == "Rod2"
    assert loop.corners == (("Rod1",), ("J3", "J2"), ("Elbow",), ("Rod2",))  # J2 and J3 share one shaft
    assert [j.name for j in loop.passive] == ["Rod1", "Elbow", "Rod2"]
    assert [j.name for j in loop.active] == ["J3", "J2"]


def test_four_bar_and_balance_cylinder():
    (four,) = loops(rswarp.load(DATA / "loops" / "four_bar.rsxml").graph)
    assert four.kind == FOUR_BAR and len(four.corners) == 4
    (cylinder,) = loops(rswarp.load(DATA / "loops" / "balance.rsxml").graph)
    assert cylinder.kind == SLIDER and [j.name for j in cylinder.passive] == ["Stroke", "Pivot", "Pin"]
    assert cylinder.corners == (("Pivot",), ("J2",), ("Pin",))  # the prismatic joint is no corner


def quad(points, axes=None):
    axes = axes or [(0, 1, 0)] * len(points)
    return tuple(Joint(f"J{i}", "A", "B", point1=p, point2=tuple(a + b for a, b in zip(p, ax)))
                 for i, (p, ax) in enumerate(zip(points, axes)))


def test_crossed_quadrilateral_and_spatial_loops_are_not_parallelograms():
    square = [(0, 0, 0), (1, 0, 0), (1, 0, 2), (0, 0, 2)]
    assert classify(quad(square))[0] == PARALLELOGRAM
    crossed = [(0, 0, 0), (1, 0, 0), (0, 0, 2), (1, 0, 2)]  # opposite sides equal, but crossed
    assert classify(quad(crossed))[0] == FOUR_BAR
    spatial = quad(square, axes=[(0, 1, 0), (0, 1, 0), (1, 0, 0), (0, 1, 0)])
    assert classify(spatial) == (GENERAL, ())


def test_info_shows_each_loop():
    text = "\n".join(mechanism_text(rswarp.load(DATA / "parallel_rod.rsxml")))
    assert "Loops:\n  closed by Rod2: parallelogram, corners Rod1, J3+J2, Elbow, Rod2; passive Rod1, Elbow, Rod2" in text


def test_info_on_many_long_loops_stays_linear():
    """20 000 closing joints back to the base: info describes the first few and counts the rest
    (describing each would walk 200 million joints)."""
    n = 20_000
    names = [f"L{i}" for i in range(n)]
    joints = [Joint(f"T{i}", names[i - 1], names[i]) for i in range(1, n)]
    joints += [Joint(f"C{i}", names[0], names[i], active=False) for i in range(1, n)]
    mech = Mechanism("M", base_link="L0", links=tuple(Part(x) for x in names), joints=tuple(joints))
    assert len(loops(mech.graph, SHOWN_LOOPS)) == SHOWN_LOOPS
    text = mechanism_text(mech)
    assert text[text.index("Loops:") + SHOWN_LOOPS + 1] == f"  ... and {n - 1 - SHOWN_LOOPS} more loops"


# -- parallelograms solved in the kinematics kernels ---------------------------------------------------


def parallel_rod():
    mech = rswarp.load(DATA / "parallel_rod.rsxml")
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(5).random((500, len(lower)))
    return mech, rswarp.Kinematics(mech), q


def angle_about_y(poses: np.ndarray) -> np.ndarray:
    return np.arctan2(poses[..., 0, 2], poses[..., 0, 0])


def test_parallelogram_passive_joints_follow_the_closed_form():
    mech, kin, q = parallel_rod()
    assert kin.passive_joints == ("Rod1", "Elbow")
    np.testing.assert_allclose(kin.passive(q), np.stack([q[:, 1] - q[:, 2], q[:, 2] - q[:, 1]], axis=1))
    g = mech.graph
    poses = kin.fk(q)  # float32, every link: the passive ones included
    point = np.append(g.closing[0].point1, 1.0)  # Rod2, seen from both of its links
    gap = (poses[:, g.link_index("Rod")] @ point)[:, :3] - (poses[:, g.link_index("Link3")] @ point)[:, :3]
    assert np.abs(gap).max() < 1e-6  # the loop closes, in float32, in metres
    # opposite sides stay parallel: the rod turns with the lower arm, the upper arm with the crank
    base = np.swapaxes(poses[:, g.link_index("Link1"), :3, :3], 1, 2)  # J1 taken out
    for link, column in (("Rod", 1), ("Link3", 2)):
        np.testing.assert_allclose(angle_about_y(base @ poses[:, g.link_index(link), :3, :3]), q[:, column], atol=1e-5)


def test_upper_arm_keeps_its_orientation_while_j2_moves():
    mech, kin, q = parallel_rod()
    k = mech.graph.link_index("Link3")
    moved = q.copy()
    moved[:, 1] = q[::-1, 1]  # other J2 values, J1 and J3 kept
    np.testing.assert_allclose(kin.fk64(moved)[:, k, :3, :3], kin.fk64(q)[:, k, :3, :3], atol=1e-12)


def test_generic_walk_agrees_with_the_unrolled_kernels():
    mech, kin, q = parallel_rod()
    k = mech.graph.link_index("Link3")
    np.testing.assert_allclose(kin.fk(q, links=["Link3"])[:, 0], kin.fk(q)[:, k], atol=1e-5)


def test_loops_that_cannot_be_solved_yet_are_refused_at_their_joint():
    with pytest.raises(rswarp.RsxmlError, match=r"spatial.rsxml:14: joint 'Closing' closes a kinematic loop .*general"):
        rswarp.Kinematics(rswarp.load(DATA / "loops" / "spatial.rsxml"))


# -- four-bars: closed form, branch, dead points ------------------------------------------------------


def turn_y(a: float, p: np.ndarray) -> np.ndarray:
    """(x, z) turned about +y by a: x -> x cos a + z sin a, z -> -x sin a + z cos a."""
    c, s = np.cos(a), np.sin(a)
    return np.array([c * p[0] + s * p[1], -s * p[0] + c * p[1]])


def continuation(file: str, thetas: np.ndarray) -> np.ndarray:
    """(Pin, Ground) by a Newton solve of the loop's closure, stepped in 0.1 degree steps from the
    assembled zero position (each step starts from the last): the branch by continuation."""
    from scipy.optimize import fsolve

    mech = rswarp.load(DATA / "loops" / file)
    j = {x.name: x for x in mech.joints}
    b0, o2, c0 = (np.asarray(j[n].point1)[[0, 2]] for n in ("Pin", "Ground", "Closing"))

    def gap(x, th):
        via_coupler = turn_y(th, b0 + turn_y(x[0], c0 - b0))
        return via_coupler - (o2 + turn_y(x[1], c0 - o2))

    out = np.zeros((len(thetas), 2))
    for i, target in enumerate(thetas):
        x = np.zeros(2)
        for th in np.linspace(0.0, target, max(2, int(abs(np.degrees(target)) / 0.1) + 1)):
            x = fsolve(gap, x, args=(th,), xtol=1e-13)
        assert np.abs(gap(x, target)).max() < 1e-12
        out[i] = x
    return out


def loop_gap(mech, poses: np.ndarray) -> np.ndarray:
    """How far the closing joint's point is from itself, seen from its two links."""
    g = mech.graph
    c = g.closing[0]
    point = np.append(c.point1, 1.0)
    return np.linalg.norm((poses[:, g.link_index(c.parent)] @ point)[:, :3] - (poses[:, g.link_index(c.child)] @ point)[:, :3], axis=1)


@pytest.mark.parametrize("file, lo, hi", [("four_bar.rsxml", -30, 30), ("four_bar_dead.rsxml", -39, 60)])
def test_four_bar_follows_its_assembly_branch_and_closes(file, lo, hi):
    """Against a continuation solve from zero (scipy), over the reachable limits: the closed form
    never jumps to the other branch; the loop closes in float32 within 1e-6 m."""
    mech = rswarp.load(DATA / "loops" / file)
    kin = rswarp.Kinematics(mech)
    assert kin.passive_joints == ("Pin", "Ground")
    q = np.radians(np.linspace(lo, hi, 41))[:, None]
    np.testing.assert_allclose(kin.passive(q), continuation(file, q[:, 0]), atol=1e-9)
    assert loop_gap(mech, kin.fk(q)).max() < 1e-6
    assert loop_gap(mech, kin.fk64(q)).max() < 1e-12
    k = mech.graph.link_index("Rocker")
    np.testing.assert_allclose(kin.fk(q, links=["Rocker"])[:, 0], kin.fk(q)[:, k], atol=1e-6)  # generic walk


def dead_point_flags(q: np.ndarray) -> np.ndarray:
    """True where the dead-point four-bar closes: the crank's pin B within reach of both the coupler
    and the rocker about O2 (|B - O2| between their difference and their sum), in mm."""
    b = np.stack([200 * np.sin(q[:, 0]), 200 * np.cos(q[:, 0])], axis=1)
    d = np.linalg.norm(b - [300, 0], axis=1)
    coupler, rocker = np.hypot(300, 50), 150
    return (d <= coupler + rocker) & (d >= coupler - rocker)


def test_configurations_past_a_dead_point_are_flagged_and_nan():
    mech = rswarp.load(DATA / "loops" / "four_bar_dead.rsxml")
    kin = rswarp.Kinematics(mech)
    q = np.random.default_rng(11).uniform(*mech.bounds(), (2000, 1))
    want = dead_point_flags(q)
    assert 0.1 < (~want).mean() < 0.3  # the dead point lies inside the limits
    np.testing.assert_array_equal(kin.loops_close(q), want)
    assert np.isnan(kin.passive(q)[~want]).all() and np.isfinite(kin.passive(q)[want]).all()
    poses = kin.fk(q)
    moved = [mech.graph.link_index(n) for n in ("Coupler", "Rocker")]
    assert np.isnan(poses[~want][:, moved]).any(axis=(2, 3)).all()  # the links the loop moves: NaN
    assert np.isfinite(poses[want]).all() and np.isfinite(poses[:, :2]).all()  # base and crank: posed
    assert np.isnan(kin.flange(q)[~want]).any(axis=(1, 2)).all()


def test_sweeps_skip_and_count_unreachable_configurations():
    from rswarp.sim.workspace import sample_chunks

    mech = rswarp.load(DATA / "loops" / "four_bar_dead.rsxml")
    ws = rswarp.workspace(mech, samples=3000, seed=4)
    q = np.concatenate(list(sample_chunks(*mech.bounds(), 3000, "random", 4)))
    assert ws.unreachable == int((~dead_point_flags(q)).sum()) > 0 and ws.samples == 3000
    assert ws.report()["unreachable_samples"] == ws.unreachable
    assert ws.flange_reach.value == pytest.approx(0.45, abs=1e-6)  # O2 at 300 mm, the rocker 150 mm long
    assert np.isfinite([ws.flange_low.value, ws.flange_high.value]).all()
    balls = rswarp.load(DATA / "collisions" / "four_bar_dead.rsxml")
    c = rswarp.collisions(balls, samples=3000, seed=4)
    assert c.unreachable == ws.unreachable and c.samples == 3000 - c.unreachable


def test_palletizer_flange_stays_horizontal():
    """The example palletizer's double parallelogram: over the joint limits the flange points
    straight down and turns only with J1 and J6; its three loops close."""
    mech = rswarp.load(examples.PALLETIZER)
    kin = rswarp.Kinematics(mech)
    assert [loop.kind for loop in loops(mech.graph)] == [PARALLELOGRAM] * 3
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(7).random((2000, len(lower)))
    flange = kin.flange(q)
    np.testing.assert_allclose(flange[:, :3, 2], np.tile([0.0, 0.0, -1.0], (len(q), 1)), atol=1e-6)
    heading = np.arctan2(flange[:, 1, 0], flange[:, 0, 0])  # the flange's x axis, seen from above
    turn = np.angle(np.exp(1j * (np.pi + q[:, 0] - q[:, 3])))  # x = -world x at zero; J6 turns it about -z
    np.testing.assert_allclose(np.angle(np.exp(1j * (heading - turn))), 0.0, atol=1e-5)
    poses = kin.fk(q)
    for closing in mech.graph.closing:
        point = np.append(closing.point1, 1.0)
        a, b = mech.graph.link_index(closing.parent), mech.graph.link_index(closing.child)
        assert np.abs((poses[:, a] @ point)[:, :3] - (poses[:, b] @ point)[:, :3]).max() < 1e-6


def test_newton_with_our_passive_values_agrees_on_the_palletizer(tmp_path):
    """The palletizer's USD loaded by Newton's add_usd (closing joints left out of the articulation):
    with rswarp's passive joint values, Newton's eval_fk puts every body where rswarp does."""
    newton = pytest.importorskip("newton")
    import warp as wp
    from scipy.spatial.transform import Rotation

    from rswarp.geometry.frames import link_origins

    mech = rswarp.load(examples.PALLETIZER)
    rswarp.to_usd(mech, tmp_path / "pal.usda")
    builder = newton.ModelBuilder()
    builder.add_usd(str(tmp_path / "pal.usda"))
    model = builder.finalize(device="cpu")
    kin = rswarp.Kinematics(mech)
    names = [label.rsplit("/", 1)[-1] for label in model.joint_label]
    starts = model.joint_q_start.numpy()
    bodies = [label.rsplit("/", 1)[-1] for label in model.body_label]
    origins, state = link_origins(mech), model.state()
    q = np.random.default_rng(8).uniform(*mech.bounds(), (50, mech.dof))
    values = np.concatenate([q, kin.passive(q)], axis=1)
    joints = [j.name for j in mech.active_joints] + list(kin.passive_joints)
    poses = kin.fk64(q)
    for i in range(len(q)):
        jq = model.joint_q.numpy().copy()
        for name, v in zip(joints, values[i]):
            jq[starts[names.index(name)]] = v
        newton.eval_fk(model, wp.array(jq, dtype=wp.float32, device="cpu"), model.joint_qd, state)
        body_q = state.body_q.numpy()
        for b, link in enumerate(bodies):
            want = poses[i, kin.links.index(link)]
            assert np.abs(body_q[b, :3] - (want[:3, :3] @ origins[link] + want[:3, 3])).max() <= 1e-5
            assert np.abs(Rotation.from_quat(body_q[b, 3:]).as_matrix() - want[:3, :3]).max() <= 1e-5


def test_balance_cylinder_length_follows_the_law_of_cosines():
    """The cylinder pivots at P below the arm joint O; the arm's pin A turns with J2 about O. The
    stroke is |A - P| by the law of cosines (minus its length at zero), and the loop closes."""
    mech = rswarp.load(DATA / "loops" / "balance.rsxml")
    kin = rswarp.Kinematics(mech)
    q = np.random.default_rng(9).uniform(*mech.bounds(), (300, 1))
    o, a0, p = np.array([0.0, 0.5]), np.array([-0.2, 0.8]), np.array([-0.2, 0.3])  # (x, z), metres
    op, oa = np.linalg.norm(p - o), np.linalg.norm(a0 - o)
    gamma0 = np.arccos(np.dot(p - o, a0 - o) / (op * oa))
    # J2 turns about +y: x, z -> (x cos q + z sin q, -x sin q + z cos q), which turns OA away from
    # OP (P lies at -135 degrees, A0 at 124 degrees from +x in the x-z plane): the angle POA grows by q
    gamma = gamma0 + q[:, 0]
    length = np.sqrt(op ** 2 + oa ** 2 - 2 * op * oa * np.cos(gamma))
    assert kin.passive_joints == ("Pivot", "Stroke")
    np.testing.assert_allclose(kin.passive(q)[:, 1], length - np.linalg.norm(a0 - p), atol=1e-12)
    g, pin = mech.graph, mech.graph.closing[0]
    poses = kin.fk(q)
    point = np.append(pin.point1, 1.0)
    gap = (poses[:, g.link_index("Piston")] @ point)[:, :3] - (poses[:, g.link_index("Arm")] @ point)[:, :3]
    assert np.abs(gap).max() < 1e-6


def test_palletizer_reach_and_work_range_figures_of_the_flange(tmp_path, capsys):
    """A palletizer has no wrist centre: its reach is the flange's, 200 + 1000 sin 85 + 1200 mm
    (J2 pivot, lower arm at its limit, upper arm kept level by the parallelogram at J3 = 0), and
    the side and top views show the flange."""
    from PIL import Image

    from rswarp.cli import main

    assert main(["sweep", str(examples.PALLETIZER), "--samples", "20000", "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    want = 200 + 1000 * np.sin(np.radians(85)) + 1200
    assert f"reach (J1 axis to flange centre; no wrist centre below five axes): {want:.1f} mm" in text
    for view in ("side.png", "top.png"):
        assert Image.open(tmp_path / view).size[0] > 400


# -- URDF: parallelograms as mimic joints -------------------------------------------------------------


def palletizer_urdf(tmp_path):
    mech = rswarp.load(examples.PALLETIZER)
    rswarp.to_urdf(mech, tmp_path / "pal.urdf")
    return mech, tmp_path / "pal.urdf"


def test_palletizer_urdf_mimics_its_active_joints(tmp_path):
    """yourdfpy, given only the four active joints, follows the mimic joints and puts every link
    where rswarp does; the closing joints are left out, so the URDF is a tree."""
    import xml.etree.ElementTree as ET

    yourdfpy = pytest.importorskip("yourdfpy")
    from rswarp.geometry.frames import link_origins

    mech, path = palletizer_urdf(tmp_path)
    joints = {j.get("name"): j for j in ET.parse(path).getroot().iter("joint")}
    assert not {c.name for c in mech.graph.closing} & set(joints)
    assert joints["Elbow"].find("mimic").get("joint") == "J3"  # Elbow = J3 - J2: two coaxial mimics
    assert joints["Elbow_by_J2"].find("mimic").get("multiplier") == "-1"
    urdf = yourdfpy.URDF.load(str(path), load_meshes=False)
    assert urdf.actuated_joint_names == ["J1", "J2", "J3", "J6"]
    kin = rswarp.Kinematics(mech)
    q = np.random.default_rng(12).uniform(*mech.bounds(), (30, mech.dof))
    poses, origins = kin.fk64(q), link_origins(mech)
    for i in range(len(q)):
        urdf.update_cfg(dict(zip(urdf.actuated_joint_names, q[i])))
        for k, link in enumerate(kin.links):
            got = np.array(urdf.get_transform(link, "Base"))
            got[:3, 3] += origins["Base"]
            want = poses[i, k][:3, :3] @ origins[link] + poses[i, k][:3, 3]
            np.testing.assert_allclose(got[:3, 3], want, atol=1e-9)
            np.testing.assert_allclose(got[:3, :3], poses[i, k][:3, :3], atol=1e-9)


def test_newton_reads_the_palletizer_urdf_mimics(tmp_path):
    """Newton's add_urdf keeps each passive joint's mimic; the joint values its mimic metadata gives
    put every body, through eval_fk, where rswarp's kinematics do."""
    newton = pytest.importorskip("newton")
    import warp as wp

    from rswarp.geometry.frames import link_origins

    mech, path = palletizer_urdf(tmp_path)
    builder = newton.ModelBuilder()
    builder.add_urdf(str(path), floating=False)
    model = builder.finalize(device="cpu")
    names = [label.rsplit("/", 1)[-1] for label in model.joint_label]
    leader, coeffs, start = model.joint_mimic_joint.numpy(), model.joint_mimic_coeffs.numpy(), model.joint_q_start.numpy()
    followers = [j for j in range(len(names)) if leader[j] >= 0]
    assert {names[j] for j in followers} >= set(rswarp.Kinematics(mech).passive_joints)
    kin, origins, state = rswarp.Kinematics(mech), link_origins(mech), model.state()
    bodies = [label.rsplit("/", 1)[-1] for label in model.body_label]
    q = np.random.default_rng(13).uniform(*mech.bounds(), (10, mech.dof))
    poses = kin.fk64(q)
    for i in range(len(q)):
        jq = np.zeros(model.joint_coord_count)
        for j, v in zip(mech.active_joints, q[i]):
            jq[start[names.index(j.name)]] = v
        for j in followers:
            jq[start[j]] = coeffs[j, 0] + coeffs[j, 1] * jq[start[leader[j]]]
        newton.eval_fk(model, wp.array(jq, dtype=wp.float32, device="cpu"), model.joint_qd, state)
        body_q = state.body_q.numpy()
        for link in kin.links:
            want = poses[i, kin.links.index(link)]
            got = body_q[bodies.index(link), :3] + origins["Base"]
            assert np.abs(got - (want[:3, :3] @ origins[link] + want[:3, 3])).max() <= 1e-5


def test_urdf_refuses_loops_that_are_not_linear():
    with pytest.raises(rswarp.RsxmlError, match=r"four_bar.rsxml:15: joint 'Closing' closes a four-bar loop whose "
                                                r"passive joints are not linear .*<mimic>"):
        rswarp.export.urdf.to_urdf_text(rswarp.load(DATA / "loops" / "four_bar.rsxml"), "x.urdf")
    with pytest.raises(rswarp.RsxmlError, match=r"five_bar.rsxml:\d+: joint .Tip. closes a general loop whose passive"):
        rswarp.export.urdf.to_urdf_text(rswarp.load(DATA / "loops" / "five_bar.rsxml"), "x.urdf")
    with pytest.raises(rswarp.RsxmlError, match=r"spatial.rsxml:14: joint 'Closing' closes a kinematic loop that "
                                                r"URDF cannot express"):
        rswarp.export.urdf.to_urdf_text(rswarp.load(DATA / "loops" / "spatial.rsxml"), "x.urdf")


def test_newton_model_of_the_palletizer_keeps_its_loops_closed_while_it_moves():
    """to_newton puts the closing joints outside the articulation; MuJoCo (through Newton) keeps
    them closed as the arm sags under gravity (the kinematics-only model has tiny drives), and its
    passive joints stay within 0.01 rad of where rswarp's closed form puts them for its active ones."""
    newton = pytest.importorskip("newton")
    import warp as wp
    from scipy.spatial.transform import Rotation

    from rswarp.export.newton import newton_q_columns, to_newton
    from rswarp.geometry.frames import link_origins

    mech = rswarp.load(examples.PALLETIZER)
    builder = to_newton(mech)
    cfg = newton.ModelBuilder.ShapeConfig(density=1000.0, has_shape_collision=False, has_particle_collision=False)
    for k, link in enumerate(mech.link_names):  # the model has no meshes: a ball of mass on each link
        builder.add_shape_sphere(k, xform=wp.transform(wp.vec3(*link_origins(mech)[link]), wp.quat_identity()),
                                 radius=0.08, cfg=cfg)
    model = builder.finalize(device="cpu")
    solver = newton.solvers.SolverMuJoCo(model)
    state, after, control = model.state(), model.state(), model.control()
    for _ in range(500):
        state.clear_forces()
        solver.step(state, after, control, None, 1 / 500)
        state, after = after, state
    g, body_q = mech.graph, state.body_q.numpy()
    for j in g.closing:
        ends = [Rotation.from_quat(body_q[g.link_index(n), 3:]).apply(j.point1) + body_q[g.link_index(n), :3]
                for n in (j.parent, j.child)]
        assert np.linalg.norm(ends[0] - ends[1]) < 5e-4  # MuJoCo's equality constraints are soft
    jq, cols = state.joint_q.numpy(), newton_q_columns(mech)
    q = np.array([jq[list(cols).index(c)] for c in range(mech.dof)])
    assert abs(q[1]) > 0.1  # it moved
    kin = rswarp.Kinematics(mech)
    names = [j.name for _, j in g.depth_first]
    np.testing.assert_allclose([jq[names.index(n)] for n in kin.passive_joints], kin.passive(q[None])[0], atol=1e-2)


# -- loops with no closed form: damped Newton steps with continuation ----------------------------------


def five_bar_tip(q: np.ndarray) -> np.ndarray:
    """The five-bar's tip (x, z in mm) where the forearms (180.28 mm) from the elbows A and B meet,
    on the side of A-B it lies at zero (above): circle intersection. NaN where they cannot meet."""
    a = np.stack([150 * np.sin(q[:, 0]), 150 * np.cos(q[:, 0])], axis=1)
    b = np.stack([200 + 150 * np.sin(q[:, 1]), 150 * np.cos(q[:, 1])], axis=1)
    d = b - a
    dd = np.linalg.norm(d, axis=1)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(np.hypot(100, 150) ** 2 - (dd / 2) ** 2)  # NaN where dd > 2 x 180.28
    up = np.stack([-d[:, 1], d[:, 0]], axis=1) / dd[:, None]  # left of A->B: above
    return (a + b) / 2 + h[:, None] * up


def elbow_gap(q: np.ndarray) -> np.ndarray:
    """The five-bar's elbow-to-elbow distance (mm)."""
    a = np.stack([150 * np.sin(q[:, 0]), 150 * np.cos(q[:, 0])], axis=1)
    return np.linalg.norm(np.stack([200 + 150 * np.sin(q[:, 1]), 150 * np.cos(q[:, 1])], axis=1) - a, axis=1)


def test_five_bar_is_solved_by_newton_steps_on_its_branch():
    """No closed form takes five corners: the damped Newton solve puts the tip where the forearms'
    circles meet, above the elbows as at zero, closes the loop within 1e-6 m in float32, and flags
    the configurations where the arms are spread too wide for the forearms to meet (and those within
    0.1 mm of it, where the solve cannot vouch for the branch)."""
    mech = rswarp.load(DATA / "loops" / "five_bar.rsxml")
    assert loops(mech.graph)[0].kind == GENERAL
    kin = rswarp.Kinematics(mech)
    q = np.random.default_rng(14).uniform(*mech.bounds(), (3000, 2))
    want = five_bar_tip(q)
    reachable = np.isfinite(want).all(axis=1)
    assert 0.02 < (~reachable).mean() < 0.5
    closes = kin.loops_close(q)
    assert not (closes & ~reachable).any()  # never a pose where the forearms cannot meet
    assert (elbow_gap(q[reachable & ~closes]) > 2 * np.hypot(100, 150) - 0.1).all()  # within 0.1 mm of it
    tip = kin.flange(q)[:, [0, 2], 3] * 1000
    np.testing.assert_allclose(tip[closes], want[closes], atol=2e-3)  # mm: 2 microns in float32
    assert np.isnan(tip[~closes]).all()
    assert loop_gap(mech, kin.fk(q[closes])).max() < 1e-6
    ws = rswarp.workspace(mech, samples=2000, seed=1)
    from rswarp.sim.workspace import sample_chunks

    sampled = np.concatenate(list(sample_chunks(*mech.bounds(), 2000, "random", 1)))
    assert ws.unreachable == int((~kin.loops_close(sampled)).sum()) >= int((~np.isfinite(five_bar_tip(sampled)).all(axis=1)).sum()) > 0


def test_cylinder_hung_from_the_arm_is_solved_by_newton_steps():
    """The balance cylinder arranged the other way (no closed form): the stroke still equals the
    law-of-cosines value, on the base that J1 turns, and the loop closes."""
    mech = rswarp.load(DATA / "loops" / "balance_hung.rsxml")
    (loop,) = loops(mech.graph)
    assert loop.kind == SLIDER
    kin = rswarp.Kinematics(mech)
    q = np.random.default_rng(15).uniform(*mech.bounds(), (500, 2))
    o, a0, p = np.array([0.0, 0.5]), np.array([-0.2, 0.8]), np.array([-0.2, 0.3])  # (x, z), metres
    c, s = np.cos(q[:, 1]), np.sin(q[:, 1])
    r = a0 - o
    pin = np.stack([o[0] + c * r[0] + s * r[1], o[1] - s * r[0] + c * r[1]], axis=1)  # J2 about +y
    stroke = dict(zip(kin.passive_joints, kin.passive(q).T))["Stroke"]
    np.testing.assert_allclose(stroke, np.linalg.norm(pin - p, axis=1) - 0.5, atol=1e-9)
    assert kin.loops_close(q).all() and loop_gap(mech, kin.fk(q)).max() < 1e-6


def test_fk_says_a_configuration_past_a_dead_point_is_unreachable(capsys):
    from rswarp.cli import main

    path = DATA / "loops" / "four_bar_dead.rsxml"
    assert main(["fk", str(path), "--q", "-50"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[-1].startswith("unreachable: a loop cannot close at these joint values")
    assert out[-2].split()[2:] == ["nan"] * 10  # the flange: no pose at all (origin, Euler angles, quaternion)
    assert main(["fk", str(path), "--q", "-50", "--json"]) == 0
    import json

    doc = json.loads(capsys.readouterr().out)
    assert doc["closes"] is False and doc["flanges"]["Tip"]["position"] == [None] * 3
    assert main(["fk", str(path), "--q", "-30", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["closes"] is True


def test_newton_continuation_never_leaves_the_parallelogram_branch():
    """The parallel rod's loop given to the Newton solve instead of its closed form (host twin and
    kernels): over 4000 random configurations it never comes out on the anti-parallelogram. Where the
    path folds the parallelogram within a few degrees of flat, the singular pose where the branches
    meet, the configuration is flagged, not guessed."""
    from rswarp.kinematics.newton_loop import newton_loop_values, newton_rows

    mech, kin, _ = parallel_rod()
    (loop,) = loops(mech.graph)
    rows, unknowns, why = newton_rows(mech.graph, loop, 0)
    assert why is None and len(unknowns) == 2
    q = np.random.default_rng(16).uniform(*mech.bounds(), (4000, mech.dof))
    order = [mech.graph.tree_joint[k].name for k in sorted(unknowns, key=unknowns.get)]
    closed = np.stack([dict(zip(kin.passive_joints, kin.passive(q).T))[n] for n in order], axis=1)
    solved = newton_loop_values(rows, q, 2)
    flagged = np.isnan(solved).any(axis=1)
    np.testing.assert_allclose(solved[~flagged], closed[~flagged], atol=1e-9)
    assert np.degrees(np.abs(closed[flagged, 0])).min() > 84  # flat is at 90 degrees from zero's shape
    assert flagged.mean() < 0.2
    # the kernels, given the same rows instead of the closed form
    newton = rswarp.Kinematics(mech)
    unknown = np.full(len(mech.link_names), -1, np.int32)
    unknown[list(unknowns)] = list(unknowns.values())
    newton.chain = newton.chain._replace(mimic=np.zeros_like(newton.chain.mimic), unknown=unknown, newton_rows=rows)
    newton._kernels, newton.newton_loops = {}, True
    poses, want = newton.fk64(q), kin.fk64(q)
    np.testing.assert_array_equal(np.isnan(poses).any(axis=(1, 2, 3)), flagged)
    np.testing.assert_allclose(poses[~flagged], want[~flagged], atol=1e-9)


def test_loops_start_closed_at_a_home_away_from_zero(tmp_path):
    """With home at J1..J6 = 30, 20, 40, 0 degrees, the USD stage (read by Newton's add_usd) and
    to_newton start every passive joint where the loops close: eval_fk of their initial joint
    state closes each closing joint within 1e-5 m."""
    newton = pytest.importorskip("newton")
    from scipy.spatial.transform import Rotation

    from rswarp.export.newton import to_newton

    text = examples.PALLETIZER.read_text().replace('<HomePosition value="0, 0, 0, 0"/>',
                                                   '<HomePosition value="30, 20, 40, 0"/>')
    (tmp_path / "pal.rsxml").write_text(text)
    mech = rswarp.load(tmp_path / "pal.rsxml")
    rswarp.to_usd(mech, tmp_path / "pal.usda")
    from_usd = newton.ModelBuilder()
    from_usd.add_usd(str(tmp_path / "pal.usda"))
    g = mech.graph
    usd_origins = rswarp.geometry.frames.link_origins(mech)  # USD bodies sit on their links' origins
    for builder, origins in ((from_usd, usd_origins), (to_newton(mech), dict.fromkeys(usd_origins, np.zeros(3)))):
        model = builder.finalize(device="cpu")
        state = model.state()
        newton.eval_fk(model, model.joint_q, model.joint_qd, state)
        body_q, bodies = state.body_q.numpy(), [label.rsplit("/", 1)[-1] for label in model.body_label]
        for j in g.closing:
            ends = [Rotation.from_quat(body_q[bodies.index(n), 3:]).apply(np.asarray(j.point1) - origins[n])
                    + body_q[bodies.index(n), :3] for n in (j.parent, j.child)]
            assert np.linalg.norm(ends[0] - ends[1]) < 1e-5, j.name
