"""The design sweep: N designs of the bundled IRB 2600 dress pack over ``pick_place.mod``, run at
once (``simulate_cables`` with a ``DesignSet``: one environment per design, each its own layout),
against the same designs run one at a time, as ``rswarp cable`` runs one design (one environment,
its own solver built and its kernel launched per design).

The sweep runs as ``rswarp dresspack`` runs it: a design's verdict reads its least clearances,
never their series, so a frame measures a clearance only where it is under the least so far
(``CableOptions.frame_clearances`` False). The table also times the sweep measuring every frame's
clearances whole, as ``rswarp cable`` does, and the run checks that the two give every design the
same figures, bit for bit (the clearance series aside). One at a time runs as ``rswarp cable``.

Both sides run in this process on the same threads, after the program is planned and the kernel
compiled (neither is timed), each once a round in turn, and each keeps its best round (a noisy
spell of the shared machine meets both alike: single runs of the sweep moved by a fifth within an
hour). One at a time is timed over the first K designs and scaled to N; the table says so. This
is the fair baseline for the sweep's engine: a user's shell loop of ``rswarp cable`` would also
pay Python's start-up and the program's planning per design.
Memory: the sweep's state is a few kilobytes per design (bodies x state and wear arrays), and the
number of designs is capped (``--designs`` at most 65 536).

Usage: python benchmarks/bench_dresspack.py [--designs N] [--alone K] [--rounds R] [--device cuda].
Ends with a JSON line.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import time
from dataclasses import replace

import numpy as np
from limits import alternated

from rswarp import examples
from rswarp.kinematics.trajectory import Trajectory
from rswarp.motion.plan import program_plan
from rswarp.rsxml.documents import load_mechanism
from rswarp.sim.cable.solver import CableOptions
from rswarp.sim.cables import SWING_AFTER, simulate_cables
from rswarp.sim.designs import DesignSet, parse_vary, sample

VARY = ["length=1.14:1.2", "Link6.z=0.03:0.08", "Link6.pitch=-12:0", "Link3.x=-0.06:0"]  # the demo's box


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", type=int, default=1024)
    ap.add_argument("--alone", type=int, default=8, help="designs run one at a time (scaled to --designs)")
    ap.add_argument("--device", default="cpu", help="the Warp device both sides run on (cpu, cuda)")
    ap.add_argument("--rounds", type=int, default=2, help="rounds, each timing both sides in turn (the best kept)")
    args = ap.parse_args()
    path = str(examples.IRB2600_DRESSPACK)
    mech, _ = load_mechanism(path)
    variables = parse_vary(VARY, mech.cables[0])
    designs = DesignSet(0, variables, sample(variables, args.designs, seed=0))
    _, plan = program_plan(path, [str(examples.IRB2600_PROGRAM)], routine="main")
    traj = [Trajectory("pick_place", plan.times, plan.q)]
    options = CableOptions(device=args.device)
    simulate_cables(mech, traj, 1, 0.1, options)  # compile and warm, untimed

    least_only = replace(options, frame_clearances=False)
    mechs = designs.mechanisms(mech)[:args.alone]
    runs = {"together": lambda: _timed(lambda: simulate_cables(mech, traj, len(designs), None, least_only,
                                                               designs=designs)),
            "alone": lambda: _timed(lambda: [simulate_cables(m, traj, 1, None, options) for m in mechs])}
    rounds = alternated(runs, args.rounds)  # a noisy spell of the shared machine meets both sides alike
    together, run = min(rounds["together"], key=lambda r: r[0])
    alone = min(t for t, _ in rounds["alone"]) / len(mechs) * len(designs)
    stopped = int(sum(s != "ok" for s in run.cables[0].status))
    every_frame, whole = _timed(lambda: simulate_cables(mech, traj, len(designs), None, options, designs=designs))
    _same_figures(run.cables[0], whole.cables[0])

    print(f"{len(designs)} designs of the IRB 2600 dress pack over pick_place.mod ({plan.times[-1]:.2f} s of "
          f"program and {SWING_AFTER:g} s still after it, each), {os.cpu_count()} cores, {_device(args.device)}")
    print("| how | seconds | designs/s |")
    print("|---|---:|---:|")
    print(f"| rswarp dresspack (all at once, best of {args.rounds} rounds) | {together:.1f} | "
          f"{len(designs) / together:.2f} |")
    print(f"| all at once, every frame's clearances whole | {every_frame:.1f} | {len(designs) / every_frame:.2f} |")
    print(f"| one at a time (first {len(mechs)} timed, scaled; best of {args.rounds} rounds) | {alone:.1f} | "
          f"{len(designs) / alone:.2f} |")
    print(f"ratio: {alone / together:.2f}x; designs that stopped: {stopped}")
    print(json.dumps({"metric": f"dresspack_designs_per_s_n{len(designs)}_{args.device}",
                      "ours": round(len(designs) / together, 3), "peer": round(len(designs) / alone, 3),
                      "peer_name": "one rswarp cable run per design", "ratio": round(alone / together, 2),
                      "every_frame_s": round(every_frame, 1)}))


def _timed(call) -> tuple[float, object]:
    """(seconds, result) of one call."""
    start = time.perf_counter()
    out = call()
    return time.perf_counter() - start, out


def _same_figures(least_only, whole) -> None:
    """Every figure of the sweep that keeps only the least clearances, bit for bit those of the
    sweep that measures every frame's, the clearance series aside (NaN in the first)."""
    for f in dataclasses.fields(whole):
        a, b = getattr(least_only, f.name), getattr(whole, f.name)
        if f.name != "gap" and isinstance(b, np.ndarray) and not np.array_equal(a, b, equal_nan=b.dtype.kind == "f"):
            raise SystemExit(f"the least-only sweep's {f.name} differs from the whole sweep's")


def _device(name: str) -> str:
    from rswarp.launch import warp_device

    return "CPU" if name == "cpu" else f"{name} ({warp_device(name).name})"


if __name__ == "__main__":
    main()
