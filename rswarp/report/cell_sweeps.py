"""``rswarp sweep CELL.toml`` and ``rswarp collisions CELL.toml``: the robot's own sweep, and what
the cell adds to it. The sweep: where the robot's flange reaches in the world over its carrier's
travel (a robot on a track reaches along it). The collision sweep: which robot links (and its
tool) can hit the external units' links and the cell's meshes, over random joint values within
the robot's limits and the external axes' (``sim.cell_check``)."""

from __future__ import annotations

import numpy as np

from ..rsxml.cell import Cell

CARRIER_STEPS = 37  # values of each rotating carrier joint tried across its range (a slide's ends suffice)
CELL_CHUNK = 65_536  # samples of the cell's pairs a launch


def flange_box(ws) -> tuple[np.ndarray, np.ndarray]:
    """The least and greatest corner (m, the robot's frame) of the voxels its flange occupied."""
    k = np.argwhere(ws.flange_voxels)
    origin = np.asarray(ws.origin, float)
    if not len(k):
        return origin, origin
    return origin + k.min(axis=0) * ws.resolution, origin + (k.max(axis=0) + 1) * ws.resolution


def cell_reach(cell: Cell, ws) -> dict:
    """The robot's flange box in the world: its own box carried over the carrier's travel (every
    carrier joint at its ends, a rotating one at ``CARRIER_STEPS`` values); where the robot stands
    on the floor, its own box placed at its frame."""
    from ..kinematics.cell import CellKinematics

    ck = CellKinematics(cell)
    lo, hi = flange_box(ws)
    corners = np.array([[x, y, z, 1.0] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    ext = ck.home()[None]
    carrier = cell.carrier
    travel = None
    if carrier is not None:
        cols = ck.slices[carrier.name]
        lower, upper = carrier.mechanism.bounds()
        axes = [np.array([a, b]) if not j.revolute else np.linspace(a, b, CARRIER_STEPS)
                for j, a, b in zip(carrier.mechanism.active_joints, lower, upper)]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
        ext = np.repeat(ext, len(grid), axis=0)
        ext[:, cols] = grid
        travel = {a: [float(x), float(y)] for a, x, y in zip(carrier.axes, lower, upper)}
    bases = ck.robot_base(ck.split(ext), len(ext))
    world = (bases @ corners.T)[:, :3].transpose(0, 2, 1).reshape(-1, 3)
    return {"carrier": None if carrier is None else carrier.name, "travel": travel,
            "flange_box_world": [world.min(axis=0).tolist(), world.max(axis=0).tolist()]}


def cell_reach_text(found: dict, length) -> list[str]:
    """The cell's reach in words (``length``: metres to the robot file's unit, as the lines above)."""
    lo, hi = (np.asarray(v) for v in found["flange_box_world"])
    box = ", ".join(f"{a} {length(u)} to {length(v)}" for a, u, v in zip("xyz", lo, hi))
    what = "(the box of its voxels, from the joint limits alone: the floor and the cell's bodies not considered)"
    if found["carrier"] is None:
        return [f"  in the cell (the robot on the floor): the flange reaches {box} {what}"]
    travel = ", ".join(f"{a} {1000 * u:g} to {1000 * v:g} mm" for a, (u, v) in found["travel"].items())
    return [f"  in the cell, on '{found['carrier']}' ({travel}): the flange reaches {box} in the world {what}"]


def cell_collisions(cell: Cell, samples: int, seed: int, tool=None, device: str = "cpu") -> dict | None:
    """Each robot body against each unit link and mesh: the share of ``samples`` random states
    (the robot's joints and the external axes uniform within their limits, seeded) in which they
    collide; pairs touching with everything at home not tested. None where the cell has no unit
    or mesh with geometry."""
    from ..kinematics.cell import CellKinematics
    from ..sim.cell_check import CellChecker, cell_pairs
    from ..sim.tool import tool_body

    ck = CellKinematics(cell, device)
    found = cell_pairs(ck, tool_body(ck.robot.mech, tool) if tool is not None else None)
    if found is None:
        return None
    checker = CellChecker(ck, found, device)
    rng = np.random.default_rng([seed, 0xCE11])
    lo, hi = ck.robot.mech.bounds()
    e_lo = np.concatenate([e.mechanism.bounds()[0] for e in cell.externals] or [np.zeros(0)])
    e_hi = np.concatenate([e.mechanism.bounds()[1] for e in cell.externals] or [np.zeros(0)])
    counts = np.zeros(len(found.bodies.pairs), int)
    for start in range(0, samples, CELL_CHUNK):
        n = min(CELL_CHUNK, samples - start)
        counts += checker.hits(rng.uniform(lo, hi, (n, len(lo))), rng.uniform(e_lo, e_hi, (n, len(e_lo)))).sum(axis=0)
    pairs = [{"body1": a, "body2": b, "tested": bool(t), "collisions": int(c) if t else None,
              "rate": float(c) / samples if t else None}
             for (a, b), t, c in zip(found.pair_names(), checker.checked, counts)]
    return {"samples": samples, "seed": seed, "pairs": pairs}


def cell_collisions_text(found: dict | None) -> list[str]:
    if found is None:
        return []
    hit = sorted((p for p in found["pairs"] if p["tested"] and p["collisions"]), key=lambda p: -p["rate"])
    lines = [f"  in the cell ({found['samples']} random states of the robot and its external axes): "
             f"{len(hit)} of {sum(p['tested'] for p in found['pairs'])} robot-cell pairs can collide"]
    lines += [f"    {p['body1']} - {p['body2']}: {100 * p['rate']:.1f} %" for p in hit[:12]]
    untested = [f"{p['body1']} - {p['body2']}" for p in found["pairs"] if not p["tested"]]
    if untested:
        lines.append(f"    not tested (touching with everything at home): {', '.join(untested)}")
    return lines
