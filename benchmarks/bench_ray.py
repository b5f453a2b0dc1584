"""Ray against the plain local run, on this machine: the same batches (a workspace sweep and a
collision sweep of the IRB 2600-12/1.65, the IRB 2600ID hose over random trajectories) run
locally (Warp threads on every core) and as tasks on a local Ray instance with one worker per
core; both give identical results (asserted here), so only time differs.

    python benchmarks/bench_ray.py [--quick] [--repeats 3] [--programs 10000] [--program-seconds 60]
                                   [--nodes 100]

Prints per workload: each batch's wall time both ways and their ratio; Ray's cost per task
(extra worker-seconds of a task, from the same batch cut into many small tasks against two per
worker); the batch size from which Ray costs under 5 %. Then a paper estimate for a cluster of
``--nodes`` nodes like this one, from the throughput of the largest local batch: 10^9 collision samples
and ``--programs`` cable programs of ``--program-seconds`` each. Ray's start-up is timed apart.

Ends with one JSON line: {"metric", "ours", "peer", "ratio"}: wall seconds of the largest
collision batch on Ray (ours) and locally (peer), ratio = peer / ours.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import time
from pathlib import Path

import rswarp
from rswarp.kinematics.trajectory import random_trajectory
from rswarp.sim.cables import SETTLE_HOLD, SETTLE_MOVE, simulate_cables
from rswarp.sim.collisions import CHUNK
from rswarp.sim.engine import Cluster, connect, identical
from rswarp.sim.workspace import SAMPLE_CHUNK

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
IRB = EXAMPLES / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
ID = EXAMPLES / "irb2600id" / "IRB2600ID_8_200__03.rsxml"
CABLE_SECONDS = 10.0  # simulated seconds per environment in the cable batches (bench_cable --whole-run's)


def best(repeats: int, run) -> tuple[float, object]:
    """The least wall time of ``repeats`` runs, and the last result."""
    times, out = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - t)
    return min(times), out




@dataclasses.dataclass
class Workload:
    """A batch of a given size, run locally or on Ray with tasks of a given size."""

    name: str
    unit: str
    sizes: list[int]
    task: int  # the default task size (Cluster.task_samples / task_envs)
    fine: int  # the smallest task: one chunk, or one environment
    run: callable  # run(size, cluster or None) -> result

    def cluster(self, task: int) -> Cluster:
        key = "task_envs" if self.unit == "environment" else "task_samples"
        return Cluster(**{key: task})


def workloads(quick: bool) -> list[Workload]:
    irb, hose = rswarp.load(IRB), rswarp.load(ID)
    programs = [random_trajectory(hose, CABLE_SECONDS, seed) for seed in range(64)]
    scale = 4 if quick else 1
    return [
        Workload("workspace sweep", "sample", [s // scale for s in (1 << 19, 1 << 21, 1 << 23)], (1 << 20) // scale,
                 SAMPLE_CHUNK, lambda n, c: rswarp.workspace(irb, samples=n, seed=1, cluster=c)),
        Workload("collision sweep", "sample", [s // scale for s in (1 << 18, 1 << 20, 1 << 22)], (1 << 20) // scale,
                 CHUNK, lambda n, c: rswarp.collisions(irb, samples=n, seed=1, cluster=c)),
        Workload("cable run", "environment", [s // scale for s in (16, 64, 256)], 64 // scale, 1,
                 lambda n, c: simulate_cables(hose, programs, n, CABLE_SECONDS, cluster=c)),
    ]


def tasks(w: Workload, n: int, task: int) -> int:
    """How many tasks a batch of ``n`` makes (small batches are cut finer, for every worker)."""
    from rswarp.sim.engine import task_spans

    return len(task_spans(w.cluster(task), -(-n // w.fine), max(1, task // w.fine)))


def measure(w: Workload, repeats: int) -> dict:
    """The batches both ways (results compared), and Ray's cost per task."""
    w.run(w.sizes[0], None)
    w.run(w.sizes[0], w.cluster(w.task))  # warm: workers started, kernels loaded
    rows = []
    for n in w.sizes:
        local, a = best(repeats, lambda n=n: w.run(n, None))
        remote, b = best(repeats, lambda n=n: w.run(n, w.cluster(w.task)))
        assert identical(a, b), f"{w.name}: Ray's result differs from the local one at {n}"
        rows.append({"size": n, "tasks": tasks(w, n, w.task), "local_s": local, "ray_s": remote})
    n = w.sizes[1]
    workers = int(connect(Cluster()).cluster_resources()["CPU"])
    big = -(-n // workers)  # as few tasks as the batch allows (two per worker)
    coarse, _ = best(repeats, lambda: w.run(n, w.cluster(big)))
    fine, _ = best(repeats, lambda: w.run(n, w.cluster(w.fine)))
    few, many = tasks(w, n, big), tasks(w, n, w.fine)
    per_task = (fine - coarse) * workers / max(many - few, 1)
    under = [r["ray_s"] <= 1.05 * r["local_s"] for r in rows]  # from here on, every batch
    even = next((r["size"] for k, r in enumerate(rows) if all(under[k:])), None)
    return {"workload": w.name, "unit": w.unit, "rows": rows, "per_task_s": per_task, "break_even": even,
            "fine_tasks": many, "coarse_tasks": few, "workers": workers}


def throughput(m: dict) -> float:
    """Units per wall second on this node: the largest batch run locally, its fixed costs included
    (a difference of two noisy timings would be less stable)."""
    last = m["rows"][-1]
    return last["size"] / last["local_s"]


def estimate(results: dict, nodes: int, programs: int, program_seconds: float) -> list[tuple[str, float]]:
    """Paper estimates on ``nodes`` nodes like this one: work / (nodes x throughput), plus each
    task's cost spread over every worker."""
    out = []
    coll = results["collision sweep"]
    tasks = 1e9 / (1 << 20)
    out.append(("10^9 collision samples", 1e9 / (nodes * throughput(coll))
                + tasks * coll["per_task_s"] / (nodes * coll["workers"])))
    cab = results["cable run"]
    per_env = (program_seconds + SETTLE_MOVE + SETTLE_HOLD) / (CABLE_SECONDS + SETTLE_MOVE + SETTLE_HOLD)
    rate = throughput(cab) / per_env  # programs per second on one node
    out.append((f"{programs} cable programs of {program_seconds:g} s", programs / (nodes * rate)
                + -(-programs // 64) * cab["per_task_s"] / (nodes * cab["workers"])))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="batches a quarter the size")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--programs", type=int, default=10_000)
    ap.add_argument("--program-seconds", type=float, default=60.0)
    ap.add_argument("--nodes", type=int, default=100)
    args = ap.parse_args()
    t = time.perf_counter()
    connect(Cluster(cpus=os.cpu_count()))
    start = time.perf_counter() - t
    print(f"local Ray instance: {os.cpu_count()} workers, started in {start:.1f} s (not in the times below)")
    results = {}
    for w in workloads(args.quick):
        m = results[w.name] = measure(w, args.repeats)
        print(f"\n{w.name} ({w.unit}s; tasks of {w.task}):")
        print(f"  {'batch':>10} {'tasks':>6} {'local s':>9} {'Ray s':>9} {'Ray/local':>10}")
        for r in m["rows"]:
            print(f"  {r['size']:>10} {r['tasks']:>6} {r['local_s']:>9.3f} {r['ray_s']:>9.3f} "
                  f"{r['ray_s'] / r['local_s']:>10.3f}")
        print(f"  cost per task: {m['per_task_s'] * 1000:.1f} worker-ms ({m['fine_tasks']} tasks of {w.fine} "
              f"against {m['coarse_tasks']}); Ray costs under 5 % from "
              f"{m['break_even'] if m['break_even'] else 'none of these'} {w.unit}s; "
              f"throughput {throughput(m):.4g} {w.unit}s/s per node")
    print(f"\npaper estimate, {args.nodes} nodes like this one ({os.cpu_count()} cores each), "
          "from the throughput per node measured above:")
    for what, seconds in estimate(results, args.nodes, args.programs, args.program_seconds):
        print(f"  {what}: {seconds:.0f} s ({seconds / 60:.1f} min)")
    last = results["collision sweep"]["rows"][-1]
    print(json.dumps({"metric": f"wall s, collision sweep of {last['size']} samples, Ray ({os.cpu_count()} "
                                "workers) vs local threads", "ours": round(last["ray_s"], 3),
                      "peer": round(last["local_s"], 3), "ratio": round(last["local_s"] / last["ray_s"], 3)}))


if __name__ == "__main__":
    main()
