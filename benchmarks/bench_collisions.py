"""Self-collision throughput on the IRB 2600-12/1.65: rswarp's Warp kernels (forward kinematics
inside, every core) against python-fcl and Coal (one core, poses given), same states, same process,
the 15 non-adjacent link pairs; then the verdict agreement table and the full collision matrix.

    python benchmarks/bench_collisions.py [--states 20000] [--peer-states 2000] [--matrix 1000000]

Ends with one JSON line: {"metric", "ours", "peer", "ratio"} (states per second, peer = python-fcl).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import rswarp
from rswarp.report.collisions import collisions_text
from rswarp.sim.bodies import Bodies, collision_bodies
from rswarp.sim.collisions import Checker, collisions

IRB = Path(__file__).resolve().parents[1] / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"


def peer_objects(lib, bodies):
    """One collision object per body: python-fcl's or Coal's OBBRSS trees of the same triangles."""
    objs = []
    for b in bodies.bodies:
        model = lib.BVHModel() if lib.__name__ == "fcl" else lib.BVHModelOBBRSS()
        model.beginModel(len(b.faces), len(b.vertices))
        if lib.__name__ == "fcl":
            model.addSubModel(b.vertices, b.faces.astype(np.int32))
        else:
            verts, tris = lib.StdVec_Vec3s(), lib.StdVec_Triangle()
            verts.extend(list(b.vertices))
            tris.extend([lib.Triangle(int(i), int(j), int(k)) for i, j, k in b.faces])
            model.addSubModel(verts, tris)
        model.endModel()
        objs.append(lib.CollisionObject(model, lib.Transform3s() if hasattr(lib, "Transform3s") else lib.Transform()))
    return objs


def peer_verdicts(lib, bodies, poses: np.ndarray) -> tuple[np.ndarray, float]:
    """Verdicts and seconds for every state and pair (the poses given, as the peers are used)."""
    objs = peer_objects(lib, bodies)
    out = np.zeros((len(poses), len(bodies.pairs)), bool)
    fcl = lib.__name__ == "fcl"
    transform = (lambda m: lib.Transform(m[:3, :3], m[:3, 3])) if fcl else (lambda m: lib.Transform3s(m[:3, :3], m[:3, 3]))
    request = lib.CollisionRequest()
    t = time.perf_counter()
    for i in range(len(poses)):
        for obj, b in zip(objs, bodies.bodies):
            obj.setTransform(transform(poses[i, b.link]))
        for p, (a, b) in enumerate(bodies.pairs):
            result = lib.CollisionResult()
            out[i, p] = lib.collide(objs[a], objs[b], request, result) > 0
    return out, time.perf_counter() - t


def per_pair(mech, bodies, q: np.ndarray) -> None:
    """Where the time goes: each pair alone, on one core (forward kinematics included in each)."""
    print(f"\n{'pair (one core)':<20} {'us/state':>9} {'collides':>9}")
    for p, names in enumerate(bodies.pair_names()):
        checker = Checker(mech, Bodies(bodies.bodies, (bodies.pairs[p],), bodies.adjacent, ()), threads=1)
        t = time.perf_counter()
        hit = checker.verdicts(q)[0]
        print(f"{'/'.join(names):<20} {(time.perf_counter() - t) / len(q) * 1e6:>9.2f} {hit.mean():>9.2%}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--states", type=int, default=200_000, help="states for rswarp")
    ap.add_argument("--peer-states", type=int, default=5_000, help="states for each peer (a prefix of ours)")
    ap.add_argument("--matrix", type=int, default=1_000_000, help="samples of the full-matrix run (0: skip)")
    ap.add_argument("--per-pair", type=int, default=20_000, help="states for the per-pair table (0: skip)")
    args = ap.parse_args()
    mech = rswarp.load(str(IRB))
    bodies = collision_bodies(mech)
    checker = Checker(mech, bodies)
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(0).random((args.states, len(lower)))
    checker.verdicts(q[:1024])  # warm-up (compiled already, pages touched)
    t = time.perf_counter()
    ours, _ = checker.verdicts(q)
    ours_s = time.perf_counter() - t
    poses = rswarp.Kinematics(mech).fk64(q[:args.peer_states])
    rows = [("rswarp (Warp, FK inside, 2 threads)", args.states, ours_s)]
    agree = {}
    for name in ("fcl", "coal"):
        try:
            lib = __import__(name)
        except ImportError:
            print(f"{name}: not installed, skipped")
            continue
        ref, secs = peer_verdicts(lib, bodies, poses)
        rows.append((f"{'python-fcl' if name == 'fcl' else 'Coal'} (poses given, 1 thread)", len(poses), secs))
        mine = ours[:len(poses)]
        agree[name] = (int((mine == ref).sum()), int((ref & ~mine).sum()), int((mine & ~ref).sum()))
    print(f"{'checker':<42} {'states':>8} {'us/state':>10} {'states/s':>12}")
    for name, n, secs in rows:
        print(f"{name:<42} {n:>8} {secs / n * 1e6:>10.2f} {n / secs:>12.0f}")
    print(f"\nverdicts on {len(poses)} states x {len(bodies.pairs)} pairs:")
    print(f"{'peer':<8} {'agree':>8} {'peer only':>10} {'ours only (containment)':>24}")
    for name, (same, peer_only, ours_only) in agree.items():
        print(f"{name:<8} {same:>8} {peer_only:>10} {ours_only:>24}")
    if args.per_pair:
        per_pair(mech, bodies, q[:args.per_pair])
    if args.matrix:
        t = time.perf_counter()
        c = collisions(mech, samples=args.matrix)
        print(f"\nfull matrix from {c.samples} samples: {time.perf_counter() - t:.1f} s")
        print(collisions_text(c, mech, {}))
    ours_rate = args.states / ours_s
    fcl_row = [r for r in rows if r[0].startswith("python-fcl")]
    peer_rate = fcl_row[0][1] / fcl_row[0][2] if fcl_row else float("nan")
    print(json.dumps({"metric": "self-collision states/s, IRB 2600, 15 pairs", "ours": round(ours_rate),
                      "peer": round(peer_rate), "ratio": round(ours_rate / peer_rate, 2)}))


if __name__ == "__main__":
    main()
