"""Inverse kinematics: our closed form against the strongest peers, in one process, on the bundled
IRB 2600-12/1.65, each peer set up as its own documentation says.

- **EAIK** (``pip install eaik``): closed form by subproblem decomposition in C++, every branch.
  Built from the URDF that ``rswarp export`` writes (``eaik.IK_URDF.UrdfRobot``), asked through
  its batched entry point ``IK_batched`` with as many worker threads as ours; only its exact
  solutions count (``is_LS`` false). Its end frame is the last joint's at zero, so the poses are
  given in it (a fixed transform, applied before the timing).
- **ik-geo** (``pip install ik-geo``): closed form by subproblems in Rust, every branch; its
  ``Robot.spherical_two_parallel`` from the arm's axes; one pose per call (it has no batched entry
  point), single-threaded.
- **pinocchio** 3: its CLIK example (Jlog6, damped Gauss-Newton), asked for 1e-10, the model
  built before the timing; cold (a random start) and warm (the answer moved by 0.05 rad).
- **roboticstoolbox-python** (``ets.ik_LM`` with its own defaults, the ETS built once) and
  **ikpy**, cold and warm, where installed (``pip install -e '.[bench]'``).

Ours gives all eight branches of every pose with their ABB configuration data. The poses are
the flange poses of configurations drawn within the joint limits, away from the wrist
singularity (|q5| > 2 deg). Threads are stated per row: ours and EAIK on 1 and on all cores.

Usage: python benchmarks/bench_ik.py [--quick]. Ends with a JSON line: the ratio is ours over
EAIK, float64, every branch, on all cores for both.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np
from limits import held_gc

import rswarp
from rswarp.examples import IRB2600
from rswarp.kinematics import ik as ikm
from rswarp.kinematics.kinematics import Kinematics

TOL = 1e-9
WARM = 0.05  # rad: how far a warm start is from the answer


def poses(kin: Kinematics, n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(q, flange poses) of n configurations within the limits, |q5| > 2 deg."""
    lo, hi = kin.mech.bounds()
    q = np.random.default_rng(seed).uniform(lo, hi, (n, kin.dof))
    q[:, 4] = np.where(np.abs(q[:, 4]) < np.radians(2), np.radians(2) * np.sign(q[:, 4] + 1e-12), q[:, 4])
    link, off = kin.flange_frame()
    out = np.empty((n, 4, 4))
    for lo_ in range(0, n, 100_000):
        out[lo_:lo_ + 100_000] = kin.fk64(q[lo_:lo_ + 100_000])[:, link] @ off
    return q, out


def errors(kin: Kinematics, q: np.ndarray, targets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per row: (position error m, rotation error rad) of FK(q) against the target poses."""
    from scipy.spatial.transform import Rotation

    link, off = kin.flange_frame()
    got = kin.fk64(q)[:, link] @ off
    pos = np.linalg.norm(got[:, :3, 3] - targets[:, :3, 3], axis=1)
    rot = Rotation.from_matrix(np.swapaxes(got[:, :3, :3], 1, 2) @ targets[:, :3, :3]).magnitude()
    return pos, rot


def best_of(run, repeats: int = 3) -> float:
    """The best of ``repeats`` timed runs, the collector held off (``limits.held_gc``, as ``timeit``
    does), ours and every peer alike."""
    best = np.inf
    with held_gc():
        for _ in range(repeats):
            t = time.perf_counter()
            run()
            best = min(best, time.perf_counter() - t)
    return best


def each(fn, args) -> None:
    """``fn`` called on each of ``args``, its answer used and dropped, as a loop over targets does."""
    for a in args:
        fn(a)


def ours(mech, q: np.ndarray, targets: np.ndarray, dtype, threads: int, check: int) -> dict:
    kin = Kinematics(mech, threads=threads)
    t = np.ascontiguousarray(targets, dtype)
    solve = kin.ik64 if dtype == np.float64 else kin.ik  # the public entry point, its input checks included
    solve(t[:64])  # compiled before timing
    # into outputs reused from call to call (``out=``), as a loop over batches does and as bench_fk
    # times ours; into fresh arrays too, their page faults included (the note says it)
    out = ikm.IKSolutions(np.empty((len(t), ikm.BRANCHES, 6), dtype), np.empty((len(t), ikm.BRANCHES, ikm.CONF),
                          np.int8), np.empty((len(t), ikm.BRANCHES), np.int8))
    wall = best_of(lambda: solve(t, out=out))
    fresh = best_of(lambda: solve(t))
    sol = solve(t[:check])
    ok = sol.status == ikm.OK
    rows = np.nonzero(ok & (np.abs(sol.q[:, :, 4]) > np.radians(2)))  # away from the wrist singularity
    pos, rot = errors(kin, sol.q[rows].astype(np.float64), targets[:check][rows[0]])
    near = np.abs(np.angle(np.exp(1j * (sol.q - q[:check, None])))).max(axis=-1)
    found = (near < (1e-6 if dtype == np.float64 else 1e-2)).any(axis=1)
    return {"rate": len(targets) / wall, "solved_rate": len(targets) / wall, "pos": pos.max(), "rot": rot.max(),
            "success": found.mean(), "threads": threads,
            "note": f"all 8 branches, {ok.sum() / check:.2f} within the limits per pose; into fresh arrays "
                    f"{len(targets) / fresh:.3e}/s"}


def eaik_robot(urdf: Path, kin: Kinematics, q: np.ndarray, flange: np.ndarray):
    """EAIK's robot from the URDF, and the fixed transform from our flange to its end frame."""
    from eaik.IK_URDF import UrdfRobot

    robot = UrdfRobot(str(urdf))
    to_end = np.linalg.inv(flange[0]) @ robot.fwdKin(q[0])
    for k in (1, 2, 3):
        assert np.allclose(flange[k] @ to_end, robot.fwdKin(q[k]), atol=1e-9), "EAIK's end frame is not rigid to ours"
    return robot, to_end


def eaik(robot, to_end: np.ndarray, kin: Kinematics, q: np.ndarray, targets: np.ndarray, threads: int,
         check: int) -> dict:
    ends = targets @ to_end
    batch = [ends[i] for i in range(len(ends))]  # its documented input: a list of 4x4 arrays
    robot.IK_batched(batch[:64], num_worker_threads=threads)
    wall = best_of(lambda: robot.IK_batched(batch, num_worker_threads=threads))
    res = robot.IK_batched(batch[:check], num_worker_threads=threads)
    sols, owners = [], []
    for i, r in enumerate(res):
        exact = ~np.asarray(r.is_LS, bool)
        sols += list(np.asarray(r.Q)[exact])
        owners += [i] * int(exact.sum())
    sols, owners = np.asarray(sols), np.asarray(owners)
    pos, rot = errors(kin, sols, targets[owners])
    good = (pos < TOL) & (rot < TOL)
    near = np.abs(np.angle(np.exp(1j * (sols - q[owners])))).max(axis=-1) < 1e-6
    found = np.zeros(check, bool)
    found[owners[near & good]] = True
    return {"rate": len(targets) / wall, "solved_rate": len(targets) / wall, "pos": pos.max(), "rot": rot.max(),
            "success": found.mean(), "threads": threads,
            "note": f"every branch, {len(sols) / check:.2f} exact per pose (joint limits not applied)"}


def ik_geo(kin: Kinematics, q: np.ndarray, targets: np.ndarray) -> dict:
    """ik-geo's spherical-wrist, two-parallel-axes solver built from the arm's axes at zero."""
    from ik_geo import Robot

    arm = kin._ik_form()
    h = np.array([arm.w1, arm.w2, arm.w2 if arm.s3 > 0 else -np.asarray(arm.w2), arm.w4, arm.w5, arm.w6])
    link, off = kin.flange_frame()
    zero = kin.fk64(np.zeros((1, kin.dof)))[0, link] @ off
    c0, p1, p2, p3 = (np.asarray(v, float) for v in (arm.c0, arm.p1, arm.p2, arm.p3))
    p = np.array([p1, p2 - p1, p3 - p2, c0 - p3, np.zeros(3), np.zeros(3), zero[:3, 3] - c0])
    robot = Robot.spherical_two_parallel(h.tolist(), p.tolist())
    rm = zero[:3, :3]  # its end frame is the world's at zero: ours turned by the flange's rotation
    rots = [np.ascontiguousarray((t[:3, :3] @ rm.T).T).tolist() for t in targets]  # it reads a rotation by columns
    trans = [t[:3, 3].tolist() for t in targets]
    robot.get_ik(rots[0], trans[0])
    start = time.perf_counter()
    res = [robot.get_ik(r, p_) for r, p_ in zip(rots, trans)]
    wall = time.perf_counter() - start
    sols, owners = [], []
    for i, branches in enumerate(res):
        for qq, is_ls in branches:
            if not is_ls:
                sols.append(qq)
                owners.append(i)
    sols, owners = np.asarray(sols), np.asarray(owners)
    pos, rot = errors(kin, sols, targets[owners])
    good = (pos < TOL) & (rot < TOL)
    near = np.abs(np.angle(np.exp(1j * (sols - q[owners])))).max(axis=-1) < 1e-6
    found = np.zeros(len(targets), bool)
    found[owners[near & good]] = True
    return {"rate": len(targets) / wall, "solved_rate": len(targets) / wall, "pos": pos.max(), "rot": rot.max(),
            "success": found.mean(), "threads": 1,
            "note": f"every branch, {len(sols) / len(targets):.2f} exact per pose; one pose per call"}


def pinocchio_setup(urdf: Path):
    """Pinocchio's inverse-kinematics example (CLIK with Jlog6), the model built once."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(urdf))
    data, fid = model.createData(), model.getFrameId("wrist")

    def solve(target: np.ndarray, q: np.ndarray) -> np.ndarray:
        want = pin.SE3(target[:3, :3], target[:3, 3])
        q = q.copy()
        for _ in range(200):
            pin.framesForwardKinematics(model, data, q)
            imd = data.oMf[fid].actInv(want)
            err = pin.log(imd).vector
            if np.linalg.norm(err) < 1e-10:
                break
            jac = -pin.Jlog6(imd.inverse()) @ pin.computeFrameJacobian(model, data, q, fid)
            q = pin.integrate(model, q, -jac.T @ np.linalg.solve(jac @ jac.T + 1e-12 * np.eye(6), err))
        return q

    return solve


def rtb_setup(urdf: Path):
    """roboticstoolbox-python's ``ets.ik_LM`` with its own defaults (tolerance, iterations), the
    ETS built once (``robot.ik_LM`` would rebuild it every call)."""
    import roboticstoolbox as rtb

    ets = rtb.Robot.URDF(str(urdf)).ets(end="wrist")
    return lambda target, q: np.asarray(ets.ik_LM(target, q0=q)[0])


def ikpy_setup(urdf: Path):
    from ikpy.chain import Chain

    chain = Chain.from_urdf_file(str(urdf), base_elements=["Base"], active_links_mask=[False] + [True] * 6 + [False])
    return lambda target, q: np.asarray(chain.inverse_kinematics_frame(
        target, initial_position=np.r_[0.0, q, 0.0], orientation_mode="all")[1:7])


def iterative(kin: Kinematics, solve, targets: np.ndarray, starts: np.ndarray, how: str) -> dict:
    solve(targets[0], starts[0])
    start = time.perf_counter()
    q = np.array([solve(t, s) for t, s in zip(targets, starts)])
    wall = time.perf_counter() - start
    pos, rot = errors(kin, q, targets)
    good = (pos < TOL) & (rot < TOL)
    return {"rate": len(targets) / wall, "solved_rate": good.sum() / wall, "pos": np.median(pos),
            "rot": np.median(rot), "success": good.mean(), "threads": 1, "note": f"one solution, {how} start"}


def peers(mech, kin: Kinematics, q: np.ndarray, targets: np.ndarray, m: int, threads: int, check: int) -> dict:
    rows = {"one a call": None}
    lo, hi = mech.bounds()
    cold = np.random.default_rng(1).uniform(lo, hi, (m, kin.dof))
    warm = q[:m] + np.random.default_rng(2).uniform(-WARM, WARM, (m, kin.dof))
    with tempfile.TemporaryDirectory() as tmp:
        urdf = Path(tmp) / "irb2600.urdf"
        rswarp.to_urdf(mech, urdf)
        link, off = kin.flange_frame()
        try:
            robot, to_end = eaik_robot(urdf, kin, q, targets)
            rows["one a call"] = one_per_call(kin, q, targets, (robot, to_end))
            for t in sorted({1, threads}):
                rows[f"EAIK, {t} thread{'s' * (t > 1)}"] = eaik(robot, to_end, kin, q, targets, t, check)
        except ImportError as exc:
            print(f"EAIK: not installed ({exc.name}); pip install -e '.[bench]'")
        try:
            rows["ik-geo"] = ik_geo(kin, q[:check], targets[:check])
        except ImportError as exc:
            print(f"ik-geo: not installed ({exc.name}); pip install -e '.[bench]'")
        for name, setup, count in (("pinocchio CLIK", pinocchio_setup, m), ("rtb ets.ik_LM", rtb_setup, m),
                                   ("ikpy", ikpy_setup, max(m // 10, 5))):
            try:
                solve = setup(urdf)
            except ImportError as exc:
                print(f"{name}: not installed ({exc.name}); pip install -e '.[bench]'")
                continue
            for how, starts in (("cold", cold), ("warm", warm)):
                rows[f"{name}, {how}"] = iterative(kin, solve, targets[:count], starts[:count], how)
    return rows


SMALL_CALLS = 5_000  # calls of one pose (one configuration) each, for the fixed cost of a call
ROUNDS = 7  # rounds of every one-a-call timing, taken in turn


def one_per_call(kin: Kinematics, q: np.ndarray, targets: np.ndarray, eaik_peer=None) -> dict:
    """Calls of one pose (or configuration) each, the best of ROUNDS runs of SMALL_CALLS calls (each
    call's runs in turn with the others', EAIK's among them), as an
    interpreter or a placement search calls: ours ``ik64`` (every branch, its input checks) and
    ``fk64``/``flange`` of one configuration; EAIK's ``IK`` of one pose (every branch), where
    installed. Each answer is dropped before the next call, as a loop that uses it does. Poses (or
    calls) per second."""
    one = [targets[k:k + 1] for k in range(SMALL_CALLS)]
    qs = [q[k:k + 1] for k in range(SMALL_CALLS)]
    from rswarp.sim.bodies import collision_bodies
    from rswarp.sim.collisions import Checker

    checker = Checker(kin.mech, collision_bodies(kin.mech), threads=1)  # its trees and grids built before
    calls = (("ik64", kin.ik64, one), ("fk64", kin.fk64, qs), ("flange", kin.flange, qs),
             ("collisions", checker.verdicts, qs))
    if eaik_peer is not None:
        robot, to_end = eaik_peer
        ends = [t[0] @ to_end for t in one]
        calls += (("EAIK IK", robot.IK, ends),)
    for _, fn, args in calls:
        fn(args[0])  # compiled and recorded before timing
    # the calls taken in turn, round after round, each its best round: a burst of the machine's
    # noise falls on one round of one, not on one side's every run
    best = {name: np.inf for name, _, _ in calls}
    for _ in range(ROUNDS):
        for name, fn, args in calls:
            best[name] = min(best[name], best_of(lambda fn=fn, args=args: each(fn, args), repeats=1))
    out = {name: SMALL_CALLS / t for name, t in best.items()}
    # a call's fixed cost: its time less an item's in a batch of all of them (one thread)
    batch = {"ik64": lambda: kin.ik64(targets[:SMALL_CALLS]), "fk64": lambda: kin.fk64(q[:SMALL_CALLS]),
             "flange": lambda: kin.flange(q[:SMALL_CALLS]), "collisions": lambda: checker.verdicts(q[:SMALL_CALLS])}
    threads, kin.launcher.threads = kin.launcher.threads, 1
    out["fixed"] = {k: 1e6 / out[k] - best_of(f) / SMALL_CALLS * 1e6 for k, f in batch.items()}
    kin.launcher.threads = threads
    return out


def clock_ghz() -> float | None:
    """The CPU's clock as /proc/cpuinfo gives it (Linux), for cycles per pose."""
    try:
        mhz = [float(line.split(":")[1]) for line in open("/proc/cpuinfo") if line.startswith("cpu MHz")]
    except OSError:
        return None
    return max(mhz) / 1000 if mhz else None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer poses (a check that the script works)")
    args = ap.parse_args()
    n, m, check = (20_000, 20, 2_000) if args.quick else (1_000_000, 200, 20_000)
    cores = os.cpu_count() or 1
    mech = rswarp.load(IRB2600)
    kin = Kinematics(mech)
    q, targets = poses(kin, n)
    rows = {}
    for t in sorted({1, cores}):
        rows[f"rswarp f64, {t} thread{'s' * (t > 1)}"] = ours(mech, q, targets, np.float64, t, check)
    rows[f"rswarp f32, {cores} threads"] = ours(mech, q, targets, np.float32, cores, check)
    rows.update(peers(mech, kin, q, targets, m, cores, check))
    small = rows.pop("one a call") or one_per_call(kin, q, targets)
    print(f"IRB 2600-12/1.65: {n} poses for rswarp and EAIK, {check} for ik-geo, {m} for the iterative peers "
          f"(ikpy {max(m // 10, 5)}); {cores}-core CPU")
    print(f"{'solver':>28} {'threads':>7} {'poses/s':>12} {'pos err m':>10} {'rot err rad':>11} {'success':>8}  note")
    for name, r in rows.items():
        print(f"{name:>28} {r['threads']:>7} {r['rate']:>12.4g} {r['pos']:>10.1e} {r['rot']:>11.1e} "
              f"{r['success']:>8.1%}  {r['note']}")
    all_ = f"{cores} thread{'s' * (cores > 1)}"
    ours_all = rows[f"rswarp f64, {all_}"]["rate"]
    if "EAIK, 1 thread" in rows:
        one = rows["rswarp f64, 1 thread"]["rate"] / rows["EAIK, 1 thread"]["rate"]
        peer = rows[f"EAIK, {all_}"]["rate"]
        print(f"ratio, ours (f64, every branch) over EAIK (every branch) at equal threads: {one:.2f}x on 1, "
              f"{ours_all / peer:.2f}x on {cores}")
    else:
        one = peer = float("nan")
        print("no ratio: EAIK, the peer it is taken against, is not installed")
    ns = 1e9 / rows["rswarp f64, 1 thread"]["rate"]
    ghz = clock_ghz()
    if ghz:
        print(f"rswarp f64 on one thread: {ns:.0f} ns a pose, {ns * ghz:.0f} cycles at the {ghz:.2f} GHz "
              "/proc/cpuinfo gives")
    print(_limit(kin, rows["rswarp f64, 1 thread"]["rate"], n))
    finite = lambda x: x if np.isfinite(x) else None  # noqa: E731  (JSON has no NaN)
    _small_lines(small, finite)
    print(json.dumps({"metric": "IK poses per second, all branches, IRB 2600, float64", "ours": ours_all,
                      "peer": finite(peer), "peer_name": "EAIK IK_batched", "threads": cores,
                      "ratio": finite(ours_all / peer), "ratio_1_thread": finite(one)}))


def _limit(kin: Kinematics, rate: float, n: int) -> str:
    """Our one-thread rate beside a copy of the same bytes (a pose in, eight branches' q, conf and
    status out) and the kernel's arithmetic, counted in its generated code."""
    from limits import kernel_flops, limit_line, module_dir

    kernel = ikm.ik_kernel(kin._ik_form(), np.float64)
    flops = kernel_flops(module_dir(kernel), "arm_ik_kernel__locals__ik")
    return limit_line("IK f64 (both arms of its branches counted)", rate, 16 * 8 + 8 * (6 * 8 + 4 + 1), n, flops)


def _small_lines(small: dict, finite) -> None:
    """The one-a-call rates, and their JSON line (ours over EAIK's single-pose call)."""
    fixed = small.pop("fixed", {})
    print(f"one pose a call ({SMALL_CALLS} calls, one thread): " + ", ".join(
        f"{k} {v:,.0f}/s ({1e6 / v:.1f} us a call)" for k, v in small.items()))
    print("a call's fixed cost (its time less an item's in one batch of them all): " + ", ".join(
        f"{k} {v:.1f} us" for k, v in fixed.items()))
    peer = small.get("EAIK IK", float("nan"))
    print(f"ratio, ours (ik64) over EAIK's one-pose IK, one call each: {small['ik64'] / peer:.2f}x")
    print(json.dumps({"metric": "IK calls of one pose per second, all branches, IRB 2600, float64",
                      "ours": small["ik64"], "peer": finite(peer), "peer_name": "EAIK IK (one pose)", "threads": 1,
                      "ratio": finite(small["ik64"] / peer), "target": 100_000, "fk64_calls": small["fk64"],
                      "flange_calls": small["flange"], "collisions_calls": small["collisions"],
                      "fixed_us": {k: round(v, 2) for k, v in fixed.items()}}))


if __name__ == "__main__":
    main()
