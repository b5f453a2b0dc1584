"""The closed forms of loops as device functions: a balance cylinder's pivot angle and stroke, and
a four-bar's passive joints, each from the angle of the active joint that drives it. Their float64
host twins solve the same rows on the host."""

import warp as wp

from .cache import cached
from .specs import ANGLE, DEAD_TOLERANCE, FOUR_BAR, SPEC


@cached
def slider_function(scalar=wp.float32):
    """slider_value(spec, theta): a balance cylinder's pivot angle (kind ANGLE) or piston stroke
    (kind STROKE) for the arm angle ``theta`` (``rswarp.kinematics.slider``: the pin turns about the arm
    joint O from A0; the cylinder runs from the pivot P to the pin)."""
    S = scalar
    V = wp.types.vector(SPEC, scalar)

    @wp.func
    def slider_value(spec: V, theta: S) -> S:
        c = wp.cos(theta)
        s = wp.sin(theta)
        rx = spec[4] - spec[2]
        ry = spec[5] - spec[3]
        dx = spec[2] + c * rx - s * ry - spec[6]
        dy = spec[3] + s * rx + c * ry - spec[7]
        ex = spec[4] - spec[6]
        ey = spec[5] - spec[7]
        if spec[0] == S(float(ANGLE)):
            return spec[1] * wp.atan2(ex * dy - ey * dx, ex * dx + ey * dy)
        return spec[1] * (wp.sqrt(dx * dx + dy * dy) - wp.sqrt(ex * ex + ey * ey))

    return slider_value


@cached
def four_bar_function(scalar=wp.float32):
    """four_bar_value(spec, theta): a four-bar's passive joint for the driven angle ``theta``
    (``four_bar_values`` on the host is its twin): the corner V2 where the
    circles about V1 and V3 meet, on its side at zero; NaN past a dead point."""
    S = scalar
    V = wp.types.vector(SPEC, scalar)
    V2 = wp.types.vector(2, scalar)

    @wp.func
    def turn(a: V2, b: V2) -> S:
        return wp.atan2(a[0] * b[1] - a[1] * b[0], wp.dot(a, b))

    @wp.func
    def four_bar_value(spec: V, theta: S) -> S:
        v0 = V2(spec[1], spec[2])
        v1_0 = V2(spec[3], spec[4])
        v2_0 = V2(spec[5], spec[6])
        v3 = V2(spec[7], spec[8])
        r = v1_0 - v0
        c = wp.cos(theta)
        s = wp.sin(theta)
        v1 = v0 + V2(c * r[0] - s * r[1], s * r[0] + c * r[1])
        e1 = v2_0 - v1_0
        e2 = v3 - v2_0
        l1 = wp.dot(e1, e1)
        d = v3 - v1
        dd = wp.dot(d, d)
        a = (l1 - wp.dot(e2, e2) + dd) / (S(2.0) * dd)  # the foot of V2 on V1-V3, as a share of it
        h2 = l1 / dd - a * a  # V2's offset across V1-V3, squared, as a share of it
        if h2 < -S(DEAD_TOLERANCE) * l1 / dd:
            return S(wp.nan)
        cross0 = (v3[0] - v1_0[0]) * e1[1] - (v3[1] - v1_0[1]) * e1[0]
        h = wp.sign(cross0) * wp.sqrt(wp.max(h2, S(0.0)))
        v2 = v1 + a * d + h * V2(-d[1], d[0])
        return spec[9] * theta + spec[10] * turn(e1, v2 - v1) + spec[11] * turn(e2, v3 - v2)

    return four_bar_value


@cached
def closed_function(scalar=wp.float32):
    """closed_value(spec, theta): a loop's passive joint by its closed form's kind (the generic
    walk, which reads specs from arrays; unrolled kernels choose the form at code generation)."""
    S = scalar
    V = wp.types.vector(SPEC, scalar)
    slider_value = slider_function(scalar)
    four_bar_value = four_bar_function(scalar)

    @wp.func
    def closed_value(spec: V, theta: S) -> S:
        if spec[0] == S(float(FOUR_BAR)):
            return four_bar_value(spec, theta)
        return slider_value(spec, theta)

    return closed_value
