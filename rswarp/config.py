"""The options of a run, one frozen object per concern, built once (``rswarp.cli`` from its
arguments, a Python caller by hand) and passed down whole: how a RAPID task runs and is checked
(``TaskOptions``), the hose's material and ratings (``HoseOptions``), a design sweep's draw
(``DesignOptions``), where a batch runs (``BatchOptions``) and a ``--video`` (``VideoOptions``).
Values are as the user gives them: lengths in the robot file's unit, angles in degrees; the
library converts them where it knows the file. Each field is the command-line option of its name
(``min_bend_radius`` is ``--min-bend-radius``), the few others the destination their option
names (``--input`` gives ``inputs``, ``--env`` ``environment``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from typing import Any, Mapping

from .errors import InputError

EXTERNAL_AXES = ("auto", "error", "ignore")
MAX_STRAIN = 0.005  # axial strain of a hose that hangs rather than pulls
MAX_TORSION_DEG = 180.0  # deg/m: the usual rating of a torsion-rated robot hose
DENSITY = 1200.0  # kg/m^3: a hose
POISSON = 0.5  # rubber: incompressible, so G = E / 3
FRICTION = 0.4  # Coulomb's coefficient of a rubber hose on painted metal, dry (0.3 to 0.6)
FRAME_RATE = 60.0  # frames per second: results are sampled per frame, substeps between
SUBSTEPS = 4  # per frame: 4.2 ms steps


def _name_ok(name: str) -> bool:
    return bool(name) and name.replace("_", "a").isalnum()


def signal_values(pairs) -> dict[str, float]:
    """``--io NAME=VALUE`` options as a dict; an InputError for one that is not."""
    out = {}
    for pair in pairs or []:
        name, sep, value = pair.partition("=")
        try:
            number = float(value)
        except ValueError:
            number = float("nan")
        if not sep or not _name_ok(name.strip()) or not math.isfinite(number):
            raise InputError(f"--io takes NAME=VALUE (a signal and a number), not '{pair}'")
        out[name.strip()] = number
    return out


def input_values(pairs) -> dict[str, tuple[str, ...]]:
    """``--input NAME=VALUE`` options as each name's values in order; an InputError for one that
    is not NAME=VALUE."""
    out: dict[str, list[str]] = {}
    for pair in pairs or []:
        name, sep, value = pair.partition("=")
        if not sep or not _name_ok(name.strip()):
            raise InputError(f"--input takes NAME=VALUE (the data a live read stores into, and its value), not "
                             f"'{pair}'")
        out.setdefault(name.strip(), []).append(value)
    return {k: tuple(v) for k, v in out.items()}


@dataclass(frozen=True)
class TaskOptions:
    """How a RAPID task runs and what it is checked against (``rswarp program``, ``cable
    --program``, ``dresspack``): its entry routine, signal values and live inputs, passes of a main
    loop, what to do with external axes the robot lacks, axis limits, a payload, a tool on the
    flange, the floor (None: none), environment meshes (``MESH@x,y,z``), an SRDF of pairs to skip, and
    whether names declared nowhere are taken as stand-ins (``--assume-missing``)."""

    routine: str = "main"
    io: Mapping[str, float] = field(default_factory=dict)
    inputs: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    cycles: int = 1
    external_axes: str = "auto"
    limits: str | None = None
    payload: Any = None  # --payload's text (KG[@x,y,z] or MODULE:NAME), or an ``rsxml.robot_data.Payload``
    tool: str | None = None
    floor: float | None = 0.0
    environment: tuple[str, ...] = ()
    collision_matrix: str | None = None
    assume_missing: bool = False  # a name declared nowhere taken as a stand-in by its use (rapid.check.Assumed)
    motion_task: str | None = None  # the task of a backup's folder to run (``T_ROB2``, MultiMove); None: its first

    def __post_init__(self):
        if self.external_axes not in EXTERNAL_AXES:
            raise InputError(f"--external-axes must be one of {', '.join(EXTERNAL_AXES)}")
        if isinstance(self.cycles, bool) or not float(self.cycles).is_integer():
            raise InputError(f"--cycles takes a whole number of passes, not {self.cycles!r}")
        set_ = lambda name, value: object.__setattr__(self, name, value)  # noqa: E731 (frozen)
        set_("cycles", int(self.cycles))
        set_("environment", _strings(self.environment))
        set_("io", _signals(self.io))
        set_("inputs", _inputs(self.inputs))
        if isinstance(self.payload, (int, float)) and not isinstance(self.payload, bool):
            set_("payload", f"{self.payload:g}")  # a mass in kg, as --payload KG


def _strings(value) -> tuple[str, ...]:
    """One string or several as a tuple of strings (``environment="mesh.stl@0,0,0"`` is one mesh)."""
    return (value,) if isinstance(value, str) else tuple(value or ())


def _signals(io) -> dict[str, float]:
    """Signal values from a dict or from NAME=VALUE texts, each a finite number."""
    if not isinstance(io, Mapping):
        return signal_values(_strings(io))
    out = {}
    for name, value in io.items():
        try:
            number = float(value)
        except (TypeError, ValueError):
            number = math.nan
        if not _name_ok(str(name)) or not math.isfinite(number):
            raise InputError(f"io: a signal's name and a finite number, not {name!r}: {value!r}")
        out[str(name)] = number
    return out


def _inputs(inputs) -> dict[str, tuple[str, ...]]:
    """Live inputs from a dict (a value or values a name) or from NAME=VALUE texts."""
    if not isinstance(inputs, Mapping):
        return input_values(_strings(inputs))
    return {str(k): tuple(str(x) for x in (v if isinstance(v, (list, tuple)) else (v,))) for k, v in inputs.items()}


@dataclass(frozen=True)
class HoseOptions:
    """What a cable run holds a hose to and what it is made of: its bend radii (dynamic, static),
    strain, torsion (deg/m), contact force and clamp load (N) ratings, its bending life (``N@R``),
    its material, the frames and steps of the simulation, and the cable model."""

    min_bend_radius: float | None = None
    static_bend_radius: float | None = None
    max_strain: float = MAX_STRAIN
    max_torsion: float = MAX_TORSION_DEG
    max_contact_force: float | None = None
    max_clamp_load: float | None = None
    rated_cycles: str | None = None
    density: float = DENSITY
    poisson: float = POISSON
    friction: float = FRICTION
    frame_rate: float = FRAME_RATE
    substeps: int = SUBSTEPS
    cable_model: str = "rod"


@dataclass(frozen=True)
class DesignOptions:
    """A dress-pack design sweep's draw: the ``--vary`` specs (or one TOML file of them), how many
    designs, the cable varied (None: the only one), the margin in % the chosen one keeps."""

    vary: tuple[str, ...] = ()
    designs: int = 64
    cable: str | None = None
    min_margin: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "vary", _strings(self.vary))


@dataclass(frozen=True)
class PlaceOptions:
    """``rswarp place``'s search: the ``--vary`` specs of the base (x, y, z in mm, yaw in degrees;
    ``MIN:MAX[:N]``), the quasi-random draws of those without N, and how many of the best bases
    are run through the whole program."""

    vary: tuple[str, ...] = ()
    samples: int | None = None
    top: int = 8

    def __post_init__(self):
        object.__setattr__(self, "vary", _strings(self.vary))
        if isinstance(self.top, bool) or not 1 <= int(self.top) <= 64:
            raise InputError(f"--top must be 1 to 64, not {self.top!r}")


@dataclass(frozen=True)
class BatchOptions:
    """Where a batch runs: the Warp device, a Ray address (None: locally; "local": a local Ray
    instance) and the sampling seed."""

    device: str = "cpu"
    ray: str | None = None
    seed: int = 0


@dataclass(frozen=True)
class VideoOptions:
    """``--video FILE``: the file (None: no video), the environment shown (None: the worst), the
    hose's colouring (``bend`` or ``wear``) and the frame's size in pixels."""

    video: str | None = None
    video_env: int | None = None
    video_color: str = "bend"
    video_size: int = 512


# the parameter name each kind travels under, in the library and in ``cli.OPTION_PARAMETERS``
OPTION_KINDS = {"task": TaskOptions, "hose": HoseOptions, "design": DesignOptions, "batch": BatchOptions,
          "video": VideoOptions, "place": PlaceOptions}


def from_namespace(kind: type, values: Mapping[str, Any]):
    """An options object of ``kind`` from a command's parsed arguments (``vars(args)``): each field
    its option's value where the command has it, else the default."""
    return kind(**{f.name: values[f.name] for f in fields(kind) if f.name in values})


def routed(changes: Mapping[str, Any], **objects) -> dict:
    """Each of ``objects`` (name -> an options object) with the ``changes`` among its fields
    applied: a Python caller's keywords (``cycles=3``, ``frame_rate=30.0``) sent to the object that
    has them. A TypeError names a keyword none has."""
    out = dict(objects)
    left = dict(changes)
    for key, options in objects.items():
        kind = OPTION_KINDS.get(key)
        if kind is not None and not isinstance(options, kind):
            raise TypeError(f"{key} must be a {kind.__name__}, not {type(options).__name__} {options!r:.60} (give a "
                            f"field as a keyword: routine='main', cycles=2)")
        names = {f.name for f in fields(options)}
        mine = {k: left.pop(k) for k in list(left) if k in names}
        if mine:
            out[key] = replace(options, **mine)
    if left:
        kinds = ", ".join(type(o).__name__ for o in objects.values())
        raise TypeError(f"no option {', '.join(sorted(left))} in {kinds}")
    return out
