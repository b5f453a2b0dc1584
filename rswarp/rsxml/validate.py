"""Checks on a read model that need the whole of it: names, references, the link graph, limits."""

from __future__ import annotations

import re
from collections import Counter

from ..errors import Diagnostic
from .cable_spans import cable_spans
from .model import KINEMATICS_FLAGS, KNOWN_ATTRIBUTE_KEYS, MECHANISM_TYPES, Mechanism, SmartComponent, iter_parts
from .units import format_number

# IRB<model>_<capacity>_<reach>_[variant]_<revision>, e.g. IRB1100_4_47__02, IRB6700_200_260_MH3_04
ROBOT_NAME = re.compile(
    r"^IRB(?P<model>[0-9]+[A-Za-z0-9]*)_(?P<capacity>[0-9]+(?:\.[0-9]+)?)_(?P<reach>[0-9]+)"
    r"_(?P<variant>[A-Za-z0-9]*)_(?P<revision>[0-9]{2})$")
SIGNAL_TYPES = ("DigitalInput", "DigitalOutput", "AnalogInput", "AnalogOutput", "DigitalGroupInput",
                "DigitalGroupOutput")


def robot_name_parts(name: str) -> dict[str, str] | None:
    """The fields of a name that follows ABB's naming standard, else None."""
    m = ROBOT_NAME.match(name)
    return m.groupdict() if m else None


class _Out:
    def __init__(self, file: str, diagnostics: list[Diagnostic]):
        self.file, self.diagnostics = file, diagnostics

    def error(self, line: int, message: str) -> None:
        self.diagnostics.append(Diagnostic(self.file, line, message))

    def warn(self, line: int, message: str) -> None:
        self.diagnostics.append(Diagnostic(self.file, line, message, "warning"))


def _duplicates(out: _Out, what: str, items) -> None:
    seen: dict[str, int] = {}
    for item in items:
        if item.name in seen:
            out.error(item.line, f"duplicate {what} name '{item.name}' (first at line {seen[item.name]})")
        else:
            seen[item.name] = item.line


def validate_mechanism(mech: Mechanism, file: str, diagnostics: list[Diagnostic]) -> None:
    """Append every semantic problem of ``mech`` to ``diagnostics``."""
    out = _Out(file, diagnostics)
    _metadata(mech, out)
    _duplicates(out, "link", mech.links)
    _duplicates(out, "joint", mech.joints)
    _duplicates(out, "flange", mech.flanges)
    _duplicates(out, "cable", mech.cables)
    links = set(mech.link_names)
    if not mech.links:
        out.error(mech.section_line("Links"), "the mechanism has no links")
    elif mech.base_link and mech.base_link not in links:
        out.error(mech.section_line("Links"), f"baseLink '{mech.base_link}' is not a link")
    for j in mech.joints:
        for role in ("parent", "child"):
            name = getattr(j, role)
            if name and name not in links:
                out.error(j.line, f"joint '{j.name}' {role} '{name}' is not a link")
        if j.parent and j.parent == j.child:
            out.error(j.line, f"joint '{j.name}' connects link '{j.parent}' to itself")
        elif j.child and j.child == mech.base_link:
            out.error(j.line, f"joint '{j.name}' moves the base link '{j.child}'")
    if mech.base_link in links:
        _graph(mech, out)
    _limits(mech, out)
    for f in mech.flanges:
        if f.link and f.link not in links:
            out.error(f.line, f"flange '{f.name}' link '{f.link}' is not a link")
    part_names = {p.name for link in mech.links for p, _ in iter_parts(link)} if mech.cables else set()
    for c in mech.cables:
        for p in c.control_points:
            if p.attached_to is not None and p.attached_to not in links | part_names:
                out.error(p.line, f"ControlPoint attachedTo '{p.attached_to}' is not a link or part")
        if c.radius > 0 and c.max_segment_length > 0:  # else the reader said why already
            try:
                spans = cable_spans(c, mech.length_factor)
            except ValueError as exc:
                out.error(c.line, str(exc))
            else:
                _slack(c, spans, mech.length_factor, out)
    _attributes(mech, out)


def _slack(c, spans, factor: float, out: _Out) -> None:
    """A cable with no length to spare: no desiredLength (it is taken as the path through its
    points), or one that is that path; the first move that spreads its clamps pulls it taut."""
    unit = lambda v: f"{v / factor:.4g}"  # noqa: E731  the file's length unit
    if c.desired_length is None:
        out.warn(c.line, f"cable '{c.name}' has no desiredLength: it is taken as the path through its control "
                         f"points ({unit(spans.polyline)}), no slack at all; give the hose's real length")
    elif spans.lengths.sum() <= spans.polyline * (1 + 1e-6):
        out.warn(c.line, f"cable '{c.name}': desiredLength {unit(c.desired_length * 1.0)} is the path through its "
                         "control points: no slack at all; give the hose's real length")


def _metadata(mech: Mechanism, out: _Out) -> None:
    if mech.type is not None and mech.type not in MECHANISM_TYPES:
        out.warn(mech.line, f"mechanism type '{mech.type}' is not one of {', '.join(MECHANISM_TYPES)}")
    for flag in mech.kinematics_flags:
        if flag not in KINEMATICS_FLAGS:
            out.warn(mech.line, f"unknown kinematicsFlags value '{flag}'")
    if mech.type != "Robot":
        return
    if not mech.kinematics_flags:
        out.error(mech.line, "a Robot needs kinematicsFlags (e.g. \"Articulated\")")
    parts = robot_name_parts(mech.name)
    if parts is None:
        out.warn(mech.line, f"name '{mech.name}' does not follow the naming standard "
                            "IRB<model>_<capacity>_<reach>_[variant]_<revision>")
    elif mech.model_name is not None:
        expected = mech.name[:-3].rstrip("_")  # drop "_<revision>" and the empty variant's "_"
        if mech.model_name != expected:
            out.warn(mech.line, f"modelName '{mech.model_name}' should be the name without its revision, '{expected}'")


def _graph(mech: Mechanism, out: _Out) -> None:
    """Links reachable from the base, and loops that only passive joints may close (asked of the
    link graph, which leaves out the joints already reported above)."""
    graph = mech.graph
    for link in mech.links:
        if graph.depth[graph.index[link.name]] < 0:
            out.error(link.line, f"link '{link.name}' is not connected to the base link '{mech.base_link}'")
    for j in graph.closing:
        if graph.closes_all_active_loop(j):
            names = ", ".join(x.name for x in graph.loop(j))
            out.error(j.line, f"joints {names} form a loop with no passive joint to close it")
    in_loops = graph.joints_in_loops
    for j in graph.joints:
        if not j.active and j.name not in in_loops and graph.depth[graph.index[j.child]] >= 0:
            out.warn(j.line, f"passive joint '{j.name}' closes no loop; it stays at zero")


def _limits(mech: Mechanism, out: _Out) -> None:
    counts = Counter(lim.joint for lim in mech.limits)
    seen = set()
    for lim in mech.limits:
        if counts[lim.joint] > 1 and lim.joint in seen:
            out.error(lim.line, f"joint '{lim.joint}' has a second Limit")
        seen.add(lim.joint)
    for j in mech.active_joints:
        if j.name not in counts:
            out.error(j.line, f"active joint '{j.name}' has no Limit")
    if mech.home is None:
        return
    for j, v in zip(mech.active_joints, mech.home):
        lim = mech.limit(j.name)
        if lim is not None and lim.min <= lim.max and not lim.min <= v <= lim.max:
            f = mech.joint_factor(j)
            out.error(mech.section_line("HomePosition"),
                      f"HomePosition of '{j.name}' is {format_number(v, f)}, outside its limits "
                      f"[{format_number(lim.min, f)}, {format_number(lim.max, f)}]")


def _attributes(mech: Mechanism, out: _Out) -> None:
    seen: dict[str, int] = {}
    for a in mech.attributes:
        if a.key in seen:
            out.error(a.line, f"duplicate attribute key '{a.key}' (first at line {seen[a.key]})")
        seen[a.key] = a.line
        if a.key not in KNOWN_ATTRIBUTE_KEYS:
            out.warn(a.line, f"attribute '{a.key}' is not one RobotStudio recognizes "
                             f"({', '.join(KNOWN_ATTRIBUTE_KEYS)})")
            continue
        if a.definition is not True:
            out.warn(a.line, f"attribute '{a.key}' belongs to the definition: set definition=\"true\"")
        if a.key == "OverrideJointLimits" and a.value.strip().lower() not in ("true", "false"):
            out.error(a.line, f"OverrideJointLimits must be true or false, not '{a.value}'")
        if a.key == "AllowedTrackModels" and not a.value.split():
            out.error(a.line, "AllowedTrackModels names no track model")


def validate_smart_component(sc: SmartComponent, file: str, diagnostics: list[Diagnostic]) -> None:
    """Names of properties and signals, signal types, and the components inside."""
    out = _Out(file, diagnostics)
    _duplicates(out, "property", sc.properties)
    _duplicates(out, "signal", sc.signals)
    for s in sc.signals:
        if s.signal_type is not None and s.signal_type not in SIGNAL_TYPES:
            out.warn(s.line, f"signal '{s.name}' has unknown signalType '{s.signal_type}'")
    for comp in sc.components:
        if isinstance(comp, Mechanism):
            validate_mechanism(comp, file, diagnostics)
        elif isinstance(comp, SmartComponent):
            validate_smart_component(comp, file, diagnostics)
