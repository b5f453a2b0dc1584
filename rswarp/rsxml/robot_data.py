"""What an RSXML file does not hold and the timing and exports need: each axis's speed,
acceleration, jerk and effort, where each comes from, the robot's mass and payload. Read from a
robot-data file beside the RSXML (``<model>.robot.toml``, found by the longest name it starts
with), or from ``--limits``: a URDF (``<limit velocity= effort=>``), MoveIt's ``joint_limits.yaml``
(``max_velocity``, ``max_acceleration``) or a robot-data file. Where none is found, every axis is
assumed to go at 90 deg/s (0.5 m/s), and the outputs that depend on it say so. docs/robot-data.md
describes the format and how the bundled robots' estimates are made."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

from ..errors import Diagnostic, InputError, RsxmlError
from ..files import read_regular
from ..transforms import quat_matrix
from .parse import parse_xml
from .units import JOINT_VELOCITY

SUFFIX = ".robot.toml"
RAMP_S = 0.25  # s: an axis with no published acceleration reaches its top speed in this time
JERK_S = 0.05  # s: an axis with no published jerk reaches its top acceleration in this time
QUANTITIES = ("velocity", "acceleration", "jerk")
SPEED_RULE = "rswarp's default: 90 deg/s (0.5 m/s) for every axis"
ACCEL_RULE = f"rswarp's rule: each axis reaches its top speed in {RAMP_S:g} s"
JERK_RULE = f"rswarp's rule: each axis reaches its top acceleration in {JERK_S:g} s"
CYCLE_KEYS = ("standard_cycle_s", "standard_cycle_kg", "standard_cycle_source")  # ABB's standard cycle time


@dataclass(frozen=True)
class AxisLimits:
    """Per active axis, in joint order, SI (rad or m): top speed, acceleration, effort (N·m or
    N; NaN where unknown), jerk; ``source`` names the file, ``*_source`` where each quantity comes
    from, ``estimated`` (axes, 3) which of velocity, acceleration, jerk are estimates rather than
    published; ``assumed``: the speeds are rswarp's default, ``accel_assumed``: some acceleration
    is not published (an estimate or rswarp's rule)."""

    velocity: np.ndarray
    acceleration: np.ndarray
    effort: np.ndarray
    source: str
    assumed: bool = False
    accel_assumed: bool = True
    jerk: np.ndarray | None = None  # rad/s^3 or m/s^3; None: the acceleration reached in JERK_S
    names: tuple[str, ...] = ()  # the active joints' names
    velocity_source: str = ""
    accel_source: str = ""
    jerk_source: str = ""
    estimated: np.ndarray | None = None  # (axes, 3) bool; None: from assumed, accel_assumed, jerk
    linear: tuple[bool, ...] = ()  # which axes slide (m, m/s): a track's; () where all turn
    axis_sources: tuple = ()  # per axis (velocity, acceleration, jerk) sources where they differ (a cell's)
    external: tuple[bool, ...] = ()  # which axes are a cell's external axes (speeddata's v_leax, v_reax cap them)

    def jerks(self) -> np.ndarray:
        """Each axis's jerk limit: the robot data's, else its acceleration reached in ``JERK_S``."""
        return self.jerk if self.jerk is not None else self.acceleration / JERK_S

    def sources(self) -> tuple[str, str, str]:
        """Where the velocities, accelerations and jerks come from, in words."""
        return (self.velocity_source or (SPEED_RULE if self.assumed else self.source),
                self.accel_source or (ACCEL_RULE if self.accel_assumed else self.source),
                self.jerk_source or (JERK_RULE if self.jerk is None else self.source))

    def estimates(self) -> np.ndarray:
        """(axes, 3) bool: which of each axis's velocity, acceleration and jerk are estimates."""
        if self.estimated is not None:
            return np.asarray(self.estimated, bool)
        flags = [self.assumed, self.accel_assumed, self.jerk is None]
        return np.tile(np.array(flags, bool), (len(self.velocity), 1))

    def rows(self) -> list[dict]:
        """One dict per axis (SI) for the JSON: its limits, where each comes from, which are
        estimates, so anyone can recompute a move's time."""
        names = self.names or tuple(f"axis {k + 1}" for k in range(len(self.velocity)))
        est, jerk = self.estimates(), self.jerks()
        sources = self.axis_sources or (self.sources(),) * len(names)
        return [{"axis": name, "velocity": float(self.velocity[k]), "acceleration": float(self.acceleration[k]),
                 "jerk": float(jerk[k]), "velocity_source": sources[k][0], "acceleration_source": sources[k][1],
                 "jerk_source": sources[k][2], "estimated": [q for q, e in zip(QUANTITIES, est[k]) if e]}
                for k, name in enumerate(names)]

    def summary(self) -> str:
        """One line: where the speeds come from (or that they are assumed), then whether the
        accelerations and jerks are given, estimated in the robot data or rswarp's rule."""
        if self.assumed:
            return "axis speeds assumed 90 deg/s (0.5 m/s): give --limits"
        speeds = "estimated in" if self.estimates()[:, 0].any() else "from"
        accel = self._origin(1, ACCEL_RULE, f"top speed in {RAMP_S:g} s")
        jerk = self._origin(2, JERK_RULE, f"top acceleration in {JERK_S:g} s")
        rest = f"accelerations and jerks {accel}" if accel == jerk else f"accelerations {accel}, jerks {jerk}"
        return f"axis speeds {self._speeds()} {speeds} {self.source}; {rest}"

    def _speeds(self) -> str:
        """The speeds' range in words: deg/s for the axes that turn, mm/s for those that slide."""
        slide = np.array(self.linear if len(self.linear) == len(self.velocity) else [False] * len(self.velocity))
        parts = []
        for mask, values, unit in ((~slide, np.degrees(self.velocity), "deg/s"), (slide, self.velocity * 1e3, "mm/s")):
            if mask.any():
                lo, hi = values[mask].min(), values[mask].max()
                parts.append(f"{lo:.0f}-{hi:.0f} {unit}" if round(lo) != round(hi) else f"{lo:.0f} {unit}")
        return " and ".join(parts)

    def _origin(self, k: int, rule: str, short: str) -> str:
        est = self.estimates()[:, k]
        if not est.any():
            return "given there"
        if self.sources()[k] == rule:
            return f"assumed ({short})"
        return "estimated there" if est.all() else f"partly assumed ({short})"


@dataclass(frozen=True)
class Payload:
    """A load on the flange, in its frame (tool0), SI: mass (kg), centre of gravity (m), principal
    moments of inertia (kg m^2) about the axes of moment ``aom`` (w, x, y, z), as RAPID's loaddata
    gives them; ``source`` says where it comes from."""

    mass: float
    cog: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: tuple[float, float, float] = (0.0, 0.0, 0.0)
    aom: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    source: str = ""

    def inertia_matrix(self) -> np.ndarray:
        """The inertia about the centre of gravity in the flange's axes (3, 3)."""
        r = quat_matrix(self.aom)
        return r @ np.diag(self.inertia) @ r.T


@dataclass(frozen=True)
class StandardCycle:
    """ABB's published time for its standard pick cycle on a robot (25 mm up, 300 mm across, 25 mm
    down and back): ``seconds`` with ``load_kg`` on the flange, and the document it is from."""

    seconds: float
    load_kg: float
    source: str


@dataclass(frozen=True)
class RobotData:
    """A robot-data file: its axis limits and, where published, total mass and payload (kg) and
    ABB's standard cycle time (``standard_cycle``; None where the file gives none)."""

    limits: AxisLimits
    mass: float | None = None
    payload: float | None = None
    source: str = ""
    path: str = ""
    standard_cycle: StandardCycle | None = None


def default_limits(revolute: list[bool], names: tuple[str, ...] = ()) -> AxisLimits:
    """rswarp's default limits: 90 deg/s (0.5 m/s), reached in ``RAMP_S``; all assumed."""
    v = np.array([JOINT_VELOCITY[r] for r in revolute])
    return AxisLimits(v, v / RAMP_S, np.full(len(v), np.nan), "rswarp's default", assumed=True, names=tuple(names),
                      linear=tuple(not r for r in revolute))


def axis_limits(mech, limits: str | None = None) -> AxisLimits:
    """The limits of ``mech``'s active axes: from ``limits`` (a file), else from the robot-data
    file beside the RSXML, else the default (``assumed``)."""
    if limits is not None:
        return read_limits(limits, mech)
    data = robot_data(mech)
    if data is not None:
        return data.limits
    active = mech.graph.active
    return default_limits([j.revolute for j in active], tuple(j.name for j in active))


def robot_data(mech) -> RobotData | None:
    """The robot-data file beside ``mech``'s RSXML, read; None where there is none."""
    found = data_file(mech.path)
    return None if found is None else read_robot_data(str(found), mech)


def data_file(rsxml: str | None) -> Path | None:
    """The ``*.robot.toml`` beside ``rsxml`` whose name (before the suffix) its name starts with,
    the longest such."""
    if not rsxml:
        return None
    path = Path(rsxml)
    stem = path.name.lower()
    best = None
    for f in path.parent.glob(f"*{SUFFIX}"):
        prefix = f.name[: -len(SUFFIX)].lower()
        if stem.startswith(prefix) and (best is None or len(prefix) > len(best.name)):
            best = f
    return best


def read_limits(path: str, mech) -> AxisLimits:
    """Axis limits from a URDF, a MoveIt joint_limits.yaml or a robot-data file, by extension."""
    lower = path.lower()
    if lower.endswith(SUFFIX) or lower.endswith(".toml"):
        return read_robot_data(path, mech).limits
    if lower.endswith((".yaml", ".yml")):
        return _from_yaml(path, mech)
    if lower.endswith((".urdf", ".xml")):
        return _from_urdf(path, mech)
    raise InputError(f"{path}: --limits takes a URDF (.urdf), MoveIt's joint_limits.yaml or a robot-data file "
                     f"(*{SUFFIX})")


def read_robot_data(path: str, mech) -> RobotData:
    """A robot-data file: ``source``, ``mass_kg``, ``payload_kg``, ABB's standard cycle time
    (``standard_cycle_s`` with ``standard_cycle_kg`` and ``standard_cycle_source``, optional) and
    ``[axes]`` with ``names``, ``speed_deg_s`` and optional ``accel_deg_s2``, ``jerk_deg_s3``,
    ``effort_Nm``; each of speed, accel and jerk may have a ``*_source`` (text) and ``*_estimated``
    (true: not published)."""
    text, doc = read_toml(path)
    axes = doc.get("axes")
    if not isinstance(axes, dict):
        raise RsxmlError(Diagnostic(path, 0, "no [axes] table: a robot-data file gives names and speed_deg_s"))
    cycle = _standard_cycle(path, text, doc, axes)
    active = mech.graph.active
    revolute = [j.revolute for j in active]
    names = axes.get("names")
    speed = _column(path, text, axes, "speed_deg_s", revolute, names, mech, required=True)
    accel = _column(path, text, axes, "accel_deg_s2", revolute, names, mech)
    jerk = _column(path, text, axes, "jerk_deg_s3", revolute, names, mech)
    effort = _column(path, text, axes, "effort_Nm", revolute, names, mech, si=True)  # N m, or N where it slides
    source = _words(path, text, doc, "source") or Path(path).name
    given = [True, not np.isnan(accel).any(), not np.isnan(jerk).any()]
    said = [(_words(path, text, axes, f"{q}_source"), _flag(path, text, axes, f"{q}_estimated"))
            for q in ("speed", "accel", "jerk")]
    rules = (source, ACCEL_RULE, JERK_RULE)  # where a quantity is not given (speeds always are)
    sources = [(words or source) if g else rule for g, (words, _), rule in zip(given, said, rules)]
    flags = [estimated or not g for g, (_, estimated) in zip(given, said)]
    limits = AxisLimits(
        speed, accel if given[1] else speed / RAMP_S, effort, Path(path).name, accel_assumed=flags[1],
        jerk=jerk if given[2] else None, names=tuple(j.name for j in active), velocity_source=sources[0],
        accel_source=sources[1], jerk_source=sources[2], estimated=np.tile(np.array(flags, bool), (len(active), 1)),
        linear=tuple(not r for r in revolute))
    return RobotData(limits, _kg(path, text, doc, "mass_kg"), _kg(path, text, doc, "payload_kg"), source, path,
                     cycle)


def _standard_cycle(path, text, doc, axes) -> StandardCycle | None:
    """ABB's standard cycle time from the file's top: ``standard_cycle_s`` (s), the load it is for
    (``standard_cycle_kg``) and where it comes from (``standard_cycle_source``), all three or none."""
    for key in CYCLE_KEYS:
        if key in axes:  # written after [axes], so TOML puts it in that table
            raise RsxmlError(Diagnostic(path, _line_of(text, key),
                                        f"{key} is in [axes]: it belongs at the top of the file, before [axes]"))
    given = [key for key in CYCLE_KEYS if key in doc]
    if not given:
        return None
    if "standard_cycle_s" not in doc:
        raise RsxmlError(Diagnostic(path, _line_of(text, given[0]), f"{given[0]} without standard_cycle_s: "
                                                                   "give ABB's cycle time with it, or neither"))
    line = _line_of(text, "standard_cycle_s")
    seconds = doc["standard_cycle_s"]
    if not _positive(seconds):
        raise RsxmlError(Diagnostic(path, line, "standard_cycle_s must be a number of seconds above 0"))
    for key, what in (("standard_cycle_kg", "the load ABB's figure is for (kg)"),
                      ("standard_cycle_source", "the document ABB's figure comes from")):
        if key not in doc:
            raise RsxmlError(Diagnostic(path, line, f"standard_cycle_s needs {key}: {what}"))
    return StandardCycle(float(seconds), _kg(path, text, doc, "standard_cycle_kg"),
                         _words(path, text, doc, "standard_cycle_source"))


def estimated_accelerations(mech, speed: np.ndarray, accel_time: float) -> tuple[np.ndarray, np.ndarray]:
    """The estimate a robot-data file writes where no acceleration is published (SI, per active
    axis): the TCP's acceleration a = (1 m/s) / ``accel_time`` (a data sheet's "acceleration time
    0-1 m/s"); axes 1-3 a / r, r the distance from the axis to the flange at the zero pose (a
    prismatic one: a); the others reach their top ``speed`` in the time the slowest of axes 1-3
    takes; the jerks: the acceleration reached in ``JERK_S``."""
    a_tcp = 1.0 / accel_time
    flange = np.asarray(mech.flanges[0].pose.t or (0.0, 0.0, 0.0), float)
    joints = mech.graph.active
    main = min(3, len(joints))
    accel = np.empty(len(joints))
    for k, j in enumerate(joints[:main]):
        reach = np.linalg.norm(np.cross(flange - np.asarray(j.point1, float), j.axis)) if j.revolute else 1.0
        accel[k] = a_tcp / reach
    ramp = float(np.max(speed[:main] / accel[:main]))
    accel[main:] = speed[main:] / ramp
    return accel, accel / JERK_S


def _column(path, text, axes, key, revolute, names, mech, required=False, si=False) -> np.ndarray:
    """One per-axis column of a robot-data file, matched to the active joints, in SI (deg to rad
    for revolute axes; a prismatic axis's value is in mm and goes to m; ``si``: as written)."""
    values = axes.get(key)
    if values is None:
        if required:
            raise RsxmlError(Diagnostic(path, 0, f"[axes] has no {key}"))
        return np.full(len(revolute), np.nan)
    line = _line_of(text, key)
    if not isinstance(values, list) or not all(_positive(v) for v in values):
        raise RsxmlError(Diagnostic(path, line, f"{key} must be a list of numbers above 0"))
    if isinstance(names, list) and len(values) != len(names):
        raise RsxmlError(Diagnostic(path, line, f"{key} has {len(values)} values for {len(names)} names"))
    by_joint = _match(path, line, names if isinstance(names, list) else None, len(values), mech)
    scale = np.array([1.0 if si else math.radians(1.0) if r else 1e-3 for r in revolute])
    return np.array([values[k] for k in by_joint], float) * scale


def _words(path, text, table, key) -> str | None:
    """A text field (a source): None where absent; an error where it is not text."""
    v = table.get(key)
    if v is None:
        return None
    if not isinstance(v, str) or not v.strip():
        raise RsxmlError(Diagnostic(path, _line_of(text, key), f"{key} must be text: where the figures come from"))
    return v.strip()


def _flag(path, text, table, key) -> bool:
    """A true/false field (an ``*_estimated``): False where absent."""
    v = table.get(key, False)
    if not isinstance(v, bool):
        raise RsxmlError(Diagnostic(path, _line_of(text, key), f"{key} must be true or false"))
    return v


def _kg(path, text, doc, key) -> float | None:
    v = doc.get(key)
    if v is None:
        return None
    if not _positive(v):
        raise RsxmlError(Diagnostic(path, _line_of(text, key), f"{key} must be a number above 0"))
    return float(v)


def _from_urdf(path: str, mech) -> AxisLimits:
    root = parse_xml(path)
    found: dict[str, tuple[float, float, int]] = {}
    for joint in root.iter("joint"):
        if joint.get("type") not in ("revolute", "continuous", "prismatic"):
            continue
        limit = joint.find("limit")
        if limit is None or limit.get("velocity") is None:
            continue
        velocity = _number(path, limit, "velocity", positive=True)
        effort = _number(path, limit, "effort") if limit.get("effort") is not None else math.nan
        found[joint.get("name", "")] = (velocity, effort if effort > 0 else math.nan, limit.sourceline or 0)
    if not found:
        raise RsxmlError(Diagnostic(path, 0, "no joint with <limit velocity=...>: not a URDF with speed limits"))
    rows = _rows(path, found, mech)
    v = np.array([r[0] for r in rows])
    return AxisLimits(v, v / RAMP_S, np.array([r[1] for r in rows]), Path(path).name,
                      names=tuple(j.name for j in mech.graph.active),
                      linear=tuple(not j.revolute for j in mech.graph.active))


def _from_yaml(path: str, mech) -> AxisLimits:
    import yaml  # MoveIt's format; loaded only for it

    text = read_text(path)
    try:
        doc = yaml.safe_load(text)  # plain data only: no tags, no objects
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        raise RsxmlError(Diagnostic(path, mark.line + 1 if mark else 0, f"YAML: {getattr(exc, 'problem', exc)}")) \
            from None
    joints = doc.get("joint_limits") if isinstance(doc, dict) else None
    if not isinstance(joints, dict) or not joints:
        raise RsxmlError(Diagnostic(path, 0, "no joint_limits: not MoveIt's joint_limits.yaml"))
    found = {}
    for name, spec in joints.items():
        if not isinstance(spec, dict) or not spec.get("has_velocity_limits", "max_velocity" in spec):
            continue
        line = _line_of(text, f"{name}:")
        velocity = _yaml_number(path, line, spec, "max_velocity")
        accel = _yaml_number(path, line, spec, "max_acceleration") if spec.get("has_acceleration_limits") \
            else math.nan
        found[str(name)] = (velocity, accel, line)
    if not found:
        raise RsxmlError(Diagnostic(path, 0, "no joint has velocity limits (has_velocity_limits: true)"))
    rows = _rows(path, found, mech)
    v, a = np.array([r[0] for r in rows]), np.array([r[1] for r in rows])
    missing = np.isnan(a)
    name = Path(path).name
    accel_source = ACCEL_RULE if missing.all() else f"{name} where given, else {ACCEL_RULE}" if missing.any() else name
    estimated = np.column_stack([np.zeros(len(v), bool), missing, np.ones(len(v), bool)])
    return AxisLimits(v, np.where(missing, v / RAMP_S, a), np.full(len(v), np.nan), name,
                      accel_assumed=bool(missing.any()), names=tuple(j.name for j in mech.graph.active),
                      linear=tuple(not j.revolute for j in mech.graph.active),
                      accel_source=accel_source, estimated=estimated)


def _rows(path: str, found: dict, mech) -> list[tuple]:
    """The file's rows for each active joint: by name, or in order where the names differ."""
    names = list(found)
    order = _match(path, max(r[2] for r in found.values()), names, len(names), mech)
    return [found[names[k]] for k in order]


def _match(path: str, line: int, names: list | None, count: int, mech) -> list[int]:
    """For each active joint of ``mech``, the index of its row: by name (case, '_' and '-'
    ignored), else in order when the counts agree."""
    active = [j.name for j in mech.graph.active]
    if names is not None:
        key = {_key(str(n)): k for k, n in enumerate(names)}
        if all(_key(a) in key for a in active):
            return [key[_key(a)] for a in active]
    if count == len(active):
        return list(range(count))
    raise RsxmlError(Diagnostic(path, line, f"{count} axes for {len(active)} active joints "
                                            f"({', '.join(active)}), and not every joint is named"))


def _key(name: str) -> str:
    return re.sub(r"[^0-9a-z]", "", name.lower())


def _number(path: str, element, attr: str, positive: bool = False) -> float:
    text = element.get(attr, "")
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not math.isfinite(v) or v < 0 or (positive and v == 0):
        raise RsxmlError(Diagnostic(path, element.sourceline or 0,
                                    f"<limit {attr}=\"{text}\">: must be a number {'above' if positive else 'from'} 0"))
    return v


def _yaml_number(path: str, line: int, spec: dict, key: str) -> float:
    v = spec.get(key)
    if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v) or v <= 0:
        raise RsxmlError(Diagnostic(path, line, f"{key}: {v!r} must be a number above 0"))
    return float(v)


def _positive(v) -> bool:
    """A finite number above 0, and not a TOML ``true`` (which Python counts as 1)."""
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0


def _line_of(text: str, key: str) -> int:
    """The line of ``key = ...`` (a TOML key, not a mention in a comment), else of ``key``'s first mention."""
    m = re.search(rf"^[ \t]*{re.escape(key)}[ \t]*=", text, re.M)
    at = m.start() if m else text.find(key)
    return text.count("\n", 0, at) + 1 if at >= 0 else 0


def read_toml(path: str) -> tuple[str, dict]:
    """(text, table) of a small TOML file; its syntax errors at their line."""
    text = read_text(path)
    try:
        return text, tomllib.loads(text)
    except RecursionError:  # arrays or inline tables nested some thousand deep: no file of ours is
        raise RsxmlError(Diagnostic(path, _deepest(text), "TOML: nested too deep (give frames and lists as "
                                                          "flat lists of numbers)")) from None
    except tomllib.TOMLDecodeError as exc:
        line = int(m.group(1)) if (m := re.search(r"line (\d+)", str(exc))) else 0
        if not line and "end of document" in str(exc):  # an array or table left open: the file's last line
            line = max(1, len(text.rstrip().splitlines()))
        raise RsxmlError(Diagnostic(path, line, f"TOML: {str(exc).split(' (at')[0]}")) from None


def _deepest(text: str) -> int:
    """The line where brackets first open deepest (strings not told apart: for the message only)."""
    depth, most, line, at = 0, 0, 1, 1
    for ch in text:
        if ch == "\n":
            line += 1
        elif ch in "[{":
            depth += 1
            if depth > most:
                most, at = depth, line
        elif ch in "]}":
            depth -= 1
    return at


def read_text(path: str) -> str:
    """A small text file (a robot-data or cell file) read whole, bounded, as UTF-8 (a BOM allowed)."""
    try:
        data = read_regular(path)
    except OSError as exc:
        raise RsxmlError(Diagnostic(path, 0, f"cannot read file: {exc.strerror or exc}")) from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise RsxmlError(Diagnostic(path, 0, f"not UTF-8 text (byte {exc.start})")) from None
