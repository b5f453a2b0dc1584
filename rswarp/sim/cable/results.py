"""What a cable run reports per cable: per environment, the extremes of each quantity and when and
where they happened, the load on every attachment, and the wear map along the cable; over time,
the spread of the main quantities across environments (``Series``)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

MAX_RECORDED = 20_000  # frames kept for playback; longer runs keep every k-th frame

SERIES = ("tension", "bend", "gap", "torque")
# a cut run keeps every environment's per-frame values as the model gives them (float64), so the
# spread it takes at the end is the one a whole run takes
VALUE = np.float64


@dataclass(frozen=True)
class Series:
    """One quantity over time across environments: least, median and greatest per frame."""

    low: np.ndarray
    median: np.ndarray
    high: np.ndarray

    @classmethod
    def of(cls, rows: list[tuple[float, float, float]]) -> "Series":
        a = np.asarray(rows, np.float64).reshape(len(rows), 3)
        return cls(a[:, 0], a[:, 1], a[:, 2])


def spread(values: np.ndarray) -> tuple[float, float, float]:
    """(least, median, greatest) of one frame's finite values; NaN when none is."""
    v = values[np.isfinite(values)]
    if len(v) == 0:
        return (np.nan, np.nan, np.nan)
    return (float(v.min()), float(np.median(v)), float(v.max()))


@dataclass(frozen=True)
class CableResult:
    """One cable over the run, per environment (arrays of length envs) and over time (``Series``
    of frames). Times in seconds of the trajectory, lengths in metres, arcs (``*_at``) in metres
    along the cable from its first control point, forces in newtons, moments in newton metres; NaN
    where a quantity never occurred. ``links`` names the slots of every per-slot array, ``attachments``
    the control points held by links, ``segments`` the arc of each segment's middle (the wear map's
    places)."""

    name: str
    length: float
    radius: float
    allowed_bend_radius: float
    axial_stiffness: float  # E A, N
    bending_stiffness: float  # E I, N m^2
    torsion_stiffness: float  # G J, N m^2
    links: tuple[str, ...]
    attachments: tuple[str, ...]
    segments: np.ndarray
    peak_tension: np.ndarray  # the rod's greatest axial force
    peak_tension_time: np.ndarray
    peak_tension_at: np.ndarray
    taut_time: np.ndarray  # when its axial strain first passed the run's max_strain (NaN: never)
    min_bend_radius: np.ndarray
    min_bend_time: np.ndarray
    min_bend_at: np.ndarray
    clearance: np.ndarray  # (envs, slots): least clearance; +inf where never within reach
    clearance_time: np.ndarray
    clearance_at: np.ndarray
    contact_time: np.ndarray  # (envs, slots): first contact
    contact_at: np.ndarray
    stretch: np.ndarray  # greatest straight distance between consecutive attachments / their cable length
    stretch_time: np.ndarray
    max_twist: np.ndarray  # rad, greatest |twist| between the first and last clamps, whole turns counted
    max_twist_rate: np.ndarray  # rad/m
    max_torque: np.ndarray  # N m, the greatest torque the cable carries about itself
    max_torque_time: np.ndarray
    max_torque_at: np.ndarray
    peak_normal: np.ndarray  # the greatest normal force on a segment's contact
    peak_normal_time: np.ndarray
    peak_normal_at: np.ndarray
    max_sliding_speed: np.ndarray  # m/s, of a touching segment
    pinch: np.ndarray  # N: the hardest a segment was pressed from opposite sides (0: never)
    pinch_time: np.ndarray
    pinch_at: np.ndarray
    pinch_slots: np.ndarray  # (envs, 2) the slots (``links``) that pressed it, -1 where none
    pinch_q: np.ndarray  # (envs, dof) the robot's joints then, in radians or metres
    clamp_force: np.ndarray  # (envs, attachments): the greatest force the cable pulls the link with
    clamp_force_time: np.ndarray
    clamp_moment: np.ndarray  # (envs, attachments): the greatest moment about the control point
    clamp_moment_time: np.ndarray
    final_clamp_force: np.ndarray  # (envs, attachments, 3) at the end, world axes
    final_clamp_moment: np.ndarray
    wear_contact_time: np.ndarray  # (envs, segments) s in contact
    wear_peak_normal: np.ndarray  # (envs, segments) N
    wear: np.ndarray  # (envs, segments, slots) J: normal force x sliding distance (Archard)
    bend_cycles: np.ndarray  # (envs, segments): below the allowed bend radius and back
    # (envs, segments): rainflow cycles of the segment's curvature (ranges past FATIGUE_FLOOR of the
    # allowed one's), and Miner's sum of count x range^FATIGUE_EXPONENT (1/m^m), over the run
    fatigue_cycles: np.ndarray
    fatigue_sum: np.ndarray
    status: np.ndarray  # "ok" or why the environment stopped
    failed_time: np.ndarray
    final_points: np.ndarray  # (envs, N, 3)
    tension: Series = field(repr=False)
    bend: Series = field(repr=False)
    gap: Series = field(repr=False)  # least clearance to anything, per frame
    torque: Series = field(repr=False)
    recorded: np.ndarray = field(repr=False)  # (kept frames, N, 3) of options.record
    stride: int = 1  # recorded keeps every stride-th frame

    @property
    def envs(self) -> int:
        return len(self.peak_tension)

    @property
    def too_tight(self) -> np.ndarray:
        return self.min_bend_radius < self.allowed_bend_radius

    @property
    def touching(self) -> np.ndarray:
        """(envs,) the environments where the cable met a link, the floor or a cable."""
        return np.isfinite(self.contact_time).any(axis=1)

    @property
    def segment_wear(self) -> np.ndarray:
        """(envs, segments) J: the Archard wear of each segment on everything it touched."""
        return self.wear.sum(axis=2)


# CableResult's fields with one row per environment (the others describe the cable or the run)
PER_ENV = ("peak_tension", "peak_tension_time", "peak_tension_at", "taut_time", "min_bend_radius", "min_bend_time",
           "min_bend_at",
           "clearance", "clearance_time", "clearance_at", "contact_time", "contact_at", "stretch", "stretch_time",
           "max_twist", "max_twist_rate", "max_torque", "max_torque_time", "max_torque_at", "peak_normal",
           "peak_normal_time", "peak_normal_at", "max_sliding_speed", "pinch", "pinch_time", "pinch_at", "pinch_slots",
           "pinch_q", "clamp_force", "clamp_force_time",
           "clamp_moment", "clamp_moment_time", "final_clamp_force", "final_clamp_moment", "wear_contact_time",
           "wear_peak_normal", "wear", "bend_cycles", "fatigue_cycles", "fatigue_sum", "status", "failed_time",
           "final_points")


def worst_wear(c: CableResult, envs: np.ndarray) -> tuple[int, int, int] | None:
    """(environment, segment, slot) of the greatest Archard wear among ``envs``: the segment that
    wears most, and what it wears on most; None where nothing slid under load."""
    if not len(envs):
        return None
    total = c.segment_wear[envs]
    if not np.any(total > 0):
        return None
    e, s = np.unravel_index(int(np.argmax(total)), total.shape)
    return int(envs[e]), int(s), int(np.argmax(c.wear[envs[e], s]))


def one_env(c: CableResult, e: int, info) -> CableResult:
    """Environment ``e`` of ``c`` as a result of its own, with the cable as ``info`` (a
    ``CableInfo``) gives it: its length and segments (a design's), the per-segment arrays cut to
    them."""
    segments, nodes = len(info.segments), len(info.arc)
    rows = {k: getattr(c, k)[e:e + 1] for k in PER_ENV}
    for k in ("wear_contact_time", "wear_peak_normal", "wear", "bend_cycles", "fatigue_cycles", "fatigue_sum"):
        rows[k] = rows[k][:, :segments]
    rows["final_points"] = rows["final_points"][:, :nodes]
    return dataclasses.replace(c, length=info.length, segments=info.segments, **rows)
