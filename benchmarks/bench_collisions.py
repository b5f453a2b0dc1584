"""Self-collision throughput on the IRB 2600-12/1.65: rswarp's Warp kernels (forward kinematics
inside, every core) against python-fcl and Coal (one core, poses given), same states, same process,
the 15 non-adjacent link pairs; then the verdict agreement table and the full collision matrix.

    python benchmarks/bench_collisions.py [--states 200000] [--peer-states 5000] [--matrix 1000000]
                                          [--per-pair 20000] [--repeats 3] [--rounds 3]

Every checker is timed once a round, in turn, and keeps its best run of all rounds: a noisy spell
of the shared machine meets ours and the peers alike. Ends with one JSON line: {"metric", "ours",
"peer", "ratio"} (states per second at equal threads, one each, peer = python-fcl; the all-core
figure beside it). Each peer is asked two ways, its trees
built before the timing: pair by pair (``collide`` on each of the 15 pairs) and, for Coal, through
its broadphase manager (a dynamic AABB tree, registered once, each object's AABB recomputed and the
tree updated per state, as its docs set it up): its native ``CollisionCallBackCollect`` gathers the
pairs whose boxes overlap, and the narrow phase is asked of those of the 15 only (Coal's Python
binding cannot subclass a callback, so the cull and the narrow phase meet here, in Python, as in any
application that uses it). python-fcl's manager is left out:
its callback is handed new wrappers of the objects with nothing to tell which bodies they are, and
its documented use (``defaultCollisionCallback`` collecting contacts) stops at ``num_max_contacts``,
so neither gives every pair's verdict.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
from limits import alternated, best_time

import rswarp
from rswarp.kernels.witness import APART, CROSSING
from rswarp.report.collisions import collisions_text
from rswarp.sim.bodies import CollisionBodies, collision_bodies
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


def peer_verdicts(lib, bodies, poses: np.ndarray, repeats: int) -> tuple[np.ndarray, float, float]:
    """Verdicts, the best of ``repeats`` timings over every state and pair (the poses given, as the
    peers are used), and the seconds to build the peer's trees."""
    t = time.perf_counter()
    objs = peer_objects(lib, bodies)
    setup = time.perf_counter() - t
    out = np.zeros((len(poses), len(bodies.pairs)), bool)
    transform = _transforms(lib)
    request = lib.CollisionRequest()

    def run():
        for i in range(len(poses)):
            for obj, b in zip(objs, bodies.bodies):
                obj.setTransform(transform(poses[i, b.link]))
            for p, (a, b) in enumerate(bodies.pairs):
                out[i, p] = lib.collide(objs[a], objs[b], request, lib.CollisionResult()) > 0

    return out, best_time(run, repeats, warm=False), setup


def _transforms(lib):
    make = lib.Transform if lib.__name__ == "fcl" else lib.Transform3s
    return lambda m: make(m[:3, :3], m[:3, 3])


def manager_verdicts(lib, bodies, poses: np.ndarray, repeats: int) -> tuple[np.ndarray, float]:
    """Verdicts and the best timing through Coal's broadphase manager (a dynamic AABB tree)."""
    objs = peer_objects(lib, bodies)
    manager = lib.DynamicAABBTreeCollisionManager()
    for obj in objs:
        manager.registerObject(obj)
    manager.setup()
    transform, request = _transforms(lib), lib.CollisionRequest()
    out = np.zeros((len(poses), len(bodies.pairs)), bool)

    def run():
        out[:] = False
        for i in range(len(poses)):
            for obj, b in zip(objs, bodies.bodies):
                obj.setTransform(transform(poses[i, b.link]))
                obj.computeAABB()
            manager.update()
            found = lib.CollisionCallBackCollect(len(objs) ** 2)
            manager.collide(found)
            for p, (a, b) in enumerate(bodies.pairs):  # the pair is kept in the tree's order: ask both
                if found.exist(objs[a], objs[b]) or found.exist(objs[b], objs[a]):
                    out[i, p] = lib.collide(objs[a], objs[b], request, lib.CollisionResult()) > 0

    return out, best_time(run, repeats, warm=False)


def our_verdicts(checker: Checker, q: np.ndarray, repeats: int) -> tuple[np.ndarray, float]:
    """Verdicts and the best of ``repeats`` timings (the machine is shared: the best is the least
    disturbed; the peers are timed the same way, the garbage collector held off for all)."""
    checker.verdicts(q[:1024])  # warm-up (compiled already, pages touched)
    best = best_time(lambda: checker.verdicts(q), repeats, warm=False)
    return checker.verdicts(q)[0], best


def per_pair(mech, bodies, q: np.ndarray) -> None:
    """Where the time goes: each pair alone, on one core (forward kinematics included in each)."""
    print(f"\n{'pair (one core)':<20} {'us/state':>9} {'collides':>9}")
    for p, names in enumerate(bodies.pair_names()):
        checker = Checker(mech, CollisionBodies(bodies.bodies, (bodies.pairs[p],), bodies.adjacent, ()), threads=1,
                          certified_cells=True)
        t = time.perf_counter()
        hit = checker.verdicts(q)[0]
        print(f"{'/'.join(names):<20} {(time.perf_counter() - t) / len(q) * 1e6:>9.2f} {hit.mean():>9.2%}")


ROUNDS = 5  # alternated timings of the checker with and without certified cells


def print_certified_cells(mech, bodies, q: np.ndarray, repeats: int) -> None:
    """What the certified cells save: one core with and without them over the same states, each
    checker's setup, and each grid's cells and the shares certified apart and crossing."""
    t = time.perf_counter()
    with_cells = Checker(mech, bodies, threads=1, certified_cells=True)
    setup = time.perf_counter() - t
    t = time.perf_counter()
    without = Checker(mech, bodies, threads=1)
    bare = time.perf_counter() - t
    runs = alternated({"with": lambda: our_verdicts(with_cells, q, repeats),
                       "without": lambda: our_verdicts(without, q, repeats)}, ROUNDS)
    (hit, _), (bare_hit, _) = runs["with"][-1], runs["without"][-1]
    a, b = (min(secs for _, secs in runs[k]) for k in ("with", "without"))
    assert np.array_equal(hit, bare_hit)
    print(f"\ncertified cells (one core, {len(q)} states, the same verdicts; best of {ROUNDS} rounds alternated): "
          f"{a / len(q) * 1e6:.2f} us a state with them, {b / len(q) * 1e6:.2f} without ({b / a:.2f}x); "
          f"checker setup {setup:.2f} s with, {bare:.2f} s without")
    grid = with_cells.certified
    for p, names in enumerate(bodies.pair_names()):
        if grid.start[p] >= 0:
            res = grid.res[2 * p:2 * p + 2]
            cells = grid.value[grid.start[p]:grid.start[p] + int(np.prod(res))]
            print(f"  {'/'.join(names)}: {' x '.join(str(int(r)) for r in res if r > 1)} cells, "
                  f"{(cells == APART).mean():.1%} apart, {(cells == CROSSING).mean():.1%} crossing")


def print_stages(mech, bodies, q: np.ndarray, one: float) -> None:
    """Where the time goes by stage, and the limit: the bytes a state moves beside a copy of them."""
    from collision_stages import stage_table
    from limits import limit_line

    rows = stage_table(Checker(mech, bodies, threads=1, certified_cells=True), bodies, q)
    print(f"\n{'stage (one core, cumulative)':<30} {'us/state':>9} {'stage us':>9} {'passes on':>10}")
    before = 0.0
    for name, us, share in rows:
        print(f"{name:<30} {us:>9.2f} {us - before:>9.2f} {share:>10.2%}")
        before = us
    pairs = len(bodies.pairs)
    print(limit_line(f"collisions, {pairs} pairs", one, 4 * q.shape[1] + pairs * 5, len(q) * 10, None)
          + "; the work is the tree walks' (above), which varies with the state: no fixed count an item")


def throughput(mech, bodies, args) -> tuple[list, dict, np.ndarray]:
    """Rows (checker, states, best seconds, setup seconds), the agreement counts per peer
    (same, peer only, ours only), and the states our checkers ran. Every checker is timed once a
    round, ``args.rounds`` rounds, and keeps its best: a noisy spell of the shared machine meets
    ours and the peers alike."""
    Checker(mech, bodies, certified_cells=True)  # compiled (or loaded from Warp's cache) before anything is timed
    t = time.perf_counter()
    checker = Checker(mech, bodies, certified_cells=True)  # as a sweep of 10**6 samples makes it
    setup = time.perf_counter() - t
    one = Checker(mech, bodies, threads=1, certified_cells=True)
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(0).random((args.states, len(lower)))
    poses = rswarp.Kinematics(mech).fk64(q[:args.peer_states])
    libs = {}
    for name in ("fcl", "coal"):
        try:
            libs[name] = __import__(name)
        except ImportError:
            print(f"{name}: not installed, skipped")
    runs = {"all": lambda: our_verdicts(checker, q, args.repeats),
            "one": lambda: our_verdicts(one, q[:args.states // 4], args.repeats)}
    for name, lib in libs.items():
        runs[name] = lambda lib=lib: peer_verdicts(lib, bodies, poses, args.repeats)
        if name == "coal":
            runs["manager"] = lambda lib=lib: manager_verdicts(lib, bodies, poses, args.repeats)
    timed = alternated(runs, args.rounds)
    found = {key: calls[-1][0] for key, calls in timed.items()}
    best = {key: min(call[1] for call in calls) for key, calls in timed.items()}
    peer_setup = {key: calls[-1][2] for key, calls in timed.items() if len(calls[-1]) > 2}
    rows = [(f"rswarp (Warp, FK inside, {checker.launcher.threads} threads)", args.states, best["all"], setup),
            ("rswarp (Warp, FK inside, 1 thread)", args.states // 4, best["one"], setup)]
    mine, agree = found["all"][:len(poses)], {}
    for key, label in (("fcl", "python-fcl pair by pair"), ("coal", "Coal pair by pair"),
                       ("manager", "Coal broadphase manager")):
        if key in found:
            rows.append((f"{label} ({'poses given, ' if key != 'manager' else ''}1 thread)", len(poses), best[key],
                         peer_setup.get(key, peer_setup.get("coal", 0.0))))
            ref = found[key]
            agree["coal manager" if key == "manager" else key] = (int((mine == ref).sum()), int((ref & ~mine).sum()),
                                                                 int((mine & ~ref).sum()))
    return rows, agree, q


def print_tables(rows: list, agree: dict, repeats: int, rounds: int, states: int, pairs: int) -> None:
    print(f"best of {repeats} runs each in each of {rounds} rounds (every checker once a round); setup: trees (and "
          "for rswarp the witness and certified grids) built once per model")
    print(f"{'checker':<46} {'states':>8} {'us/state':>10} {'states/s':>12} {'setup s':>8}")
    for name, n, secs, build in rows:
        print(f"{name:<46} {n:>8} {secs / n * 1e6:>10.2f} {n / secs:>12.0f} {build:>8.2f}")
    print(f"\nverdicts on {states} states x {pairs} pairs:")
    print(f"{'peer':<14} {'agree':>8} {'peer only':>10} {'ours only (containment)':>24}")
    for name, (same, peer_only, ours_only) in agree.items():
        print(f"{name:<14} {same:>8} {peer_only:>10} {ours_only:>24}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--states", type=int, default=200_000, help="states for rswarp")
    ap.add_argument("--peer-states", type=int, default=5_000, help="states for each peer (a prefix of ours)")
    ap.add_argument("--matrix", type=int, default=1_000_000, help="samples of the full-matrix run (0: skip)")
    ap.add_argument("--per-pair", type=int, default=20_000, help="states for the per-pair table (0: skip)")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs of each checker a round (the best is kept)")
    ap.add_argument("--rounds", type=int, default=3, help="rounds, each checker timed once in each")
    args = ap.parse_args()
    mech = rswarp.load(str(IRB))
    bodies = collision_bodies(mech)
    rows, agree, q = throughput(mech, bodies, args)
    print_tables(rows, agree, args.repeats, args.rounds, min(args.peer_states, args.states), len(bodies.pairs))
    if args.per_pair:
        per_pair(mech, bodies, q[:args.per_pair])
        print_stages(mech, bodies, q[:args.per_pair], rows[1][1] / rows[1][2])
        print_certified_cells(mech, bodies, q[:args.states // 4], args.repeats)
    if args.matrix:
        collisions(mech, samples=2000)  # every kernel it uses compiled (or loaded) before the timing
        t = time.perf_counter()
        c = collisions(mech, samples=args.matrix)
        secs = time.perf_counter() - t
        print(f"\nfull matrix from {c.samples} samples (setup included: trees, witness and certified grids): "
              f"{secs:.1f} s")
        print(collisions_text(c, mech, {}))
    all_cores, one = rows[0][1] / rows[0][2], rows[1][1] / rows[1][2]
    rates = {r[0]: r[1] / r[2] for r in rows[2:]}
    best_peer = max(rates, key=rates.get) if rates else "none"
    fcl_row = [r for r in rows if r[0].startswith("python-fcl pair")]
    peer_rate = fcl_row[0][1] / fcl_row[0][2] if fcl_row else float("nan")
    if fcl_row:
        print(f"ratio over python-fcl at equal threads (1): {one / peer_rate:.1f}x; ours on every core: "
              f"{all_cores / peer_rate:.1f}x")
    if rates:
        print(f"ratio over the fastest peer ({best_peer}) at equal threads (1): {one / rates[best_peer]:.1f}x")
    else:
        print("no ratio: neither python-fcl nor Coal is installed (pip install -e '.[test]')")
    top = rates.get(best_peer, float("nan"))
    num = lambda x, digits=None: round(x, digits) if np.isfinite(x) else None  # noqa: E731  (JSON has no NaN)
    print(json.dumps({"metric": "self-collision states/s, IRB 2600, 15 pairs, 1 thread", "ours": num(one),
                      "peer": num(top), "peer_name": best_peer, "ratio": num(one / top, 2),
                      "ours_all_cores": num(all_cores), "ratio_all_cores": num(all_cores / top, 2),
                      "python_fcl_pairs": num(peer_rate), "ratio_python_fcl_pairs": num(one / peer_rate, 2)}))


if __name__ == "__main__":
    main()
