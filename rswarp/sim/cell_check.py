"""A cell program's trajectory checked against the cell's other bodies: every link of the robot
(and its tool) against every link of the external units (a track's rail and carriage, a
positioner's stand, tilt frame and face plate) and the cell's environment meshes, at every
sample, the robot's base where its carrier puts it and the units' links where the external axes
put them. Exact mesh against mesh (``kernels.collide``'s verdict, with poses the host computes,
as the bodies move on two chains); pairs touching with everything at home (the robot's base bolted
to the carriage) are not tested, as the robot's own sweep leaves them out."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .bodies import Body, CollisionBodies, DeviceBodies, Environment, collision_bodies, environment_body, placed_body

CHUNK = 4096  # samples a launch


@dataclass(frozen=True)
class CellPairs:
    """The robot's bodies against the cell's: ``bodies`` (the robot's first, then the units'
    links and the environment meshes) and their pairs, and what poses each body: ("robot",
    link), ("unit", name, link), ("on", unit) for a mesh on a unit's flange, or ("fixed",
    None). Which pairs are tested (not touching at home) is ``CellChecker.checked``."""

    bodies: CollisionBodies
    owner: tuple

    def pair_names(self) -> list[tuple[str, str]]:
        return self.bodies.pair_names()


def cell_pairs(ck, tool=None) -> CellPairs | None:
    """The pairs of the cell ``ck`` (``CellKinematics``) with the robot's ``tool`` body (or None);
    None where the cell has nothing beside the robot with a mesh."""
    from ..geometry.meshes import link_mesh

    robot = collision_bodies(ck.robot.mech, (), (), tool)
    mine = list(robot.bodies)
    owner = [("robot", b.link) for b in mine]
    others: list[Body] = []
    warnings: list[str] = []
    for e in ck.cell.externals:
        for k, name in enumerate(e.mechanism.graph.links):
            mesh = link_mesh(e.mechanism, name)
            if mesh is not None and len(mesh.faces):
                others.append(placed_body(f"{e.name}.{name}", mesh, np.eye(4), warnings))
                owner.append(("unit", e.name, k))
    taken = {b.name for b in mine + others}
    for m in ck.cell.environment:  # a mesh on a unit (the work on a face plate): posed by its flange
        home = ck.unit_flange(m.on, ck.split(ck.home()[None])[m.on])[0] @ m.pose if m.on else m.pose
        body = environment_body(ck.robot.mech, Environment(m.name, m.path, home), taken, warnings)
        others.append(replace(body, pose=m.pose) if m.on else body)
        owner.append(("on", m.on) if m.on else ("fixed", None))
    if not others:
        return None
    pairs = tuple((i, len(mine) + j) for i in range(len(mine)) for j in range(len(others)))
    bodies = CollisionBodies(tuple(mine + others), pairs, frozenset(), tuple(warnings))
    return CellPairs(bodies, tuple(owner))


def body_poses(ck, found: CellPairs, q: np.ndarray, ext: np.ndarray) -> np.ndarray:
    """(N, bodies, 4, 4) every body's pose at the robot's joints ``q`` and external joints ``ext``."""
    joints = ck.split(ext)
    robot = ck.robot_base(joints, len(q))[:, None] @ ck.robot.fk64(q)
    units = {e.name: ck.unit_links(e.name, joints[e.name]) for e in ck.cell.externals}
    out = np.empty((len(q), len(found.owner), 4, 4))
    for b, (who, *where) in enumerate(found.owner):
        if who == "robot":
            out[:, b] = robot[:, where[0]]
        elif who == "unit":
            out[:, b] = units[where[0]][:, where[1]]
        elif who == "on":
            out[:, b] = ck.unit_flange(where[0], joints[where[0]]) @ found.bodies.bodies[b].pose
        else:
            out[:, b] = found.bodies.bodies[b].pose
    return out


class CellChecker:
    """The posed-pair kernel over a cell's pairs on a device: ``hits(q, ext)`` (N, pairs)."""

    def __init__(self, ck, found: CellPairs, device: str = "cpu", threads: int | None = None, poses=None,
                 home=None):
        """``poses(q, ext)``: the bodies' poses (``body_poses`` where not given); ``home``: the (q,
        ext) whose touching pairs are a build that touches, left unchecked (every unit at home)."""
        from ..kernels.collide import posed_kernel
        from ..launch import Launcher, init_warp

        wp = init_warp()
        self.ck, self.found = ck, found
        self.launcher = Launcher(device, chunk=8192, threads=threads)
        self._device = DeviceBodies(found.bodies, 0.0, self.launcher.device)
        self._kernel = posed_kernel(wp.float32)
        self.launcher.load(self._kernel)
        self._wp = wp
        self._poses = poses or (lambda q, ext: body_poses(ck, found, q, ext))
        q0, ext0 = home or (ck.robot.mech.home_position(), ck.home())
        self.checked = ~self.hits(np.asarray(q0, float)[None], np.asarray(ext0, float)[None])[0]

    def hits(self, q: np.ndarray, ext: np.ndarray) -> np.ndarray:
        """(N, pairs) whether each pair collides (surfaces cross, or one contains the other)."""
        pairs = np.array(self.found.bodies.pairs, np.int32).reshape(-1, 2)
        out = np.zeros((len(q), len(pairs)), bool)
        for lo in range(0, len(q), CHUNK):
            poses = self._poses(q[lo:lo + CHUNK], ext[lo:lo + CHUNK])[:, :, :3, :]
            n = len(poses)
            a = poses[:, pairs[:, 0]].reshape(-1, 3, 4).astype(np.float32)
            b = poses[:, pairs[:, 1]].reshape(-1, 3, 4).astype(np.float32)
            which = np.tile(np.arange(len(pairs), dtype=np.int32), n)
            gap = np.empty(len(which), np.float32)
            self.launcher.launch(self._kernel, len(which), params=[self._device.struct(self._wp.float32)],
                                 inputs=[a, b, which], outputs=[gap])
            out[lo:lo + n] = (gap <= 0.0).reshape(n, len(pairs))
        return out
