"""Export a robot to USD, load it into Newton as many parallel worlds, and compare Newton's
forward kinematics with rswarp's.

Run: python examples/newton_worlds.py [FILE.rsxml] [--worlds 64] [--out robot.usdc]
     (default: the bundled IRB 2600-12/1.65, written to a temporary folder)
"""

import argparse
import tempfile
from pathlib import Path

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = Path(__file__).parent / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
    parser.add_argument("file", nargs="?", default=str(default))
    parser.add_argument("--worlds", type=int, default=64)
    parser.add_argument("--out", help="where to write the USD (default: a temporary folder)")
    args = parser.parse_args()

    import newton
    import warp as wp

    import rswarp
    from rswarp.geometry.frames import link_origins

    mech = rswarp.load(args.file)
    usd = Path(args.out) if args.out else Path(tempfile.mkdtemp()) / f"{mech.name}.usdc"
    for warning in rswarp.to_usd(mech, usd):
        print(warning)
    print(f"wrote {usd}")

    robot = newton.ModelBuilder()
    robot.add_usd(str(usd))
    scene = newton.ModelBuilder()
    scene.replicate(robot, args.worlds)
    model = scene.finalize(device="cpu")
    print(f"Newton: {args.worlds} worlds, {model.body_count} bodies, {model.joint_count} joints")

    # random joint values within the limits, one configuration per world, by joint name
    q = np.random.default_rng(0).uniform(*mech.bounds(), (args.worlds, mech.dof))
    names = [label.rsplit("/", 1)[-1] for label in model.joint_label]
    joint_q = model.joint_q.numpy()
    starts = model.joint_q_start.numpy()
    per_world = len(names) // args.worlds
    for w in range(args.worlds):
        for j, value in zip(mech.active_joints, q[w]):
            joint_q[starts[w * per_world + names[:per_world].index(j.name)]] = value
    state = model.state()
    newton.eval_fk(model, wp.array(joint_q, dtype=wp.float32, device="cpu"), model.joint_qd, state)

    # rswarp's link frames are world-aligned at zero; the USD bodies sit at each link's origin
    poses = rswarp.Kinematics(mech).fk(q)
    origins = link_origins(mech)
    body_q = state.body_q.numpy().reshape(args.worlds, -1, 7)
    links = [label.rsplit("/", 1)[-1] for label in model.body_label[: body_q.shape[1]]]
    err = 0.0
    for b, link in enumerate(links):
        t = poses[:, mech.link_names.index(link)].astype(float)
        expected = np.einsum("nij,j->ni", t[:, :3, :3], origins[link]) + t[:, :3, 3]
        err = max(err, float(np.abs(body_q[:, b, :3] - expected).max()))
    print(f"largest difference between Newton's and rswarp's link positions: {err:.2e} m")


if __name__ == "__main__":
    main()
