"""Batched forward kinematics: rswarp's Kinematics against Newton's eval_fk on a replicated model.

Same process, same 6-axis robot (the bundled IRB 2600-12/1.65), same joint configurations.
Newton evaluates a model replicated into B worlds (B = min(N, 100 000), one configuration per
world) in N/B batches, as one would to keep memory bounded; its build time is that of the
replicated model. Timings are the best of 7 runs after a warm-up call (Warp compiles kernels on
the first call), ours and the peers alike, with the garbage collector held off as ``timeit`` does:
on a shared machine the least disturbed run is the one that measures the code. "all links" is every link's pose: ours as
(N, 7, 4, 4) float32 matrices, as their top rows (N, 7, 3, 4) (``fk(q, rows=3)``) and as
position + quaternion (N, 7, 7) (``fk_transforms``), the form Newton's body_q holds (28 bytes a
pose); the JSON line's ratio is that one's, the 3x4 and 4x4 ones beside it. Ours is timed writing
into a reused output buffer (as Newton writes into its state), the flange too; the fresh-array
figure, which adds first-touch page faults for the output, is shown too. Accuracy: the largest
link-origin distance from Newton's (float32) and from pinocchio's (float64; its link frames differ
from ours by a constant offset per link), ours as 4x4 and as position + quaternion (which rounds
its rotations differently: ``kernels/fk_lanes.py``).

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
import time

import numpy as np
from limits import best_time, copy_rate


def ours_rates(kin, q: np.ndarray) -> tuple[float, float, float, float, float]:
    """Configurations per second: all links as 4x4, as 3x4 and as position + quaternion into reused
    buffers, 4x4 into a fresh array, the flange."""
    n = len(q)
    out = np.empty((n, len(kin.links), 4, 4), np.float32)
    out3 = np.empty((n, len(kin.links), 3, 4), np.float32)
    out7 = np.empty((n, len(kin.links), 7), np.float32)
    fout = np.empty((n, 4, 4), np.float32)
    return (n / best_time(lambda: kin.fk(q, out=out)), n / best_time(lambda: kin.fk(q, out=out3, rows=3)),
            n / best_time(lambda: kin.fk_transforms(q, out=out7)), n / best_time(lambda: kin.fk(q)),
            n / best_time(lambda: kin.flange(q, out=fout)))


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

    rate = n / best_time(newton_fk)
    last = q[(len(batches) - 1) * worlds:]  # both give the same poses: check the last batch
    body_q = state.body_q.numpy().reshape(worlds, len(kin.links), 7)[: len(last)]
    return worlds, rate, build, float(np.abs(body_q[..., :3] - kin.fk(last)[..., :3, 3]).max())


def pinocchio_rate(kin, q: np.ndarray) -> tuple[float, float, float]:
    """Pinocchio's forwardKinematics, one configuration a call, one thread: (configurations/s, the
    largest distance between its link origins and ours, as 4x4 and as position + quaternion, metres,
    over 2000 configurations). Its link
    frames (the URDF's, origins on the joint axes) differ from ours by a constant offset per link,
    taken at the zero configuration."""
    import tempfile
    from pathlib import Path

    import pinocchio as pin

    import rswarp

    with tempfile.TemporaryDirectory() as tmp:
        urdf = Path(tmp) / "robot.urdf"
        rswarp.to_urdf(kin.mech, urdf)
        model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    rows = [np.asarray(c, np.float64) for c in q[:20_000]]

    def run():
        for c in rows:
            pin.forwardKinematics(model, data, c)

    rate = len(rows) / best_time(run)
    frames = [(k, model.getFrameId(name)) for k, name in enumerate(kin.links) if model.existFrame(name)]

    def placements(c):
        pin.framesForwardKinematics(model, data, np.asarray(c, np.float64))
        return [data.oMf[f].homogeneous.copy() for _, f in frames]

    zero = placements(np.zeros(kin.dof))
    ours_zero = kin.fk64(np.zeros((1, kin.dof)))[0]
    offsets = [np.linalg.inv(m) @ ours_zero[k] for (k, _), m in zip(frames, zero)]
    ours, ours7 = kin.fk(q[:2000]), kin.fk_transforms(q[:2000])
    err = err7 = 0.0
    for i, c in enumerate(q[:2000]):
        for (k, _), m, o in zip(frames, placements(c), offsets):
            err = max(err, float(np.abs((m @ o)[:3, 3] - ours[i, k, :3, 3]).max()))
            err7 = max(err7, float(np.abs((m @ o)[:3, 3] - ours7[i, k, :3]).max()))
    return rate, err, err7


SINCOS_FLOPS = 24  # the lanes' float32 sine and cosine: the reduction (7), the two polynomials (7 and 9), z (1)


def compose_flops(codes: tuple) -> int:
    """A pose after a joint's motion (``lane_algebra.compose_after``): per entry a product a term whose
    factor of the motion is neither zero nor one, and the sums between; the translation's terms
    added onto the parent's."""
    total = 0
    for terms in ((codes[c], codes[3 + c], codes[6 + c]) for c in range(3)):
        total += 3 * (sum(t == 2 for t in terms) + max(sum(t != 0 for t in terms) - 1, 0))
    return total + 3 * (sum(t == 2 for t in codes[9:]) + sum(t != 0 for t in codes[9:]))


def flops_per_config(kin) -> int:
    """The arithmetic of one configuration's every-link poses, counted as the lanes kernel does it
    (``kernels/fk_lanes.py``): per revolute joint its sine and cosine, its motion's entries (a
    product and a sum per nonzero coefficient) and the composition after its parent's pose (none on
    the root); per prismatic joint its slide (21). A count of the code, not of the machine."""
    from rswarp.kernels.motion import codes_of, revolute_parts

    total = 0
    chain = kin.chain
    for k in range(len(chain.parent)):
        if chain.qidx[k] < 0:
            continue
        on_root = chain.parent[chain.parent[k]] < 0
        if chain.jtype[k] != 0:  # prismatic
            total += 21
            continue
        parts = revolute_parts(chain.axis[k], chain.point[k])
        terms = sum(int(x != 0) for part in parts[1:] for x in part)
        total += SINCOS_FLOPS + 2 * terms + (0 if on_root else compose_flops(codes_of(*parts)))
    return total


def print_limit(kin, n: int, rates: dict) -> tuple[float, int]:
    """Our one-thread rates beside the copy's and as arithmetic a second: how near the limit."""
    flops = flops_per_config(kin)
    copies = {}
    for form, nbytes in (("4x4", 64), ("3x4", 48), ("position + quaternion", 28)):
        copies[form] = copy_rate(len(kin.links) * nbytes, n)
        print(f"the limit, {form}: writing {len(kin.links) * nbytes} bytes a configuration, a copy of the same "
              f"bytes runs {copies[form] / 1e6:.1f} M/s (ours on one thread at {rates[form] / copies[form]:.0%} of it)")
    print(f"the arithmetic: {flops} floating-point operations a configuration (counted from the code), "
          f"{rates['3x4'] * flops / 1e9:.2f} GFLOP/s on one thread (3x4)")
    return copies["position + quaternion"], flops


def print_table(rows: list[tuple], cores: int, limit: tuple = (None, None)) -> None:
    head = ("N", "worlds", "ours 4x4, 1 thread", "ours 3x4, 1 thread", "ours pos+quat, 1 thread",
            f"ours 4x4, {cores} threads", "ours 4x4 (fresh array)", "ours flange", "Newton (1 thread)",
            "pinocchio (1 thread)", "ratio pos+quat", "ratio 3x4", "ratio 4x4", f"ratio 4x4, ours on {cores}",
            "Newton build", "max |dp| Newton m", "max |dp| pinocchio m", "max |dp| pinocchio m, pos+quat")
    print(" | ".join(head))
    for n, worlds, one, one3, one7, a, fr, fl, p, pin, nb, err, pin_err, pin_err7 in rows:
        print(" | ".join([f"{n}", f"{worlds}", *(f"{x / 1e6:.2f} M/s" for x in (one, one3, one7, a, fr, fl, p)),
                          f"{pin / 1e6:.3f} M/s", *(f"{x / p:.1f}x" for x in (one7, one3, one, a)), f"{nb:.1f} s",
                          f"{err:.1e}", f"{pin_err:.1e}", f"{pin_err7:.1e}"]))
    n, _, one, one3, one7, a, _, _, p, pin, _, _, pin_err, pin_err7 = rows[-1]
    print(json.dumps({"metric": f"fk_all_links_configs_per_s_n{n}_1_thread", "ours": round(one7), "peer": round(p),
                      "peer_name": "Newton eval_fk (one thread)", "ratio": round(one7 / p, 2),
                      "form": "position + quaternion (Newton's body_q form)", "ours_3x4": round(one3),
                      "ratio_3x4": round(one3 / p, 2), "ours_4x4": round(one), "ratio_4x4": round(one / p, 2),
                      "ours_all_cores_4x4": round(a), "ratio_all_cores_4x4": round(a / p, 2), "pinocchio": round(pin),
                      "max_dp_pinocchio_m": pin_err, "max_dp_pinocchio_pq_m": pin_err7,
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
        all_links, _, _, fresh, flange = ours_rates(kin, q)
        single, single3, single7 = ours_rates(one, q)[:3]
        worlds, peer, build, err = newton_rate(mech, kin, q, args.max_worlds)
        pin_rate, pin_err, pin_err7 = pinocchio_rate(one, q)
        rows.append((n, worlds, single, single3, single7, all_links, fresh, flange, peer, pin_rate, build, err,
                     pin_err, pin_err7))
    print(f"rswarp Kinematics vs Newton {newton.__version__} eval_fk, {mech.name}, {os.cpu_count()} CPU cores, "
          f"Warp {wp.__version__}")
    first = "compiling into an empty cache" if args.cold_cache else \
        "building the kernels, compiled or loaded from Warp's cache"
    print(f"model build: ours {ours_build * 1e3:.1f} ms ({ours_first:.2f} s the first time in a process: "
          f"{first}); Newton per row below (replicated worlds)")
    last = rows[-1]
    limit = print_limit(one, last[0], {"4x4": last[2], "3x4": last[3], "position + quaternion": last[4]})
    print_table(rows, os.cpu_count() or 1, limit)


if __name__ == "__main__":
    main()
