"""Loop closure by damped Newton steps with continuation, as device code the FK kernels call once
per configuration before posing links (the host twin, ``newton_loop_values``, says why).

Each loop is specialized at code generation: its two paths' joints are unrolled with their axes
and points folded in as constants; the unknowns (the loop's passive joints) live in one vector
shared by all loops, ``solve(q, i)``, NaN for a loop that cannot close at that configuration.
"""

from typing import Any

import numpy as np
import warp as wp

from .cache import cached
from .motion import revolute_motion
from .specs import (
    CLOSING,
    CLOSURE_TOLERANCE,
    FINE_ITERATIONS,
    FINE_STEPS,
    ITERATIONS,
    MAX_STEP,
    NEAR,
    PATH_A,
    PATH_B,
    POLISH,
    SINGULAR,
    STEPS,
    square_rows,
)
from .types import Chain, types_of


def unknowns(chain: Chain) -> int:
    """How many passive joints the Newton solve sets (at least 1: the vector the kernels carry)."""
    return max(1, int(chain.unknown.max()) + 1)


def loop_solver(chain: Chain, scalar=wp.float32):
    """``solve(q, i) -> x``: every Newton-solved passive joint at configuration ``q[i]`` (a vector
    of ``unknowns(chain)``), or None when the chain has no such loop."""
    if not len(chain.newton_rows):
        return None
    VM = wp.types.vector(unknowns(chain), scalar)
    rows = np.asarray(chain.newton_rows)
    loops = tuple(_loop_solve(rows[rows[:, 0] == lid], VM, scalar) for lid in np.unique(rows[:, 0]))

    @wp.func
    def solve(q: wp.array2d(dtype=scalar), i: int) -> VM:
        x = VM()
        for n in range(wp.static(len(loops))):
            x = wp.static(loops[n])(q, i, x)
        return x

    return solve


def _loop_solve(rows: np.ndarray, VM, scalar):
    """One loop's solve: continuation from zero in STEPS steps of ITERATIONS Newton steps, POLISH
    more at the target; a path that comes near a singular pose (the square part's determinant
    under NEAR of zero's) is taken again in FINE_STEPS steps. NaN for its unknowns where the
    closure's residual stays above CLOSURE_TOLERANCE or the path meets a singular pose (under SINGULAR)."""
    S = scalar
    V3 = types_of(scalar).vec3
    u = rows[:, 4][rows[:, 4] >= 0].astype(int)
    first, m = int(u.min()), int(u.max() - u.min() + 1)
    ends = _ends(rows, first, m, VM, scalar)
    newton = _newton_step(rows, first, m, ends, VM, scalar)

    @wp.func
    def passage(q: wp.array2d(dtype=S), i: int, x0: VM, steps: int, iterations: int):
        x = x0
        for a in range(wp.static(m)):
            x[wp.static(first) + a] = S(0.0)
        ratio = S(wp.inf)
        for k in range(steps + 1):
            s = S(1.0)
            n = POLISH
            if k < steps:
                s = S(k + 1) / S(steps)
                n = iterations
            for _ in range(n):
                x, r = newton(q, i, x, s)
                if wp.isnan(r) or r < ratio:
                    ratio = r
        return x, ratio

    @wp.func
    def loop_solve(q: wp.array2d(dtype=S), i: int, x0: VM) -> VM:
        x, ratio = passage(q, i, x0, STEPS, ITERATIONS)
        if wp.isnan(ratio) or ratio < S(NEAR):
            x, ratio = passage(q, i, x0, FINE_STEPS, FINE_ITERATIONS)
        e = ends(q, i, x, S(1.0), wp.zeros(shape=wp.static(m), dtype=V3), wp.zeros(shape=wp.static(m), dtype=V3))
        gap = wp.length(V3(e[0, 0] - e[2, 0], e[0, 1] - e[2, 1], e[0, 2] - e[2, 2]))
        gap += wp.length(V3(e[1, 0] - e[3, 0], e[1, 1] - e[3, 1], e[1, 2] - e[3, 2]))
        if wp.isnan(gap) or gap > S(CLOSURE_TOLERANCE) or wp.isnan(ratio) or ratio < S(SINGULAR):
            for a in range(wp.static(m)):
                x[wp.static(first) + a] = S(wp.nan)
        return x

    return loop_solve


def _ends(rows: np.ndarray, first: int, m: int, VM, scalar):
    """``ends(q, i, x, s, axes, anchors) -> (4, 3)``: the closing joint's point and axis carried by path A,
    then by path B (rows), with active joints at ``s`` times their values; each unknown's world axis
    and point before its joint go to ``axes[a]``, ``anchors[a]`` (local arrays)."""
    T = types_of(scalar)
    S, V3 = T.scalar, T.vec3
    M43 = wp.types.matrix((4, 3), S)
    closing = rows[rows[:, 1] == CLOSING][0]
    pc, ac = V3(*(float(v) for v in closing[8:11])), V3(*(float(v) for v in closing[5:8]))
    path_a, path_b = (_path(rows[rows[:, 1] == role], first, T) for role in (PATH_A, PATH_B))

    @wp.func
    def ends(q: wp.array2d(dtype=S), i: int, x: VM, s: S, axes: Any, anchors: Any) -> M43:
        ra = wp.identity(n=3, dtype=S)
        ta = V3()
        for n in range(wp.static(len(path_a))):
            ra, ta = wp.static(path_a[n])(q, i, x, s, ra, ta, axes, anchors)
        rb = wp.identity(n=3, dtype=S)
        tb = V3()
        for n in range(wp.static(len(path_b))):
            rb, tb = wp.static(path_b[n])(q, i, x, s, rb, tb, axes, anchors)
        xa = ra * wp.static(pc) + ta
        aa = ra * wp.static(ac)
        xb = rb * wp.static(pc) + tb
        ab = rb * wp.static(ac)
        return M43(xa[0], xa[1], xa[2], aa[0], aa[1], aa[2], xb[0], xb[1], xb[2], ab[0], ab[1], ab[2])

    return ends


def _path(rows: np.ndarray, first: int, T) -> tuple:
    """A wp.func per joint of one path: ``(q, i, x, s, r, t, axes, anchors) -> (r, t)`` applies the joint."""
    V3 = T.vec3
    out = []
    for row in rows:
        jtype, col, u = int(row[2]), int(row[3]), int(row[4])
        axis, point = V3(*(float(v) for v in row[5:8])), V3(*(float(v) for v in row[8:11]))
        rot, tra = revolute_motion(row[5:8], row[8:11], T) if jtype == 0 else (None, None)
        out.append(_joint(jtype, col, u - first if u >= 0 else -1, u, axis, point, rot, tra, T))
    return tuple(out)


def _joint(jtype: int, col: int, local: int, u: int, axis, point, rot, tra, T):
    S, V3, M33 = T.scalar, T.vec3, T.mat33
    revolute = jtype == 0

    @wp.func
    def joint(q: wp.array2d(dtype=S), i: int, x: Any, s: S, r: M33, t: V3, axes: Any, anchors: Any):
        v = S(0.0)
        if wp.static(col >= 0):
            v = s * q[i, wp.static(max(col, 0))]
        if wp.static(local >= 0):
            v = x[wp.static(max(u, 0))]
            axes[wp.static(max(local, 0))] = r * wp.static(axis)
            anchors[wp.static(max(local, 0))] = r * wp.static(point) + t
        if wp.static(revolute):
            c = wp.cos(v)
            sn = wp.sin(v)
            return r * wp.static(rot)(c, sn), r * wp.static(tra)(c, sn) + t
        return r, r * (v * wp.static(axis)) + t

    return joint


def _newton_step(rows: np.ndarray, first: int, m: int, ends, VM, scalar):
    """``newton(q, i, x, s) -> (x, ratio)``: one Gauss-Newton step on the closure (normal equations
    solved by elimination, unrolled), damped to MAX_STEP; and the determinant of the closure's square
    part before the step, relative to zero's (``specs.square_rows``)."""
    T = types_of(scalar)
    S, V3 = T.scalar, T.vec3
    kinds, sides = np.zeros(m, int), np.zeros(m)
    for row in rows[rows[:, 4] >= 0]:
        kinds[int(row[4]) - first] = int(row[2])
        sides[int(row[4]) - first] = 1.0 if row[1] == PATH_A else -1.0
    kinds, sides = tuple(int(k) for k in kinds), tuple(float(v) for v in sides)
    solve = _normal_solve(m, scalar)
    square = _square_det(tuple(square_rows(rows)), float(rows[rows[:, 1] == CLOSING][0, 12]), scalar)

    @wp.func
    def newton(q: wp.array2d(dtype=S), i: int, x: VM, s: S):
        axes = wp.zeros(shape=wp.static(m), dtype=V3)
        anchors = wp.zeros(shape=wp.static(m), dtype=V3)
        e = ends(q, i, x, s, axes, anchors)
        xa = V3(e[0, 0], e[0, 1], e[0, 2])
        aa = V3(e[1, 0], e[1, 1], e[1, 2])
        xb = V3(e[2, 0], e[2, 1], e[2, 2])
        ab = V3(e[3, 0], e[3, 1], e[3, 2])
        ep = xa - xb
        ea = aa - ab
        JP = wp.zeros(shape=wp.static(m), dtype=V3)
        JA = wp.zeros(shape=wp.static(m), dtype=V3)
        for a in range(wp.static(m)):
            sign = S(wp.static(sides[a]))
            end = xb
            ax = ab
            if sign > S(0.0):
                end = xa
                ax = aa
            if wp.static(kinds[a] == 0):
                JP[a] = sign * wp.cross(axes[a], end - anchors[a])
                JA[a] = sign * wp.cross(axes[a], ax)
            else:
                JP[a] = sign * axes[a]
                JA[a] = V3()
        dx = solve(JP, JA, ep, ea)
        norm = S(0.0)
        for a in range(wp.static(m)):
            norm += dx[a] * dx[a]
        scale = S(1.0)
        if norm > S(MAX_STEP * MAX_STEP):
            scale = S(MAX_STEP) / wp.sqrt(norm)
        out = x
        for a in range(wp.static(m)):
            out[wp.static(first) + a] = x[wp.static(first) + a] - scale * dx[a]
        return out, square(JP, JA)

    return newton


def _square_det(square: tuple, det0: float, scalar):
    """``ratio(JP, JA)``: the determinant of the Jacobian's rows ``square`` (0-2 position, 3-5
    axis), by elimination, relative to ``det0`` (its value at zero); NaN where a pivot vanishes."""
    S = scalar
    m = len(square)
    Mm = wp.types.matrix((m, m), S)

    @wp.func
    def ratio(JP: Any, JA: Any) -> S:
        a = Mm()
        for r in range(wp.static(m)):
            for c in range(wp.static(m)):
                if wp.static(square[r] < 3):
                    a[r, c] = JP[c][wp.static(square[r] % 3)]
                else:
                    a[r, c] = JA[c][wp.static(square[r] % 3)]
        det = S(1.0)
        for k in range(wp.static(m)):
            det = det * a[k, k]
            for r in range(k + 1, wp.static(m)):
                f = a[r, k] / a[k, k]
                for c in range(wp.static(m)):
                    a[r, c] = a[r, c] - f * a[k, c]
        return det / S(det0)

    return ratio


@cached
def _normal_solve(m: int, scalar):
    """``solve(JP, JA, ep, ea) -> dx``: (JᵀJ + εI) dx = Jᵀe for the m columns (JP[a], JA[a]) and
    the residual (ep, ea), by Gaussian elimination (JᵀJ is symmetric positive definite)."""
    S = scalar
    Vm = wp.types.vector(m, S)
    Mm = wp.types.matrix((m, m), S)

    @wp.func
    def solve(JP: Any, JA: Any, ep: Any, ea: Any) -> Vm:
        a = Mm()
        b = Vm()
        for r in range(wp.static(m)):
            b[r] = wp.dot(JP[r], ep) + wp.dot(JA[r], ea)
            for c in range(wp.static(m)):
                a[r, c] = wp.dot(JP[r], JP[c]) + wp.dot(JA[r], JA[c])
            a[r, r] = a[r, r] + S(1.0e-12)
        for k in range(wp.static(m)):
            for r in range(k + 1, wp.static(m)):
                f = a[r, k] / a[k, k]
                for c in range(wp.static(m)):
                    a[r, c] = a[r, c] - f * a[k, c]
                b[r] = b[r] - f * b[k]
        dx = Vm()
        for kk in range(wp.static(m)):
            k = wp.static(m) - 1 - kk
            v = b[k]
            for c in range(k + 1, wp.static(m)):
                v -= a[k, c] * dx[c]
            dx[k] = v / a[k, k]
        return dx

    return solve
