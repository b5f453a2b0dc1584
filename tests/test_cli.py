"""The command line: exit codes, readable and JSON output, and no traceback for bad input."""

import json
import subprocess
import sys

import pytest

import rswarp
from rswarp import examples
from rswarp.cli import main

from conftest import DATA


def test_check_clean_file(capsys):
    assert main(["check", str(examples.IRB1300), str(examples.IRB2600)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out == [f"{examples.IRB1300}: OK (Mechanism; 0 errors, 0 warnings)",
                   f"{examples.IRB2600}: OK (Mechanism; 0 errors, 0 warnings)"]


def test_check_prints_warnings_and_still_passes(capsys):
    assert main(["check", str(DATA / "naming.rsxml")]) == 0
    out = capsys.readouterr().err
    assert f"{DATA / 'naming.rsxml'}:3: warning: name 'MyRobot' does not follow" in out


def test_check_fails_on_any_bad_file(capsys):
    bad = DATA / "bad" / "home_outside_limits.rsxml"
    assert main(["check", str(examples.IRB1300), str(bad)]) == 1
    out = capsys.readouterr().err
    assert f"{bad}:19: HomePosition of 'J2' is 120, outside its limits [-90, 90]" in out


def test_check_json(capsys):
    bad = DATA / "bad" / "unknown_child.rsxml"
    assert main(["check", "--json", str(bad)]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["ok"] is False
    assert {"file": str(bad), "line": 10, "message": "joint 'J2' child 'Link3' is not a link"} in doc["files"][0]["errors"]


def test_info_text_is_in_file_units(capsys):
    assert main(["info", str(examples.IRB2600ID)]) == 0
    out = capsys.readouterr().out
    assert "units mm and deg, 6 axes" in out
    assert "(1088, 0, 1495) -> (1088, 1, 1495)" in out and "-120 deg" in out
    assert "Cable Hose: radius 25 mm, segments <= 50 mm, colour (32, 32, 32)" in out


def test_info_json_is_si_and_snake_case(capsys):
    assert main(["info", "--json", str(examples.IRB2600ID)]) == 0
    doc = json.loads(capsys.readouterr().out)
    model = doc["model"]
    assert model["model_name"] == "IRB2600ID_8_200" and model["dof"] == 6
    j5 = model["joints"][4]
    assert j5["point1"] == [1.088, 0.0, 1.495] and abs(j5["limits"][1] - 2.0943951023931957) < 1e-12
    assert abs(model["home_position"][4] - 0.5235987755982988) < 1e-12
    assert model["cables"][0]["radius"] == 0.025 and model["cables"][0]["max_segment_length"] == 0.05

    def keys(obj):
        if isinstance(obj, dict):
            for k, v in obj.items():
                yield k
                yield from keys(v)
        elif isinstance(obj, list):
            for v in obj:
                yield from keys(v)

    assert all(k == k.lower() for k in keys(doc))


def test_info_smart_component_and_library(capsys):
    assert main(["info", str(DATA / "smart" / "Counter.rsxml")]) == 0
    out = capsys.readouterr().out
    assert "Counter: SmartComponent - Counts rising edges." in out
    assert "code-behind Counter.CodeBehind,Counter.dll (named only" in out
    assert "Increment  DigitalInput   Adds one on a rising edge." in out
    assert main(["info", "--json", str(DATA / "library" / "Robots.xml")]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [lib["file_name"] for lib in doc["model"]["libraries"]] == ["IRB1_1_1__02.rslib", "Marker.rslib"]
    assert doc["sources"][0]["model"]["name"] == "IRB1_1_1__02"


def test_info_on_bad_file_is_one_line_per_problem(capsys):
    bad = DATA / "bad" / "coincident_axis_points.rsxml"
    assert main(["info", str(bad)]) == 1
    err = capsys.readouterr().err.splitlines()
    assert err == [f"{bad}:10: point1 and point2 coincide: the joint has no axis"]


def test_demo_runs_on_the_bundled_examples(capsys, demo_run):
    tmp_path, code, out = demo_run  # the session's one run of the demo (conftest.py)
    assert code == 0
    for path in examples.ALL:
        assert f"== rswarp check {path.name}" in out
    assert "Cable Hose" in out and "link_6.stl" in out
    assert "== IRB1300_11_90__01: flange at home" in out and "reach 901.9 mm" in out
    assert "reach 1999.9 mm" in out and "reach 1.6533 m" in out and "reach 2396.2 mm (J1 axis to flange" in out
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["meshes", "library", "IRB2600_12_165__01-collisions",
                                                                 "IRB2600ID_8_200__03-cables", ".rswarp.json",
                                                                 "IRB2600_12_165__01-pick_place.csv",
                                                                 "IRB2600_12_165__01-service.csv",
                                                                 "IRB2600_12_165__01-cell.csv",
                                                                 "IRB2600_12_165__01-service.gif", "dresspack-program",
                                                                 "dresspack-program.gif", "dresspack-random",
                                                                 "dresspack-random.gif", "dresspack-sweep", "cells", "place"] + [
        f"{n}.{e}" for n in ("IRB1300_11_90__01", "IRB2600ID_8_200__03", "IRB2600_12_165__01", "IRB9460_110_240__01")
        for e in ("urdf", "srdf", "usdc")])
    assert "matrix disables 6 adjacent, 1 default, 0 always" in out
    assert "cables (16 random programs, free of the floor and the robot itself, 4 s; no meshes" in out
    assert "bend radius: least" in out
    assert "program pick_place.mod" in out and "program service.mod" in out
    assert out.count("standard cycle 25 x 300 x 25 mm with 1 kg") == 3  # the three 6-axis arms, their robot data
    assert "from IRB1300_11_90.robot.toml" in out and "from IRB2600ID_8_200.robot.toml" in out
    assert "task cell/ (3 modules, rswarp program)" in out and "one pass of the main loop at MainModule.mod:10" in out
    assert "line 18: fail: tool Gripper 335 mm below the floor" in out  # the service draft's finding, its tool lowest
    assert "program pick_place.mod (rswarp program, with --tool irb2600_12_165/gripper/Gripper.rsxml)" in out
    assert "== dress pack: IRB2600_12_165_DressPack_01.rsxml" in out and "rubs on Link4" in out
    assert "no meshes ship with this robot, so its hose meets only the floor" in out
    assert "dresspack: 32 designs of cable 'ProcessHose'" in out and "the shortest hose that passes" in out
    assert (tmp_path / "dresspack-sweep" / "best.rsxml").is_file()
    assert "== cell track_cell.toml: track_transfer.mod" in out and "eax_a 3200" in out
    assert "== cell positioner_cell.toml: positioner_weld.mod" in out and "eax_a 20, eax_b 90" in out
    assert "== cell multimove_cell.toml: each robot's task of the backup multimove/" in out
    assert "WaitSyncTask sync_ready at 0.98 s" in out and "robots against each other: no link of one meets" in out
    assert "== place: where IRB2600_12_165__01.rsxml should stand for its palletizing task" in out
    assert "75 bases tried against 27 poses of 73 moves" in out and (tmp_path / "place" / "best.toml").is_file()
    assert "== cell track_dresspack_cell.toml: the dress pack over track_transfer.mod" in out
    assert sorted(p.name for p in (tmp_path / "cells").iterdir()) == sorted([".rswarp.json", "track-dresspack"] + [
        f"{c}-{m}.{e}" for c, m in (("track_cell", "track_transfer"), ("positioner_cell", "positioner_weld"))
        for e in ("csv", "gif")])
    assert (tmp_path / "IRB2600ID_8_200__03-cables" / "report.json").is_file()
    assert (tmp_path / "IRB2600_12_165__01-collisions" / "collision_matrix.srdf").is_file()
    assert (tmp_path / "meshes" / "IRB2600_12_165__01" / "Link6.stl").is_file()  # each robot its own meshes
    assert sorted(p.name for p in (tmp_path / "library").iterdir()) == [
        ".rswarp.json", "IRB1300_11_90__01.usdz", "IRB2600_12_165__01.png", "IRB2600_12_165__01.usdz"]
    assert "== rswarp build IRB2600_12_165.xml: 1 of 1 built" in out and "1 with a preview" in out
    assert main(["demo", "--json", "--out", str(tmp_path)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["ok"] is True and [round(r["reach"], 4) for r in doc["robots"]] == [0.9019, 1.9999, 1.6533, 2.3962]


def test_console_script_gives_no_traceback():
    """The installed entry point, in a fresh process, on a file that is not XML at all."""
    bad = DATA / "bad" / "empty_file.rsxml"
    proc = subprocess.run([sys.executable, "-m", "rswarp.cli", "info", str(bad)], capture_output=True, text=True)
    assert proc.returncode == 1
    assert proc.stderr == f"{bad}:1: XML syntax error: Document is empty\n" and proc.stdout == ""


def test_version():
    assert rswarp.__version__


def test_fk_in_file_units(capsys):
    assert main(["fk", str(examples.IRB1300), "--q", "0,0,0,0,90,0"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[2].split() == ["frame", "x", "[mm]", "y", "[mm]", "z", "[mm]", "rx", "[deg]", "ry", "[deg]", "rz", "[deg]",
                              "q1", "q2", "q3", "q4"]  # under two lines that say what a frame is
    flange = next(line for line in out if line.startswith("flange wrist")).split()
    assert [float(v) for v in flange[2:5]] == [475, 0, 919]  # analytic: J5 turns the 90 mm offset down


def test_fk_json_is_si(capsys):
    assert main(["fk", str(examples.IRB2600), "--q", "90, 0, 0, 0, 0, 0", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["q"][0] == 1.5707963267948966
    x, y, z = doc["flanges"]["wrist"]["position"]
    assert abs(x) < 1e-6 and abs(y - 1.03) < 1e-6 and abs(z - 1.26) < 1e-6


def test_fk_bad_joint_values(capsys):
    assert main(["fk", str(examples.IRB1300), "--q", "0,0,0"]) == 1
    assert capsys.readouterr().err == "rswarp: --q needs 6 values (J1, J2, J3, J4, J5, J6), got '0,0,0'\n"
    assert main(["fk", str(examples.IRB1300), "--q", "-90,0,0,0,0,0"]) == 0  # a leading '-' is a value
    capsys.readouterr()
    assert main(["fk", str(examples.IRB1300), "--q", "0,200,0,0,0,0"]) == 0
    assert "rswarp: warning: J2 = 200 is outside its limits [-100, 130]" in capsys.readouterr().err


def _cuda_available() -> bool:
    import warp as wp

    return wp.is_cuda_available()


@pytest.mark.skipif(_cuda_available(), reason="this machine has CUDA: the error path cannot happen")
def test_unavailable_device_is_one_line(capsys):
    assert main(["fk", str(examples.IRB1300), "--q", "0,0,0,0,0,0", "--device", "cuda"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("rswarp: device 'cuda' is not available here") and err.count("\n") == 1


GOOD_MECHANISMS = sorted(p for p in (DATA.glob("*.rsxml")) if p.name not in ("warnings.rsxml",)) + [
    DATA / "meshes" / "Cell.rsxml", DATA / "smart" / "Positioner.rsxml", *examples.ALL]


@pytest.mark.parametrize("path", GOOD_MECHANISMS, ids=lambda p: p.name)
def test_every_command_ends_cleanly_on_every_good_file(path, tmp_path, capsys):
    """fk, sweep and export on every good input: a result (0) or a one-line refusal (1), never an
    internal error (2) or a traceback."""
    report = rswarp.check(path)
    mech = report.model
    runs = [["export", str(path), "-o", str(tmp_path / "x.usda")], ["export", str(path), "-o", str(tmp_path / "x.urdf")],
            ["export", str(path), "-o", str(tmp_path / "x.usdz"), "--layout", "component"]]
    if isinstance(mech, rswarp.Mechanism):
        home = ",".join(str(v / mech.joint_factor(j)) for v, j in zip(mech.home_position(), mech.active_joints))
        runs += [["fk", str(path), "--q", home or "0"], ["sweep", str(path), "--samples", "50", "--out", str(tmp_path / "s")]]
    for argv in runs:
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse or a one-line refusal
            code = 1 if str(exc).startswith("rswarp:") else exc.code
        captured = capsys.readouterr()
        assert code in (0, 1), (argv, captured.err)
        assert "Traceback" not in captured.err and "internal error" not in captured.err
