"""Reading each feature of the format into SI units and world frames (one input file per feature)."""

import math

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.rsxml.model import Group, Part, iter_parts
from rswarp.transforms import euler_zyx_matrix, quat_matrix

from conftest import DATA

MM, DEG, IN = 1e-3, math.pi / 180, 0.0254


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def test_spec_irb1300_in_si():
    m = rswarp.load(examples.IRB1300)
    assert (m.name, m.type, m.model_name, m.kinematics_flags) == ("IRB1300_11_90__01", "Robot", "IRB1300_11_90", ("Articulated",))
    assert m.link_names == ("Base", "Link1", "Link2", "Link3", "Link4", "Link5", "Link6")
    assert m.dof == 6 and m.base_link == "Base"
    j2 = m.joint("J2")
    assert j2.point1 == pytest.approx((0.05, -0.1005, 0.544)) and j2.point2 == pytest.approx((0.05, 0.0945, 0.544))
    assert np.allclose(j2.axis, [0, 1, 0])
    lo, hi = m.bounds()
    assert lo == pytest.approx(np.radians([-180, -100, -210, -230, -130, -400]))
    assert hi == pytest.approx(np.radians([180, 130, 65, 230, 130, 400]))
    assert m.home == pytest.approx((0, 0, 0, 0, 30 * DEG, 0))
    assert m.joint_mask == (1, 1, 1, 1, 1, 1)
    flange = m.flanges[0].pose.matrix()
    assert flange[:3, 3] == pytest.approx([0.565, 0, 1.009])
    assert np.allclose(flange[:3, :3], [[0, 0, 1], [0, 1, 0], [-1, 0, 0]])  # columns x, y, z
    assert m.base_frame is not None and m.base_frame.is_identity


def test_default_units_are_metres_and_radians():
    m = rswarp.load(DATA / "units_default.rsxml")
    assert m.length_unit is None and m.angle_unit is None
    assert m.limits[0].min == -1.5 and m.home == (0.25,)
    assert m.joint("J1").point1 == (0, 0, 0.5)


def test_inch_units_and_prismatic_limits_in_length_unit():
    m = rswarp.load(DATA / "units_inch.rsxml")
    x, c = m.joints
    assert not x.revolute and c.revolute
    assert m.limit("X").max == pytest.approx(40 * IN) and m.limit("C").max == pytest.approx(math.pi / 2)
    assert m.home == pytest.approx((20 * IN, 45 * DEG))
    assert m.flanges[0].pose.t == pytest.approx((0, 0, 12 * IN))


def test_every_transform_form():
    m = rswarp.load(DATA / "transforms.rsxml")
    parts = {p.name: t for link in m.links for p, t in iter_parts(link)}
    assert np.allclose(parts["Base"], np.eye(4))
    assert np.allclose(parts["Matrix"][:3, :3], rot_z(math.pi / 2)) and parts["Matrix"][:3, 3] == pytest.approx([0.1, 0, 0])
    assert np.allclose(parts["Euler"][:3, :3], rot_x(math.pi / 2))  # euler = (rx, ry, rz)
    assert np.allclose(parts["Quat"][:3, :3], rot_z(math.pi / 2)) and parts["Quat"][:3, 3] == pytest.approx([0, 0, 0.05])
    # group at z=1 m holds Inner (x+10 mm) and Nested (rotated 90 deg about z) holding Deep (y+20 mm)
    assert parts["Inner"][:3, 3] == pytest.approx([0.01, 0, 1.0])
    assert parts["Deep"][:3, 3] == pytest.approx([-0.02, 0, 1.0])  # (0, 20 mm) turned 90 deg about z
    tool0, aux = (f.pose.matrix() for f in m.flanges)
    assert np.allclose(tool0[:3, :3], rot_y(math.pi / 2))
    assert np.allclose(aux[:3, :3], np.eye(3)) and aux[:3, 3] == pytest.approx([0, 0, 1.1])
    bf = m.base_frame.matrix()
    assert np.allclose(bf[:3, :3], rot_z(math.pi)) and bf[:3, 3] == pytest.approx([0.5, 0, 0])
    assert isinstance(m.link("Group"), Group) and isinstance(m.link("Base"), Part)
    assert m.parts("Group")[1][0].name == "Deep"


def test_euler_is_zyx():
    rx, ry, rz = 0.3, -0.7, 1.1
    assert np.allclose(euler_zyx_matrix(rx, ry, rz), rot_z(rz) @ rot_y(ry) @ rot_x(rx))
    h = math.sqrt(0.5)
    assert np.allclose(quat_matrix((h, h, 0, 0)), rot_x(math.pi / 2))


def test_spec_irb2600id_groups_and_cable():
    m = rswarp.load(examples.IRB2600ID)
    assert m.motion_control == "Kinematic"
    link1 = m.link("Link1")
    assert isinstance(link1, Group) and [p.name for p, _ in iter_parts(link1)] == ["Link1", "Cables", "Cables"]
    (hose,) = m.cables
    assert (hose.name, hose.color) == ("Hose", (32, 32, 32))
    assert hose.radius == pytest.approx(0.025) and hose.max_segment_length == pytest.approx(0.05)
    assert [p.attached_to for p in hose.control_points] == ["Link4", "Link5"]
    assert hose.control_points[1].position == pytest.approx((1.205, 0, 1.495))
    assert hose.control_points[0].direction == (1, 0, 0)


def test_cable_optional_attributes():
    (c,) = rswarp.load(DATA / "cable.rsxml").cables
    assert c.desired_length == pytest.approx(0.9) and c.youngs_modulus == 2e7 and c.radius == pytest.approx(0.0125)
    first, routing, bracket = c.control_points
    assert first.direction == (0, 0, 2) and first.unit_direction.tolist() == [0, 0, 1]
    assert routing.attached_to is None and routing.direction is None
    assert bracket.attached_to == "Bracket"  # a part of link Arm


def test_parallel_rod_loop_closed_by_passive_joints():
    report = rswarp.check(DATA / "parallel_rod.rsxml")
    assert report.ok and not report.warnings
    m = report.model
    assert m.dof == 3 and [j.name for j in m.joints if not j.active] == ["Rod1", "Elbow", "Rod2"]
    assert m.kinematics_flags == ("Articulated", "ParallelRod", "Palletizer")


def test_attributes():
    report = rswarp.check(DATA / "attributes.rsxml")
    m = report.model
    assert m.allowed_track_models == ("IRBT4004", "IRBT2005") and m.override_joint_limits
    assert m.attribute("WorkEnvelopeData") == "opaque-data" and m.attributes[3].definition is False
    assert [(w.line, w.message.split(" is ")[0]) for w in report.warnings] == [(8, "attribute 'PaintColor'")]


def test_warnings_do_not_stop_loading():
    report = rswarp.check(DATA / "warnings.rsxml")
    assert report.ok
    assert sorted((w.line, w.message) for w in report.warnings) == [
        (4, "modelName 'IRB120_3' should be the name without its revision, 'IRB120_3_58'"),
        (6, "unknown attribute 'colour' on <Part> ignored"),
        (7, "<Part> quat has length 2; normalized"),
        (15, "unknown element <Payload> in <Mechanism> ignored"),
    ]
    assert report.model.link("Link1").pose.quat == (1, 0, 0, 0)
    with pytest.warns(rswarp.RsxmlWarning):
        rswarp.load(DATA / "warnings.rsxml")
    naming = rswarp.check(DATA / "naming.rsxml")
    assert [w.message for w in naming.warnings] == [
        "name 'MyRobot' does not follow the naming standard IRB<model>_<capacity>_<reach>_[variant]_<revision>"]


def test_smart_component_and_its_resource():
    report = rswarp.check(DATA / "smart" / "Counter.rsxml")
    sc = report.model
    assert isinstance(sc, rswarp.SmartComponent)
    assert sc.code_behind == "Counter.CodeBehind,Counter.dll" and sc.option("canBeSimulated") == "true"
    assert [(p.name, p.value_type, p.value) for p in sc.properties] == [("Count", "System.Int32", "0"), ("Step", "System.Double", "1.5")]
    assert sc.properties[1].attributes == (("Quantity", "Length"), ("AutoApply", "true"))
    assert [(s.name, s.signal_type) for s in sc.signals] == [("Increment", "DigitalInput"), ("Overflow", "DigitalOutput")]
    assert sc.bindings[0].kind == "PropertyBinding" and dict(sc.bindings[0].options) == {"source": "Step", "target": "Marker/Size"}
    assert sc.components[0].pose.t == (0, 0, 0.1) and sc.assets == ("Counter.dll",)
    desc = dict(sc.descriptions)
    assert desc[""] == "Counts rising edges." and desc["Increment"] == "Adds one on a rising edge."
    assert [(w.line, w.message) for w in report.warnings] == [(7, "IOSignal 'Reset' is not in SmartComponent 'Counter'")]


def test_library_resource_file():
    report = rswarp.check(DATA / "smart" / "Counter.en.xml")
    res = report.model
    assert report.kind == "LibraryResource" and res.language == "en"
    assert res.descriptions("Counter")["Count"] == "Edges seen so far."


def test_library_compiler_file():
    report = rswarp.check(DATA / "library" / "Robots.xml")
    assert report.ok
    lib = report.model
    robot, marker = lib.libraries
    assert robot.source == "sub\\IRB1_1_1__02.rsxml" and robot.source_path.endswith("sub/IRB1_1_1__02.rsxml")
    assert robot.file_name == "IRB1_1_1__02.rslib"  # defaults to the source's name
    p = robot.properties
    assert (p.title, p.author, p.revision) == ("IRB 1 test robot", "ABB", "01")
    assert p.image.source == "preview.png" and p.image.flip == "true" and p.image.generate is None  # whole Image replaced
    assert lib.defaults.image.pany == 10 and lib.defaults.image.generate is True
    (variant,) = robot.variants
    assert variant.name == "Foundry" and dict(variant.options)["fileName"] == "IRB1_1_1_FP_02.rslib"
    assert variant.properties.title == "IRB 1 Foundry Plus" and variant.properties.author == "ABB"
    assert isinstance(marker.component, rswarp.SmartComponent) and marker.properties.revision == "03"
    assert [c.model.name for c in report.children] == ["IRB1_1_1__02"]
    assert [(w.line, w.message) for w in report.warnings] == [
        (11, "Revision 01 disagrees with the revision 02 in the name 'IRB1_1_1__02'")]
    with pytest.warns(rswarp.RsxmlWarning, match="Revision 01 disagrees"):
        assert rswarp.load_library(DATA / "library" / "Robots.xml") == lib


def test_spec_library_file():
    lib = rswarp.load_library(examples.IRB1300_LIBRARY)
    (entry,) = lib.libraries
    assert entry.file_name == "IRB1300_11_90__01.rslib"
    assert entry.properties.title == "IRB1300 11kg 0.90m Standard/IP67/Clean Room"
    assert (entry.properties.author, entry.properties.revision) == ("ABB", "01")


def test_load_refuses_a_library_and_names_the_right_call():
    with pytest.raises(rswarp.RsxmlError, match="use rswarp.load_library"):
        rswarp.load(examples.IRB1300_LIBRARY)
