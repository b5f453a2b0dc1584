"""Every pose a task moves to, in the world: the task run once (``motion.plan``, as ``rswarp
program`` runs it: live inputs and signals from the task options), each robtarget of each move taken
as the controller resolves it (``Offs`` and ``RelTool`` evaluated, the tool and the work object
applied), as the flange pose in the world. A base then puts each in the robot's frame. MoveAbsJ's
joint targets are the same wherever the robot stands, and are not placed."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import InputError
from ...motion.tcp import Frames, frames

PLACED = ("joint", "linear", "circular")  # the move kinds whose targets are poses


@dataclass(frozen=True)
class ProgramPoses:
    """The distinct poses of a task: flange poses in the world (P, 4, 4), their confdata (P, 4)
    and whether it is checked (ConfJ/ConfL on), the TCP in the world (P, 3) for the map, and the
    first move to each (target name, ``file:line``); ``moves`` counts the moves placed."""

    world: np.ndarray
    conf: np.ndarray
    checked: np.ndarray
    tcp: np.ndarray
    names: tuple[str, ...]
    where: tuple[str, ...]
    moves: int
    mount: np.ndarray | None = None  # (P, 4, 4): a carried robot's base in its carrier's frame at each pose

    def bases(self, frames: np.ndarray) -> np.ndarray:
        """(n, P, 4, 4) the robot's base at each pose for candidate frames (n, 4, 4): the frames
        themselves, or, where a unit carries the robot, the carrier's frame times the mount."""
        if self.mount is None:
            return np.broadcast_to(frames[:, None], (len(frames), len(self.world), 4, 4))
        return frames[:, None] @ self.mount[None]


def program_poses(plan, mech, base: np.ndarray, mounts=None) -> ProgramPoses:
    """The poses of the moves of ``plan`` (run with the robot at ``base``, its frame in the world;
    ``mounts(row)``: where a unit carries the robot, its base in the carrier's frame at a row of
    the trajectory); an InputError where it moves to none, or where a work object moves with a unit
    or robot."""
    world, conf, checked, tcp, names, where, mount, count = [], [], [], [], [], [], [], 0
    seen: dict[tuple, int] = {}
    for m in plan.moves:
        mo = m.motion
        if mo.kind not in PLACED or mo.tool is None or mo.wobj is None:
            continue
        if mo.wobj.ufmec.strip() or not mo.wobj.ufprog:
            raise InputError(f"{mo.file}:{mo.line}: {mo.instruction}: its work object moves with "
                             f"'{mo.wobj.ufmec or 'a unit'}': a base is placed for targets fixed in the world")
        fr = frames(mech, mo.tool, mo.wobj)
        fixed = Frames(np.eye(4), fr.tool, fr.wobj, fr.stationary)
        count += 1
        at = np.eye(4) if mounts is None else mounts(m.rows[1] - 1)
        for t in mo.targets:
            flange = fixed.flange(t.pose.matrix()[None])[0]
            key = (tuple(np.round(flange[:3].ravel(), 9)), tuple(np.round(at[:3, 3], 9)), tuple(t.conf), bool(mo.conf))
            if key in seen:
                continue
            seen[key] = len(world)
            world.append(flange)
            conf.append(t.conf)
            mount.append(at)
            checked.append(bool(mo.conf))
            tcp.append(fixed.world(flange[None])[0, :3, 3])
            names.append(m.target or mo.instruction)
            where.append(f"{Path(mo.file).name}:{mo.line}")
    if not world:
        raise InputError("the task moves to no robtarget (only MoveAbsJ, or no move at all): nothing to place the "
                         "robot for")
    return ProgramPoses(np.array(world), np.array(conf, np.int32), np.array(checked), np.array(tcp), tuple(names),
                        tuple(where), count, None if mounts is None else np.array(mount))
