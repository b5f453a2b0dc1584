"""The crossing walk's box test, one box against four at once (``quad.quad_gap_function``): clang's
vector path against the looped path any other compiler takes, bit for bit, and both against
Gottschalk's separating-axis test written here in float64, on the IRB 2600's own box records."""

import numpy as np
import pytest
from ptx import ptx_of
from scipy.spatial.transform import Rotation

import rswarp
from rswarp.examples import IRB2600
from rswarp.kernels.cache import FUSED, INLINE_ALL, cpu_flags
from rswarp.kernels.geometry import EPS_AXIS
from rswarp.kernels.quad import lane_types, quad_gap_function
from rswarp.kernels.types import types_of
from rswarp.launch import init_warp
from rswarp.sim.bodies import DeviceBodies, collision_bodies

from conftest import DATA

wp = init_warp()
N = 20_000
# m: a separation the lanes must decide as the plain test does. Their edge axes are not normalized
# (an axis |A_i x B_j| = 1e-3 long scales float32 rounding and EPS_AXIS's widening by 1e3)
HAIR = 1e-3


def _gaps_kernel(scalar, flags: str):
    """A kernel giving ``quad_gaps`` of record k[i] against box i, compiled with ``flags``."""
    S, V3, M33, _, _ = types_of(scalar)
    V4, L2 = lane_types(scalar)
    quad_gaps = quad_gap_function(scalar)

    @wp.kernel(enable_backward=False, module="unique")
    def gaps(axes: wp.array2d(dtype=V4), center: wp.array2d(dtype=V4), halfs: wp.array2d(dtype=V4),
             k: wp.array(dtype=wp.int32), rq: wp.array(dtype=M33), cq: wp.array(dtype=V3), hq: wp.array(dtype=V3),
             out: wp.array(dtype=L2)):
        i = wp.tid()
        out[i] = quad_gaps(axes, center, halfs, k[i], rq[i], cq[i], hq[i])

    cpu_flags(gaps.module, f"{FUSED} {INLINE_ALL} {flags}".rstrip())  # as the sweep's module is compiled
    return gaps


@pytest.fixture(scope="module")
def records():
    """The IRB 2600's box records (float32 and float64), and N boxes about them: random turns,
    centres within a few box sizes of the record's first box, sizes from a millimetre to 20 cm."""
    bodies = DeviceBodies(collision_bodies(rswarp.load(IRB2600)), 0.0, "cpu")
    rng = np.random.default_rng(11)
    by_scalar = {}
    for scalar in (wp.float32, wp.float64):
        s = bodies.struct(scalar)
        by_scalar[scalar] = (s.quad_axes, s.quad_center, s.quad_half)
    centre = by_scalar[wp.float64][1].numpy()
    k = rng.integers(0, len(centre), N).astype(np.int32)
    cq = centre[k, :, 0] + rng.normal(size=(N, 3)) * 0.05
    rq = Rotation.random(N, random_state=12).as_matrix()
    hq = 10.0 ** rng.uniform(-3, np.log10(0.2), (N, 3))
    return by_scalar, k, rq, cq, hq


def _run(records, scalar, flags: str) -> np.ndarray:
    by_scalar, k, rq, cq, hq = records
    S, V3, M33, _, _ = types_of(scalar)
    _, L2 = lane_types(scalar)
    np_type = np.float32 if scalar == wp.float32 else np.float64
    out = wp.zeros(N, dtype=L2, device="cpu")
    inputs = [*by_scalar[scalar], wp.array(k, dtype=wp.int32, device="cpu"),
              wp.array(rq.astype(np_type), dtype=M33, device="cpu"), wp.array(cq.astype(np_type), dtype=V3, device="cpu"),
              wp.array(hq.astype(np_type), dtype=V3, device="cpu")]
    wp.launch(_gaps_kernel(scalar, flags), N, inputs=inputs, outputs=[out], device="cpu")
    return out.numpy()


@pytest.mark.parametrize("scalar", [wp.float32, wp.float64], ids=["float32", "float64"])
def test_the_vector_lanes_are_the_looped_lanes_bit_for_bit(records, scalar):
    """Clang's vector path and the looped one (``-DRSW_LANES_LOOP``, the path CUDA's compiler
    takes): every key and every separation, the same bits."""
    vector, looped = _run(records, scalar, ""), _run(records, scalar, "-DRSW_LANES_LOOP")
    assert np.array_equal(vector, looped, equal_nan=True)
    assert (vector[:, 1] <= 0).any() and (vector[:, 1] > 0).any()  # overlapping and parted boxes both met


def _separation(axes: np.ndarray, centre: np.ndarray, half: np.ndarray, rq, cq, hq) -> np.ndarray:
    """Gottschalk's fifteen axes in float64, written out plainly: the largest of (|T.L| - the two
    boxes' radii along L) / |L| over the six face axes and the nine edge axes A_i x B_j (those of
    |L|^2 <= 1e-6 left out); positive where an axis parts the boxes."""
    best = np.full(len(centre), -np.inf)
    t = cq - centre
    lines = [axes[:, :, i] for i in range(3)] + [rq[:, :, j] for j in range(3)]
    lines += [np.cross(axes[:, :, i], rq[:, :, j]) for i in range(3) for j in range(3)]
    for line in lines:
        n2 = np.einsum("ij,ij->i", line, line)
        ra = sum(half[:, i] * np.abs(np.einsum("ij,ij->i", axes[:, :, i], line)) for i in range(3))
        rb = sum(hq[:, j] * np.abs(np.einsum("ij,ij->i", rq[:, :, j], line)) for j in range(3))
        sep = (np.abs(np.einsum("ij,ij->i", t, line)) - ra - rb) / np.sqrt(np.maximum(n2, 1e-300))
        best = np.where(n2 > 1e-6, np.maximum(best, sep), best)
    return best


def test_the_box_test_is_gottschalks_separating_axes(records):
    """Each of the four boxes of a record against the given box: where the plain test parts them by
    more than ``HAIR`` the lanes say apart; where they overlap by more, not apart; and the key is
    the centres' squared distance."""
    assert EPS_AXIS * 0.4 / 1e-3 < HAIR / 2  # the widening, at the shortest edge axis, within the hair
    by_scalar, k, rq, cq, hq = records
    got = _run(records, wp.float32, "")
    axes, centre, half = (a.numpy()[k] for a in by_scalar[wp.float64])  # (N, 9 | 3, 4)
    decided = 0
    for lane in range(4):
        live = half[:, 0, lane] >= 0  # an empty slot's half sizes are -FAR: apart from everything
        assert (got[~live, 1, lane] > 0).all()
        box_axes = axes[:, :, lane].reshape(-1, 3, 3)  # entry 3 r + c: column c is the box's axis c
        sep = _separation(box_axes, centre[:, :, lane], half[:, :, lane], rq, cq, hq)
        key = np.sum((cq - centre[:, :, lane]) ** 2, axis=1)
        clear = live & (np.abs(sep) > HAIR)
        assert np.array_equal(got[clear, 1, lane] > 0, sep[clear] > 0)
        np.testing.assert_allclose(got[live, 0, lane], key[live], rtol=1e-5, atol=1e-8)  # float32 centres
        decided += clear.sum()
    assert decided > 0.9 * 4 * N * (half[:, 0] >= 0).mean()  # nearly every box pair clearly one or the other


def test_the_box_test_compiles_for_cuda(tmp_path):
    """No GPU is here, but NVRTC is: the looped path (the one CUDA's compiler takes) compiles to PTX."""
    assert ".entry" in ptx_of(_gaps_kernel(wp.float32, "").module, tmp_path)


def test_the_sweep_compiles_for_cuda(tmp_path):
    """The whole float32 collision module (the sweep, with the walk and what its steps keep, and the
    witness, apart and distance kernels) through NVRTC: no GPU is lent to most runs of these tests."""
    from rswarp.kernels.collide import collision_kernels
    from rswarp.kinematics.chain import mechanism_chain

    mech = rswarp.load(str(DATA / "collisions" / "fold.rsxml"))
    bodies = collision_bodies(mech)
    sweep = collision_kernels(mechanism_chain(mech), bodies.links, len(bodies.bodies), wp.float32)[0]
    ptx = ptx_of(sweep.module, tmp_path)
    assert ptx.count(".entry") >= 5
