"""Helpers for the cable-model checks: a mechanism's cables as Cosserat rods, stepped with the
joints a test gives, straight from the solver (no run around it)."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

import rswarp
from rswarp.sim.cable.rod import CosseratRod
from rswarp.sim.cable.solver import CableOptions, contact_meshes

from conftest import DATA

FRAME = 1 / 60
WEIGHT = 1200 * 9.81  # N/m^3: the default density times g


def rod(name: str, envs: int = 1, text: dict | None = None, tmp=None, **options):
    """(mechanism, solver, state) of ``tests/data/cables/<name>.rsxml``, with attribute texts
    replaced (``text``, written under ``tmp``) and ``CableOptions`` given."""
    path = DATA / "cables" / f"{name}.rsxml"
    if text:
        source = path.read_text()
        for old, new in text.items():
            assert old in source
            source = source.replace(old, new)
        path = tmp / path.name
        path.write_text(source)
    mech = rswarp.load(path)
    solver = CosseratRod(mech, CableOptions(**options), contact_meshes(mech))
    return mech, solver, solver.state(envs)


def run(solver, state, seconds: float, joints=None, t0: float = 0.0, each=None) -> float:
    """Steps ``seconds`` of frames; ``joints(t)`` gives (envs, dof) at time t (default zeros);
    ``each(t)`` is called after every frame. Returns the time reached."""
    envs, subs = state.x.shape[0], solver.options.substeps
    frames = int(round(seconds / FRAME))
    for f in range(frames):
        t = t0 + (f + (np.arange(subs) + 1) / subs) * FRAME
        qs = np.zeros((envs, subs, solver.dof)) if joints is None else np.stack([joints(s) for s in t], axis=1)
        solver.step(state, qs, FRAME)
        if each is not None:
            each(t[-1])
    return t0 + frames * FRAME


def linking_number(a: np.ndarray, b: np.ndarray) -> float:
    """The Gauss linking number of two closed polylines (N, 3) and (M, 3), each segment pair's
    solid angle taken exactly (Klenin and Langowski, Biopolymers 54, 2000)."""
    p1, p2 = a[:, None], np.roll(a, -1, axis=0)[:, None]
    p3, p4 = b[None], np.roll(b, -1, axis=0)[None]
    r13, r14, r23, r24 = p3 - p1, p4 - p1, p3 - p2, p4 - p2

    def unit(v):
        return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)

    n = [unit(np.cross(r13, r14)), unit(np.cross(r14, r24)), unit(np.cross(r24, r23)), unit(np.cross(r23, r13))]
    omega = sum(np.arcsin(np.clip(np.sum(n[k] * n[(k + 1) % 4], axis=-1), -1, 1)) for k in range(4))
    sign = np.sign(np.sum(np.cross(p4 - p3, p2 - p1) * r13, axis=-1))
    return float(np.sum(omega * sign) / (4 * np.pi))


def ribbon_link(nodes: np.ndarray, d1: np.ndarray, axis: np.ndarray, width: float, far: float = 100.0) -> float:
    """The link (twist plus writhe) of a rod whose ends are clamped along ``axis``: the linking
    number of its centreline ``nodes`` with the ribbon drawn ``width`` along its material axis
    ``d1`` (per node), both carried on straight along ``axis`` and closed ``far`` away."""
    side = np.cross(axis, d1[0])
    side /= np.linalg.norm(side)

    def closed(curve, o0, o1):
        head, foot = curve[-1] + o1 + far * axis, curve[0] + o0 - far * axis
        return np.vstack([curve, head, head + far * side, foot + far * side, foot])

    ribbon = nodes + width * d1
    return linking_number(closed(nodes, 0, 0), closed(ribbon, width * d1[0], width * d1[-1]))


def energy(solver, state, env: int = 0) -> float:
    """The rods' kinetic, gravitational and elastic energy (J), from the joints' stiffness as the
    model states it (``rswarp.kernels.rod.joint``: 1/2 k gap^2 and 1/2 k (2 Im(a* b))^2)."""
    lay = solver.layout
    x, q, v, w = (a.numpy()[env] for a in (state.x, state.q, state.v, state.w))
    rot = Rotation.from_quat(q)
    axes = rot.apply([0.0, 0.0, 1.0])
    m = lay.mass
    spin = np.einsum("ij,ij->i", w, axes)
    kinetic = 0.5 * np.sum(m * np.sum(v * v, axis=1)) + 0.5 * np.sum(
        lay.inertia[:, 0] * (np.sum(w * w, axis=1) - spin ** 2) + lay.inertia[:, 1] * spin ** 2)
    total = kinetic + 9.81 * np.sum(m * x[:, 2])
    for k in range(len(x) - 1):
        if lay.stiff[k, 2] > 0:
            total += _joint(x[k] + lay.half[k] * axes[k], rot[k], x[k + 1] - lay.half[k + 1] * axes[k + 1],
                            rot[k + 1], lay.stiff[k])
    poses = solver._poses(state.joints[env:env + 1], state.joints[env:env + 1, None])[0, 0]
    for a, k in enumerate(lay.attach_body):
        pose = poses[lay.attach_link[a]]
        p = pose[:3, :3] @ lay.attach_point[a] + pose[:3, 3]
        frame = Rotation.from_matrix(pose[:3, :3]) * Rotation.from_quat(lay.attach_frame[a])
        if lay.attach_end[a] > 0:
            total += _joint(x[k] + lay.half[k] * axes[k], rot[k], p, frame, lay.attach_stiff[a])
        else:
            total += _joint(p, frame, x[k] - lay.half[k] * axes[k], rot[k], lay.attach_stiff[a])
    return float(total)


def _joint(pa, ra, pb, rb, k) -> float:
    gap = ra.inv().apply(pb - pa)
    v = 2 * (ra.inv() * rb).as_quat()[:3]
    return 0.5 * (k[0] * (gap[0] ** 2 + gap[1] ** 2) + k[2] * gap[2] ** 2 + np.sum(k[3:] * v ** 2))
