"""On a machine with a GPU: the kernels on CUDA against the CPU, and Ray tasks on CUDA workers (and
on CPU workers) against local runs on the same device; and the time of one cable frame (the hose
of the IRB 2600ID, 10 substeps) for 256 and 4096 environments, the state kept on the device.
Prints what agrees and by how much; not a peer comparison, so no JSON line.

    python benchmarks/check_cuda.py [--samples 262144] [--cpus 8]

The "Checked on an H100" figures of docs/ray.md come from this script's runs there.
"""

from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

import numpy as np

import rswarp
from rswarp.kinematics.kinematics import Kinematics
from rswarp.kinematics.trajectory import random_trajectory
from rswarp.launch import init_warp
from rswarp.sim.cables import CableOptions, simulate_cables
from rswarp.sim.engine import Cluster, identical

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def timed(label: str, run):
    t = time.perf_counter()
    out = run()
    print(f"{label}: {time.perf_counter() - t:.2f} s", flush=True)
    return out


def local_runs(irb, hose, programs, n: int) -> dict:
    """The workspace sweep, the collision sweep and a cable run on the CPU and on CUDA."""
    out = {}
    for dev in ("cpu", "cuda"):
        out[dev, "ws"] = timed(f"workspace {dev}", lambda dev=dev: rswarp.workspace(
            irb, samples=n, seed=1, kinematics=Kinematics(irb, device=dev)))
        out[dev, "col"] = timed(f"collisions {dev}", lambda dev=dev: rswarp.collisions(irb, samples=n, seed=1,
                                                                                      device=dev))
        out[dev, "cab"] = timed(f"cables {dev}", lambda dev=dev: simulate_cables(
            hose, programs, len(programs), 2.0, CableOptions(device=dev)))
    return out


def compare_devices(res: dict) -> None:
    a, b = res["cpu", "ws"], res["cuda", "ws"]
    print("workspace reach cpu/cuda:", a.reach.value, b.reach.value, "voxel cells differing:",
          int((a.flange_voxels != b.flange_voxels).sum()), "of", int(a.flange_voxels.sum()))
    a, b = res["cpu", "col"], res["cuda", "col"]
    print("collision counts equal:", [p.collisions for p in a.pairs] == [p.collisions for p in b.pairs],
          "matrix equal:", a.disabled() == b.disabled())
    a, b = res["cpu", "cab"].cables[0], res["cuda", "cab"].cables[0]
    print("cable final points max |cpu - cuda| m:", float(np.nanmax(np.abs(a.final_points - b.final_points))),
          "peak tension max relative difference:",
          float(np.nanmax(np.abs(a.peak_tension - b.peak_tension) / np.maximum(a.peak_tension, 1e-9))),
          "ok cpu/cuda:", list(a.status).count("ok"), list(b.status).count("ok"),
          "least bend radius cpu/cuda:", float(np.nanmin(a.min_bend_radius)), float(np.nanmin(b.min_bend_radius)))


def frame_times(hose, device: str, envs_list=(256, 4096), frames: int = 120) -> None:
    """Seconds per frame of one cable's solver stepping ``envs`` environments, after a warm-up."""
    from rswarp.sim.cable.models import make_solver

    solver = make_solver(hose, hose.cables[0], CableOptions(device=device), None)
    for envs in envs_list:
        state = solver.state(envs)
        qs = np.zeros((envs, solver.substeps, hose.dof), np.float32)
        for _ in range(10):
            solver.step(state, qs, 1 / 60)
        solver.statistics(state)  # waits for the device
        t = time.perf_counter()
        for _ in range(frames):
            solver.step(state, qs, 1 / 60)
            solver.statistics(state)  # what a run reads each frame
        ms = 1e3 * (time.perf_counter() - t) / frames
        print(f"cable frame on {device}, {envs} environments: {ms:.3f} ms ({ms * 1e3 / envs:.2f} us per environment)")


def ray_runs(irb, hose, programs, n: int, res: dict) -> None:
    """Ray with the driver and the workers on CUDA, then on CPU workers: identical to local runs."""
    c = Cluster(device="cuda", task_samples=1 << 16, task_envs=4)
    ws = timed("workspace ray cuda", lambda: rswarp.workspace(
        irb, samples=n, seed=1, kinematics=Kinematics(irb, device="cuda"), cluster=c))
    col = timed("collisions ray cuda", lambda: rswarp.collisions(irb, samples=n, seed=1, device="cuda", cluster=c))
    cab = timed("cables ray cuda", lambda: simulate_cables(hose, programs, len(programs), 2.0, CableOptions(),
                                                           cluster=c))
    print("ray on cuda identical to local cuda: workspace", identical(ws, res["cuda", "ws"]), "collisions",
          identical(col, res["cuda", "col"]), "cables", identical(cab.cables, res["cuda", "cab"].cables))
    cpu = Cluster(device="cpu", task_samples=1 << 16)
    col = timed("collisions ray cpu", lambda: rswarp.collisions(irb, samples=n, seed=1, cluster=cpu))
    print("ray on cpu identical to local cpu: collisions", identical(col, res["cpu", "col"]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1 << 18)
    ap.add_argument("--cpus", type=int, default=8, help="CPUs of the local Ray instance")
    args = ap.parse_args()
    wp = init_warp()
    print("cuda devices:", wp.get_cuda_device_count(), wp.get_device("cuda").name)
    irb = rswarp.load(EXAMPLES / "irb2600_12_165" / "IRB2600_12_165__01.rsxml")
    hose = rswarp.load(EXAMPLES / "irb2600id" / "IRB2600ID_8_200__03.rsxml")
    programs = [random_trajectory(hose, 2.0, seed) for seed in range(16)]
    for device in ("cpu", "cuda"):
        frame_times(hose, device)
    res = local_runs(irb, hose, programs, args.samples)
    compare_devices(res)
    import ray

    ray.init(address="local", num_cpus=args.cpus, num_gpus=1, include_dashboard=False, logging_level=logging.ERROR,
             log_to_driver=False)
    ray_runs(irb, hose, programs, args.samples, res)


if __name__ == "__main__":
    main()
