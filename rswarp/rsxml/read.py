"""Read GraphicComponent XML (.rsxml) into the model, collecting every problem with its line.

Parsing is safe (``parse``): no entity expansion, no network, no huge trees, regular files within
the size limit. Values are checked for physical sense as they are read: lengths within 1 km, angles
within ``MAX_ANGLE``, so nothing downstream overflows float32 or turns into NaN.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Callable

import numpy as np
from lxml import etree

from ..errors import Diagnostic
from .model import (
    JOINT_TYPES,
    Attribute,
    Binding,
    Cable,
    Component,
    ControlPoint,
    DynamicProperty,
    Flange,
    Group,
    IOSignal,
    Joint,
    Limit,
    Mechanism,
    Part,
    SmartComponent,
)
from .parse import local, namespace, prolog_comments
from .units import ANGLE_UNITS, LENGTH_UNITS
from .values import ValueReader

NS_COMPONENT = "urn:abb-robotics-robotstudio-graphiccomponent"
NS_LIBRARY = "urn:abb-robotics-robotstudio-librarycompiler"
NS_RESOURCE = "urn:abb-robotics-robotstudio-libraryresource"

POSE_ATTRS = ("t", "x", "y", "z", "euler", "quat")
MECHANISM_SECTIONS = ("Attributes", "Links", "Joints", "Limits", "Flanges", "BaseFrame", "HomePosition",
                      "JointMask", "AdditionalComponents")


YOUNG_MIN, YOUNG_MAX = 1e5, 1e13  # Pa: a cable's Young's modulus, softer than any hose to past any metal


class Reader(ValueReader):
    """Turns XML elements into model objects; records each problem as ``file:line: message``."""

    # -- components --------------------------------------------------------------------------------
    def component(self, el: etree._Element) -> Component | None:
        """A Part or GraphicComponentGroup (with nested GraphicComponents)."""
        kind = local(el)
        if kind == "Part":
            self.known(el, ("name", "source", *POSE_ATTRS))
            return Part(name=self.text(el, "name", True) or "", source=self.text(el, "source"),
                        pose=self.pose(el), line=el.sourceline or 0)
        if kind == "GraphicComponentGroup":
            self.known(el, ("name", *POSE_ATTRS))
            kids: list[Component] = []
            for c in self.children(el):
                if local(c) == "GraphicComponents":
                    kids.extend(self.components(c))
                else:
                    self.warn(c, f"unknown element <{local(c)}> in <GraphicComponentGroup> ignored")
            return Group(name=self.text(el, "name", True) or "", children=tuple(kids),
                         pose=self.pose(el), line=el.sourceline or 0)
        self.warn(el, f"unknown element <{kind}> ignored")
        return None

    def components(self, el: etree._Element) -> list[Component]:
        out = []
        for c in self.children(el):
            comp = self.component(c)
            if comp is not None:
                out.append(comp)
        return out

    # -- Mechanism ---------------------------------------------------------------------------------
    def units(self, el: etree._Element) -> tuple[str | None, str | None]:
        lu, au = self.text(el, "lengthUnit"), self.text(el, "angleUnit")
        if lu is not None and lu not in LENGTH_UNITS:
            self.error(el, f"unknown lengthUnit '{lu}' (use one of {', '.join(LENGTH_UNITS)})")
        if au is not None and au not in ANGLE_UNITS:
            self.error(el, f"unknown angleUnit '{au}' (use one of {', '.join(ANGLE_UNITS)})")
        self.length = LENGTH_UNITS.get(lu or "m", 1.0)
        self.angle = ANGLE_UNITS.get(au or "rad", 1.0)
        return lu, au

    def mechanism(self, root: etree._Element, path: str | None = None) -> Mechanism:
        self.known(root, ("type", "name", "modelName", "kinematicsFlags", "lengthUnit", "angleUnit",
                          "motionControl"))
        lu, au = self.units(root)
        sections = self.sections(root)

        def each(section: str, tag: str) -> list[etree._Element]:
            return self.each(sections.get(section), section, tag)

        links_el = sections.get("Links")
        base_link, links = "", []
        if links_el is not None:
            self.known(links_el, ("baseLink",))
            base_link = self.text(links_el, "baseLink", True) or ""
            links = self.components(links_el)

        joints = [self.joint(el) for el in each("Joints", "Joint")]
        by_name = {j.name: j for j in joints}
        limits = [lim for el in each("Limits", "Limit") if (lim := self.limit(el, by_name)) is not None]
        flanges = []
        for el in each("Flanges", "Flange"):
            self.known(el, ("name", "link", *POSE_ATTRS))
            flanges.append(Flange(name=self.text(el, "name", True) or "", link=self.text(el, "link", True) or "",
                                  pose=self.pose(el), line=el.sourceline or 0))
        base_frame = None
        if (bf := sections.get("BaseFrame")) is not None:
            self.known(bf, POSE_ATTRS)
            base_frame = self.pose(bf)
        active = [j for j in joints if j.active]
        home = self.home(sections.get("HomePosition"), active)
        mask = self.joint_mask(sections.get("JointMask"), active)
        attributes = [self.attribute(el) for el in each("Attributes", "Attribute")]
        cables = [self.cable(el) for el in each("AdditionalComponents", "Cable")]
        flags = tuple((self.text(root, "kinematicsFlags") or "").split())
        return Mechanism(
            name=self.text(root, "name", True) or "", type=self.text(root, "type"),
            model_name=self.text(root, "modelName"), kinematics_flags=flags, length_unit=lu, angle_unit=au,
            motion_control=self.text(root, "motionControl"), base_link=base_link, links=tuple(links),
            joints=tuple(joints), limits=tuple(limits), flanges=tuple(flanges), base_frame=base_frame,
            home=home, joint_mask=mask, attributes=tuple(attributes), cables=tuple(cables),
            path=path, line=root.sourceline or 0,
            section_lines=tuple((k, v.sourceline or 0) for k, v in sections.items()),
        )

    def sections(self, root: etree._Element) -> dict[str, etree._Element]:
        """The Mechanism's top-level elements by name; unknown and repeated ones are reported."""
        sections: dict[str, etree._Element] = {}
        for c in self.children(root):
            name = local(c)
            if name not in MECHANISM_SECTIONS:
                self.warn(c, f"unknown element <{name}> in <Mechanism> ignored")
            elif name in sections:
                self.error(c, f"<{name}> appears twice (first at line {sections[name].sourceline})")
            else:
                sections[name] = c
        return sections

    def each(self, el: etree._Element | None, section: str, tag: str) -> list[etree._Element]:
        """The ``tag`` children of a section (others are reported and skipped)."""
        out = []
        for c in self.children(el) if el is not None else ():
            if local(c) == tag:
                out.append(c)
            else:
                self.warn(c, f"unknown element <{local(c)}> in <{section}> ignored")
        return out

    def home(self, hp: etree._Element | None, active: list[Joint]) -> tuple[float, ...] | None:
        """HomePosition: one value per active joint, in SI."""
        if hp is None:
            return None
        self.known(hp, ("value",))
        raw = self.floats(hp, "value", required=True)
        if raw is None:
            return None
        if len(raw) != len(active):
            self.error(hp, f"HomePosition has {_count(len(raw), 'value')} for {len(active)} active joints")
            return None
        si = tuple(v * (self.angle if j.revolute else self.length) for v, j in zip(raw, active))
        for v, s, j in zip(raw, si, active):
            if not self.within(hp, "value", format(v, "g"), s, "angle" if j.revolute else "length"):
                return None
        return si

    def joint_mask(self, jm: etree._Element | None, active: list[Joint]) -> tuple[int, ...] | None:
        """JointMask: one whole number >= 0 per active joint."""
        if jm is None:
            return None
        self.known(jm, ("value",))
        raw = self.floats(jm, "value", required=True)
        if raw is None:
            return None
        if any(v != int(v) or v < 0 for v in raw):
            self.error(jm, "JointMask values must be whole numbers >= 0")
        elif len(raw) != len(active):
            self.error(jm, f"JointMask has {_count(len(raw), 'value')} for {len(active)} active joints")
        else:
            return tuple(int(v) for v in raw)
        return None

    def joint(self, el: etree._Element) -> Joint:
        self.known(el, ("name", "parent", "child", "type", "active", "point1", "point2"))
        jtype = self.text(el, "type", True) or "Rotational"
        if jtype not in JOINT_TYPES:
            self.error(el, f"joint type '{jtype}' is neither Rotational nor Prismatic")
            jtype = "Rotational"
        p1 = self.floats(el, "point1", 3, self.length, True, "length")
        p2 = self.floats(el, "point2", 3, self.length, True, "length")
        if p1 is not None and p2 is not None and math.dist(p1, p2) <= 1e-9 * max(1.0, *map(abs, p1)):
            self.error(el, "point1 and point2 coincide: the joint has no axis")
            p2 = None
        return Joint(
            name=self.text(el, "name", True) or "", parent=self.text(el, "parent", True) or "",
            child=self.text(el, "child", True) or "", type=jtype,
            active=bool(self.boolean(el, "active", True)),
            point1=p1 or (0.0, 0.0, 0.0), point2=p2 or _unit_z_from(p1),
            line=el.sourceline or 0,
        )

    def limit(self, el: etree._Element, joints: dict[str, Joint]) -> Limit | None:
        self.known(el, ("joint", "min", "max"))
        name = self.text(el, "joint", True)
        if not name:
            return None
        joint = joints.get(name)
        if joint is None:
            self.error(el, f"Limit names unknown joint '{name}'")
            return None
        factor, bound = (self.angle, "angle") if joint.revolute else (self.length, "length")
        lo = self.number(el, "min", factor, True, bound)
        hi = self.number(el, "max", factor, True, bound)
        if lo is None or hi is None:
            return None
        if lo > hi:
            self.error(el, f"Limit of '{name}' has min {el.get('min').strip()} > max {el.get('max').strip()}")
        return Limit(joint=name, min=lo, max=hi, line=el.sourceline or 0)

    def attribute(self, el: etree._Element) -> Attribute:
        self.known(el, ("definition", "key", "value"))
        return Attribute(key=self.text(el, "key", True) or "", value=el.get("value", ""),
                         definition=self.boolean(el, "definition", None), line=el.sourceline or 0)

    def cable(self, el: etree._Element) -> Cable:
        self.known(el, ("radius", "maxSegmentLength", "name", "color", "desiredLength", "youngsModulus"))
        radius = self.number(el, "radius", self.length, True, "length")
        seg = self.number(el, "maxSegmentLength", self.length, True, "length")
        desired = self.number(el, "desiredLength", self.length, bound="length")
        young = self.number(el, "youngsModulus")
        for key, value in (("radius", radius), ("maxSegmentLength", seg), ("desiredLength", desired),
                           ("youngsModulus", young)):
            if value is not None and value <= 0:
                self.error(el, f"Cable {key} must be positive, not {el.get(key).strip()}")
        if young is not None and young > 0 and not YOUNG_MIN <= young <= YOUNG_MAX:
            self.error(el, f"Cable youngsModulus must be {YOUNG_MIN:g} to {YOUNG_MAX:g} Pa (from softer than any "
                           "hose's jacket, silicone's 1e6, to past steel's 2e11), not "
                           f"{el.get('youngsModulus').strip()}")
        color = None
        if (rgb := self.floats(el, "color", 3)) is not None:
            if any(c != int(c) or not 0 <= c <= 255 for c in rgb):
                self.error(el, "Cable color must be three whole numbers 0-255")
            else:
                color = tuple(int(c) for c in rgb)
        points = []
        for c in self.children(el):
            if local(c) != "ControlPoints":
                self.warn(c, f"unknown element <{local(c)}> in <Cable> ignored")
                continue
            for p in self.children(c):
                if local(p) != "ControlPoint":
                    self.warn(p, f"unknown element <{local(p)}> in <ControlPoints> ignored")
                    continue
                points.append(self.control_point(p))
        if len(points) < 2:
            self.error(el, f"Cable has {_count(len(points), 'control point')}; it needs at least two")
        return Cable(name=self.text(el, "name", True) or "", radius=radius or 0.0, max_segment_length=seg or 0.0,
                     control_points=tuple(points), color=color, desired_length=desired, youngs_modulus=young,
                     line=el.sourceline or 0)

    def control_point(self, el: etree._Element) -> ControlPoint:
        self.known(el, ("attachedTo", "position", "direction"))
        pos = self.floats(el, "position", 3, self.length, True, "length")
        direction = self.floats(el, "direction", 3)
        if direction is not None and float(np.linalg.norm(direction)) < 1e-12:
            self.error(el, "ControlPoint direction is zero")
            direction = None
        return ControlPoint(position=pos or (0.0, 0.0, 0.0), attached_to=self.text(el, "attachedTo"),
                            direction=direction, line=el.sourceline or 0)

    # -- SmartComponent ----------------------------------------------------------------------------
    def smart_component(self, root: etree._Element, path: str | None = None) -> SmartComponent:
        self.units(root)
        props, signals, bindings, comps, assets = [], [], [], [], []
        for section in self.children(root):
            kind = local(section)
            items = self.children(section)
            if kind == "Properties":
                props += [self.dynamic_property(p) for p in items if self._expect(p, "DynamicProperty", kind)]
            elif kind == "Signals":
                for s in items:
                    if self._expect(s, "IOSignal", kind):
                        signals.append(IOSignal(name=self.text(s, "name", True) or "",
                                                signal_type=self.text(s, "signalType"),
                                                options=self.options(s, ("name", "signalType")),
                                                line=s.sourceline or 0))
            elif kind == "Bindings":
                bindings += [Binding(kind=local(b), options=self.options(b), line=b.sourceline or 0) for b in items]
            elif kind == "GraphicComponents":
                for c in items:
                    comp = self.nested(c, path)
                    if comp is not None:
                        comps.append(comp)
            elif kind == "Assets":
                for a in items:
                    if self._expect(a, "Asset", kind):
                        assets.append(self.text(a, "source", True) or "")
            else:
                self.warn(section, f"unknown element <{kind}> in <SmartComponent> ignored")
        return SmartComponent(name=self.text(root, "name", True) or "", options=self.options(root, ("name",)),
                              properties=tuple(props), signals=tuple(signals), bindings=tuple(bindings),
                              components=tuple(comps), assets=tuple(assets), path=path, line=root.sourceline or 0)

    def _expect(self, el: etree._Element, tag: str, section: str) -> bool:
        if local(el) == tag:
            return True
        self.warn(el, f"unknown element <{local(el)}> in <{section}> ignored")
        return False

    def dynamic_property(self, el: etree._Element) -> DynamicProperty:
        attrs = []
        for a in self.children(el):
            if self._expect(a, "Attribute", "DynamicProperty"):
                attrs.append((self.text(a, "key", True) or "", a.get("value", "")))
        return DynamicProperty(name=self.text(el, "name", True) or "", value_type=self.text(el, "valueType"),
                               value=el.get("value"), options=self.options(el, ("name", "valueType", "value")),
                               attributes=tuple(attrs), line=el.sourceline or 0)

    def nested(self, el: etree._Element, path: str | None):
        """A component inside a SmartComponent: a Part, group, Mechanism or SmartComponent."""
        kind = local(el)
        saved = (self.length, self.angle)
        try:
            if kind == "Mechanism":
                return self.mechanism(el, path)
            if kind == "SmartComponent":
                return self.smart_component(el, path)
            return self.component(el)
        finally:
            self.length, self.angle = saved


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'s' if n != 1 else ''}"


def _unit_z_from(p: tuple[float, ...] | None) -> tuple[float, float, float]:
    """A stand-in second axis point for a joint whose axis is already reported as broken."""
    x, y, z = p or (0.0, 0.0, 0.0)
    return (x, y, z + 1.0)


ROOT_READERS: dict[str, Callable[[Reader, etree._Element, str], object]] = {
    "Mechanism": lambda r, el, p: r.mechanism(el, p),
    "SmartComponent": lambda r, el, p: r.smart_component(el, p),
    "GraphicComponentGroup": lambda r, el, p: r.component(el),
    "Part": lambda r, el, p: r.component(el),
}


def read_component_root(root: etree._Element, file: str, diagnostics: list[Diagnostic]):
    """Read a GraphicComponent root element (Mechanism, SmartComponent, group or Part)."""
    r = Reader(file, diagnostics)
    ns = namespace(root)
    if ns is None:
        r.warn(root, f"<{local(root)}> has no namespace; RobotStudio expects xmlns=\"{NS_COMPONENT}\"")
    elif ns != NS_COMPONENT:
        r.error(root, f"<{local(root)}> is in namespace '{ns}', expected '{NS_COMPONENT}'")
        return None
    reader = ROOT_READERS.get(local(root))
    if reader is None:
        r.error(root, f"unknown root element <{local(root)}> (expected Mechanism, SmartComponent, "
                      "GraphicComponentGroup or Part)")
        return None
    model = reader(r, root, file)
    if isinstance(model, (Mechanism, SmartComponent)) and root.getparent() is None:
        model = replace(model, comments=prolog_comments(root))
    return model
