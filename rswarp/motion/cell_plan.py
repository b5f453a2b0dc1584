"""A RAPID task planned over a cell (``rsxml.cell.Cell``): the robot's axes and the external
units' moved together, as the controller moves them.

- A robtarget's ``extax`` (and a jointtarget's) sets the logical axes (eax_a .. eax_f) the cell
  maps to its units' joints; an axis a target leaves at 9E9 stays where it is.
- The robot's inverse kinematics is solved from its base where the carrier (a track's carriage)
  puts it, and in a work object a unit moves (``ufprog`` FALSE, ``ufmec`` naming the unit) where
  that unit's flange (a positioner's face plate) is.
- MoveJ and MoveAbsJ move the external axes with the robot's, synchronized: one joint move over
  every axis. MoveL and MoveC move them linearly with the share of the way while the TCP keeps
  its line or circle in the work object: each probe of the path is solved with the frames there.
- Their speeds, accelerations and jerks time the moves with the robot's (the trajectory's columns
  after the robot's are the external joints, SI)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..kinematics.cell import CellKinematics, rapid_factor
from ..rapid.motion import Motion, Run
from ..rsxml.robot_data import AxisLimits, axis_limits
from . import plan_steps, timing
from .planner import Plan, Planner
from .tcp import Frames

LEVER = 1.0  # m of travel a radian of a rotating external axis counts as, for the probes' spacing


class Along:
    """A path move's frames along its way, the external joints going linearly from ``e0`` to
    ``e1`` with the share of the way; ``travel``: (m, rad) how far they go, so the path is probed
    densely enough for them too."""

    def __init__(self, planner: CellPlanner, m: Motion, e0: np.ndarray, e1: np.ndarray):
        self.planner, self.motion, self.e0, self.e1 = planner, m, e0, e1
        way = np.abs(e1 - e0)
        linear = np.array([not r for r in planner.ext_revolute], bool)
        slide = float(way[linear].max()) if linear.any() else 0.0
        turn = float(way[~linear].max()) if (~linear).any() else 0.0
        self.travel = (max(slide, LEVER * turn), turn)

    def joints(self, u: np.ndarray) -> np.ndarray:
        return self.e0 + np.asarray(u, float)[:, None] * (self.e1 - self.e0)

    def __call__(self, u: np.ndarray) -> Frames:
        return self.planner.frames_at(self.motion.tool, self.motion.wobj, self.joints(u))


def cell_limits(cellkin: CellKinematics, robot: AxisLimits, units: dict[str, AxisLimits] | None = None) -> AxisLimits:
    """The robot's axis limits with each unit's after them (its robot-data file's, or
    ``units[name]``), named by their logical axes: what the timing of a cell's moves uses."""
    parts = [(robot, robot.names or tuple(f"axis {k + 1}" for k in range(len(robot.velocity))))]
    for e in cellkin.cell.externals:
        lim = (units or {}).get(e.name) or axis_limits(e.mechanism)
        axis = {j: a for a, j in zip(e.axes, e.joints)}
        parts.append((lim, tuple(f"{axis.get(j.name, '-')} ({e.name} {j.name})" for j in e.mechanism.active_joints)))
    lims = [p[0] for p in parts]

    def cat(get):
        return np.concatenate([np.asarray(get(x), float) for x in lims])

    linear = tuple(v for x in lims for v in (x.linear if len(x.linear) == len(x.velocity) else
                                             [False] * len(x.velocity)))
    source = " and ".join(dict.fromkeys(x.source for x in lims))
    return AxisLimits(cat(lambda x: x.velocity), cat(lambda x: x.acceleration), cat(lambda x: x.effort),
                      source, robot.assumed, any(x.accel_assumed for x in lims), cat(lambda x: x.jerks()),
                      tuple(n for p in parts for n in p[1]), *robot.sources(),
                      np.concatenate([x.estimates() for x in lims]), linear,
                      tuple(s for x in lims for s in [x.sources()] * len(x.velocity)),
                      (False,) * len(robot.velocity) + (True,) * (len(linear) - len(robot.velocity)))


class CellPlanner(Planner):
    """``Planner`` over a cell: its state is the robot's joints (``q``) and the external joints
    (``ext``, SI, the units' joints in the cell's order)."""

    def __init__(self, cellkin: CellKinematics, rate: float = timing.RATE, external_axes: str = "auto",
                 limits: AxisLimits | None = None, load_scale=None, unit_limits: dict | None = None):
        robot = limits if limits is not None else axis_limits(cellkin.robot.mech)
        super().__init__(cellkin.robot, rate, external_axes, cell_limits(cellkin, robot, unit_limits), load_scale)
        self.cellkin = cellkin
        self.ext = cellkin.home()
        self.ext_ahead = self.ext  # where the batch being prepared leaves the external axes
        self.ext_revolute = tuple(j.revolute for e in cellkin.cell.externals for j in e.mechanism.active_joints)
        self.driven = tuple(cellkin.mapping)
        self.units = {e.name.lower(): e.name for e in cellkin.cell.externals}
        self.at_target: dict = {}  # id(motion) -> its Frames at its target
        self.rows = [np.concatenate([self.q, self.ext])[None]]

    # -- the frames where the external axes are -----------------------------------------------------
    def frames_at(self, tool, wobj, ext: np.ndarray) -> Frames:
        """The move's frames with the external joints at ``ext`` (N, all): the robot's base on its
        carrier, the work object on the unit that moves it; (N, 4, 4) each."""
        ext = np.atleast_2d(ext)
        joints = self.cellkin.split(ext)
        base = self.cellkin.robot_base(joints, len(ext))
        frame = np.broadcast_to(wobj.matrix(), (len(ext), 4, 4))
        unit = self.moved_by(wobj)
        if unit is not None and tool.robhold:
            frame = self.cellkin.unit_flange(unit, joints[unit]) @ wobj.matrix()
        return Frames(base, tool.tframe.matrix(), frame, not tool.robhold)

    def moved_by(self, wobj) -> str | None:
        """The cell's unit that moves a coordinated work object (``ufmec``, case ignored), or None."""
        if wobj is None or not wobj.coordinated:
            return None
        return self.units.get((wobj.ufmec or "").strip().lower())

    def single(self, tool, wobj, ext: np.ndarray) -> Frames:
        fr = self.frames_at(tool, wobj, ext[None])
        return Frames(fr.base[0], fr.tool, fr.wobj[0], fr.stationary)

    def ext_of(self, extax, held: np.ndarray) -> np.ndarray:
        """The external joints logical axes' values ``extax`` (RAPID's units, None or 9E9: not
        given) set, those not given where ``held`` has them."""
        values = [9e9 if v is None else float(v) for v in (*(extax or ()), *[None] * 6)][:6]
        return self.cellkin.joined(self.cellkin.unit_joints(np.array(values)[None], self.cellkin.split(held)))[0]

    def target_ext(self, m: Motion, held: np.ndarray) -> np.ndarray:
        """The external joints a move's target sets (the circle point's are not used)."""
        return held if m.kind == "wait" or not m.targets else self.ext_of(m.targets[-1].extax, held)

    def query_frames(self, tool, wobj, extax=()) -> Frames:
        if tool.robhold == wobj.robhold:
            return super().query_frames(tool, wobj)  # the error it raises
        return self.single(tool, wobj, self.ext_of(extax, self.ext))

    def prepared(self, m: Motion) -> plan_steps.Prepared:
        """The move's frames at its target's external joints, and along its way where they move."""
        e0 = self.ext_ahead
        e1 = self.ext_ahead = self.target_ext(m, e0)
        if m.kind in ("wait", "absolute"):
            return plan_steps.Prepared(ext=(e0, e1))
        if m.tool.robhold == m.wobj.robhold:
            return plan_steps.frames_of(self, m)  # the error it says
        key = (m.tool, m.wobj, e1.tobytes())
        fr = self.frames.get(key)
        if fr is None:
            fr = self.frames[key] = self.single(m.tool, m.wobj, e1)
        self.at_target[id(m)] = fr
        moving = not np.array_equal(e0, e1) and m.kind in ("linear", "circular")
        return plan_steps.Prepared(fr, along=Along(self, m, e0, e1) if moving else None, ext=(e0, e1))

    def target_flange(self, m: Motion) -> np.ndarray | None:
        fr = self.at_target.get(id(m))
        return None if fr is None or not m.targets else fr.flange(m.targets[-1].pose.matrix()[None])[0]

    # -- the external axes in the steps ----------------------------------------------------------
    def extend(self, motions) -> None:
        self.ext_ahead = self.ext
        super().extend(motions)

    def resolved(self, m: Motion, p: plan_steps.Prepared) -> plan_steps.Step:
        """The step with the external joints after the robot's: a joint move's at its ends, a
        path's at each probe (linear in the share of the way)."""
        why = self.outside(m, p.ext[1]) if p.ext is not None else None
        s = plan_steps.Step(m, "skip", why) if why is not None else plan_steps.resolve(self, m, p)
        if s.kind == "skip":
            return s
        e0 = self.ext
        e1 = p.ext[1] if p.ext is not None else e0
        s.q0 = np.concatenate([s.q0, e0])
        if s.kind == "joint":
            s.q1 = np.concatenate([s.q1, e1])
            self.ext = e1
        elif s.kind == "path":
            ext = e0 + s.u[:, None] * (e1 - e0)
            s.q = np.hstack([s.q[:len(s.u)], ext]) if len(s.u) else np.zeros((0, len(s.q0)))
            self.ext = ext[-1] if len(ext) >= 2 else (e1 if not len(s.u) else e0)
        return s

    def outside(self, m: Motion, ext: np.ndarray) -> str | None:
        """Why a move's target puts an external axis outside its unit's limits (RAPID's units), or None."""
        for e, (name, cols) in zip(self.cellkin.cell.externals, self.cellkin.slices.items()):
            lower, upper = e.mechanism.bounds()
            axis = dict(zip(e.joints, e.axes))
            for j, v, lo, hi in zip(e.mechanism.active_joints, ext[cols], lower, upper):
                if not lo - 1e-9 <= v <= hi + 1e-9:
                    f = rapid_factor(j)
                    unit = "deg" if j.revolute else "mm"
                    return (f"'{m.names[-1]}' puts {axis.get(j.name, j.name)} at {v / f:g} {unit}, outside {name}'s "
                            f"limits [{lo / f:g}, {hi / f:g}] {unit}")
        return None

    def joint_tcps(self, steps) -> np.ndarray:
        """The TCP along joint steps in each move's work object (where it moves with a unit, as the
        speed is the TCP's relative to the work), its base where the track puts it."""
        dof = self.dof
        q0, q1 = np.array([s.q0 for s in steps]), np.array([s.q1 for s in steps])
        shares = np.linspace(0, 1, timing.JOINT_PROBES)[None, :, None]
        x = (q0[:, None] + shares * (q1 - q0)[:, None]).reshape(-1, q0.shape[1])
        flanges = self.flanges(x[:, :dof]).reshape(len(steps), timing.JOINT_PROBES, 4, 4)
        ext = x[:, dof:].reshape(len(steps), timing.JOINT_PROBES, -1)
        out = []
        for s, f, e in zip(steps, flanges, ext):
            m = s.motion
            if m.tool is None:
                out.append(self.cellkin.robot_base(self.cellkin.split(e), len(e)) @ f)
                continue
            fr = self.frames_at(m.tool, m.wobj, e)
            out.append(fr.relative(f) if not fr.stationary else fr.base @ f)
        return np.array(out)

    def load_factor(self, m: Motion):
        found = super().load_factor(m)
        if found is None:
            return None
        return timing.widened(found, self.dof + len(self.ext))

    # -- what the interpreter asks ----------------------------------------------------------------
    def extax_after(self, motions) -> tuple:
        self.extend(motions)
        return self.cellkin.logical(self.ext)

    def lacks(self, axis: str) -> str:
        used = ", ".join(self.driven) or "none"
        return f"the cell drives no {axis} (its axes: {used})"

    def uncoordinated(self, m: Motion) -> str | None:
        if m.wobj is None or not m.wobj.coordinated or self.moved_by(m.wobj) is not None:
            return None
        units = ", ".join(self.units.values()) or "none"
        return (f"the work object is moved by {m.wobj.ufmec or 'a mechanical unit'} (ufprog FALSE), a unit the cell "
                f"does not have (its units: {units}; --external-axes ignore runs it as a fixed frame)")

    def finish(self, run: Run) -> Plan:
        plan = super().finish(run)
        dof = self.dof
        mapping = {v: k for k, v in self.cellkin.mapping.items()}
        axes = tuple((mapping.get((e.name, j.name)), e.name, j.name, j.revolute)
                     for e in self.cellkin.cell.externals for j in e.mechanism.active_joints)
        return replace(plan, q=plan.q[:, :dof], ext=plan.q[:, dof:], ext_axes=axes, framer=self.single)
