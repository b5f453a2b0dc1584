"""The RSXML model: frozen dataclasses in SI units (m, rad), world frames at the zero position.

Every element keeps the source line it came from (``line``, excluded from equality) so later
checks can point at it. Values keep the form they were written in (a ``Pose`` remembers whether it
was a matrix, Euler angles or a quaternion) so that saving an unchanged model changes no value.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Iterator, Union

import numpy as np

from ..transforms import euler_zyx_matrix, quat_matrix
from .units import ANGLE_UNITS, DEFAULT_ANGLE_UNIT, DEFAULT_LENGTH_UNIT, LENGTH_UNITS

Vec3 = tuple[float, float, float]
Vec4 = tuple[float, float, float, float]

MECHANISM_TYPES = ("Robot", "Tool", "ExternalAxis", "Device", "Conveyor", "Other")
KINEMATICS_FLAGS = (
    "Articulated", "ParallelRod", "Palletizer", "Scara", "Gantry",
    "HollowWrist", "ElbowWristOffset", "Picker", "Other",
)
JOINT_TYPES = ("Rotational", "Prismatic")
KNOWN_ATTRIBUTE_KEYS = ("AllowedTrackModels", "OverrideJointLimits", "WorkEnvelopeData")


def _line() -> int:
    return field(default=0, compare=False, repr=False)


@dataclass(frozen=True)
class Pose:
    """A 3D transform as written: ``t`` plus at most one of ``x/y/z`` (matrix columns), ``euler``
    (ZYX, radians) or ``quat`` (q1 = w first, as ABB writes it). ``None`` fields were omitted."""

    t: Vec3 | None = None
    x: Vec3 | None = None
    y: Vec3 | None = None
    z: Vec3 | None = None
    euler: Vec3 | None = None
    quat: Vec4 | None = None

    def rotation(self) -> np.ndarray:
        """3x3 rotation matrix (identity when no rotation was given)."""
        if self.x is not None and self.y is not None and self.z is not None:
            return np.array([self.x, self.y, self.z], dtype=float).T
        if self.euler is not None:
            return euler_zyx_matrix(*self.euler)
        if self.quat is not None:
            return quat_matrix(self.quat)
        return np.eye(3)

    def matrix(self) -> np.ndarray:
        """4x4 homogeneous transform in metres."""
        m = np.eye(4)
        m[:3, :3] = self.rotation()
        if self.t is not None:
            m[:3, 3] = self.t
        return m

    @property
    def is_identity(self) -> bool:
        return bool(np.allclose(self.matrix(), np.eye(4), atol=0.0))


IDENTITY = Pose()


@dataclass(frozen=True)
class Part:
    """A piece of geometry; ``source`` is the CAD name as written, ``pose`` moves it to its place."""

    name: str
    source: str | None = None
    pose: Pose = IDENTITY
    line: int = _line()


@dataclass(frozen=True)
class Group:
    """A ``GraphicComponentGroup``: named parts (and groups) that move together."""

    name: str
    children: tuple[Union[Part, "Group"], ...] = ()
    pose: Pose = IDENTITY
    line: int = _line()


Component = Union[Part, Group]


def iter_parts(node: Component, parent: np.ndarray | None = None) -> Iterator[tuple[Part, np.ndarray]]:
    """Every Part below ``node`` with the transform that places its geometry in the world."""
    here = (np.eye(4) if parent is None else parent) @ node.pose.matrix()
    if isinstance(node, Part):
        yield node, here
    else:
        for child in node.children:
            yield from iter_parts(child, here)


@dataclass(frozen=True)
class Joint:
    """A joint; its axis runs from ``point1`` to ``point2`` (metres, world frame at zero position)."""

    name: str
    parent: str
    child: str
    type: str = "Rotational"
    active: bool = True
    point1: Vec3 = (0.0, 0.0, 0.0)
    point2: Vec3 = (0.0, 0.0, 1.0)
    line: int = _line()

    @property
    def revolute(self) -> bool:
        return self.type == "Rotational"

    @property
    def axis(self) -> np.ndarray:
        """Unit direction from point1 to point2."""
        d = np.subtract(self.point2, self.point1)
        return d / np.linalg.norm(d)


@dataclass(frozen=True)
class Limit:
    """Joint range in SI (rad for rotational joints, m for prismatic)."""

    joint: str
    min: float
    max: float
    line: int = _line()


@dataclass(frozen=True)
class Flange:
    """A mounting frame on a link, given at the zero position (``tool0`` for a robot)."""

    name: str
    link: str
    pose: Pose = IDENTITY
    line: int = _line()


@dataclass(frozen=True)
class Attribute:
    """A RobotStudio key/value attribute; ``definition`` says if it belongs to the model definition."""

    key: str
    value: str
    definition: bool | None = None
    line: int = _line()


@dataclass(frozen=True)
class ControlPoint:
    """A cable point in world coordinates at the zero position; ``direction`` as written (None:
    the cable turns freely there), ``unit_direction`` normalized."""

    position: Vec3
    attached_to: str | None = None
    direction: Vec3 | None = None
    line: int = _line()

    @property
    def unit_direction(self) -> np.ndarray | None:
        return None if self.direction is None else np.asarray(self.direction) / np.linalg.norm(self.direction)


@dataclass(frozen=True)
class Cable:
    """A dress-pack cable or hose (``AdditionalComponents/Cable``)."""

    name: str
    radius: float
    max_segment_length: float
    control_points: tuple[ControlPoint, ...] = ()
    color: tuple[int, int, int] | None = None
    desired_length: float | None = None
    youngs_modulus: float | None = None  # Pa
    line: int = _line()


@dataclass(frozen=True)
class Mechanism:
    """A robot, tool or external axis: links, joints, limits, flanges, cables and metadata."""

    name: str
    type: str | None = None
    model_name: str | None = None
    kinematics_flags: tuple[str, ...] = ()
    length_unit: str | None = None  # as written; None = omitted (metres)
    angle_unit: str | None = None  # as written; None = omitted (radians)
    motion_control: str | None = None
    base_link: str = ""
    links: tuple[Component, ...] = ()
    joints: tuple[Joint, ...] = ()
    limits: tuple[Limit, ...] = ()
    flanges: tuple[Flange, ...] = ()
    base_frame: Pose | None = None
    home: tuple[float, ...] | None = None  # per active joint, SI
    joint_mask: tuple[int, ...] | None = None
    attributes: tuple[Attribute, ...] = ()
    cables: tuple[Cable, ...] = ()
    path: str | None = field(default=None, compare=False, repr=False)
    line: int = _line()
    section_lines: tuple[tuple[str, int], ...] = field(default=(), compare=False, repr=False)
    comments: tuple[str, ...] = field(default=(), compare=False, repr=False)  # before the root, kept by save

    def section_line(self, name: str) -> int:
        """Source line of a top-level element (Links, HomePosition, ...), or the root's."""
        return dict(self.section_lines).get(name, self.line)

    # -- units ---------------------------------------------------------------------------------
    @property
    def length_factor(self) -> float:
        """Metres per file length unit."""
        return LENGTH_UNITS.get(self.length_unit or DEFAULT_LENGTH_UNIT, 1.0)

    @property
    def angle_factor(self) -> float:
        """Radians per file angle unit."""
        return ANGLE_UNITS.get(self.angle_unit or DEFAULT_ANGLE_UNIT, 1.0)

    def joint_factor(self, joint: Joint) -> float:
        """SI per file unit for this joint's values (angle or length)."""
        return self.angle_factor if joint.revolute else self.length_factor

    def si_length(self, value: float | None) -> float | None:
        """A length given in the file's unit (a command-line value) in metres; None stays None."""
        return None if value is None else value * self.length_factor

    # -- lookup ----------------------------------------------------------------------------------
    @property
    def link_names(self) -> tuple[str, ...]:
        return tuple(link.name for link in self.links)

    @cached_property
    def graph(self):
        """The link graph (``rswarp.rsxml.graph.LinkGraph``), built on first use and kept."""
        from .graph import LinkGraph

        return LinkGraph.build(self)

    @cached_property
    def _by_name(self) -> tuple[dict, dict, dict]:
        """Links, joints and limits by name (the first of a repeated name)."""
        return tuple({x_name(x): x for x in reversed(items)} for items, x_name in (
            (self.links, lambda x: x.name), (self.joints, lambda x: x.name), (self.limits, lambda x: x.joint)))

    def link(self, name: str) -> Component:
        return self._by_name[0][name]

    def joint(self, name: str) -> Joint:
        return self._by_name[1][name]

    @property
    def active_joints(self) -> tuple[Joint, ...]:
        """The joints driven by joint values, in file order (the order of HomePosition)."""
        return tuple(j for j in self.joints if j.active)

    @property
    def dof(self) -> int:
        return len(self.active_joints)

    def limit(self, joint: str) -> Limit | None:
        return self._by_name[2].get(joint)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper limits of the active joints (SI); ±inf where a joint has no limit."""
        lo, hi = [], []
        for j in self.active_joints:
            lim = self.limit(j.name)
            lo.append(lim.min if lim else -np.inf)
            hi.append(lim.max if lim else np.inf)
        return np.array(lo), np.array(hi)

    def home_position(self) -> np.ndarray:
        """Initial joint values (SI): HomePosition, or zeros when the file gives none."""
        return np.array(self.home if self.home is not None else [0.0] * self.dof)

    def attribute(self, key: str) -> str | None:
        for a in self.attributes:
            if a.key == key:
                return a.value
        return None

    @property
    def allowed_track_models(self) -> tuple[str, ...]:
        return tuple((self.attribute("AllowedTrackModels") or "").split())

    @property
    def override_joint_limits(self) -> bool:
        return (self.attribute("OverrideJointLimits") or "").strip().lower() == "true"

    def parts(self, link: str) -> list[tuple[Part, np.ndarray]]:
        """The Parts of a link with their world transforms at the zero position (metres)."""
        return list(iter_parts(self.link(link)))


# -- SmartComponent ------------------------------------------------------------------------------


@dataclass(frozen=True)
class DynamicProperty:
    """A SmartComponent property: name, .NET value type, value text and its UI attributes."""

    name: str
    value_type: str | None = None
    value: str | None = None
    options: tuple[tuple[str, str], ...] = ()  # other XML attributes (readOnly, uiVisible, ...)
    attributes: tuple[tuple[str, str], ...] = ()  # child <Attribute key value>
    line: int = _line()


@dataclass(frozen=True)
class IOSignal:
    """A SmartComponent I/O signal (DigitalInput, DigitalOutput, AnalogInput, ...)."""

    name: str
    signal_type: str | None = None
    options: tuple[tuple[str, str], ...] = ()
    line: int = _line()


@dataclass(frozen=True)
class Binding:
    """A property binding or I/O connection, kept as its element name and attributes."""

    kind: str
    options: tuple[tuple[str, str], ...] = ()
    line: int = _line()


@dataclass(frozen=True)
class SmartComponent:
    """The declarative parts of a SmartComponent; its code-behind (``code_behind``) is only named."""

    name: str
    options: tuple[tuple[str, str], ...] = ()  # icon, codeBehind, canBeSimulated, ...
    properties: tuple[DynamicProperty, ...] = ()
    signals: tuple[IOSignal, ...] = ()
    bindings: tuple[Binding, ...] = ()
    components: tuple[Union[Component, Mechanism, "SmartComponent"], ...] = ()
    assets: tuple[str, ...] = ()
    descriptions: tuple[tuple[str, str], ...] = field(default=(), compare=False)  # from LibraryResource
    path: str | None = field(default=None, compare=False, repr=False)
    comments: tuple[str, ...] = field(default=(), compare=False, repr=False)  # before the root, kept by save
    line: int = _line()

    def option(self, key: str) -> str | None:
        return dict(self.options).get(key)

    @property
    def code_behind(self) -> str | None:
        return self.option("codeBehind")
