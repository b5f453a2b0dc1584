"""Kinematic loops and their kinds (parallelogram, four-bar, slider, general), asked of the graph."""

from __future__ import annotations

import numpy as np
import pytest

import rswarp
from rswarp.report.info import SHOWN_LOOPS, mechanism_text
from rswarp.rsxml.loops import FOUR_BAR, GENERAL, PARALLELOGRAM, SLIDER, classify, loops
from rswarp.rsxml.model import Joint, Mechanism, Part

from rswarp import examples

from conftest import DATA


def test_parallel_rod_is_a_parallelogram_with_coaxial_active_joints():
    (loop,) = rswarp.load(DATA / "parallel_rod.rsxml").graph.loops
    assert loop.kind == PARALLELOGRAM and loop.closing.name == "Rod2"
    assert loop.corners == (("Rod1",), ("J3", "J2"), ("Elbow",), ("Rod2",))  # J2 and J3 share one shaft
    assert [j.name for j in loop.passive] == ["Rod1", "Elbow", "Rod2"]
    assert [j.name for j in loop.active] == ["J3", "J2"]


def test_four_bar_and_balance_cylinder():
    (four,) = rswarp.load(DATA / "loops" / "four_bar.rsxml").graph.loops
    assert four.kind == FOUR_BAR and len(four.corners) == 4
    (cylinder,) = rswarp.load(DATA / "loops" / "balance.rsxml").graph.loops
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
    np.testing.assert_array_equal(kin.closes(q), want)
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
    assert [loop.kind for loop in mech.graph.loops] == [PARALLELOGRAM] * 3
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

    from rswarp.export.frames import link_origins

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
