"""The rod's mesh queries skip a capsule that a mesh's bounding box holds beyond a contact's reach,
or (for a clearance) farther than the least clearance found so far or the gap of the body nearest
the box, and a clearance's queries reach no further than that. The skips change nothing: a run
whose boxes hold everything (so nothing is skipped and every query reaches the whole distance)
gives every figure, and every frame's clearance to every slot, bit for bit (a bound 2 mm tighter
than the nearest body's gap fails here)."""

from __future__ import annotations

import dataclasses

import numpy as np

from rswarp import examples
from rswarp.kinematics.trajectory import random_trajectory
from rswarp.rsxml.documents import load_mechanism
from rswarp.sim.cable.rod import CosseratRod
from rswarp.sim.cables import simulate_cables


def _figures(run) -> dict:
    out = {}
    for c, cable in enumerate(run.cables):
        for f in dataclasses.fields(cable):
            value = getattr(cable, f.name)
            if isinstance(value, np.ndarray):
                out[f"{c}.{f.name}"] = value
    return out


def _run(monkeypatch, mech, trajectory, boxes=None) -> dict:
    """The run's figures, and every frame's clearance and its arc per cable and slot; with ``boxes``,
    each mesh's bounding box replaced by ``boxes(box)`` (one that still holds it)."""
    made, measured = CosseratRod._mesh_arrays, CosseratRod.statistics
    frames = []

    def patched(self, p, meshes):
        made(self, p, meshes)
        if boxes is not None:
            import warp as wp

            p.box = wp.array(boxes(p.box.numpy()), dtype=wp.vec3d, device=self.launcher.device)

    def recorded(self, state):
        out = measured(self, state)
        frames.append(np.concatenate([np.stack([c["clearance"], c["clearance_at"]]) for c in out]))
        return out

    with monkeypatch.context() as m:
        m.setattr(CosseratRod, "_mesh_arrays", patched)
        m.setattr(CosseratRod, "statistics", recorded)
        figures = _figures(simulate_cables(mech, [trajectory], envs=2))
    figures["frames"] = np.stack(frames)
    return figures


def _same(culled: dict, other: dict) -> None:
    assert culled.keys() == other.keys() and "0.clearance" in culled
    assert np.isfinite(culled["0.clearance"]).any()  # a hose near the links: the queries ran
    for name, value in culled.items():
        assert np.array_equal(value, other[name], equal_nan=value.dtype.kind == "f"), name


def test_the_box_skip_changes_no_figure(monkeypatch):
    mech, _ = load_mechanism(str(examples.IRB2600_DRESSPACK))
    trajectory = random_trajectory(mech, 1.5, 7)
    culled = _run(monkeypatch, mech, trajectory)
    # boxes that hold the whole world: no capsule is skipped, every query reaches the whole distance
    _same(culled, _run(monkeypatch, mech, trajectory,
                       lambda box: np.tile(np.array([[-1e6] * 3, [1e6] * 3]), (box.shape[0], 1, 1))))


def test_the_bound_from_another_body_changes_no_figure(monkeypatch):
    """Boxes grown unevenly (still holding their meshes) make other bodies the nearest a box: their
    gaps, not the least, bound the rest. Every frame's clearances stay the same, bit for bit."""
    mech, _ = load_mechanism(str(examples.IRB2600_DRESSPACK))
    trajectory = random_trajectory(mech, 1.5, 7)
    culled = _run(monkeypatch, mech, trajectory)
    rng = np.random.default_rng(3)
    for _ in range(2):
        grow = rng.uniform(0.0, 0.15, (2, 3))
        _same(culled, _run(monkeypatch, mech, trajectory,
                           lambda box, g=grow: np.stack([box[:, 0] - g[0], box[:, 1] + g[1]], axis=1)))
