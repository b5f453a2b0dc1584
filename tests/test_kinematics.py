"""Batched forward kinematics against an independent float64 reference, analytic poses and Newton."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rswarp
from rswarp import examples
from rswarp.kinematics.kinematics import Kinematics

from conftest import DATA

MODELS = {"irb1300": examples.IRB1300, "irb2600id": examples.IRB2600ID, "irb2600": examples.IRB2600,
          "branching": DATA / "branching.rsxml", "inch": DATA / "units_inch.rsxml", "transforms": DATA / "transforms.rsxml"}


@pytest.fixture(scope="module")
def kins():
    cache = {}

    def get(name, **kw):
        key = (name, tuple(sorted(kw.items())))
        if key not in cache:
            cache[key] = Kinematics(rswarp.load(MODELS[name]), **kw)
        return cache[key]

    return get


def reference_fk(mech, q):
    """Link poses by walking each link's joints back to the base (float64, scipy rotations)."""
    values = dict(zip((j.name for j in mech.active_joints), q))
    into = {j.child: j for j in mech.joints}
    done = {mech.base_link: np.eye(4)}

    def pose(link):
        if link in done:
            return done[link]
        j = into[link]
        p1, p2 = np.array(j.point1), np.array(j.point2)
        w = (p2 - p1) / np.linalg.norm(p2 - p1)
        theta = values.get(j.name, 0.0)
        m = np.eye(4)
        if j.type == "Rotational":
            m[:3, :3] = Rotation.from_rotvec(w * theta).as_matrix()
            m[:3, 3] = p1 - m[:3, :3] @ p1
        else:
            m[:3, 3] = w * theta
        done[link] = pose(j.parent) @ m
        return done[link]

    return {link: pose(link) for link in mech.link_names}


def random_q(mech, n, seed=0):
    lo, hi = mech.bounds()
    return np.random.default_rng(seed).uniform(lo, hi, (n, mech.dof))


def rotation_error(a, b):
    """Angle (rad) between the rotation parts of two stacks of 4x4 matrices: ||A - B||_F = 2 sqrt(2)
    sin(angle / 2) for rotations, well conditioned for small angles (arccos of the trace is not)."""
    d = np.linalg.norm(a[..., :3, :3].astype(np.float64) - b[..., :3, :3], axis=(-2, -1))
    return 2 * np.arcsin(np.minimum(1.0, d / (2 * np.sqrt(2))))


@pytest.mark.parametrize("name", list(MODELS))
def test_float32_matches_float64_reference(kins, name):
    kin = kins(name)
    mech = kin.mech
    q = random_q(mech, 200)
    got = kin.fk(q)
    assert got.dtype == np.float32 and got.shape == (200, len(mech.links), 4, 4)
    ref = np.array([[poses[link] for link in kin.links] for poses in map(lambda qi: reference_fk(mech, qi), q)])
    assert np.abs(got[..., :3, 3] - ref[..., :3, 3]).max() < 1e-5  # metres
    assert rotation_error(got, ref).max() < 1e-5  # radians
    assert np.array_equal(got[..., 3, :], np.broadcast_to([0, 0, 0, 1], got[..., 3, :].shape))
    for f in mech.flanges:
        fl = kin.flange(q, f.name)
        want = ref[:, kin.links.index(f.link)] @ f.pose.matrix()
        assert np.abs(fl[:, :3, 3] - want[:, :3, 3]).max() < 1e-5 and rotation_error(fl, want).max() < 1e-5


def test_analytic_poses_of_the_irb1300(kins):
    kin = kins("irb1300")
    deg = math.pi / 180
    q = np.array([[0, 0, 0, 0, 0, 0], [90 * deg, 0, 0, 0, 0, 0], [0, 0, 0, 0, 90 * deg, 0]])
    f = kin.flange(q)
    assert f[0, :3, 3] == pytest.approx([0.565, 0, 1.009], abs=1e-6)
    assert np.allclose(f[0, :3, :3], [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-6)  # tool0 z along +x
    assert f[1, :3, 3] == pytest.approx([0, 0.565, 1.009], abs=1e-6)  # J1 turns it about z
    # J5 (axis +y through x=475, z=1009) by +90 deg turns the 90 mm wrist offset downwards
    assert f[2, :3, 3] == pytest.approx([0.475, 0, 0.919], abs=1e-6)
    assert np.allclose(f[2, :3, 2], [0, 0, -1], atol=1e-6)


def test_prismatic_and_branching(kins):
    kin = kins("branching")
    assert kin.links == ("Arm", "Slide", "Column", "Swivel", "Forearm")  # the file's order, base third
    deg = math.pi / 180
    q = np.array([[0.25, 90 * deg, 0, 0]])  # Lift 250 mm, Shoulder 90 deg
    t = {name: m for name, m in zip(kin.links, kin.fk(q)[0])}
    assert t["Slide"][:3, 3] == pytest.approx([0, 0, 0.25], abs=1e-6) and np.allclose(t["Slide"][:3, :3], np.eye(3))
    assert t["Arm"][:3, 3] == pytest.approx([0, 0, 0], abs=1e-6)
    assert kin.flange(q, "tool0")[0, :3, 3] == pytest.approx([0, 0.7, 0.8], abs=1e-6)
    assert kin.flange(q, "gripper")[0, :3, 3] == pytest.approx([-0.2, 0.1, 0.55], abs=1e-6)  # lifted only
    w, g = kin.wrist_flange(q, "gripper", wrist=False)  # four axes: no wrist centre, any flange
    assert w is None and np.array_equal(g, kin.flange(q, "gripper")[:, :3, 3])
    with pytest.raises(ValueError, match="a wrist centre needs J4 and J5"):
        kin.wrist_flange(q)
    only = kin.fk(q, links=["Swivel", "Arm"])
    assert only.shape == (1, 2, 4, 4) and np.allclose(only[0, 1], t["Arm"], atol=1e-6)  # generic kernel


def test_units_inch_prismatic(kins):
    kin = kins("inch")
    f = kin.flange(np.array([[0.0254 * 10, 0.0]]))
    assert f[0, :3, 3] == pytest.approx([0.254, 0, 0.3048], abs=1e-6)


@pytest.mark.parametrize("n", [1, 6, 7, 8, 15, 64])
def test_chunk_boundaries_and_threads(kins, n):
    """Chunks of 7 on two threads give exactly what one launch on one thread gives."""
    small = kins("irb2600", chunk=7, threads=2)
    whole = kins("irb2600", chunk=1 << 16, threads=1)
    q = random_q(small.mech, n, seed=n)
    assert np.array_equal(small.fk(q), whole.fk(q))
    assert np.array_equal(small.flange(q), whole.flange(q))
    w1, f1 = small.wrist_flange(q)
    w2, f2 = whole.wrist_flange(q)
    assert np.array_equal(w1, w2) and np.array_equal(f1, f2)


def test_out_buffer_is_filled_in_place(kins):
    kin = kins("irb2600")
    q = random_q(kin.mech, 10)
    out = np.zeros((10, 7, 4, 4), np.float32)
    assert kin.fk(q, out=out) is out and np.array_equal(out, kin.fk(q))
    with pytest.raises(ValueError, match="out must be"):
        kin.fk(q, out=np.zeros((9, 7, 4, 4), np.float32))


def test_wrist_centre_is_on_j5_axis_nearest_j4(kins):
    kin = kins("irb2600id")
    q = random_q(kin.mech, 50)
    wrist, flange = kin.wrist_flange(q)
    ref = kin.fk64(q)
    # the IRB 2600ID's J4 and J5 axes meet: the wrist centre is that point, J5's anchor moved by Link4
    j5 = kin.mech.joint("J5")
    want = (ref[:, kin.links.index("Link4")] @ np.array([*j5.point1, 1.0]))[:, :3]
    assert np.abs(wrist - want).max() < 1e-5
    # two kernels (flange eight configurations a thread, this one one a thread): float32 rounding apart
    assert np.abs(flange - kin.flange(q)[:, :3, 3]).max() < 2e-6


def test_bad_inputs(kins):
    kin = kins("irb1300")
    with pytest.raises(ValueError, match=r"q must have shape \(N, 6\)"):
        kin.fk(np.zeros((3, 5)))
    with pytest.raises(KeyError, match="no link 'Link9'"):
        kin.fk(np.zeros((1, 6)), links=["Link9"])
    with pytest.raises(KeyError, match="no flange 'tool9'"):
        kin.flange(np.zeros((1, 6)), "tool9")
    with pytest.raises(rswarp.RsxmlError, match=r"spatial.rsxml:\d+: joint 'Closing' closes a kinematic loop"):
        Kinematics(rswarp.load(DATA / "loops" / "spatial.rsxml"))


@pytest.mark.parametrize("name", ["irb2600", "branching"])
def test_agrees_with_newton_eval_fk(kins, name):
    """The same mechanism built with newton.ModelBuilder, replicated 100 times, evaluated by Newton."""
    newton = pytest.importorskip("newton")
    import warp as wp

    from rswarp.export.newton import newton_q_columns, to_newton

    kin = kins(name)
    mech = kin.mech
    q = random_q(mech, 100, seed=3)
    one = to_newton(mech)
    many = newton.ModelBuilder()
    many.replicate(one, 100)
    model = many.finalize(device="cpu")
    state = model.state()
    cols = newton_q_columns(mech)
    joint_q = wp.array(q[:, cols].astype(np.float32).ravel(), dtype=wp.float32, device="cpu")
    newton.eval_fk(model, joint_q, wp.zeros(model.joint_dof_count, dtype=wp.float32, device="cpu"), state)
    body_q = state.body_q.numpy().reshape(100, len(kin.links), 7)
    ours = kin.fk(q)
    assert np.abs(body_q[..., :3] - ours[..., :3, 3]).max() < 1e-5
    rot = Rotation.from_quat(body_q[..., 3:].reshape(-1, 4)).as_matrix().reshape(100, len(kin.links), 3, 3)
    full = np.zeros_like(ours, dtype=np.float64)
    full[..., :3, :3] = rot
    assert rotation_error(ours, full).max() < 1e-5
    assert [model.body_label[i] for i in range(len(kin.links))] == list(kin.links)


def _long_chain(n: int, seed: int = 1):
    """A chain of n links with random joint axes and points, alternating revolute and prismatic."""
    from rswarp.rsxml.model import Joint, Mechanism, Part

    rng = np.random.default_rng(seed)
    links = tuple(Part(f"L{i}") for i in range(n))
    joints = []
    for i in range(1, n):
        p = rng.uniform(-0.5, 0.5, 3)
        d = rng.normal(size=3)
        joints.append(Joint(f"J{i}", f"L{i - 1}", f"L{i}", "Prismatic" if i % 5 == 0 else "Rotational",
                            point1=tuple(p), point2=tuple(p + d / np.linalg.norm(d))))
    return Mechanism("Chain", base_link="L0", links=links, joints=tuple(joints))


def test_long_chain_takes_the_generic_walk_and_agrees():
    from rswarp.kernels.fk import MAX_UNROLLED_LINKS

    mech = _long_chain(MAX_UNROLLED_LINKS + 6)
    kin = Kinematics(mech, threads=2, chunk=5)
    assert not kin.unrolled
    q = np.random.default_rng(2).uniform(-0.2, 0.2, (12, mech.dof))
    got = kin.fk(q)
    ref = np.array([[poses[link] for link in kin.links] for poses in map(lambda qi: reference_fk(mech, qi), q)])
    assert np.abs(got[..., :3, 3] - ref[..., :3, 3]).max() < 1e-4  # 70 joints of float32
    assert np.abs(kin.fk64(q) - ref).max() < 1e-12


def test_float64_kernels_match_the_reference(kins):
    kin = kins("irb2600id")
    mech = kin.mech
    q = random_q(mech, 50, seed=5)
    ref = np.array([[poses[link] for link in kin.links] for poses in map(lambda qi: reference_fk(mech, qi), q)])
    assert kin.fk64(q).dtype == np.float64 and np.abs(kin.fk64(q) - ref).max() < 1e-12
    w32, f32 = kin.wrist_flange(q)
    w64, f64 = kin.wrist_flange64(q)
    assert np.abs(w64 - w32).max() < 1e-5 and np.abs(f64 - f32).max() < 1e-5
    flange = ref[:, kin.links.index(mech.flanges[0].link)] @ mech.flanges[0].pose.matrix()
    assert np.abs(f64 - flange[:, :3, 3]).max() < 1e-12


def test_no_generated_source_anywhere():
    """Kernels are closures specialized with wp.static: no Python source is written or imported."""
    from pathlib import Path

    import rswarp.kernels

    for root in (Path(rswarp.__file__).parent, Path(rswarp.kernels.__file__).parent):
        for f in root.rglob("*.py"):
            assert "spec_from_file_location" not in f.read_text(), f


def test_generic_walk_gives_what_the_unrolled_kernels_give(kins, monkeypatch):
    """Every method through the generic walk (forced by a low chain-length limit) against the
    unrolled kernels of the same robot."""
    import rswarp.kernels.fk as fk_kernels

    unrolled = kins("irb2600id")
    monkeypatch.setattr(fk_kernels, "MAX_UNROLLED_LINKS", 3)
    generic = Kinematics(unrolled.mech, threads=2)
    assert not generic.unrolled and unrolled.unrolled
    q = random_q(unrolled.mech, 40, seed=7)
    assert np.abs(generic.fk(q) - unrolled.fk(q)).max() < 1e-5
    assert np.abs(generic.flange(q) - unrolled.flange(q)).max() < 1e-5
    for a, b in zip(generic.wrist_flange(q), unrolled.wrist_flange(q)):
        assert np.abs(a - b).max() < 1e-5
    assert np.abs(generic.fk64(q) - unrolled.fk64(q)).max() < 1e-12
    for a, b in zip(generic.wrist_flange64(q), unrolled.wrist_flange64(q)):
        assert np.abs(a - b).max() < 1e-12
