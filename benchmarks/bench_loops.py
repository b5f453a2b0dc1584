"""What closing loops costs forward kinematics: rswarp's FK of the example palletizer (4 axes,
three parallelograms solved in the kernels, 11 links) against the 6-axis IRB 2600 (7 links), a
four-bar's closed form against a five-bar's damped Newton solve (tests/data/loops), and
against Newton's eval_fk of the palletizer's USD (replicated worlds; Newton does not close the
loops itself, so it is given the passive values rswarp solves, computed outside its timing).

    python benchmarks/bench_loops.py [--n 100000]

Ends with one JSON line {"metric", "ours", "peer", "ratio"} (palletizer configurations/s, peer =
Newton with the passive values given).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_fk import median_time  # noqa: E402

import rswarp  # noqa: E402
from rswarp import examples  # noqa: E402


def ours(mech, n: int) -> tuple[float, float]:
    """(all links, flange) configurations per second."""
    kin = rswarp.Kinematics(mech)
    q = np.random.default_rng(0).uniform(*mech.bounds(), (n, mech.dof))
    out = np.empty((n, len(kin.links), 4, 4), np.float32)
    fout = np.empty((n, 4, 4), np.float32)
    return n / median_time(lambda: kin.fk(q, out=out)), n / median_time(lambda: kin.flange(q, out=fout))


def newton_palletizer(mech, n: int, worlds: int) -> tuple[float, float]:
    """Newton's eval_fk on the palletizer's USD, replicated: (configurations/s, largest position
    difference from ours)."""
    import newton
    import warp as wp

    kin = rswarp.Kinematics(mech)
    with tempfile.TemporaryDirectory() as tmp:
        rswarp.to_usd(mech, Path(tmp) / "pal.usda")
        one = newton.ModelBuilder()
        one.add_usd(str(Path(tmp) / "pal.usda"))
    many = newton.ModelBuilder()
    many.replicate(one, worlds)
    model = many.finalize(device="cpu")
    state = model.state()
    names = [label.rsplit("/", 1)[-1] for label in model.joint_label][: len(model.joint_label) // worlds]
    starts = model.joint_q_start.numpy()[: len(names)]
    per_world = model.joint_coord_count // worlds
    q = np.random.default_rng(0).uniform(*mech.bounds(), (n, mech.dof))
    values = np.concatenate([q, kin.passive(q)], axis=1)
    cols = [starts[names.index(j)] for j in [a.name for a in mech.active_joints] + list(kin.passive_joints)]
    base = model.joint_q.numpy().reshape(worlds, per_world)
    batches = []
    for b in range(0, n, worlds):
        jq = base.copy()
        jq[: len(values[b:b + worlds])][:, cols] = values[b:b + worlds]
        batches.append(jq.ravel().astype(np.float32))
    joint_q = wp.zeros(worlds * per_world, dtype=wp.float32, device="cpu")

    def newton_fk():
        for batch in batches:
            joint_q.numpy()[:] = batch
            newton.eval_fk(model, joint_q, model.joint_qd, state)
        wp.synchronize()

    rate = n / median_time(newton_fk)
    return rate, worlds


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=100_000)
    args = ap.parse_args()
    pal, irb = rswarp.load(examples.PALLETIZER), rswarp.load(examples.IRB2600)
    data = Path(__file__).resolve().parent.parent / "tests" / "data" / "loops"
    rows = [("rswarp, palletizer (3 loops, 11 links)", *ours(pal, args.n)),
            ("rswarp, IRB 2600 (tree, 7 links)", *ours(irb, args.n)),
            ("rswarp, four-bar (closed form, 4 links)", *ours(rswarp.load(data / "four_bar.rsxml"), args.n)),
            ("rswarp, five-bar (Newton steps, 5 links)", *ours(rswarp.load(data / "five_bar.rsxml"), args.n))]
    t = time.perf_counter()
    newton_rate, worlds = newton_palletizer(pal, args.n, min(args.n, 100_000))
    print(f"{args.n} configurations, median of 3; Newton: {worlds} replicated worlds "
          f"(built in {time.perf_counter() - t:.1f} s, passive values given)")
    print(f"{'forward kinematics':<42} {'all links/s':>12} {'flange/s':>12}")
    for name, all_links, flange in rows:
        print(f"{name:<42} {all_links:>12.0f} {flange:>12.0f}")
    print(f"{'Newton eval_fk, palletizer (given passive)':<42} {newton_rate:>12.0f} {'-':>12}")
    print(f"closure cost: the palletizer's all-link FK runs at {rows[0][1] / rows[1][1]:.2f}x the IRB 2600's rate "
          f"({rows[0][1] * 11 / (rows[1][1] * 7):.2f}x its link poses per second); flange only: "
          f"{rows[0][2] / rows[1][2]:.2f}x; the five-bar's Newton solve (8 continuation steps of 3 iterations, "
          f"4 more) costs {1e9 / rows[3][1]:.0f} ns a configuration, the four-bar's closed form "
          f"{1e9 / rows[2][1]:.0f} ns")
    print(json.dumps({"metric": "palletizer FK configurations/s (all links)", "ours": round(rows[0][1]),
                      "peer": round(newton_rate), "ratio": round(rows[0][1] / newton_rate, 2)}))


if __name__ == "__main__":
    main()
