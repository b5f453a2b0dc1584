"""Preview rendering of the IRB 2600-12/1.65 at home, 512 x 512 with 4 rays a pixel: rswarp's Warp
kernel (every core, shading included) against Intel Embree through trimesh (``intersects_first``,
the first hit of the same rays, no shading), same process.

    python benchmarks/bench_preview.py [--size 512] [--repeats 3]

The issue's target: under a second for 512 x 512 on 2 cores, once compiled. Ends with one JSON line
{"metric", "ours", "peer", "ratio"} (rays per second, peer = Embree).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import rswarp
from rswarp.kernels.render import SAMPLES
from rswarp.sim.preview import View, camera, home_scene, render

IRB = Path(__file__).resolve().parents[1] / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
OFFSETS = ((0.125, 0.375), (0.625, 0.125), (0.875, 0.625), (0.375, 0.875))  # as kernels/render.py


def rays(scene, size: int) -> tuple[np.ndarray, np.ndarray]:
    """The preview's rays: origins (size * size * SAMPLES, 3) and one direction."""
    c = camera(scene.vertices, View(), size)
    y, x = np.mgrid[0:size, 0:size]
    origins = []
    for ox, oy in OFFSETS:
        u = ((x + ox) - size / 2) * c["pixel"]
        v = (size / 2 - (y + oy)) * c["pixel"]
        origins.append(c["origin"] + u.reshape(-1, 1) * c["right"] + v.reshape(-1, 1) * c["up"])
    return np.concatenate(origins), c["forward"]


def best(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    mech = rswarp.load(str(IRB))
    scene = home_scene(mech, rswarp.Kinematics(mech).fk64(mech.home_position()[None])[0])
    render(scene, View(), 64)  # compiled (or loaded from Warp's cache) before anything is timed
    n = args.size * args.size * SAMPLES
    ours = best(lambda: render(scene, View(), args.size), args.repeats)
    rows = [(f"rswarp (Warp, shaded, {args.size}x{args.size})", ours)]
    peer = float("nan")
    try:
        import trimesh
        from trimesh.ray.ray_pyembree import RayMeshIntersector

        origins, forward = rays(scene, args.size)
        hit_test = RayMeshIntersector(trimesh.Trimesh(scene.vertices, scene.faces, process=False))
        directions = np.tile(forward, (len(origins), 1))
        peer = best(lambda: hit_test.intersects_first(origins, directions), args.repeats)
        rows.append(("Embree via trimesh (first hits only)", peer))
    except ImportError as exc:
        print(f"Embree (trimesh + embreex): not installed ({exc}), skipped")
    print(f"{len(scene.faces)} triangles, {n} rays ({SAMPLES} a pixel), best of {args.repeats}")
    print(f"{'renderer':<42} {'seconds':>8} {'Mrays/s':>8}")
    for name, secs in rows:
        print(f"{name:<42} {secs:>8.3f} {n / secs / 1e6:>8.2f}")
    print(json.dumps({"metric": f"preview rays/s, IRB 2600, {args.size}x{args.size}x{SAMPLES}", "ours": round(n / ours),
                      "peer": round(n / peer) if peer == peer else None,
                      "ratio": round(peer / ours, 2) if peer == peer else None}))


if __name__ == "__main__":
    main()
