"""Batched forward kinematics of one mechanism: kernels made once per mechanism, then any batch.

Poses are link frames in the file's link order (``mech.link_names``); ``q`` is ``(N, dof)``
active-joint values in SI (rad, m), in the file's order of active joints.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, model_error
from ..kernels import fk as fk_kernels
from ..kernels import fk_lanes, walk
from ..kernels.ik import FAR_M, NOT_RIGID
from ..launch import Launcher, init_warp
from ..rsxml.model import Mechanism
from . import ik, ik_numeric, ik_planar
from .chain import loops_close, mechanism_chain
from .ik_inputs import checked_conf, rigid_poses
from .loops import passive_values
from .quick import Quick

LOOPS_CHUNK = 1 << 14  # configurations whose poses ``loops_close`` holds at once


class Kinematics:
    """Forward kinematics of one mechanism on a Warp device.

    ``fk(q)`` gives every link's pose, ``flange(q)`` a flange's, ``wrist_flange(q)`` the wrist
    centre and flange positions; ``fk64`` and ``wrist_flange64`` do the same in float64.
    Chains up to ``MAX_UNROLLED_LINKS`` links get unrolled kernels; longer ones the generic walk."""

    def __init__(self, mech: Mechanism, device: str = "cpu", chunk: int | None = None, threads: int | None = None):
        self.mech = mech
        self.graph = mech.graph
        self.chain = mechanism_chain(mech)
        self.launcher = Launcher(device, chunk, threads)
        self.device = self.launcher.device
        self.unrolled = len(self.chain.parent) <= fk_kernels.MAX_UNROLLED_LINKS
        self.newton_loops = len(self.chain.newton_rows) > 0  # loops the kernels solve by damped Newton steps
        if self.newton_loops and not self.unrolled:
            j = self.graph.closing[0]
            raise model_error(mech, f"loops with no closed form are solved in chains of at most "
                                    f"{fk_kernels.MAX_UNROLLED_LINKS} links; this one has {len(self.links)}", j.line)
        self._flanges = tuple((self.graph.link_index(f.link), f.pose.matrix()) for f in mech.flanges)
        self._wrist = self._wrist_constants()
        self._arm_links = tuple(self.graph.link_index(j.child) for j in self.graph.active)
        self._kernels: dict = {}
        self._loaded: set = set()  # lanes kernels whose module is compiled (``_launch_lanes``)
        self._kernels_for(np.float32)  # compiled (or loaded from Warp's cache) now, not mid-batch
        self._quick = Quick(self)  # one to a few items a call (``quick``)

    # -- public ------------------------------------------------------------------------------------
    @property
    def links(self) -> tuple[str, ...]:
        """Link names in the order of ``fk``'s second axis: the file's order (``mech.link_names``)."""
        return self.mech.link_names

    @property
    def dof(self) -> int:
        return len(self.graph.active)

    def fk(self, q, links: list[str] | None = None, out: np.ndarray | None = None, rows: int = 4) -> np.ndarray:
        """``(N, n_links, 4, 4)`` float32 link poses in metres (only ``links`` when given); NaN for
        the links a loop moves where it cannot close (``loops_close(q)`` is False). ``rows=3``
        gives the top three rows, (N, n_links, 3, 4): a quarter fewer bytes to write and keep.

        ``out`` (C-contiguous float32 of that shape) is filled in place: reusing one buffer in a loop
        saves the page faults of a fresh array."""
        if rows not in (3, 4):
            raise ValueError(f"rows must be 3 or 4, got {rows}")
        lanes = self._lanes() if links is None else None
        if lanes is not None:  # eight configurations a thread, in AVX registers
            return self._launch_lanes(lanes[0][rows], q, out, (len(self.links), rows, 4))
        whole = out if rows == 4 else None
        if links is not None:
            poses = self.frames(q, [(self.graph.link_index(n), np.eye(4)) for n in links], whole)
        else:
            poses = self._all_links(q, whole, np.float32)
        if rows == 4:
            return poses
        out = self._out(out, poses.shape[:2] + (3, 4), np.float32)
        out[...] = poses[:, :, :3]
        return out

    def fk_transforms(self, q, out: np.ndarray | None = None) -> np.ndarray:
        """``(N, n_links, 7)`` float32 link poses as position and unit quaternion (x, y, z, w), as
        Newton's ``body_q`` holds them: 28 bytes a pose where a 4x4 takes 64. A quaternion and its
        negative are the same turn; which one comes is not promised. On the CPU's eight-a-thread
        path the rotations come from the joints' half angles, so the positions round a little
        differently from ``fk``'s (within 2e-6 m of ``fk64``'s)."""
        lanes = self._lanes()
        if lanes is not None:
            return self._launch_lanes(lanes[0][7], q, out, (len(self.links), 7))
        from scipy.spatial.transform import Rotation

        poses = self.fk(q)
        out = self._out(out, poses.shape[:2] + (7,), np.float32)
        out[..., :3] = poses[..., :3, 3]
        turns = Rotation.from_matrix(poses[..., :3, :3].reshape(-1, 3, 3).astype(np.float64))
        out[..., 3:] = turns.as_quat().reshape(poses.shape[:2] + (4,))
        return out

    @property
    def passive_joints(self) -> tuple[str, ...]:
        """The passive joints that follow the active ones (those of solved loops), in file order."""
        return tuple(j.name for _, j in self._passive_rows())

    def passive(self, q) -> np.ndarray:
        """``(N, len(passive_joints))`` values of the passive joints at ``q`` (rad / m), as the FK
        kernels solve them (``loops.passive_map``), computed here in float64; NaN where a loop cannot
        close (``loops_close``)."""
        values = passive_values(self.chain, q)
        cols = [values[k] for k, _ in self._passive_rows()]
        return np.stack(cols, axis=1) if cols else np.zeros((len(np.atleast_2d(q)), 0))

    def loops_close(self, q) -> np.ndarray:
        """``(N,)`` the per-configuration flag of closed loops: False where a loop cannot close at
        ``q`` (past a dead point); there ``fk`` and the sweeps' poses are NaN. Loops solved by
        Newton steps are asked of the device kernels (the host twin is slow), the rest on the host."""
        if not self.newton_loops:
            return loops_close(self.chain, q)
        q = self._q(q, np.float64)
        out = np.ones(len(q), bool)
        for lo in range(0, len(q), LOOPS_CHUNK):  # memory: one chunk of poses at a time
            out[lo:lo + LOOPS_CHUNK] = np.isfinite(self.fk64(q[lo:lo + LOOPS_CHUNK])).all(axis=(1, 2, 3))
        return out

    def _passive_rows(self) -> list:
        """(link, its tree joint) for each passive joint that follows the active ones, file order."""
        c = self.chain
        moved = {j.name: k for k, j in self.graph.tree_order
                 if np.any(c.mimic[k] != 0) or c.closed_form[k, 0] != 0 or c.unknown[k] >= 0}
        return [(moved[j.name], j) for j in self.mech.joints if j.name in moved]

    def fk64(self, q) -> np.ndarray:
        """``(N, n_links, 4, 4)`` float64 link poses: for checks and for refining extremes."""
        quick = self._quick.fk64(q)
        return self._all_links(q, None, np.float64) if quick is None else quick

    def flange(self, q, name: str | None = None, out: np.ndarray | None = None) -> np.ndarray:
        """``(N, 4, 4)`` float32 flange poses (the first flange, or the one named)."""
        if name is None and out is None:
            quick = self._quick.flange(q)
            if quick is not None:
                return quick
        f = self._flange_index(name)
        lanes = self._lanes()
        if lanes is not None:
            return self._launch_lanes(lanes[1][f], q, out, (4, 4))
        if not self.unrolled:
            link, m = self._flanges[f]
            res = self.frames(q, [(link, m)], None if out is None else out[:, None])
            return res[:, 0]
        q = self._q(q, np.float32)
        out = self._out(out, (q.shape[0], 4, 4), np.float32)
        self.launcher.launch(self._kernels_for(np.float32)[1][f], q.shape[0], inputs=[q], outputs=[out])
        return out

    def frames(self, q, outputs: list[tuple[int, np.ndarray]], out: np.ndarray | None = None) -> np.ndarray:
        """``(N, len(outputs), 4, 4)``: pose of link index ``k`` times a 4x4 ``offset``, per output
        (the generic tree walk)."""
        return self._frames(q, outputs, out, np.float32)

    def wrist_flange(self, q, flange: str | None = None, wrist: bool = True) -> tuple[np.ndarray | None, np.ndarray]:
        """``(N, 3)`` wrist-centre positions (the point of the J5 axis nearest the J4 axis) and
        ``(N, 3)`` flange positions, float32 metres. The wrist needs five active joints or more;
        with ``wrist=False`` only the flange is computed and the first result is None."""
        w, f = self._wrist_flange(q, flange, wrist, np.float32)
        return (w if wrist else None), f

    def wrist_flange64(self, q, flange: str | None = None) -> tuple[np.ndarray | None, np.ndarray]:
        """As ``wrist_flange`` in float64 (the wrist is None below five axes)."""
        w, f = self._wrist_flange(q, flange, self._wrist is not None, np.float64)
        return (w if self._wrist is not None else None), f

    def flange_frame(self, name: str | None = None) -> tuple[int, np.ndarray]:
        """(link index, 4x4 zero-position pose) of a flange (the first when ``name`` is None)."""
        return self._flanges[self._flange_index(name)]

    def ik(self, poses, conf=None, out: ik.IKSolutions | None = None):
        """Inverse kinematics of ``(N, 4, 4)`` flange poses (the first flange, metres), float32.

        With no ``conf``: every solution, an ``IKSolutions`` (the 8 closed-form branches of an arm,
        q4 and q6 turned into their limits nearest zero; ``ik.turns`` adds the other turns). With
        ``conf`` ((4,) or (N, 4): cf1, cf4, cf6, cfx): ``(q (N, dof), found (N,))``, the solution
        with that configuration data, NaN where none has it. See docs/kinematics.md.

        ``out`` (an arm's every solution, no ``conf``): an ``IKSolutions`` of C-contiguous arrays
        shaped and typed as the answer's, filled in place and returned: reusing one in a loop saves
        the page faults of fresh arrays."""
        return self._ik(poses, conf, np.float32, out)

    def ik64(self, poses, conf=None, out: ik.IKSolutions | None = None):
        """As ``ik`` in float64."""
        quick = self._quick.ik64(poses) if conf is None and out is None else None
        return self._ik(poses, conf, np.float64, out) if quick is None else quick

    def confdata(self, q) -> np.ndarray:
        """``(N, 4)`` int ABB configuration data (cf1, cf4, cf6, cfx) of joint values ``q``; a
        palletizer's cf4 is 0 and its cfx has no axis 5 (``ik_planar.confdata``)."""
        form = self._ik_form()
        q = self._q(q, np.float64)
        if isinstance(form, ik.ArmConstants):
            return ik.confdata(form, q, self.fk64(q), self._arm_links)
        if isinstance(form, ik_planar.PlanarArm):
            link, m = self.flange_frame()
            return ik_planar.confdata(form, q, (self.fk64(q)[:, link] @ m)[:, :3, 3])
        raise model_error(self.mech, f"'{self.mech.name}' is neither a 6-axis arm with a spherical wrist nor a "
                                     "palletizer: it has no ABB configuration data")

    @property
    def ik_method(self) -> str:
        """"arm" or "palletizer" (closed forms) or "numerical"."""
        form = self._ik_form()
        return "arm" if isinstance(form, ik.ArmConstants) else "palletizer" if form is not None else "numerical"

    def close(self) -> None:
        self.launcher.close()

    # -- plumbing ----------------------------------------------------------------------------------
    def solutions64(self, poses):
        """Every solution of ``(N, 4, 4)`` flange poses in float64 with the whole turns of the axes
        that turn without end (an arm's 4 and 6, a palletizer's last) that fit their limits."""
        poses = self._poses(poses, np.float64)
        return self._turned(self._solve(self._ik_form(), poses, np.float64))

    def _ik(self, poses, conf, dtype, out=None):
        poses = self._poses(poses, dtype)
        if conf is not None:
            if out is not None:
                raise ValueError("out holds every solution: it is not taken with conf")
            conf = checked_conf(conf, len(poses))
        form = self._ik_form()
        sol = self._solve(form, poses, dtype, out)
        if conf is None:
            return sol
        return ik.pick(self._turned(sol), conf, ik.quadrant_axes(form), ik.wrist_axis(form), form, self.mech.bounds())

    def _poses(self, poses, dtype) -> np.ndarray:
        """Flange poses checked as rigid transforms: on the host, or by the arm's kernel."""
        return rigid_poses(poses, dtype, checked=not isinstance(self._ik_form(), ik.ArmConstants))

    def _turned(self, sol):
        form = self._ik_form()
        if isinstance(form, ik.ArmConstants):
            return ik.turns(sol, *self.mech.bounds())
        if isinstance(form, ik_planar.PlanarArm):
            return ik.turns(sol, *self.mech.bounds(), axes=(form.last,), conf_columns=(2,))
        return sol

    def _solve(self, form, poses, dtype, out=None):
        sol = self._solve_form(form, poses, dtype, out)
        if not isinstance(form, ik.ArmConstants):  # the arm's kernel says so itself
            far = np.abs(poses[:, :3, 3]).max(axis=1) > FAR_M
            if far.any():  # out of reach, whatever a solver's rounding made of it
                sol.status[far] = ik.NO_REACH
        return sol

    def _solve_form(self, form, poses, dtype, out=None):
        if out is not None and not isinstance(form, ik.ArmConstants):
            raise ValueError("out is for an arm's closed form (8 branches a pose)")
        if isinstance(form, ik.ArmConstants):
            sol = ik.closed_form(self.launcher, form, poses, dtype, self._arm_kernel(form, dtype), out)
            if NOT_RIGID in sol.status[:, 0].tolist():  # the kernel refuses every branch of it
                k = int(np.argmax(sol.status[:, 0] == NOT_RIGID))
                rigid_poses(poses[k:k + 1], np.float64, offset=k, total=len(poses))  # says why
                raise InputError(f"pose {k} of {len(poses)} is not a rigid transform")
            return sol
        if isinstance(form, ik_planar.PlanarArm):
            return ik_planar.solve(self.launcher, form, poses, *self.mech.bounds(), self.dof)
        return ik_numeric.solve(self, poses.astype(np.float64))

    def _arm_kernel(self, form, dtype):
        """The arm's (``form``) closed-form IK kernel in one precision, made once."""
        key = ("ik", dtype)
        kernel = self._kernels.get(key)
        if kernel is None:
            kernel = self._kernels[key] = ik.ik_kernel(form, dtype)
        return kernel

    def _ik_form(self):
        """The closed form that fits the mechanism (found on first use, and proven on its own forward
        kinematics: each of 16 configurations is among the solutions of its pose), or None."""
        if not hasattr(self, "_form"):
            self._form = None
            if self.mech.flanges and not self.newton_loops:
                link, m = self.flange_frame()
                for form in (ik.arm_constants(self.mech), ik_planar.planar_arm(self.chain, link, m)):
                    if form is not None and self._proven(form):
                        self._form = form
                        break
        return self._form

    def _proven(self, form) -> bool:
        lower, upper = self.mech.bounds()
        q = np.random.default_rng(0).uniform(np.maximum(lower, -np.pi), np.minimum(upper, np.pi), (16, self.dof))
        link, m = self.flange_frame()
        sol = self._solve(form, self.fk64(q)[:, link] @ m, np.float64)
        near = np.abs(np.angle(np.exp(1j * (sol.q - q[:, None])))).max(axis=-1) < 1e-6
        return bool(np.all(np.any(near & sol.ok, axis=1)))

    def _wrist_constants(self):
        joints = self.graph.wrist_joints
        if joints is None:
            return None
        return tuple((self.graph.link_index(j.parent), tuple(float(v) for v in j.point1),
                      tuple(float(v) for v in j.axis)) for j in joints)

    def _kernels_for(self, dtype):
        """(all_links, flange kernels, wrist kernels) of one precision, made on first use."""
        if dtype not in self._kernels:
            wp = init_warp()
            scalar = wp.float32 if dtype == np.float32 else wp.float64
            if self.unrolled:
                kernels = fk_kernels.chain_kernels(self.chain, self._flanges, self._wrist, scalar)
                self.launcher.load(kernels[0])
            else:
                kernels = None
            self._kernels[dtype] = kernels
        return self._kernels[dtype]

    def _lanes(self):
        """(all_links by rows, flange kernels) eight configurations a thread (``fk_lanes``), made
        and compiled on first use; None on a GPU (a thread each is its parallelism) or for a chain
        with loops, mimics or closed forms."""
        if "lanes" not in self._kernels:
            fits = self.unrolled and self.device.is_cpu and fk_lanes.lanes_fit(self.chain)
            self._kernels["lanes"] = fk_lanes.lane_kernels(self.chain, self._flanges) if fits else None
        return self._kernels["lanes"]

    def _launch_lanes(self, kernel, q, out, shape: tuple) -> np.ndarray:
        """A lanes kernel over ``q`` into ``out`` (N, *shape), its module loaded first (``_load``)."""
        self._load(kernel)
        q = self._q(q, np.float32)
        out = self._out(out, (q.shape[0], *shape), np.float32)
        self.launcher.launch(kernel, q.shape[0], inputs=[q], outputs=[out], lanes=fk_lanes.LANES, overwrites=True)
        return out

    def _load(self, kernel) -> None:
        """A lanes kernel's module compiled (or loaded from Warp's cache) here, once: not by two
        worker threads at once."""
        if kernel not in self._loaded:
            self.launcher.load(kernel)
            self._loaded.add(kernel)

    def _generic(self, dtype):
        """(tree struct on the device, frames kernel, wrist kernel) of the generic walk."""
        key = ("generic", dtype)
        if key not in self._kernels:
            wp = init_warp()
            scalar = wp.float32 if dtype == np.float32 else wp.float64
            Tree, frames, wrist = walk.generic_kernels(scalar)
            tree = Tree()
            c = self.chain
            for name in ("parent", "jtype", "qidx", "order"):
                setattr(tree, name, wp.array(getattr(c, name), dtype=wp.int32, device=self.device))
            for name in ("axis", "point"):
                setattr(tree, name, wp.array(getattr(c, name).astype(dtype), dtype=wp.types.vector(3, scalar),
                                             device=self.device))
            follows = np.any(c.mimic != 0, axis=1) | (c.closed_form[:, 0] != 0)
            tree.follows = wp.array(follows.astype(np.int32), dtype=wp.int32, device=self.device)
            tree.mimic = wp.array(np.ascontiguousarray(c.mimic, dtype), dtype=scalar, device=self.device)
            tree.closed_form = wp.array(np.ascontiguousarray(c.closed_form, dtype),
                                        dtype=wp.types.vector(c.closed_form.shape[1], scalar), device=self.device)
            tree.closed_input = wp.array(np.ascontiguousarray(c.closed_input, dtype), dtype=scalar, device=self.device)
            self.launcher.load(frames)
            self._kernels[key] = (tree, frames, wrist)
        return self._kernels[key]

    def _all_links(self, q, out, dtype) -> np.ndarray:
        if not self.unrolled:
            return self._frames(q, [(k, np.eye(4)) for k in range(len(self.links))], out, dtype)
        q = self._q(q, dtype)
        out = self._out(out, (q.shape[0], len(self.links), 4, 4), dtype)
        self.launcher.launch(self._kernels_for(dtype)[0], q.shape[0], inputs=[q], outputs=[out], overwrites=True)
        return out

    def _frames(self, q, outputs: list[tuple[int, np.ndarray]], out, dtype) -> np.ndarray:
        """The generic walk's frames kernel in one precision (the unrolled kernel's links times the
        offsets, where a loop needs the Newton solve, which only unrolled kernels carry)."""
        wp = init_warp()
        q = self._q(q, dtype)
        out = self._out(out, (q.shape[0], len(outputs), 4, 4), dtype)
        if self.newton_loops:
            poses = self._all_links(q, None, dtype)
            out[:] = poses[:, [k for k, _ in outputs]] @ np.array([m for _, m in outputs], dtype)
            return out
        tree, frames, _ = self._generic(dtype)
        links = wp.array(np.array([k for k, _ in outputs], np.int32), dtype=wp.int32, device=self.device)
        offsets = wp.array(np.array([m for _, m in outputs], dtype), dtype=frames.adj.args[2].type.dtype,
                           device=self.device)
        self.launcher.launch(frames, q.shape[0], params=[tree, links, offsets], inputs=[q], outputs=[out],
                             scratch=len(self.links))
        return out

    def _wrist_flange(self, q, flange, wrist: bool, dtype):
        if wrist and self._wrist is None:
            raise model_error(self.mech, f"'{self.mech.name}' has {self.dof} axes: a wrist centre needs J4 and J5")
        f = self._flange_index(flange)
        q = self._q(q, dtype)
        wpos, fpos = np.empty((q.shape[0], 3), dtype), np.empty((q.shape[0], 3), dtype)
        if self.unrolled:
            self.launcher.launch(self._kernels_for(dtype)[2][f], q.shape[0], inputs=[q], outputs=[wpos, fpos])
        else:
            self._generic_wrist(f, q, wpos, fpos, dtype)
        return wpos, fpos

    def _generic_wrist(self, f: int, q, wpos, fpos, dtype) -> None:
        wp = init_warp()
        tree, frames, kernel = self._generic(dtype)
        link, m = self._flanges[f]
        links, consts = [link], [m[:3, 3]]
        if self._wrist is not None:
            (l4, p4, a4), (l5, p5, a5) = self._wrist
            links += [l4, l5]
            consts += [p4, a4, p5, a5]
        vec3 = kernel.adj.args[2].type.dtype  # consts
        self.launcher.launch(kernel, q.shape[0], params=[
            tree, wp.array(np.array(links, np.int32), dtype=wp.int32, device=self.device),
            wp.array(np.array(consts, dtype), dtype=vec3, device=self.device)],
            inputs=[q], outputs=[wpos, fpos], scratch=len(self.links))

    def _flange_index(self, name: str | None) -> int:
        names = [f.name for f in self.mech.flanges]
        if not names:
            raise model_error(self.mech, f"'{self.mech.name}' has no flange (a Flanges/Flange element names one)")
        if name is None:
            return 0
        if name not in names:
            raise KeyError(f"no flange '{name}' (flanges: {', '.join(names)})")
        return names.index(name)

    def _q(self, q, dtype) -> np.ndarray:
        q = np.ascontiguousarray(np.atleast_2d(q), dtype=dtype)
        if q.ndim != 2 or q.shape[1] != self.dof:
            raise ValueError(f"q must have shape (N, {self.dof}), got {q.shape}")
        return q

    @staticmethod
    def _out(out: np.ndarray | None, shape: tuple[int, ...], dtype) -> np.ndarray:
        if out is None:
            return np.empty(shape, dtype)
        if out.shape != shape or out.dtype != dtype or not out.flags.c_contiguous:
            raise ValueError(f"out must be a C-contiguous {np.dtype(dtype).name} array of shape {shape}")
        return out
