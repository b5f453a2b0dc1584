"""The rod's mesh queries skip a capsule that a mesh's bounding box holds beyond a contact's reach,
or (for a clearance) farther than the least clearance found so far or the gap of the body nearest
the box, and a clearance's queries reach no further than that. The skips change nothing: a run
whose boxes hold everything (so nothing is skipped and every query reaches the whole distance)
gives every figure bit for bit."""

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


def test_the_box_skip_changes_no_figure(monkeypatch):
    mech, _ = load_mechanism(str(examples.IRB2600_DRESSPACK))
    trajectory = random_trajectory(mech, 1.5, 7)
    culled = _figures(simulate_cables(mech, [trajectory], envs=2))
    made = CosseratRod._mesh_arrays

    def every_query(self, p, meshes):  # boxes that hold the whole world: no capsule is skipped
        made(self, p, meshes)
        import warp as wp

        huge = np.tile(np.array([[-1e6] * 3, [1e6] * 3]), (p.box.shape[0], 1, 1))
        p.box = wp.array(huge, dtype=wp.vec3d, device=self.launcher.device)

    monkeypatch.setattr(CosseratRod, "_mesh_arrays", every_query)
    queried = _figures(simulate_cables(mech, [trajectory], envs=2))
    assert culled.keys() == queried.keys() and "0.clearance" in culled
    assert np.isfinite(culled["0.clearance"]).any()  # a hose near the links: the queries ran
    for name, value in culled.items():
        assert np.array_equal(value, queried[name], equal_nan=value.dtype.kind == "f"), name
