"""Inverse trigonometry inline in float64, for kernels that spend their time in it (the arm's
closed-form IK takes 20 angles a pose): libm's ``atan2`` is a call the compiler cannot see
through, and took half that kernel's time. Float32 goes through the same float64 polynomial.

``atan2`` reduces to atan(s), s in [0, 1], then evaluates atan(s) = s + s^3 P(s^2) by Estrin's
scheme. P's 19 coefficients are a Chebyshev fit of (atan(s) - s) / s^3 over t = s^2 in [0, 1]
(mpmath's ``chebyfit`` at 40 digits; its error 1.9e-16), within 2 ulp of numpy's ``arctan2``
(tests/test_trig.py). ``acos(x)`` is ``atan2(sqrt((1 + x)(1 - x)), x)``, accurate near +-1."""

from types import SimpleNamespace

import numpy as np
import warp as wp

from .cache import cached

ATAN_POLY = (  # P(t), from t^0 up
    -0.33333333333333315, 0.1999999999998641, -0.14285714284072867, 0.11111111032045885,
    -0.0909090706749639, 0.07692275905014771, -0.06666332509211019, 0.05879865489802981,
    -0.05249518584337663, 0.04705209153071265, -0.04165211802350559, 0.03536066107263382,
    -0.027590832895856107, 0.01880522404364234, -0.01059534604369583, 0.004642163938026353,
    -0.0014627303082646208, 0.00029221739308086863, -2.7633793313601145e-05,
)


@cached
def trig_funcs(scalar):
    """``atan2(y, x)``, ``acos(x)`` and ``acos_args(x)`` of one precision (x in [-1, 1])."""
    if scalar != wp.float64:
        return _through_float64(scalar)
    S = scalar
    A = wp.types.vector(len(ATAN_POLY), S)(*(S(x) for x in ATAN_POLY))
    HALF_PI, PI = S(0.5 * np.pi), S(np.pi)

    @wp.func
    def atan2(y: S, x: S) -> S:
        ax = wp.abs(x)
        ay = wp.abs(y)
        swap = ay > ax  # past 45 degrees: atan(y/x) = pi/2 - atan(x/y)
        den = wp.where(swap, ay, ax)
        s = wp.where(swap, -ax, ay) / wp.where(den > S(0.0), den, S(1.0))  # atan2(0, 0) = 0
        t = wp.max(s * s, S(1e-32))  # t^8 stays a normal number (subnormals are slow); s t P(t) is below s's ulp
        t2 = t * t
        t4 = t2 * t2
        t8 = t4 * t4
        p0 = (A[0] + A[1] * t) + (A[2] + A[3] * t) * t2
        p1 = (A[4] + A[5] * t) + (A[6] + A[7] * t) * t2
        p2 = (A[8] + A[9] * t) + (A[10] + A[11] * t) * t2
        p3 = (A[12] + A[13] * t) + (A[14] + A[15] * t) * t2
        p4 = (A[16] + A[17] * t) + A[18] * t2
        r = s + s * (t * ((p0 + p1 * t4) + ((p2 + p3 * t4) + p4 * t8) * t8))
        r = wp.where(swap, HALF_PI + r, r)
        r = wp.where(x < S(0.0), PI - r, r)
        return wp.where(y < S(0.0), -r, r)

    @wp.func
    def acos_args(x: S):
        """(y, x) with acos x = atan2(y, x): for a kernel that takes its angles later (the IK)."""
        return wp.sqrt((S(1.0) + x) * (S(1.0) - x)), x

    @wp.func
    def acos(x: S) -> S:
        y, xx = acos_args(x)
        return atan2(y, xx)

    return SimpleNamespace(atan2=atan2, acos=acos, acos_args=acos_args)


# The same atan2 over eight float64 lanes at once (``atan2_lanes``), for a kernel whose angles are
# known only once its other work is done (the arm's IK: twenty a pose, each a leaf). A native
# snippet: Warp's vectors do not become SIMD. Under clang the lanes are one vector (an AVX-512
# register, two AVX ones); any other compiler loops over them. The expression is the one above,
# operation for operation, so each lane's angle is bit for bit ``atan2``'s of the same module.
_ATAN2_EXPR = r"""
T ax = RSW_ABS(x), ay = RSW_ABS(y);
RSW_MASK swap = ay > ax;
T den = swap ? ay : ax;
T s = (swap ? -ax : ay) / (den > 0.0 ? den : (T)1.0);
T t = RSW_MAX(s * s, (T)1e-32);
T t2 = t * t, t4 = t2 * t2, t8 = t4 * t4;
T p0 = (A[0] + A[1] * t) + (A[2] + A[3] * t) * t2;
T p1 = (A[4] + A[5] * t) + (A[6] + A[7] * t) * t2;
T p2 = (A[8] + A[9] * t) + (A[10] + A[11] * t) * t2;
T p3 = (A[12] + A[13] * t) + (A[14] + A[15] * t) * t2;
T p4 = (A[16] + A[17] * t) + A[18] * t2;
T r = s + s * (t * ((p0 + p1 * t4) + ((p2 + p3 * t4) + p4 * t8) * t8));
r = swap ? HALF_PI + r : r;
r = x < 0.0 ? PI - r : r;
r = y < 0.0 ? -r : r;
"""
_ATAN2_LANES = (
    "const double A[19] = {" + ", ".join(repr(c) for c in ATAN_POLY) + "};\n"
    f"const double HALF_PI = {0.5 * np.pi!r}, PI = {np.pi!r};\n"
    "wp::vec_t<8, double> out;\n"
    "#if defined(__clang__) && !defined(__CUDA_ARCH__) && !defined(RSW_LANES_LOOP)\n"
    "typedef double T __attribute__((ext_vector_type(8)));\n"
    "#define RSW_ABS(v) __builtin_elementwise_abs(v)\n#define RSW_MAX(a, b) __builtin_elementwise_max(a, b)\n"
    "#define RSW_MASK __typeof__((T)0.0 > (T)0.0)\n"
    "T y, x;\n__builtin_memcpy(&y, &yv, 64);\n__builtin_memcpy(&x, &xv, 64);\n"
    + _ATAN2_EXPR + "__builtin_memcpy(&out, &r, 64);\n"
    "#else\n"
    "typedef double T;\n#define RSW_ABS(v) wp::abs(v)\n#define RSW_MAX(a, b) wp::max(a, b)\n#define RSW_MASK bool\n"
    "for (int ln = 0; ln < 8; ++ln) {\nT y = yv.c[ln], x = xv.c[ln];\n" + _ATAN2_EXPR + "out.c[ln] = r;\n}\n"
    "#endif\n#undef RSW_ABS\n#undef RSW_MAX\n#undef RSW_MASK\nreturn out;\n")
LANES = 8
V8D = wp.types.vector(LANES, wp.float64)


@wp.func_native(_ATAN2_LANES)
def atan2_lanes(yv: V8D, xv: V8D) -> V8D:
    """``atan2(y, x)`` of each of eight float64 lanes, as ``trig_funcs(float64).atan2``."""
    ...


def _through_float64(scalar):
    """``atan2`` and ``acos`` of another precision, evaluated in float64."""
    f = trig_funcs(wp.float64)

    @wp.func
    def atan2(y: scalar, x: scalar) -> scalar:
        return scalar(f.atan2(wp.float64(y), wp.float64(x)))

    @wp.func
    def acos(x: scalar) -> scalar:
        return scalar(f.acos(wp.float64(x)))

    @wp.func
    def acos_args(x: scalar):
        """As float64's, in float64: the angle is float64's too."""
        y, xx = f.acos_args(wp.float64(x))
        return y, xx

    return SimpleNamespace(atan2=atan2, acos=acos, acos_args=acos_args)


# sin and cos of one argument, inline: the quadrant by Cody-Waite reduction with pi/2 in three parts
# (fdlibm's pio2_1, pio2_2 of 33 bits each, whose products with the quadrant's number are exact
# below 2^20 quarter turns, and pio2_2t: the remainder keeps its digits near a zero of sin or cos),
# then fdlibm's kernel polynomials on [-pi/4, pi/4], in float64 (within 2 ulp of libm's,
# tests/test_trig.py).
SIN_POLY = (-1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04,
            2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10)
COS_POLY = (4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05,
            -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11)
PIO2_1, PIO2_2, PIO2_2T = 1.57079632673412561417e+00, 6.07710050630396597660e-11, 2.02226624879595063154e-21
TWO_OVER_PI = 6.36619772367581382433e-01


@cached
def sincos_func(scalar):
    """``sincos(x) -> vec2(sin x, cos x)`` of one precision, computed in float64."""
    D = wp.float64
    S = scalar
    V2 = wp.types.vector(2, S)
    s1, s2, s3, s4, s5, s6 = (D(c) for c in SIN_POLY)
    c1, c2, c3, c4, c5, c6 = (D(c) for c in COS_POLY)
    p1, p2, p2t, inv = D(PIO2_1), D(PIO2_2), D(PIO2_2T), D(TWO_OVER_PI)

    big = D(PIO2_1 * 2.0**20)  # beyond it (or not finite) libm's reduction, exact at any size

    @wp.func
    def sincos(x: S) -> V2:
        a = D(x)
        if not (wp.abs(a) < big):
            return V2(wp.sin(x), wp.cos(x))
        k = wp.round(a * inv)
        r = ((a - k * p1) - k * p2) - k * p2t
        z = r * r
        sr = r + r * z * (s1 + z * (s2 + z * (s3 + z * (s4 + z * (s5 + z * s6)))))
        cr = D(1.0) - D(0.5) * z + z * z * (c1 + z * (c2 + z * (c3 + z * (c4 + z * (c5 + z * c6)))))
        q = int(k) & 3  # the quadrant (two's complement: -1 is 3)
        swap = (q & 1) == 1
        sn = wp.where(swap, cr, sr)
        cn = wp.where(swap, sr, cr)
        return V2(S(wp.where((q & 2) != 0, -sn, sn)), S(wp.where(((q + 1) & 2) != 0, -cn, cn)))

    return sincos


# The same in float32 for the FK lanes (``fk_lanes``), where eight configurations share an AVX
# register and float64 would halve that: Cody-Waite with pi/2 in three float32 parts (Cephes'
# sinf), exact below 2^13 quarter turns, and Cephes' float32 polynomials on [-pi/4, pi/4].
SIN32_POLY = (-1.6666654611e-1, 8.3321608736e-3, -1.9515295891e-4)
COS32_POLY = (4.166664568298827e-2, -1.388731625493765e-3, 2.443315711809948e-5)
PIO2_32 = (1.5703125, 4.837512969970703125e-4, 7.54978995489188216e-8)
BIG32 = 8192.0  # beyond it (or not finite) libm's reduction


@cached
def sincos32_funcs():
    """(core(x) -> vec2f(sin x, cos x) for |x| < BIG32 with no branch, so a loop over lanes of it
    vectorizes; sincos(x) for any x, libm's past BIG32)."""
    S = wp.float32
    s1, s2, s3 = (S(c) for c in SIN32_POLY)
    c1, c2, c3 = (S(c) for c in COS32_POLY)
    p1, p2, p3 = (S(c) for c in PIO2_32)
    inv, big = S(TWO_OVER_PI), S(BIG32)

    @wp.func
    def core(x: S) -> wp.vec2f:
        k = wp.round(x * inv)
        r = ((x - k * p1) - k * p2) - k * p3
        z = r * r
        sr = r + r * z * (s1 + z * (s2 + z * s3))
        cr = S(1.0) - S(0.5) * z + z * z * (c1 + z * (c2 + z * c3))
        q = int(k) & 3  # the quadrant (two's complement: -1 is 3)
        swap = (q & 1) == 1
        sn = wp.where(swap, cr, sr)
        cn = wp.where(swap, sr, cr)
        return wp.vec2f(wp.where((q & 2) != 0, -sn, sn), wp.where(((q + 1) & 2) != 0, -cn, cn))

    @wp.func
    def sincos(x: S) -> wp.vec2f:
        if not (wp.abs(x) < big):
            return wp.vec2f(wp.sin(x), wp.cos(x))
        return core(x)

    return core, sincos
