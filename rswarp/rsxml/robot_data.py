"""What an RSXML file does not hold and the timing and exports need: each axis's speed,
acceleration and effort, the robot's mass and payload. Read from a robot-data file beside the
RSXML (``<model>.robot.toml``, found by the longest name it starts with), or from ``--limits``: a
URDF (``<limit velocity= effort=>``), MoveIt's ``joint_limits.yaml`` (``max_velocity``,
``max_acceleration``) or a robot-data file. Where none is found, every axis is assumed to go at
90 deg/s (0.5 m/s), and the outputs that depend on it say so."""

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


@dataclass(frozen=True)
class AxisLimits:
    """Per active axis, in joint order, SI (rad or m): top speed, acceleration, effort (N·m or
    N; NaN where unknown); ``source`` says where they come from, ``assumed`` that the speeds are
    rswarp's default, not the robot's."""

    velocity: np.ndarray
    acceleration: np.ndarray
    effort: np.ndarray
    source: str
    assumed: bool = False
    accel_assumed: bool = True

    def summary(self) -> str:
        """One line: where the speeds come from, or that they are assumed."""
        if self.assumed:
            return "axis speeds assumed 90 deg/s (0.5 m/s): give --limits"
        ramp = f"; accelerations assumed (top speed in {RAMP_S:g} s)" if self.accel_assumed else ""
        deg = np.degrees(self.velocity)
        return f"axis speeds {deg.min():.0f}-{deg.max():.0f} deg/s from {self.source}{ramp}"


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
class RobotData:
    """A robot-data file: its axis limits and, where published, total mass and payload (kg)."""

    limits: AxisLimits
    mass: float | None = None
    payload: float | None = None
    source: str = ""
    path: str = ""


def default_limits(revolute: list[bool]) -> AxisLimits:
    v = np.array([JOINT_VELOCITY[r] for r in revolute])
    return AxisLimits(v, v / RAMP_S, np.full(len(v), np.nan), "rswarp's default", assumed=True)


def axis_limits(mech, limits: str | None = None) -> AxisLimits:
    """The limits of ``mech``'s active axes: from ``limits`` (a file), else from the robot-data
    file beside the RSXML, else the default (``assumed``)."""
    if limits is not None:
        return read_limits(limits, mech)
    data = robot_data(mech)
    return data.limits if data is not None else default_limits([j.revolute for j in mech.graph.active])


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
    """A robot-data file: ``source``, ``mass_kg``, ``payload_kg`` and ``[axes]`` with
    ``names``, ``speed_deg_s`` (or ``speed`` in SI) and optional ``accel_deg_s2``, ``effort_Nm``."""
    text = _text(path)
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        line = int(m.group(1)) if (m := re.search(r"line (\d+)", str(exc))) else 0
        raise RsxmlError(Diagnostic(path, line, f"TOML: {str(exc).split(' (at')[0]}")) from None
    axes = doc.get("axes")
    if not isinstance(axes, dict):
        raise RsxmlError(Diagnostic(path, 0, "no [axes] table: a robot-data file gives names and speed_deg_s"))
    revolute = [j.revolute for j in mech.graph.active]
    names = axes.get("names")
    speed = _column(path, text, axes, "speed_deg_s", revolute, names, mech, required=True)
    accel = _column(path, text, axes, "accel_deg_s2", revolute, names, mech)
    effort = _column(path, text, axes, "effort_Nm", [False] * len(revolute), names, mech)
    source = str(doc.get("source", Path(path).name))
    limits = AxisLimits(speed, np.where(np.isnan(accel), speed / RAMP_S, accel), effort, Path(path).name,
                        accel_assumed=bool(np.isnan(accel).any()))
    return RobotData(limits, _kg(path, text, doc, "mass_kg"), _kg(path, text, doc, "payload_kg"), source, path)


def _column(path, text, axes, key, revolute, names, mech, required=False) -> np.ndarray:
    """One per-axis column of a robot-data file, matched to the active joints, in SI (deg to rad
    for revolute axes; a prismatic axis's value is in mm and goes to m)."""
    values = axes.get(key)
    if values is None:
        if required:
            raise RsxmlError(Diagnostic(path, 0, f"[axes] has no {key}"))
        return np.full(len(revolute), np.nan)
    line = _line_of(text, key)
    if not isinstance(values, list) or not all(isinstance(v, (int, float)) and math.isfinite(v) and v > 0
                                                for v in values):
        raise RsxmlError(Diagnostic(path, line, f"{key} must be a list of numbers above 0"))
    by_joint = _match(path, line, names if isinstance(names, list) else None, len(values), mech)
    scale = np.array([math.radians(1.0) if r else 1e-3 for r in revolute])
    return np.array([values[k] for k in by_joint], float) * scale


def _kg(path, text, doc, key) -> float | None:
    v = doc.get(key)
    if v is None:
        return None
    if not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
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
    return AxisLimits(v, v / RAMP_S, np.array([r[1] for r in rows]), Path(path).name)


def _from_yaml(path: str, mech) -> AxisLimits:
    import yaml  # MoveIt's format; loaded only for it

    text = _text(path)
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
    return AxisLimits(v, np.where(missing, v / RAMP_S, a), np.full(len(v), np.nan),
                      Path(path).name, accel_assumed=bool(missing.any()))


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


def _line_of(text: str, key: str) -> int:
    at = text.find(key)
    return text.count("\n", 0, at) + 1 if at >= 0 else 0


def _text(path: str) -> str:
    try:
        data = read_regular(path)
    except OSError as exc:
        raise RsxmlError(Diagnostic(path, 0, f"cannot read file: {exc.strerror or exc}")) from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise RsxmlError(Diagnostic(path, 0, f"not UTF-8 text (byte {exc.start})")) from None
