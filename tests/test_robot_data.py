"""Robot data for every bundled robot (issue 48): each robot's file is found beside its RSXML and
read, its axes named as the active joints, speeds, accelerations and jerks above 0 with where each
comes from and which are estimates; the estimates are the rule the file states, recomputed from
the RSXML's geometry; a bad entry is said at its line; URDF and joint_limits.yaml limits say
their accelerations and jerks are rswarp's rule; the program JSON's axis limits carry it all."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from rswarp import examples
from rswarp.errors import RsxmlError
from rswarp.report.output import json_safe
from rswarp.report.program_doc import _limits_dict
from rswarp.rsxml.documents import load_mechanism
from rswarp.rsxml.robot_data import (
    ACCEL_RULE,
    JERK_RULE,
    JERK_S,
    QUANTITIES,
    axis_limits,
    data_file,
    estimated_accelerations,
    read_limits,
    read_robot_data,
    robot_data,
)

from conftest import DATA

LIMITS = DATA / "limits"
ACCEL_TIME = 0.07  # s: the "acceleration time 0-1 m/s" the bundled files' estimates assume
BUNDLED = {  # RSXML: its robot-data file, its speeds (deg/s) and whether it gives the robot's mass
    examples.IRB1300: ("IRB1300_11_90.robot.toml", [280, 228, 330, 500, 415, 720], True),
    examples.IRB2600ID: ("IRB2600ID_8_200.robot.toml", [175, 175, 175, 360, 360, 500], False),
    examples.IRB2600: ("IRB2600_12_165.robot.toml", [175, 175, 175, 360, 360, 500], True),
}


def mech_of(path):
    return load_mechanism(path)[0]


@pytest.mark.parametrize("rsxml", list(BUNDLED), ids=lambda p: p.name)
def test_each_bundled_robot_has_robot_data_with_sourced_limits(rsxml):
    name, speeds, has_mass = BUNDLED[rsxml]
    mech = mech_of(rsxml)
    assert data_file(str(rsxml)).name == name
    data = robot_data(mech)
    limits = data.limits
    assert limits.names == tuple(j.name for j in mech.graph.active)
    np.testing.assert_allclose(np.degrees(limits.velocity), speeds)
    assert (limits.acceleration > 0).all() and (limits.jerks() > 0).all() and limits.jerk is not None
    assert data.payload > 0 and (data.mass is not None) == has_mass and data.source
    assert not limits.assumed and limits.accel_assumed  # speeds published, accelerations not
    assert all(s and s not in (ACCEL_RULE, JERK_RULE) for s in limits.sources())  # the file says, not the rule
    rows = limits.rows()
    assert [r["axis"] for r in rows] == list(limits.names)
    assert all(r["estimated"] == ["acceleration", "jerk"] for r in rows)
    assert all(r["velocity_source"] and r["acceleration_source"].startswith("estimate") for r in rows)
    assert axis_limits(mech).source == name  # the timing's limits are the file's
    assert f"from {name}; accelerations and jerks estimated there" in limits.summary()


@pytest.mark.parametrize("rsxml", list(BUNDLED), ids=lambda p: p.name)
def test_robot_data_estimates_are_the_rule_their_file_states(rsxml):
    """TCP 0-1 m/s in 0.07 s over each arm axis's distance to the flange at the zero pose, the
    wrist at the arm's time to top speed; jerks: the acceleration reached in 0.05 s."""
    mech = mech_of(rsxml)
    limits = robot_data(mech).limits
    accel, jerk = estimated_accelerations(mech, limits.velocity, ACCEL_TIME)
    np.testing.assert_allclose(limits.acceleration, accel, rtol=0.005)  # the file rounds to 1 deg/s^2
    np.testing.assert_allclose(limits.jerks(), limits.acceleration / JERK_S, rtol=1e-9)
    np.testing.assert_allclose(jerk, accel / JERK_S)


@pytest.mark.parametrize("rsxml", list(BUNDLED), ids=lambda p: p.name)
def test_bundled_accelerations_say_they_rest_on_an_assumption_and_give_no_cycle_time(rsxml):
    """No published acceleration or standard cycle time was found for the bundled robots (issue
    59): each file says its 0.07 s is an assumption, not a recollection of ABB's figures, and gives
    no ABB cycle time rather than one from memory."""
    data = robot_data(mech_of(rsxml))
    text = data_file(str(rsxml)).read_text()
    assert data.standard_cycle is None and "standard_cycle_s =" not in text
    assert "an assumption" in data.limits.sources()[1] and "from memory" not in text
    assert data.limits.estimates()[:, 1:].all()  # accel_estimated, jerk_estimated: true


def _cycle_file(tmp_path, *lines: str) -> tuple:
    """A copy of the IRB 2600's RSXML beside a robot-data file whose top (before [axes]) holds
    ``lines``: the 2nd line on."""
    folder = tmp_path / "cycle"
    folder.mkdir(parents=True)
    shutil.copy(examples.IRB2600, folder / examples.IRB2600.name)
    text = ['source = "test"', *lines, "", "[axes]", 'names = ["J1", "J2", "J3", "J4", "J5", "J6"]',
            "speed_deg_s = [175, 175, 175, 360, 360, 500]"]
    path = folder / "IRB2600_12_165.robot.toml"
    path.write_text("\n".join(text) + "\n")
    return path, mech_of(folder / examples.IRB2600.name)


def test_a_published_standard_cycle_time_is_read_with_its_load_and_source(tmp_path):
    path, mech = _cycle_file(tmp_path, "standard_cycle_s = 0.45", "standard_cycle_kg = 1",
                             'standard_cycle_source = "ABB data sheet, 1 kg picking cycle 25 x 300 x 25 mm"')
    cycle = read_robot_data(str(path), mech).standard_cycle
    assert (cycle.seconds, cycle.load_kg) == (0.45, 1.0) and cycle.source.startswith("ABB data sheet")
    path, mech = _cycle_file(tmp_path / "none")  # none given: None, no error
    assert read_robot_data(str(path), mech).standard_cycle is None


@pytest.mark.parametrize("lines, line, message", [
    (["standard_cycle_s = -0.4", "standard_cycle_kg = 1", 'standard_cycle_source = "x"'], 2,
     "standard_cycle_s must be a number of seconds above 0"),
    (['standard_cycle_s = "0.4 s"', "standard_cycle_kg = 1", 'standard_cycle_source = "x"'], 2,
     "standard_cycle_s must be a number of seconds above 0"),
    (["standard_cycle_s = true", "standard_cycle_kg = 1", 'standard_cycle_source = "x"'], 2,
     "standard_cycle_s must be a number of seconds above 0"),
    (["standard_cycle_kg = 1", "standard_cycle_s = 0.4"], 3,
     "standard_cycle_s needs standard_cycle_source: the document ABB's figure comes from"),
    (["standard_cycle_s = 0.4", 'standard_cycle_source = "x"'], 2,
     "standard_cycle_s needs standard_cycle_kg: the load ABB's figure is for (kg)"),
    (["standard_cycle_s = 0.4", "standard_cycle_kg = 0", 'standard_cycle_source = "x"'], 3,
     "standard_cycle_kg must be a number above 0"),
    (["standard_cycle_s = 0.4", "standard_cycle_kg = 1", 'standard_cycle_source = " "'], 4,
     "standard_cycle_source must be text"),
    (['standard_cycle_source = "ABB data sheet"'], 2, "standard_cycle_source without standard_cycle_s"),
])
def test_a_bad_standard_cycle_entry_is_said_at_its_line(tmp_path, lines, line, message):
    path, mech = _cycle_file(tmp_path, *lines)
    with pytest.raises(RsxmlError) as exc:
        read_robot_data(str(path), mech)
    assert str(exc.value).startswith(f"{path}:{line}: ") and message in str(exc.value)


def test_a_standard_cycle_written_under_axes_is_refused_at_its_line(tmp_path):
    """Appended at the end of a file, after [axes], TOML puts the key in that table: said, not
    silently dropped."""
    path, mech = _bad_file(tmp_path, "standard_cycle_s = 0.45")
    with pytest.raises(RsxmlError) as exc:
        read_robot_data(str(path), mech)
    assert str(exc.value) == f"{path}:8: standard_cycle_s is in [axes]: it belongs at the top of the file, " \
                             "before [axes]"


def _bad_file(tmp_path, line: str) -> tuple:
    """A copy of the IRB 2600's RSXML beside a robot-data file with ``line`` as its 8th line."""
    folder = tmp_path / "robot"
    folder.mkdir()
    shutil.copy(examples.IRB2600, folder / examples.IRB2600.name)
    text = ['source = "test"', "", "[axes]", 'names = ["J1", "J2", "J3", "J4", "J5", "J6"]',
            "speed_deg_s = [175, 175, 175, 360, 360, 500]", "accel_deg_s2 = [795, 682, 922, 1404, 1404, 1950]",
            "# a comment that names jerk_deg_s3 and accel_estimated before the line", line]
    path = folder / "IRB2600_12_165.robot.toml"
    path.write_text("\n".join(text) + "\n")
    return path, mech_of(folder / examples.IRB2600.name)


@pytest.mark.parametrize("line, message", [
    ("jerk_deg_s3 = [1, 2, 3, 4, 5, -6]", "jerk_deg_s3 must be a list of numbers above 0"),
    ('jerk_deg_s3 = [1, 2, "fast", 4, 5, 6]', "jerk_deg_s3 must be a list of numbers above 0"),
    ("jerk_deg_s3 = [1, 2, 3]", "jerk_deg_s3 has 3 values for 6 names"),
    ("jerk_deg_s3 = [1, 2, 3, 4, 5, true]", "jerk_deg_s3 must be a list of numbers above 0"),  # TOML's true is no 1
    ('accel_estimated = "yes"', "accel_estimated must be true or false"),
    ("jerk_source = 3", "jerk_source must be text"),
])
def test_a_bad_robot_data_entry_is_said_at_its_line(tmp_path, line, message):
    path, mech = _bad_file(tmp_path, line)
    with pytest.raises(RsxmlError) as exc:
        read_robot_data(str(path), mech)
    assert str(exc.value).startswith(f"{path}:8: ") and message in str(exc.value)


def test_robot_data_without_jerks_or_accelerations_falls_back_to_the_rule(tmp_path):
    path, mech = _bad_file(tmp_path, "")
    limits = read_robot_data(str(path), mech).limits
    assert limits.jerk is None and not limits.accel_assumed  # accelerations given, no word they are estimates
    assert limits.sources()[1:] == ("test", JERK_RULE)
    np.testing.assert_allclose(limits.jerks(), limits.acceleration / JERK_S)
    assert "accelerations given there, jerks assumed (top acceleration in 0.05 s)" in limits.summary()
    path.write_text(path.read_text().replace("accel_deg_s2", "#"))
    limits = read_robot_data(str(path), mech).limits
    assert limits.accel_assumed and limits.sources()[1] == ACCEL_RULE
    assert limits.rows()[0]["estimated"] == ["acceleration", "jerk"]


def test_urdf_and_yaml_limits_say_their_accelerations_and_jerks_are_the_rule():
    mech = mech_of(examples.IRB2600)
    urdf = read_limits(str(LIMITS / "irb2600_12_165.urdf"), mech)
    assert urdf.jerk is None and urdf.names == ("J1", "J2", "J3", "J4", "J5", "J6")
    assert urdf.sources() == ("irb2600_12_165.urdf", ACCEL_RULE, JERK_RULE)
    assert all(r["estimated"] == ["acceleration", "jerk"] for r in urdf.rows())
    assert "accelerations assumed (top speed in 0.25 s), jerks assumed" in urdf.summary()
    yaml = read_limits(str(LIMITS / "joint_limits.yaml"), mech)  # accelerations on joints 1 and 2 only
    assert [r["estimated"] for r in yaml.rows()][:3] == [["jerk"], ["jerk"], ["acceleration", "jerk"]]
    assert "joint_limits.yaml where given" in yaml.sources()[1]
    assert "accelerations partly assumed (top speed in 0.25 s)" in yaml.summary()
    np.testing.assert_allclose(yaml.jerks(), yaml.acceleration / JERK_S)


def test_the_default_limits_say_every_quantity_is_assumed(tmp_path):
    shutil.copy(examples.IRB2600, tmp_path / examples.IRB2600.name)
    limits = axis_limits(mech_of(tmp_path / examples.IRB2600.name))
    assert limits.assumed and limits.names[0] == "J1"
    assert all(r["estimated"] == list(QUANTITIES) for r in limits.rows())
    assert "assumed 90 deg/s" in limits.summary()


def test_the_program_json_gives_the_axis_limits_per_axis():
    limits = axis_limits(mech_of(examples.IRB1300))
    doc = json.loads(json.dumps(json_safe(_limits_dict(limits))))
    assert {"source", "assumed", "accelerations_assumed", "velocity", "acceleration", "summary"} <= set(doc)
    assert doc["jerk"] == pytest.approx(list(limits.jerks())) and len(doc["axes"]) == 6
    first = doc["axes"][0]
    assert first["axis"] == "J1" and first["velocity"] == pytest.approx(np.radians(280))
    assert set(first) == {"axis", "velocity", "acceleration", "jerk", "velocity_source", "acceleration_source",
                          "jerk_source", "estimated"}
