"""The Cosserat rod cable model (``rswarp.kernels.rod``): every cable of a mechanism as rigid
segments joined by elastic joints (stretch, shear, bend, twist), clamped, ball-jointed or free at
its control points, in contact with links, the environment, the floor and each other, with
friction. Here: the kernel's model struct made from a ``RodLayout``, and ``CosseratRod``, the
``CableSolver`` that steps many environments on the shared launcher, its state kept on the device.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...kernels.rod.slots import BIG, CABLES_NAME, CRUSHED, FLOOR_NAME, slot_names
from ...kinematics.kinematics import Kinematics
from ...launch import Launcher, init_warp
from ...rsxml.model import Mechanism
from .layout import RodLayout, rod_layout
from .rest_checks import above_floor, outside_links
from .solver import (
    FAILURES,
    GRAVITY,
    MAX_SPEED,
    REACH,
    SLIP,
    CableInfo,
    CableOptions,
    CableSolver,
    ContactMeshes,
    allowed_bend_radius,
)

NO_FLOOR = -1.0e6  # m: the floor's height where there is none
CHUNK = 64  # environments per CPU launch: each one's scratch stays in cache


@dataclass
class RodState:
    """Many environments of every cable, as Warp arrays on the solver's device: each segment's
    centre, orientation, velocity, angular velocity and last acceleration (envs, bodies), status
    (envs,), the wear map (``wear_*``, ``bend``: each body's curvature, ``cycles``), the last
    frame's statistics; and on the host, the joints at the end of the last frame (envs, dof). The
    kernel takes the device arrays in its groups (``groups``: ``rswarp.kernels.rod.types``'
    ``RodBodies``, ``RodWear`` and ``RodFrame`` of these same arrays)."""

    x: object
    q: object
    v: object
    w: object
    a: object
    status: object
    wear_time: object
    wear_peak: object
    wear: object
    bend: object
    cycles: object
    stats: object
    clear: object
    clear_at: object
    load: object
    least: object  # (envs, cables, slots) the least clearance so far, where a frame measures only lower ones
    joints: np.ndarray
    design: object  # (envs,) each environment's design, on the device
    designs: np.ndarray  # the same on the host
    base: np.ndarray | None = None  # (envs, 3) the robot's base moved from its start, at the end of the last frame
    groups: tuple = ()  # the kernel's structs of the arrays above, made with the state (``_groups``)


class CosseratRod(CableSolver):
    """Frames of many environments of a mechanism's cables as discrete Cosserat rods."""

    kind = "rod"
    designs_at_once = True

    def __init__(self, mech: Mechanism, options: CableOptions = CableOptions(), meshes: ContactMeshes | None = None,
                 designs: tuple[Mechanism, ...] = ()):
        """``designs``: mechanisms alike but for their cables' lengths and control points; environment
        e then runs design e modulo their number (``designs[0]`` as ``mech`` itself by default)."""
        from ...kernels.rod.kernel import rod_kernel

        self.layouts = tuple(rod_layout(m, options.density, options.poisson) for m in (designs or (mech,)))
        self.layout = self.layouts[0]
        _alike(mech, self.layouts)
        for m, lay in zip(designs or (mech,), self.layouts):
            above_floor(m, lay, options.floor)
        self.options, self.dof = options, mech.dof
        meshes = meshes or ContactMeshes((None,) * len(mech.graph.links))
        # the kernel's slots (``rswarp.kernels.rod.slots``): its meshes as ``_mesh_arrays`` lists them, then
        # the floor and the cables
        self.slots = slot_names((*mech.graph.links, *(m[0] for m in meshes.environment), *(m[0] for m in meshes.tool)))
        self.designs = tuple(_infos(lay, m, options) for lay, m in zip(self.layouts, designs or (mech,)))
        self.cables = self.designs[0]
        self.failures = FAILURES | {CRUSHED + j: f"the robot pressed a cable into {_what(name)} half its radius "
                                                 "deep: the trajectory drives it through" for j, name in
                                    enumerate(self.slots)}
        self.settle_failures = FAILURES | {
            CRUSHED + j: f"a cable lay half its radius deep in {_what(name)}: its rest shape crosses it, or the "
                         "robot's move from the zero position to the trajectory's start drives it through"
            for j, name in enumerate(self.slots)}
        self.kinematics = Kinematics(mech) if mech.dof else None
        self.links = len(mech.graph.links)
        self.kernel = rod_kernel()
        self.launcher = Launcher(options.device, chunk=CHUNK, threads=options.threads)
        self.launcher.load(self.kernel)
        self._meshes: list = []  # Warp keeps a mesh's BVH only while the Mesh lives
        self.bodies = max(lay.bodies for lay in self.layouts)
        # (designs, cables): where each design's cable starts among its bodies, and its segments
        self._first = np.array([[c.first for c in lay.cables] for lay in self.layouts])
        self._count = np.array([[c.segments for c in lay.cables] for lay in self.layouts])
        self.params = self._params(meshes, options)

    @classmethod
    def cable_infos(cls, mech: Mechanism, options: CableOptions) -> tuple[CableInfo, ...]:
        """Its cables as a solver of ``mech`` would describe them (a design's, for its report)."""
        return _infos(rod_layout(mech, options.density, options.poisson), mech, options)

    @classmethod
    def check(cls, mech: Mechanism, options: CableOptions, links: bool = True) -> None:
        layout = rod_layout(mech, options.density, options.poisson)
        above_floor(mech, layout, options.floor)
        if links:
            outside_links(mech, layout)

    def _params(self, meshes: ContactMeshes, options: CableOptions):
        """The kernel's model: every design's per-body and per-attachment arrays as a row each,
        padded to the most bodies (a padded body is never read)."""
        from ...kernels.rod.types import RodParams

        wp = init_warp()
        dev = self.launcher.device
        arr = lambda a, dtype: wp.array(np.ascontiguousarray(a), dtype=dtype, device=dev)  # noqa: E731
        rows = lambda get, fill=0.0: _rows([np.asarray(get(lay)) for lay in self.layouts], fill)  # noqa: E731
        v6 = wp.types.vector(6, wp.float64)
        layout = self.layout
        p = RodParams()
        p.bodies = arr(np.array([lay.bodies for lay in self.layouts], np.int32), wp.int32)
        for name in ("half", "mass", "radius", "arc", "contact_stiff"):
            setattr(p, name, arr(rows(lambda lay, n=name: getattr(lay, n)), wp.float64))
        p.cable = arr(rows(lambda lay: lay.cable, -1).astype(np.int32), wp.int32)
        for name in ("attach_body", "attach_first", "cable_first"):
            setattr(p, name, arr(rows(lambda lay, n=name: np.asarray(getattr(lay, n), np.int32)).astype(np.int32),
                                 wp.int32))
        p.attach_end = arr(layout.attach_end, wp.float64)
        p.attach_link = arr(np.asarray(layout.attach_link, np.int32), wp.int32)
        p.inertia = arr(rows(lambda lay: lay.inertia), wp.vec2d)
        p.stiff = arr(rows(lambda lay: lay.stiff), v6)
        p.attach_stiff = arr(rows(lambda lay: lay.attach_stiff.reshape(-1, 6)), v6)
        p.touch = arr(rows(lambda lay: lay.touch).astype(np.int32), wp.int32)
        p.attach_point = arr(rows(lambda lay: lay.attach_point), wp.vec3d)
        p.attach_frame = arr(rows(lambda lay: lay.attach_frame, 1.0), wp.quatd)
        p.allowed = arr([c.allowed_bend_radius for c in self.cables], wp.float64)
        p.clamp_a, p.clamp_b = (arr(a, wp.int32) for a in layout.clamps())
        pair_a, pair_b, pair_cable, _ = layout.pairs()
        p.pair_a, p.pair_b, p.pair_cable = arr(pair_a, wp.int32), arr(pair_b, wp.int32), arr(pair_cable, wp.int32)
        p.pair_length = arr(rows(lambda lay: lay.pairs()[3]), wp.float64)
        self._mesh_arrays(p, meshes)
        p.gravity = wp.vec3d(*GRAVITY)
        p.damping, p.friction, p.slip = float(options.damping), float(options.friction), SLIP
        p.floor = NO_FLOOR if options.floor is None else float(options.floor)
        p.margin = arr([2 * lay.half.max() for lay in self.layouts], wp.float64)
        p.reach, p.max_speed = REACH, MAX_SPEED
        p.lowering = 0 if options.frame_clearances else 1
        return p

    def _mesh_arrays(self, p, meshes: ContactMeshes) -> None:
        """The link meshes (when ``contact``), then the environment's, then the tool's, as Warp meshes
        with bounding spheres and boxes in their own frames: the kernel's mesh slots, in order."""
        wp = init_warp()
        dev = self.launcher.device
        links = meshes.links if self.options.contact else (None,) * len(meshes.links)
        entries = [(m, j, np.eye(4)) for j, m in enumerate(links)] + [((v, f), -1, pose) for _, v, f, pose in
                                                                    meshes.environment]
        # the tool rides its link as the link's own mesh does, and like it only with contact
        entries += [((v, f) if self.options.contact else None, j, np.eye(4)) for _, j, v, f in meshes.tool]
        ids, spheres = np.zeros(len(entries), np.uint64), np.zeros((len(entries), 4))
        boxes = np.zeros((len(entries), 2, 3))
        for j, (m, _, _) in enumerate(entries):
            if m is not None:
                mesh = wp.Mesh(points=wp.array(m[0].astype(np.float32), dtype=wp.vec3, device=dev),
                               indices=wp.array(m[1].astype(np.int32).ravel(), dtype=wp.int32, device=dev),
                               support_winding_number=True)
                self._meshes.append(mesh)
                ids[j] = mesh.id
                centre = (m[0].min(axis=0) + m[0].max(axis=0)) / 2
                spheres[j] = (*centre, np.linalg.norm(m[0] - centre, axis=1).max())
                boxes[j] = m[0].min(axis=0), m[0].max(axis=0)
        p.mesh = wp.array(ids, dtype=wp.uint64, device=dev)
        p.sphere = wp.array(spheres, dtype=wp.vec4d, device=dev)
        p.box = wp.array(boxes, dtype=wp.vec3d, device=dev)
        p.mesh_link = wp.array(np.array([j for _, j, _ in entries], np.int32), dtype=wp.int32, device=dev)
        p.mesh_pose = wp.array(np.array([pose for _, _, pose in entries], np.float64).reshape(-1, 4, 4),
                               dtype=wp.mat44d, device=dev)

    def state(self, envs: int) -> RodState:
        from ...kernels.rod.types import LOADS, STATS

        wp = init_warp()
        dev = self.launcher.device
        design = np.arange(envs, dtype=np.int32) % len(self.layouts)
        start = lambda get, fill, dtype: wp.array(_rows([get(lay) for lay in self.layouts], fill)[design],  # noqa
                                                  dtype=dtype, device=dev)
        zeros = lambda shape, dtype=wp.float64: wp.zeros(shape, dtype=dtype, device=dev)  # noqa: E731
        b, c, slots = self.bodies, len(self.layout.cables), len(self.slots)
        vec = lambda: zeros((envs, b), wp.vec3d)  # noqa: E731
        state = RodState(start(lambda lay: lay.x, 0.0, wp.vec3d), start(lambda lay: lay.q, 1.0, wp.quatd), vec(),
                         vec(), vec(), zeros(envs, wp.int32),
                         zeros((envs, b)), zeros((envs, b)), zeros((envs, b, slots)), zeros((envs, b)),
                         zeros((envs, b), wp.int32), zeros((envs, c, STATS)), zeros((envs, c, slots)),
                         zeros((envs, c, slots)), zeros((envs, max(len(self.layout.attach_body), 1), LOADS)),
                         wp.full((envs, c, slots), BIG, dtype=wp.float64, device=dev), np.zeros((envs, self.dof)),
                         wp.array(design, dtype=wp.int32, device=dev), design)
        state.groups = _groups(state)
        return state

    def set_damping(self, damping: float) -> None:
        self.params.damping = float(damping)

    def step(self, state: RodState, qs: np.ndarray, dt: float, base: np.ndarray | None = None) -> None:
        from ...kernels.rod.types import MAX_CONTACTS

        envs = state.x.shape[0]
        qs = np.asarray(qs, np.float64)
        if qs.ndim != 3 or qs.shape[:2] != (envs, self.options.substeps):
            raise ValueError(f"qs must have shape ({envs}, {self.options.substeps}, dof), got {qs.shape}")
        poses = self._poses(state.joints, qs)
        if base is not None:  # the links carried with the base (a track's carriage), in the frame it starts in
            start = state.base if state.base is not None else np.zeros((envs, 3))
            poses[..., :3, 3] += np.concatenate([start[:, None], base], axis=1)[:, :, None, :]
            state.base = np.asarray(base[:, -1], np.float64).copy()
        bodies = self.bodies
        self.launcher.launch(self.kernel, envs, params=[self.params, float(dt), int(self.options.iterations)],
                             inputs=[poses, state.design], scratch=(bodies, bodies, bodies * MAX_CONTACTS, bodies),
                             outputs=list(state.groups))
        state.joints = qs[:, -1].copy()

    def _poses(self, start: np.ndarray, qs: np.ndarray) -> np.ndarray:
        """(envs, substeps + 1, links, 4, 4): every link's pose at the frame's start and at each
        substep's end (float64 forward kinematics)."""
        envs, subs = qs.shape[:2]
        if self.kinematics is None:
            return np.ascontiguousarray(np.broadcast_to(np.eye(4), (envs, subs + 1, self.links, 4, 4)))
        q = np.concatenate([start[:, None], qs], axis=1).reshape(envs * (subs + 1), -1)
        return self.kinematics.fk64(q).reshape(envs, subs + 1, self.links, 4, 4)

    def statistics(self, state: RodState) -> list[dict[str, np.ndarray]]:
        from ...kernels.rod import types as t

        stats, clear, at, load = (a.numpy() for a in (state.stats, state.clear, state.clear_at, state.load))
        status = state.status.numpy().copy()
        out = []
        for c in range(len(self.cables)):
            s = stats[:, c]
            own = list(self.layout.cables[c].attachments)
            loads = load[:, own] if own else np.zeros((len(status), 0, t.LOADS))
            out.append({
                "status": status, "tension": s[:, t.TENSION], "tension_at": _at(s[:, t.TENSION_AT]),
                "bend_radius": _far(s[:, t.BEND]), "bend_at": _at(s[:, t.BEND_AT]), "twist": s[:, t.TWIST],
                "twist_rate": s[:, t.TWIST_RATE], "torque": s[:, t.TORQUE], "torque_at": _at(s[:, t.TORQUE_AT]),
                "stretch": s[:, t.STRETCH], "normal_force": s[:, t.NORMAL], "sliding_speed": s[:, t.SLIDING],
                "contact_at": _at(s[:, t.CONTACT_AT]), "pinch": s[:, t.PINCH], "pinch_at": _at(s[:, t.PINCH_AT]),
                "pinch_slots": s[:, [t.PINCH_A, t.PINCH_B]].astype(np.int64), "clearance": _far(clear[:, c]),
                "clearance_at": _at(at[:, c]),
                "clamp_force": loads[:, :, t.FORCE:t.FORCE + 3], "clamp_moment": loads[:, :, t.MOMENT:t.MOMENT + 3],
                "clamp_force_peak": loads[:, :, t.FORCE_PEAK], "clamp_moment_peak": loads[:, :, t.MOMENT_PEAK]})
        return out

    def reset_totals(self, state: RodState) -> None:
        for a in (state.wear_time, state.wear_peak, state.wear, state.cycles):
            a.zero_()
        state.least.fill_(BIG)

    def totals(self, state: RodState) -> list[dict[str, np.ndarray]]:
        time, peak, wear, cycles = (a.numpy() for a in (state.wear_time, state.wear_peak, state.wear, state.cycles))
        out = []
        for c in range(len(self.layout.cables)):
            own = self._segments(state, c)
            out.append({"contact_time": own(time), "peak_normal": own(peak), "wear": own(wear),
                        "bend_cycles": own(cycles).astype(np.int64)})
        return out

    def curvatures(self, state: RodState) -> list[np.ndarray]:
        """Per cable, each environment's segments' curvature now (envs, segments), 1/m."""
        bend = state.bend.numpy()
        return [self._segments(state, c)(bend) for c in range(len(self.layout.cables))]

    def _segments(self, state: RodState, cable: int):
        """A function taking a per-body array (envs, bodies, ...) to cable ``cable``'s segments in each
        environment's design (envs, its most segments over the designs, ...), zero past a design's."""
        first, count = self._first[state.designs, cable], self._count[state.designs, cable]
        if len(self.layouts) == 1:
            return lambda a: a[:, first[0]:first[0] + count[0]].copy()
        s = np.arange(count.max())
        have = s[None] < count[:, None]
        rows, cols = np.arange(len(first))[:, None], np.where(have, first[:, None] + s[None], 0)

        def own(a: np.ndarray) -> np.ndarray:
            out = a[rows, cols]
            out[~have] = 0
            return out
        return own

    def points(self, state: RodState, cable: int, env: int | None = None) -> np.ndarray:
        """(envs, nodes, 3) cable ``cable``'s nodes (NaN past a design's), or (nodes, 3) of ``env``'s."""
        envs = range(state.x.shape[0]) if env is None else (env,)
        x_all, q_all = state.x.numpy(), state.q.numpy()
        rows = []
        for e in envs:
            lay = self.layouts[state.designs[e]]
            c = lay.cables[cable]
            own = slice(c.first, c.first + c.segments)
            x, half, axis = x_all[e, own], lay.half[own][:, None], _axes(q_all[e, own])
            rows.append(np.concatenate([x[:1] - half[:1] * axis[:1], x + half * axis]))
        if env is not None:
            return rows[0]
        most = max(len(r) for r in rows)
        return np.stack([np.pad(r, ((0, most - len(r)), (0, 0)), constant_values=np.nan) for r in rows])

    def frames(self, state: RodState, cable: int, env: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """(centres (S, 3), frames (S, 3, 3): each segment's material axes as columns) of one
        environment's cable, for checks that read the material frame (twist, writhe)."""
        c = self.layouts[state.designs[env]].cables[cable]
        own = slice(c.first, c.first + c.segments)
        return state.x[env].numpy()[own], _matrices(state.q[env].numpy()[own])


def _groups(state: RodState) -> tuple:
    """The kernel's groups of ``state``'s device arrays: its bodies and status, its wear map, its
    frame's statistics (``rswarp.kernels.rod.types``)."""
    from ...kernels.rod.types import RodBodies, RodFrame, RodWear

    bodies, wear, frame = RodBodies(), RodWear(), RodFrame()
    bodies.x, bodies.q, bodies.v, bodies.w, bodies.a, bodies.status = (state.x, state.q, state.v, state.w, state.a,
                                                                       state.status)
    wear.time, wear.peak, wear.wear, wear.bend, wear.cycles = (state.wear_time, state.wear_peak, state.wear,
                                                               state.bend, state.cycles)
    wear.least = state.least
    frame.stats, frame.clear, frame.at, frame.load = state.stats, state.clear, state.clear_at, state.load
    return bodies, wear, frame


def _what(slot: str) -> str:
    return {FLOOR_NAME: "the floor", CABLES_NAME: "a cable"}.get(slot, f"'{slot}'")


def _rows(arrays: list[np.ndarray], fill: float) -> np.ndarray:
    """The arrays stacked as rows, each padded along its first axis to the longest with ``fill``."""
    most = max(len(a) for a in arrays)
    return np.stack([np.concatenate([a, np.full((most - len(a), *a.shape[1:]), fill, a.dtype)]) for a in arrays])


def _alike(mech: Mechanism, layouts: tuple[RodLayout, ...]) -> None:
    """Designs share their cables and attachments (ends, links, clamps): each design's differ only in
    length and place."""
    first = layouts[0]
    for lay in layouts[1:]:
        if len(lay.cables) != len(first.cables) or not np.array_equal(lay.attach_link, first.attach_link) or \
                not np.array_equal(lay.attach_end, first.attach_end) or \
                not all(np.array_equal(a, b) for a, b in zip(lay.clamps(), first.clamps())):
            raise ValueError(f"{mech.name}: designs must share their cables' control points and what holds them")


def _infos(layout: RodLayout, mech: Mechanism, options: CableOptions) -> tuple[CableInfo, ...]:
    return tuple(_info(c, allowed_bend_radius(cable, options)) for c, cable in zip(layout.cables, mech.cables))


def _info(c, allowed: float) -> CableInfo:
    return CableInfo(c.name, c.length, c.section.radius, allowed, c.section.axial, c.section.bending,
                     c.section.torsion, c.arc.copy(), c.centres, c.labels)


def _matrices(q: np.ndarray) -> np.ndarray:
    """Rotation matrices of quaternions (..., 4) as (x, y, z, w)."""
    x, y, z, w = np.moveaxis(q, -1, 0)
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
                     np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
                     np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], -2)


def _axes(q: np.ndarray) -> np.ndarray:
    return _matrices(q)[..., :, 2]


def _far(a: np.ndarray) -> np.ndarray:
    """The kernel's "nothing within reach" (BIG) as +inf."""
    return np.where(a >= BIG, np.inf, a)


def _at(a: np.ndarray) -> np.ndarray:
    return np.where(a < 0, np.nan, a)
