"""The kinematics of a cell (``rsxml.cell.Cell``): where every link of the robot and of the
external units is in the world, for the robot's joints and the external axes' values. A unit's
links are its own forward kinematics placed at its frame; the robot's base is its frame on the
floor, or on the carrier link (a track's carriage, a positioner's face plate) of the unit it
stands on, wherever that unit's joints put it: one more frame in the same product of transforms.

Logical axes come as RAPID writes them in a robtarget's ``extax`` (mm for a linear axis, degrees
for a rotating one, 9E9 for an axis not given); joints are SI."""

from __future__ import annotations

import numpy as np

from ..rsxml.cell import LOGICAL_AXES, Cell
from .kinematics import Kinematics

UNSET = 8.9e9  # an extax value at or above this is RAPID's 9E9: the axis is not given


def rapid_factor(joint) -> float:
    """SI per RAPID unit of a joint's value: RAPID writes degrees and mm whatever the RSXML's units."""
    return float(np.radians(1.0)) if joint.revolute else 1e-3


class CellKinematics:
    """The robot's and each external unit's ``Kinematics``, compiled once, and the cell's frames."""

    def __init__(self, cell: Cell, device: str = "cpu"):
        self.cell = cell
        self.robot = Kinematics(cell.robot.mechanism, device)
        self.units = {e.name: Kinematics(e.mechanism, device) for e in cell.externals}
        self.mapping = cell.mapping  # logical axis -> (unit, joint)

    def unit_joints(self, extax, held: dict[str, np.ndarray] | None = None) -> dict[str, np.ndarray]:
        """Each unit's joint values (N, its dof; SI) from logical axes' values (N, 6) in RAPID's
        units (eax_a .. eax_f; mm or degrees); an axis not given (9E9) keeps its value in
        ``held`` (unit -> (dof,) or (N, dof)), else its joint's home."""
        extax = np.atleast_2d(np.asarray(extax, float))
        out = {}
        for e in self.cell.externals:
            mech = e.mechanism
            q = np.broadcast_to(held[e.name] if held and e.name in held else mech.home_position(),
                                (len(extax), mech.dof)).copy()
            for axis, joint in zip(e.axes, e.joints):
                col = LOGICAL_AXES.index(axis)
                k = [j.name for j in mech.active_joints].index(joint)
                given = np.abs(extax[:, col]) < UNSET
                q[given, k] = extax[given, col] * rapid_factor(mech.active_joints[k])
            out[e.name] = q
        return out

    def unit_links(self, name: str, q) -> np.ndarray:
        """(N, links, 4, 4) world poses of a unit's links at its joints ``q`` (N, dof)."""
        return self.cell.external(name).frame @ self.units[name].fk64(q)

    def robot_base(self, joints: dict[str, np.ndarray], count: int = 1) -> np.ndarray:
        """(N, 4, 4) world pose of the robot's base: its frame on the floor, or on its carrier at
        that unit's ``joints`` (unit -> (N, dof))."""
        frame = self.cell.robot.frame
        carrier = self.cell.carrier
        if carrier is None:
            return np.broadcast_to(frame, (count, 4, 4)).copy()
        return self.unit_flange(carrier.name, joints[carrier.name]) @ frame  # the robot rides the unit's flange

    def robot_links(self, q, joints: dict[str, np.ndarray]) -> np.ndarray:
        """(N, links, 4, 4) world poses of the robot's links at its joints ``q`` (N, dof)."""
        q = np.atleast_2d(np.asarray(q, float))
        return self.robot_base(joints, len(q))[:, None] @ self.robot.fk64(q)

    def flange(self, q, joints: dict[str, np.ndarray]) -> np.ndarray:
        """(N, 4, 4) world pose of the robot's flange."""
        link, offset = self.robot.flange_frame()
        return self.robot_links(q, joints)[:, link] @ offset

    def unit_flange(self, name: str, q) -> np.ndarray:
        """(N, 4, 4) world pose of a unit's mounting flange (a positioner's face plate, where a work
        object it moves is defined; a track's mount) at its joints ``q`` (N, dof): where whatever
        rides the unit sits. A unit without a Flange: its carrying link's frame."""
        unit = self.cell.external(name)
        kin = self.units[name]
        if unit.mount is None:
            link, offset = kin.graph.link_index(unit.carrier_link), np.eye(4)
        else:
            link, offset = kin.flange_frame(unit.mount.name)
        return self.unit_links(name, np.atleast_2d(q))[:, link] @ offset

    # -- the external joints as one vector (each unit's joints, in the cell's order) ---------------
    @property
    def slices(self) -> dict[str, slice]:
        """Each unit's columns in the cell's vector of external joints."""
        out, at = {}, 0
        for e in self.cell.externals:
            out[e.name] = slice(at, at + e.mechanism.dof)
            at += e.mechanism.dof
        return out

    def split(self, ext) -> dict[str, np.ndarray]:
        """Unit -> its joints (N, dof) of external joint vectors ``ext`` (N, all)."""
        ext = np.atleast_2d(np.asarray(ext, float))
        return {name: ext[:, s] for name, s in self.slices.items()}

    def joined(self, joints: dict[str, np.ndarray], count: int = 1) -> np.ndarray:
        """External joint vectors (N, all) of each unit's joints (N, dof); (count, 0) for a cell
        with no external unit (a robot alone in its cell)."""
        if not self.cell.externals:
            return np.zeros((count, 0))
        return np.concatenate([np.atleast_2d(joints[e.name]) for e in self.cell.externals], axis=1)

    def home(self) -> np.ndarray:
        """The external joints at every unit's home (all,)."""
        return np.concatenate([np.asarray(e.mechanism.home_position(), float) for e in self.cell.externals] or
                              [np.zeros(0)])

    def logical(self, ext) -> tuple[float | None, ...]:
        """The six logical axes (RAPID's units) of one external joint vector (None: not in the cell)."""
        joints = self.split(ext)
        out = []
        for axis in LOGICAL_AXES:
            found = self.mapping.get(axis)
            if found is None:
                out.append(None)
                continue
            mech = self.cell.external(found[0]).mechanism
            k = [j.name for j in mech.active_joints].index(found[1])
            out.append(float(joints[found[0]][0, k] / rapid_factor(mech.active_joints[k])))
        return tuple(out)
