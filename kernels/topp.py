"""Time-optimal path parameterization (TOPP-RA's reachability analysis) as device code: one path
per thread, its probes in order.

A path is joint values q(u) at probes u in [0, 1]. Along it, with x = (du/dt)² and a = d²u/dt²
held constant between neighbouring probes (x' = x + 2 Δu a), every axis's speed is |q'| √x and its
acceleration q' a + q'' x. The constraints hold at each probe and, with the stretch's a, at the
next one (TOPP-RA's interpolation scheme, which errs on the safe side of the continuous optimum):
|q' a + q'' x| ≤ A per axis, |q'| √x ≤ V per axis, √x ≤ the path's own speed cap. The backward
pass finds at each probe the fastest x from which the path can still stop at its end; the forward
pass then takes the greatest acceleration that stays within it, from rest to rest. At each probe
the constraints are bounds on a that are linear in x, so the fastest x is the least crossing of
a lower bound with an upper one: exact, no LP solver."""

import warp as wp

from .cache import cached, module_name

TINY = 1e-12  # |q'| below this: the axis does not move along the path there (only q'' x bounds it)


@wp.func
def slope(q: wp.array2d(dtype=wp.float64), u: wp.array(dtype=wp.float64), lo: int, n: int, k: int, i: int):
    """dq/du of axis i at probe k: central, one-sided at the ends."""
    a = wp.max(k - 1, 0)
    b = wp.min(k + 1, n - 1)
    return (q[lo + b, i] - q[lo + a, i]) / (u[lo + b] - u[lo + a])


@wp.func
def bend(q: wp.array2d(dtype=wp.float64), u: wp.array(dtype=wp.float64), lo: int, n: int, k: int, i: int):
    """d²q/du² of axis i at probe k (that of the probe next to it at the ends; 0 on 2 probes)."""
    if n < 3:
        return wp.float64(0.0)
    c = wp.min(wp.max(k, 1), n - 2)
    h0 = u[lo + c] - u[lo + c - 1]
    h1 = u[lo + c + 1] - u[lo + c]
    d0 = (q[lo + c, i] - q[lo + c - 1, i]) / h0
    d1 = (q[lo + c + 1, i] - q[lo + c, i]) / h1
    return wp.float64(2.0) * (d1 - d0) / (h0 + h1)


@wp.func
def ramp(u0: wp.float64, u1: wp.float64, head: wp.float64, tail: wp.float64, up: wp.float64,
         down: wp.float64):
    """|a| on the stretch [u0, u1]: a zone's ramp where it lies in one, else no bound."""
    a = wp.float64(1e300)
    if u0 < head:
        a = up
    if u1 > tail:
        a = wp.min(a, down)
    return a


@wp.func
def stretch_time(v0: wp.float64, v1: wp.float64, h: wp.float64, speed_up: wp.float64, slow_down: wp.float64):
    """The time over a stretch of ``h`` from speed v0 to v1: the change at the most the stretch's
    start allows, then the cruise (what a probe grid's constant acceleration would overstate)."""
    if v1 > v0:
        a = wp.max(speed_up, (v1 * v1 - v0 * v0) / (wp.float64(2.0) * h))
        return (v1 - v0) / a + (h - (v1 * v1 - v0 * v0) / (wp.float64(2.0) * a)) / v1
    if v1 < v0:
        a = wp.max(slow_down, (v0 * v0 - v1 * v1) / (wp.float64(2.0) * h))
        return (v0 - v1) / a + (h - (v0 * v0 - v1 * v1) / (wp.float64(2.0) * a)) / v0
    return h / v0


@wp.func
def speed_cap(q: wp.array2d(dtype=wp.float64), u: wp.array(dtype=wp.float64), lo: int, n: int, k: int,
              cap: wp.array(dtype=wp.float64), vel: wp.array2d(dtype=wp.float64), m: int):
    """The greatest x at probe k the axes' speeds and the path's cap there allow."""
    x = cap[lo + k] * cap[lo + k]
    for i in range(q.shape[1]):
        d = wp.abs(slope(q, u, lo, n, k, i))
        if d > TINY:
            x = wp.min(x, (vel[m, i] / d) * (vel[m, i] / d))
    return x


@cached
def _stretch_bounds(dof: int):
    """(bounds, fastest) for ``dof`` axes: a stretch's bounds on the path's acceleration, held in
    vectors of their count, and the fastest x they allow."""
    rows = 2 * dof + 1  # each axis at the probe and at the next, then the zone's bound on the path itself
    vec = wp.types.vector(length=rows, dtype=wp.float64)

    @wp.func
    def bounds(q: wp.array2d(dtype=wp.float64), u: wp.array(dtype=wp.float64), lo: int, n: int, k: int,
               acc: wp.array2d(dtype=wp.float64), m: int, zone: wp.float64):
        """The stretch from probe k's bounds on a, each ``|a - s[r] x| <= w[r]`` (axes at k, then at
        k + 1 with the stretch's a, then ``zone``: |a| within a zone's ramp), and the greatest x the
        axes that stand still at the probe allow (their ``q'' x`` alone)."""
        w = vec()
        s = vec()
        w[rows - 1] = zone
        still = wp.float64(1e300)
        h = u[lo + k + 1] - u[lo + k]
        for i in range(dof):
            for side in range(2):
                b = bend(q, u, lo, n, k + side, i)
                a = slope(q, u, lo, n, k + side, i)
                if side == 1:
                    a = a + wp.float64(2.0) * h * b
                r = i + i + side
                if wp.abs(a) > TINY:
                    inv = wp.float64(1.0) / a
                    w[r] = acc[m, i] * wp.abs(inv)
                    s[r] = -b * inv
                else:
                    w[r] = wp.float64(1e300)
                    s[r] = wp.float64(0.0)
                    if wp.abs(b) > TINY:
                        still = wp.min(still, acc[m, i] / wp.abs(b))
        return w, s, still

    @wp.func
    def fastest(w: vec, s: vec, reach: wp.float64, h: wp.float64, x: wp.float64):
        """The greatest x up to ``x`` at which some a meets every bound and x + 2 h a lies in
        [0, reach]: the least crossing of a lower bound with an upper one."""
        top = reach / (wp.float64(2.0) * h)  # the reach as a bound: -x / 2h <= a <= top - x / 2h
        sr = wp.float64(-1.0) / (wp.float64(2.0) * h)
        for a in range(rows):
            gap = s[a] - sr  # an axis's lower bound against the reach's upper one, and the reverse
            room = wp.where(gap > wp.float64(0.0), top + w[a], w[a])
            if room < x * wp.abs(gap):  # divided only where it binds
                x = room / wp.abs(gap)
            for b in range(a + 1, rows):
                room = w[a] + w[b]
                grow = wp.abs(s[a] - s[b])
                if room < x * grow:
                    x = room / grow
        return wp.max(x, wp.float64(0.0))

    return bounds, fastest


@cached
def _advance(dof: int):
    """The forward pass's step for ``dof`` axes."""
    rows = 2 * dof + 1
    vec = wp.types.vector(length=rows, dtype=wp.float64)

    @wp.func
    def advance(w: vec, s: vec, x: wp.float64, reach: wp.float64, h: wp.float64):
        """(x at the stretch's end, its time): the greatest acceleration the bounds and the next
        probe's reach allow, timed with what holds at both ends of the stretch (so all along it)."""
        a = (reach - x) / (wp.float64(2.0) * h)
        for r in range(rows):
            a = wp.min(a, w[r] + s[r] * x)
        x1 = wp.min(wp.max(x + wp.float64(2.0) * h * a, wp.float64(0.0)), reach)
        speed_up = wp.float64(1e300)
        slow_down = wp.float64(1e300)
        for r in range(rows):
            speed_up = wp.min(speed_up, wp.min(w[r] + s[r] * x, w[r] + s[r] * x1))
            slow_down = wp.min(slow_down, wp.min(w[r] - s[r] * x, w[r] - s[r] * x1))
        return x1, stretch_time(wp.sqrt(x), wp.sqrt(x1), h, speed_up, slow_down)

    return advance


@cached
def topp_kernel(dof: int):
    """The kernel for paths of ``dof`` axes; per path ``first`` and ``count`` locate its probes in
    the flat ``u`` (P,) and ``q`` (P, dof)."""
    bounds, fastest = _stretch_bounds(dof)
    advance = _advance(dof)

    @wp.kernel(enable_backward=False, module=module_name("topp", dof))
    def topp(
        # every path's probes, flat
        u: wp.array(dtype=wp.float64),
        q: wp.array2d(dtype=wp.float64),
        # per probe: the path's speed cap there (du/dt: the TCP's speed and turn, a corner's share of both)
        cap: wp.array(dtype=wp.float64),
        # per path: where its probes are, its axes' speeds and accelerations
        first: wp.array(dtype=wp.int32),
        count: wp.array(dtype=wp.int32),
        vel: wp.array2d(dtype=wp.float64),
        acc: wp.array2d(dtype=wp.float64),
        # per path: the share up to which it speeds up into a zone and from which it slows into one
        head: wp.array(dtype=wp.float64),
        tail: wp.array(dtype=wp.float64),
        # out, per probe: x = (du/dt)² as planned (the backward pass's reach until the forward pass
        # overwrites it), and the time at each probe from its path's start
        x_out: wp.array(dtype=wp.float64),
        t_out: wp.array(dtype=wp.float64),
    ):
        m = wp.tid()
        lo = first[m]
        n = count[m]
        reach = x_out
        reach[lo + n - 1] = wp.float64(0.0)
        c0 = cap[lo] * cap[lo]  # a zone's ramp: from rest to the cap over its share of the way, or down
        c1 = cap[lo + n - 1] * cap[lo + n - 1]
        up = wp.where(head[m] > wp.float64(0.0), c0 / (wp.float64(2.0) * head[m]), wp.float64(1e300))
        down = wp.where(tail[m] < wp.float64(1.0), c1 / (wp.float64(2.0) * (wp.float64(1.0) - tail[m])),
                        wp.float64(1e300))
        ahead = speed_cap(q, u, lo, n, n - 1, cap, vel, m)  # the axes' speeds at probes k + 1 and k
        here = speed_cap(q, u, lo, n, wp.max(n - 2, 0), cap, vel, m)
        for j in range(n - 1):  # backward: the controllable sets
            k = n - 2 - j
            w, s, still = bounds(q, u, lo, n, k, acc, m, ramp(u[lo + k], u[lo + k + 1], head[m], tail[m], up, down))
            behind = speed_cap(q, u, lo, n, wp.max(k - 1, 0), cap, vel, m)
            # within the speeds at the probe and its neighbours: the path between them holds within them
            x = wp.min(wp.min(ahead, here), wp.min(behind, still))
            reach[lo + k] = fastest(w, s, reach[lo + k + 1], u[lo + k + 1] - u[lo + k], x)
            ahead = here
            here = behind
        x = wp.float64(0.0)
        t = wp.float64(0.0)
        t_out[lo] = t
        for k in range(n - 1):  # forward: the greatest acceleration that stays controllable
            w, s, still = bounds(q, u, lo, n, k, acc, m, ramp(u[lo + k], u[lo + k + 1], head[m], tail[m], up, down))
            x1, dt = advance(w, s, x, reach[lo + k + 1], u[lo + k + 1] - u[lo + k])
            x_out[lo + k] = x  # probe k's reach is read no more
            t += dt
            t_out[lo + k + 1] = t
            x = x1
        x_out[lo + n - 1] = x

    return topp
