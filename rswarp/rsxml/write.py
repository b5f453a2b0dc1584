"""Write the model back to RSXML in the file's own units (atomically: temp file, then rename).

Numbers are written as the shortest text that reads back to the same SI value, so an unchanged
model saves to the same values and load -> save -> load gives an equal model.
"""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from ..files import atomic_write
from .model import Component, Group, Mechanism, Part, Pose, SmartComponent
from .read import NS_COMPONENT
from .units import ANGLE_UNITS, LENGTH_UNITS, format_number


def _vec(values, factor: float = 1.0) -> str:
    return ", ".join(format_number(v, factor) for v in values)


class _Writer:
    def __init__(self, length: float, angle: float):
        self.length, self.angle = length, angle

    def el(self, _parent, _tag: str, **attrs) -> etree._Element:
        tag = f"{{{NS_COMPONENT}}}{_tag}"
        node = etree.Element(tag, nsmap={None: NS_COMPONENT}) if _parent is None else etree.SubElement(_parent, tag)
        for k, v in attrs.items():
            if v is not None:
                node.set(k, v)
        return node

    def pose(self, node: etree._Element, pose: Pose) -> None:
        if pose.t is not None:
            node.set("t", _vec(pose.t, self.length))
        if pose.x is not None:
            for k in "xyz":
                node.set(k, _vec(getattr(pose, k)))
        if pose.euler is not None:
            node.set("euler", _vec(pose.euler, self.angle))
        if pose.quat is not None:
            node.set("quat", _vec(pose.quat))

    def component(self, parent, comp) -> None:
        if isinstance(comp, Part):
            self.pose(self.el(parent, "Part", name=comp.name, source=comp.source), comp.pose)
        elif isinstance(comp, Group):
            node = self.el(parent, "GraphicComponentGroup", name=comp.name)
            self.pose(node, comp.pose)
            inner = self.el(node, "GraphicComponents")
            for c in comp.children:
                self.component(inner, c)
        elif isinstance(comp, Mechanism):
            mechanism_element(comp, parent)
        elif isinstance(comp, SmartComponent):
            smart_component_element(comp, parent)


def mechanism_element(mech: Mechanism, parent: etree._Element | None = None) -> etree._Element:
    """The ``<Mechanism>`` element of a model."""
    w = _Writer(LENGTH_UNITS.get(mech.length_unit or "m", 1.0), ANGLE_UNITS.get(mech.angle_unit or "rad", 1.0))
    root = w.el(parent, "Mechanism", type=mech.type, name=mech.name, modelName=mech.model_name,
                kinematicsFlags=" ".join(mech.kinematics_flags) or None, lengthUnit=mech.length_unit,
                angleUnit=mech.angle_unit, motionControl=mech.motion_control)
    if mech.attributes:
        node = w.el(root, "Attributes")
        for a in mech.attributes:
            w.el(node, "Attribute", definition=None if a.definition is None else str(a.definition).lower(),
                 key=a.key, value=a.value)
    links = w.el(root, "Links", baseLink=mech.base_link)
    for link in mech.links:
        w.component(links, link)
    if mech.cables:
        node = w.el(root, "AdditionalComponents")
        for c in mech.cables:
            cable = w.el(node, "Cable", radius=format_number(c.radius, w.length),
                         maxSegmentLength=format_number(c.max_segment_length, w.length), name=c.name,
                         color=None if c.color is None else ", ".join(map(str, c.color)),
                         desiredLength=None if c.desired_length is None else format_number(c.desired_length, w.length),
                         youngsModulus=None if c.youngs_modulus is None else format_number(c.youngs_modulus))
            points = w.el(cable, "ControlPoints")
            for p in c.control_points:
                w.el(points, "ControlPoint", attachedTo=p.attached_to, position=_vec(p.position, w.length),
                     direction=None if p.direction is None else _vec(p.direction))
    joints = w.el(root, "Joints")
    for j in mech.joints:
        w.el(joints, "Joint", name=j.name, parent=j.parent, child=j.child, type=j.type,
             active=str(j.active).lower(), point1=_vec(j.point1, w.length), point2=_vec(j.point2, w.length))
    if mech.limits:
        node = w.el(root, "Limits")
        for lim in mech.limits:
            f = mech.joint_factor(mech.joint(lim.joint))
            w.el(node, "Limit", joint=lim.joint, min=format_number(lim.min, f), max=format_number(lim.max, f))
    if mech.flanges:
        node = w.el(root, "Flanges")
        for fl in mech.flanges:
            w.pose(w.el(node, "Flange", name=fl.name, link=fl.link), fl.pose)
    if mech.base_frame is not None:
        w.pose(w.el(root, "BaseFrame"), mech.base_frame)
    if mech.home is not None:
        w.el(root, "HomePosition", value=", ".join(
            format_number(v, mech.joint_factor(j)) for v, j in zip(mech.home, mech.active_joints)))
    if mech.joint_mask is not None:
        w.el(root, "JointMask", value=", ".join(map(str, mech.joint_mask)))
    return root


def smart_component_element(sc: SmartComponent, parent: etree._Element | None = None) -> etree._Element:
    """The ``<SmartComponent>`` element: properties, bindings, signals, components, assets."""
    w = _Writer(1.0, 1.0)
    root = w.el(parent, "SmartComponent", name=sc.name, **dict(sc.options))
    props = w.el(root, "Properties")
    for p in sc.properties:
        node = w.el(props, "DynamicProperty", name=p.name, valueType=p.value_type, value=p.value, **dict(p.options))
        for k, v in p.attributes:
            w.el(node, "Attribute", key=k, value=v)
    bindings = w.el(root, "Bindings")
    for b in sc.bindings:
        w.el(bindings, b.kind, **dict(b.options))
    signals = w.el(root, "Signals")
    for s in sc.signals:
        w.el(signals, "IOSignal", name=s.name, signalType=s.signal_type, **dict(s.options))
    comps = w.el(root, "GraphicComponents")
    for c in sc.components:
        w.component(comps, c)
    assets = w.el(root, "Assets")
    for a in sc.assets:
        w.el(assets, "Asset", source=a)
    return root


def to_rsxml(model: Mechanism | SmartComponent | Component) -> bytes:
    """The RSXML document of a model, as UTF-8 bytes."""
    if isinstance(model, Mechanism):
        root = mechanism_element(model)
    elif isinstance(model, SmartComponent):
        root = smart_component_element(model)
    else:
        holder = etree.Element("holder")
        _Writer(1.0, 1.0).component(holder, model)
        root = holder[0]
        etree.cleanup_namespaces(root, top_nsmap={None: NS_COMPONENT})
    for text in getattr(model, "comments", ()):  # the note before the root (licence, provenance)
        root.addprevious(etree.Comment(text))
    return etree.tostring(root.getroottree(), xml_declaration=True, encoding="utf-8", pretty_print=True)


def save(model: Mechanism | SmartComponent | Component, path: str | Path) -> None:
    """Write a model as RSXML in its own units (atomic). The comments before the root element are
    kept; comments inside it are not (the model does not hold them)."""
    atomic_write(path, to_rsxml(model))
