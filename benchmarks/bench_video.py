"""Video of a robot program: 10 s at 30 frames/s of the IRB 2600-12/1.65 running its bundled
pick-and-place routine (held at its end), 512 x 512, ``rswarp.sim.video.render_frames`` (the
previews' Warp ray caster, 2 rays a pixel, the BVH refitted per frame, every core), against
Intel Embree through trimesh (``intersects_first``: the first hits of the same rays, no shading,
a BVH built per frame) on a tenth of the frames, scaled; same process.

    python benchmarks/bench_video.py [--size 512] [--seconds 10]

The issue's target: under 30 s on this 2-core machine. Ends with one JSON line
{"metric", "ours", "peer", "ratio"} (seconds for the whole video; peer = Embree, scaled).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from rswarp.examples import IRB2600, IRB2600_PROGRAM
from rswarp.kinematics.kinematics import Kinematics
from rswarp.motion.plan import program_plan
from rswarp.sim.preview import View, camera
from rswarp.sim.video import SAMPLES, _Scene, render_frames

FPS = 30.0


def frames_of(seconds: float):
    mech, plan = program_plan(str(IRB2600), str(IRB2600_PROGRAM))
    t = np.arange(0.0, seconds, 1.0 / FPS)
    rows = np.clip(np.searchsorted(plan.times, t), 0, len(plan.times) - 1)
    return mech, Kinematics(mech).fk64(plan.q[rows])


def embree(mech, poses: np.ndarray, size: int, every: int) -> tuple[float, int]:
    """Seconds for the first hits of the video's rays on every ``every``-th frame (a BVH each)."""
    import trimesh

    scene = _Scene(mech, poses, [])
    c = camera(scene.vertices(0), View(), size)
    y, x = np.mgrid[0:size, 0:size]
    origins = []
    for ox, oy in ((0.125, 0.375), (0.625, 0.125))[:SAMPLES]:
        u = ((x + ox) - size / 2) * c["pixel"]
        v = (size / 2 - (y + oy)) * c["pixel"]
        origins.append(c["origin"] + u.reshape(-1, 1) * c["right"] + v.reshape(-1, 1) * c["up"])
    origins = np.concatenate(origins)
    directions = np.tile(c["forward"], (len(origins), 1))
    done, wall = 0, time.perf_counter()
    for f in range(0, len(poses), every):
        mesh = trimesh.Trimesh(scene.vertices(f), scene.faces, process=False)
        mesh.ray.intersects_first(origins, directions)
        done += 1
    return time.perf_counter() - wall, done


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--seconds", type=float, default=10.0)
    args = ap.parse_args()
    mech, poses = frames_of(args.seconds)
    render_frames(mech, poses[:2], [], 64)  # kernels compiled before timing
    wall = time.perf_counter()
    frames = render_frames(mech, poses, [], args.size)
    ours = time.perf_counter() - wall
    peer_wall, peer_frames = embree(mech, poses, args.size, 10)
    import trimesh

    engine = "Embree" if trimesh.ray.has_embree else "trimesh's NumPy ray caster (no embreex)"
    peer = peer_wall / peer_frames * len(poses)
    print(f"{len(frames)} frames ({args.seconds:g} s at {FPS:g}/s), {args.size} x {args.size}, {SAMPLES} rays a pixel")
    print(f"  rswarp (Warp, shaded, every core): {ours:.1f} s, {ours / len(frames) * 1e3:.0f} ms a frame")
    print(f"  {engine} (first hits only, {peer_frames} frames timed): {peer:.1f} s for the video, "
          f"{peer / len(frames) * 1e3:.0f} ms a frame")
    print(f"  ratio: {peer / ours:.1f}x; target: under 30 s")
    print(json.dumps({"metric": "seconds to render the video", "ours": ours, "peer": peer, "ratio": peer / ours}))


if __name__ == "__main__":
    main()
