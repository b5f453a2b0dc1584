"""Inverse kinematics: our closed form (every branch of every pose, on the CPU's cores) against
pinocchio's damped least squares, roboticstoolbox-python's ``ik_LM`` and ikpy, in one process, on
the bundled IRB 2600-12/1.65.

The poses are the flange poses of configurations drawn uniformly within the joint limits, away
from the wrist singularity (|q5| > 2 deg). Ours returns all eight branches of each pose (and their
configuration data); each peer returns one solution per pose from a random start, asked for
1e-10. The peers read the URDF that ``rswarp export`` writes. Figures:

- poses per second (wall, all threads for ours; the peers are single-threaded);
- error: the largest distance (m) and rotation (rad) between FK of a returned solution and its
  pose (for ours, over every valid branch with |q5| > 2 deg: the other branches of a pose may be
  near the wrist singularity; the peers' median);
- success: the share of poses answered within 1e-9 m and 1e-9 rad (for ours: every pose with the
  configuration it came from among its branches).

Usage: python benchmarks/bench_ik.py [--quick]. Ends with a JSON line: the ratio is ours (float64,
all branches) over the best peer's solved poses per second.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np

import rswarp
from rswarp.examples import IRB2600
from rswarp.kinematics import ik as ikm
from rswarp.kinematics.kinematics import Kinematics

TOL = 1e-9


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


def ours(kin: Kinematics, q: np.ndarray, targets: np.ndarray, dtype, check: int) -> dict:
    t32 = np.ascontiguousarray(targets, dtype)
    ikm.closed_form(kin.launcher, kin._ik_form(), t32[:64], dtype)  # compiled before timing
    best = np.inf
    for _ in range(3):
        t = time.perf_counter()
        sol = ikm.closed_form(kin.launcher, kin._ik_form(), t32, dtype)
        best = min(best, time.perf_counter() - t)
    ok = sol.status[:check] == ikm.OK
    rows = np.nonzero(ok & (np.abs(sol.q[:check, :, 4]) > np.radians(2)))  # away from the wrist singularity
    pos, rot = errors(kin, sol.q[:check][rows].astype(np.float64), targets[:check][rows[0]])
    near = np.abs(np.angle(np.exp(1j * (sol.q[:check] - q[:check, None])))).max(axis=-1)
    found = (near < (1e-6 if dtype == np.float64 else 1e-2)).any(axis=1)
    return {"rate": len(targets) / best, "pos": pos.max(), "rot": rot.max(), "success": found.mean(),
            "note": f"all 8 branches, {ok.sum() / check:.2f} valid per pose"}


def pinocchio_dls(urdf: Path, targets: np.ndarray, starts: np.ndarray) -> list:
    """Pinocchio's inverse-kinematics example (CLIK with Jlog6), full Gauss-Newton steps."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    fid = model.getFrameId("wrist")
    out = []
    for target, q in zip(targets, starts):
        want = pin.SE3(target[:3, :3], target[:3, 3])
        q = q.copy()
        for _ in range(200):
            pin.framesForwardKinematics(model, data, q)
            imd = data.oMf[fid].actInv(want)
            err = pin.log(imd).vector
            if np.linalg.norm(err) < 1e-10:
                break
            jac = -pin.Jlog6(imd.inverse()) @ pin.computeFrameJacobian(model, data, q, fid)
            v = -jac.T @ np.linalg.solve(jac @ jac.T + 1e-12 * np.eye(6), err)
            q = pin.integrate(model, q, v)
        out.append(q)
    return out


def rtb_lm(urdf: Path, targets: np.ndarray, starts: np.ndarray) -> list:
    import roboticstoolbox as rtb

    robot = rtb.Robot.URDF(str(urdf))
    out = []
    for target, q in zip(targets, starts):
        sol = robot.ik_LM(target, q0=q, tol=1e-20, ilimit=200, slimit=1, end="wrist")
        out.append(np.asarray(sol[0]))
    return out


def ikpy_chain(urdf: Path, targets: np.ndarray, starts: np.ndarray) -> list:
    from ikpy.chain import Chain

    chain = Chain.from_urdf_file(str(urdf), base_elements=["Base"], active_links_mask=[False] + [True] * 6 + [False])
    out = []
    for target, q in zip(targets, starts):
        full = chain.inverse_kinematics_frame(target, initial_position=np.r_[0.0, q, 0.0], orientation_mode="all")
        out.append(np.asarray(full[1:7]))
    return out


def peer(kin: Kinematics, fn, urdf: Path, targets: np.ndarray, starts: np.ndarray) -> dict:
    t = time.perf_counter()
    q = np.array(fn(urdf, targets, starts))
    wall = time.perf_counter() - t
    pos, rot = errors(kin, q, targets)
    good = (pos < TOL) & (rot < TOL)
    return {"rate": len(targets) / wall, "solved_rate": good.sum() / wall, "pos": np.median(pos),
            "rot": np.median(rot), "success": good.mean(), "note": "one solution from a random start"}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer poses (a check that the script works)")
    args = ap.parse_args()
    n, m = (100_000, 20) if args.quick else (1_000_000, 200)
    mech = rswarp.load(IRB2600)
    kin = Kinematics(mech)
    q, targets = poses(kin, n)
    lo, hi = mech.bounds()
    starts = np.random.default_rng(1).uniform(lo, hi, (m, kin.dof))
    rows = {}
    for name, dtype in (("rswarp f64", np.float64), ("rswarp f32", np.float32)):
        rows[name] = ours(kin, q, targets, dtype, check=min(n, 100_000))
    with tempfile.TemporaryDirectory() as tmp:
        urdf = Path(tmp) / "irb2600.urdf"
        rswarp.to_urdf(mech, urdf)
        for name, fn, count in (("pinocchio", pinocchio_dls, m), ("rtb ik_LM", rtb_lm, m),
                                ("ikpy", ikpy_chain, max(m // 10, 5))):
            rows[name] = peer(kin, fn, urdf, targets[:count], starts[:count])
    print(f"IRB 2600-12/1.65, {n} poses (ours), the peers on {m} (ikpy on {max(m // 10, 5)}); 2-core CPU")
    print(f"{'solver':>12} {'poses/s':>12} {'pos err m':>10} {'rot err rad':>11} {'success':>8}  note")
    for name, r in rows.items():
        print(f"{name:>12} {r['rate']:>12.4g} {r['pos']:>10.1e} {r['rot']:>11.1e} {r['success']:>8.1%}  {r['note']}")
    best = max(r["solved_rate"] for k, r in rows.items() if not k.startswith("rswarp"))
    ratio = rows["rswarp f64"]["rate"] / best
    print(f"ratio: ours (f64, all branches) / best peer (solved poses per second): {ratio:.0f}x")
    print(json.dumps({"metric": "IK poses per second, all branches, IRB 2600", "ours": rows["rswarp f64"]["rate"],
                      "peer": best, "ratio": ratio}))


if __name__ == "__main__":
    main()
