"""Batched forward kinematics: rswarp's Kinematics against Newton's eval_fk on a replicated model.

Same process, same 6-axis robot (the bundled IRB 2600-12/1.65), same joint configurations.
Newton evaluates a model replicated into B worlds (B = min(N, 100 000), one configuration per
world) in N/B batches, as one would to keep memory bounded; its build time is that of the
replicated model. Timings are the median of 3 runs after a warm-up call (Warp compiles kernels on
the first call). "all links" is every link's pose: ours as (N, 7, 4, 4) float32 matrices, Newton's
as its body_q transforms. Ours is timed writing into a reused output buffer (as Newton writes into
its state), the flange too; the fresh-array figure, which adds first-touch page faults for the
output, is shown too.

Threads: Warp runs a CPU launch on one thread, so Newton's eval_fk uses one core; ours spreads its
launches over every core. The ratio in the JSON line is at equal threads (ours on one thread
against Newton); the all-core figure is beside it. Pinocchio's forwardKinematics (every joint's
placement; its Python API takes one configuration a call) is timed on one thread over up to
20 000 configurations, its model built from the URDF ``rswarp export`` writes before the timing.

Run: python benchmarks/bench_fk.py [--sizes 10000,100000,1000000]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

import numpy as np


def median_time(fn, repeats: int = 3) -> float:
    fn()  # warm-up: compiles and touches memory
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def ours_rates(kin, q: np.ndarray) -> tuple[float, float, float]:
    """Configurations per second: all links into a reused buffer, into a fresh array, the flange."""
    n = len(q)
    out = np.empty((n, len(kin.links), 4, 4), np.float32)
    fout = np.empty((n, 4, 4), np.float32)
    return (n / median_time(lambda: kin.fk(q, out=out)), n / median_time(lambda: kin.fk(q)),
            n / median_time(lambda: kin.flange(q, out=fout)))


def newton_rate(mech, kin, q: np.ndarray, max_worlds: int) -> tuple[int, float, float, float]:
    """Newton's eval_fk on a replicated model: (worlds, configurations/s, build seconds, largest
    position difference from ours on the last batch)."""
    import newton
    import warp as wp

    from rswarp.export.newton import newton_q_columns, to_newton

    n, cols = len(q), newton_q_columns(mech)
    worlds = min(n, max_worlds)
    t = time.perf_counter()
    many = newton.ModelBuilder()
    many.replicate(to_newton(mech), worlds)
    model = many.finalize(device="cpu")
    state = model.state()
    build = time.perf_counter() - t
    joint_q = wp.zeros(worlds * len(cols), dtype=wp.float32, device="cpu")
    joint_qd = wp.zeros(model.joint_dof_count, dtype=wp.float32, device="cpu")
    batches = [np.ascontiguousarray(q[b:b + worlds][:, cols]).ravel() for b in range(0, n, worlds)]

    def newton_fk():
        for batch in batches:
            joint_q.numpy()[: batch.size] = batch  # zero-copy view on the CPU
            newton.eval_fk(model, joint_q, joint_qd, state)
        wp.synchronize()

    rate = n / median_time(newton_fk)
    last = q[(len(batches) - 1) * worlds:]  # both give the same poses: check the last batch
    body_q = state.body_q.numpy().reshape(worlds, len(kin.links), 7)[: len(last)]
    return worlds, rate, build, float(np.abs(body_q[..., :3] - kin.fk(last)[..., :3, 3]).max())


def pinocchio_rate(mech, q: np.ndarray) -> float:
    """Pinocchio's forwardKinematics, one configuration a call, one thread: configurations/s."""
    import tempfile
    from pathlib import Path

    import pinocchio as pin

    import rswarp

    with tempfile.TemporaryDirectory() as tmp:
        urdf = Path(tmp) / "robot.urdf"
        rswarp.to_urdf(mech, urdf)
        model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    rows = [np.asarray(c, np.float64) for c in q[:20_000]]

    def run():
        for c in rows:
            pin.forwardKinematics(model, data, c)

    return len(rows) / median_time(run)


SINCOS_FLOPS = 34  # the inline sin and cos: the reduction (6), two degree-6 polynomials (12 each), the quadrant (4)


def flops_per_config(kin) -> int:
    """The arithmetic of one configuration's every-link poses, counted as the unrolled kernel does it:
    per revolute joint its sine and cosine, R's entries (a term per nonzero coefficient), rp R and
    rp t + tp over R's and t's nonzero entries (``kernels.motion.revolute_after``); a prismatic one
    3 products and 3 sums. A count of the code, not of the machine: what the limit line divides."""
    total = 0
    for j in kin.graph.active:
        if not j.revolute:
            total += 6
            continue
        a, p = np.asarray(j.axis, float), np.asarray(j.point1, float)
        outer = np.outer(a, a)
        ortho, skew = np.eye(3) - outer, np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
        terms = sum(int(x != 0) for m in (outer, ortho, skew) for x in m.ravel())
        nz = (outer != 0) | (ortho != 0) | (skew != 0)
        tz = (p - outer @ p != 0) | (ortho @ p != 0) | (skew @ p != 0)
        total += SINCOS_FLOPS + 2 * terms + 2 * 3 * int(nz.sum()) + 2 * 3 * int(tz.sum())
    return total


def copy_rate(n: int, links: int) -> float:
    """Configurations a second that a copy of the all-links output's bytes allows (one thread, a
    copy between two buffers of N x links x 64 bytes): the memory's limit on writing the poses."""
    a = np.ones((n, links, 4, 4), np.float32)
    b = np.empty_like(a)
    return n / median_time(lambda: np.copyto(b, a))


def print_limit(kin, n: int, one: float) -> tuple[float, int]:
    """Our one-thread rate beside the copy's and as arithmetic a second: how near the limit."""
    copy, flops = copy_rate(n, len(kin.links)), flops_per_config(kin)
    print(f"the limit: writing {len(kin.links) * 64} bytes a configuration, a copy of the same bytes runs "
          f"{copy / 1e6:.1f} M/s (ours on one thread at {one / copy:.0%} of it); {flops} floating-point operations "
          f"a configuration (counted from the code), {one * flops / 1e9:.2f} GFLOP/s on one thread")
    return copy, flops


def print_table(rows: list[tuple], cores: int, limit: tuple = (None, None)) -> None:
    head = ("N", "worlds", "ours all links, 1 thread", f"ours all links, {cores} threads", "ours (fresh array)",
            "ours flange", "Newton all links (1 thread)", "pinocchio (1 thread)", "ratio, 1 thread",
            f"ratio, ours on {cores}", "Newton build", "max |dp| m")
    print(" | ".join(head))
    for n, worlds, one, a, fr, fl, p, pin, nb, err in rows:
        print(" | ".join([f"{n}", f"{worlds}", f"{one / 1e6:.2f} M/s", f"{a / 1e6:.2f} M/s", f"{fr / 1e6:.2f} M/s",
                          f"{fl / 1e6:.2f} M/s", f"{p / 1e6:.2f} M/s", f"{pin / 1e6:.3f} M/s", f"{one / p:.1f}x",
                          f"{a / p:.1f}x", f"{nb:.1f} s", f"{err:.1e}"]))
    n, _, one, a, _, _, p, pin, _, _ = rows[-1]
    print(json.dumps({"metric": f"fk_all_links_configs_per_s_n{n}_1_thread", "ours": round(one), "peer": round(p),
                      "peer_name": "Newton eval_fk (one thread)", "ratio": round(one / p, 2),
                      "ours_all_cores": round(a), "ratio_all_cores": round(a / p, 2), "pinocchio": round(pin),
                      "copy_same_bytes": limit[0] and round(limit[0]), "flops_per_config": limit[1]}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="10000,100000,1000000")
    parser.add_argument("--max-worlds", type=int, default=100_000)
    parser.add_argument("--cold-cache", action="store_true",
                        help="an empty Warp kernel cache, to time the first compile of a new mechanism on a machine")
    args = parser.parse_args()
    if args.cold_cache:  # before Warp is imported: it reads the cache path at start-up
        import tempfile

        os.environ["WARP_CACHE_PATH"] = os.path.join(tempfile.mkdtemp(prefix="rswarp-bench-"), "warp")

    import newton
    import warp as wp

    import rswarp
    from rswarp import examples
    from rswarp.kinematics.kinematics import Kinematics
    from rswarp.launch import init_warp

    init_warp()  # quiet Warp
    mech = rswarp.load(examples.IRB2600)
    t = time.perf_counter()
    Kinematics(mech).close()  # builds the mechanism's kernels: Warp compiles them, or loads them from its cache
    ours_first = time.perf_counter() - t
    t = time.perf_counter()
    kin = Kinematics(mech)
    ours_build = time.perf_counter() - t
    one = Kinematics(mech, threads=1)
    rows = []
    for n in (int(s) for s in args.sizes.split(",")):
        q = np.random.default_rng(n).uniform(*mech.bounds(), (n, mech.dof)).astype(np.float32)
        all_links, fresh, flange = ours_rates(kin, q)
        single = ours_rates(one, q)[0]
        worlds, peer, build, err = newton_rate(mech, kin, q, args.max_worlds)
        rows.append((n, worlds, single, all_links, fresh, flange, peer, pinocchio_rate(mech, q), build, err))
    print(f"rswarp Kinematics vs Newton {newton.__version__} eval_fk, {mech.name}, {os.cpu_count()} CPU cores, "
          f"Warp {wp.__version__}")
    first = "compiling into an empty cache" if args.cold_cache else \
        "building the kernels, compiled or loaded from Warp's cache"
    print(f"model build: ours {ours_build * 1e3:.1f} ms ({ours_first:.2f} s the first time in a process: "
          f"{first}); Newton per row below (replicated worlds)")
    limit = print_limit(one, rows[-1][0], rows[-1][2])
    print_table(rows, os.cpu_count() or 1, limit)


if __name__ == "__main__":
    main()
