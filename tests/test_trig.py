"""The kernels' inline atan2 and acos against NumPy's (libm's), in both precisions."""

import numpy as np
import pytest

from rswarp.kernels.trig import trig_funcs
from rswarp.launch import init_warp

wp = init_warp()


def _evaluate(scalar, y: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(atan2(y, x), acos(x clamped into [-1, 1])) by the device functions on the CPU."""
    f = trig_funcs(scalar)

    @wp.kernel(enable_backward=False, module="unique")
    def run(y: wp.array(dtype=scalar), x: wp.array(dtype=scalar), a_out: wp.array(dtype=scalar),
            c_out: wp.array(dtype=scalar)):
        i = wp.tid()
        a_out[i] = f.atan2(y[i], x[i])
        c_out[i] = f.acos(wp.clamp(x[i], scalar(-1.0), scalar(1.0)))

    dtype = np.float64 if scalar == wp.float64 else np.float32
    ins = [wp.array(np.asarray(v, dtype), dtype=scalar, device="cpu") for v in (y, x)]
    outs = [wp.zeros(len(x), dtype=scalar, device="cpu") for _ in range(2)]
    wp.launch(run, len(x), inputs=ins, outputs=outs, device="cpu")
    return outs[0].numpy(), outs[1].numpy()


def _inputs(dtype) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(7)
    y, x = rng.normal(size=(2, 100_000)) * 10.0 ** rng.integers(-6, 4, (2, 100_000))
    edges = np.array([0.0, 1.0, -1.0, 1e-300, 3.0, -3.0])  # a zero's sign is not read: atan2(-0, -1) is pi
    ey, ex = (a.ravel() for a in np.meshgrid(edges, edges))
    near_one = 1.0 - np.logspace(-15, -1, 50)  # acos near +-1, where sqrt(1 - x^2) alone loses digits
    y = np.concatenate([y, ey, np.ones(100), np.ones(100), near_one, near_one])
    x = np.concatenate([x, ex, np.linspace(-1, 1, 100), np.tan(np.linspace(-1.5, 1.5, 100)), near_one, -near_one])
    return y.astype(dtype), x.astype(dtype)


@pytest.mark.parametrize("scalar, ulps", [(wp.float64, 2), (wp.float32, 1)])
def test_atan2_and_acos_are_within_two_ulp_of_libm(scalar, ulps):
    dtype = np.float64 if scalar == wp.float64 else np.float32
    y, x = _inputs(dtype)
    got_atan, got_acos = _evaluate(scalar, y, x)
    want_atan = np.arctan2(y.astype(np.float64), x.astype(np.float64))
    want_acos = np.arccos(np.clip(x.astype(np.float64), -1.0, 1.0))
    for got, want in ((got_atan, want_atan), (got_acos, want_acos)):
        ulp = np.spacing(np.maximum(np.abs(want), np.finfo(dtype).tiny).astype(dtype)).astype(np.float64)
        err = np.abs(got.astype(np.float64) - want) / ulp
        assert err.max() <= ulps, (err.max(), y[np.argmax(err)], x[np.argmax(err)])
    # the quadrants, signed: atan2(0, -1) is pi and atan2(-1, 0) is -pi/2
    assert (got_atan[(y == 0) & (x == -1)] == np.pi).all()
    assert np.allclose(got_atan[(y == -1) & (x == 0)], -np.pi / 2)


def _sincos(scalar, x: np.ndarray) -> np.ndarray:
    """(N, 2) sin and cos of ``x`` by the inline device function on the CPU."""
    from rswarp.kernels.trig import sincos_func

    f = sincos_func(scalar)
    V2 = wp.types.vector(2, scalar)

    @wp.kernel(enable_backward=False, module="unique")
    def run(x: wp.array(dtype=scalar), out: wp.array(dtype=V2)):
        i = wp.tid()
        out[i] = f(x[i])

    dtype = np.float64 if scalar == wp.float64 else np.float32
    out = wp.zeros(len(x), dtype=V2, device="cpu")
    wp.launch(run, len(x), inputs=[wp.array(np.asarray(x, dtype), dtype=scalar, device="cpu")], outputs=[out],
              device="cpu")
    return out.numpy()


@pytest.mark.parametrize("scalar", [wp.float64, wp.float32])
def test_inline_sincos_is_within_two_ulp_of_libm(scalar):
    """Joint angles over ten turns either way, quadrant edges, tiny and huge arguments (libm's own
    reduction past 2^20 quarter turns), and NaN: within 2 ulp of NumPy's sin and cos, or of the
    float64 value rounded to float32, as the inline atan2 is held."""
    rng = np.random.default_rng(3)
    x = np.concatenate([rng.uniform(-20 * np.pi, 20 * np.pi, 200_000), np.arange(-16, 17) * np.pi / 4,
                        np.nextafter(np.arange(-8, 9) * np.pi / 2, np.inf), [0.0, 1e-300, 1e-8, 1e7, -3e9, 1e300]])
    dtype = np.float64 if scalar == wp.float64 else np.float32
    with np.errstate(over="ignore"):
        x = x.astype(dtype)
    x = x[np.isfinite(x)]
    got = _sincos(scalar, x)
    exact = np.stack([np.sin(x.astype(np.float64)), np.cos(x.astype(np.float64))], axis=1).astype(dtype)
    ulp = np.spacing(np.maximum(np.abs(exact), np.finfo(dtype).tiny)).astype(np.float64)
    err = np.abs(got.astype(np.float64) - exact.astype(np.float64)) / ulp
    assert err.max() <= 2.0, (x[np.argmax(err.max(axis=1))], err.max())
    assert np.isnan(_sincos(scalar, np.array([np.nan, np.inf], dtype))).all()


def test_float32_sincos_of_the_fk_lanes():
    """The FK lanes' float32 sine and cosine (Cephes' reduction and polynomials): within 2 ulp of
    the float64 value rounded to float32 where |value| > 1e-3, within 2e-10 near a zero (the
    reduction's last part, a float32, keeps the rest to that); libm's past BIG32, NaN for NaN."""
    from rswarp.kernels.trig import BIG32, sincos32_funcs

    f = sincos32_funcs()[1]

    @wp.kernel(enable_backward=False, module="unique")
    def run(x: wp.array(dtype=wp.float32), out: wp.array(dtype=wp.vec2f)):
        i = wp.tid()
        out[i] = f(x[i])

    rng = np.random.default_rng(4)
    x = np.concatenate([rng.uniform(-20 * np.pi, 20 * np.pi, 200_000), rng.uniform(-BIG32, BIG32, 50_000),
                        np.arange(-16, 17) * np.pi / 4, [0.0, 1e-30, 1e-8, 1e5, -3e9]]).astype(np.float32)
    x = np.concatenate([x, np.nextafter(x[-38:-5], np.float32(np.inf))])
    out = wp.zeros(len(x), dtype=wp.vec2f, device="cpu")
    wp.launch(run, len(x), inputs=[wp.array(x, dtype=wp.float32, device="cpu")], outputs=[out], device="cpu")
    got = out.numpy().astype(np.float64)
    exact = np.stack([np.sin(x.astype(np.float64)), np.cos(x.astype(np.float64))], axis=1).astype(np.float32)
    big = np.abs(exact) > 1e-3
    ulp = np.spacing(np.abs(exact)).astype(np.float64)
    assert (np.abs(got - exact)[big] / ulp[big]).max() <= 2.0
    assert np.abs(got - exact)[~big].max() < 2e-10
    out = wp.zeros(2, dtype=wp.vec2f, device="cpu")
    wp.launch(run, 2, inputs=[wp.array(np.float32([np.nan, np.inf]), device="cpu")], outputs=[out], device="cpu")
    assert np.isnan(out.numpy()).all()
