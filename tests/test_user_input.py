"""Every bad number is a clear error (issue "Hardening the newer surfaces"): no DTD changes a value;
the user's faults are one line and exit 1, never an internal error; every numeric option has its
bound, checked before any work; every file rswarp opens, or that a mesh names, is read as inputs
are; a flood of warnings is counted, not printed; far or huge geometry keeps the collision walks
bounded; reports say what happened."""

from __future__ import annotations

import json
import os
import time

import numpy as np
import pytest
import trimesh

import rswarp
from rswarp.cli import main
from rswarp.options import BOUNDS
from rswarp.sim.cables import CableOptions, simulate_cables

from conftest import DATA

IRB = DATA.parent.parent / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
ID = DATA.parent.parent / "examples" / "irb2600id" / "IRB2600ID_8_200__03.rsxml"
FOLD = DATA / "collisions" / "fold.rsxml"
BAD = DATA / "bad" / "home_outside_limits.rsxml"


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err.strip().splitlines()


# -- DTDs that change the model --------------------------------------------------------------------


@pytest.mark.parametrize("encoding", ["utf-8", "utf-16", "iso-8859-1"])
def test_no_dtd_supplies_or_changes_a_value(tmp_path, encoding):
    """An attribute default, an undeclared entity inside an attribute value, any declaration: an
    error at its line, in every encoding; a comment that mentions them is harmless."""
    text = BAD.read_text().replace("<!-- expect: 19: HomePosition of 'J2' is 120, outside its limits [-90, 90] -->\n", "")
    cases = {
        "default": (text.replace("<Mechanism ", '<!DOCTYPE Mechanism [ <!ATTLIST Limit max CDATA "45"> ]>\n<Mechanism ', 1),
                    1, "the DOCTYPE declares"),
        "reference": (text.replace("<Mechanism ", '<!DOCTYPE Mechanism SYSTEM "x.dtd">\n<Mechanism ', 1)
                      .replace('min="-90" max="90"', 'min="-90" max="9&ext;0"'), 14, "entity reference &ext;"),
        "element": (text.replace("<Mechanism ", "<!DOCTYPE Mechanism [ <!ELEMENT Limit EMPTY> ]>\n<Mechanism ", 1),
                    1, "the DOCTYPE declares"),
    }
    for name, (body, line, says) in cases.items():
        path = tmp_path / f"{name}.rsxml"
        path.write_bytes(f'<?xml version="1.0" encoding="{encoding}"?>\n{body}'.encode(encoding))
        report = rswarp.check(path)
        assert [(d.line, says in d.message) for d in report.errors][:1] == [(line + 1, True)], (name, report.errors)
    quiet = text.replace("<Links", "<!-- &foo; <!ATTLIST Limit max CDATA '45'> -->\n  <Links", 1)
    (tmp_path / "c.rsxml").write_bytes(quiet.encode(encoding))
    assert [d.message for d in rswarp.check(tmp_path / "c.rsxml").errors] == [
        "HomePosition of 'J2' is 120, outside its limits [-90, 90]"]


# -- the user's faults are one line, exit 1 ---------------------------------------------------------


def test_trajectory_csv_faults_name_their_line(tmp_path, capsys):
    """A field over the csv module's limit, bytes that are not UTF-8: ``file:line``, exit 1."""
    big = tmp_path / "big.csv"
    big.write_text("time,J1,J2,J3,J4,J5,J6\n0,0,0,0,0,0,0\n1," + "x" * 200_000 + ",0,0,0,0,0\n")
    bad = tmp_path / "bad.csv"
    bad.write_bytes(b"time,J1,J2,J3,J4,J5,J6\n0,0,0,0,0,0,0\n1,0,0,\xff,0,0,0\n")
    for csv, says in ((big, "field larger than field limit"), (bad, "not UTF-8 text")):
        code, _, err = run(["cable", ID, "--trajectory", csv, "--out", tmp_path / "o"], capsys)
        assert code == 1 and len(err) == 1 and err[0].startswith(f"{csv}:3: ") and says in err[0]


@pytest.mark.parametrize("change, says", [
    (('maxSegmentLength="50"', 'maxSegmentLength="0.001"'), "segments of at most"),
    (('desiredLength="700"', 'desiredLength="1e6"'), "segments of at most"),
])
def test_check_reports_what_a_cable_run_would_refuse(tmp_path, capsys, change, says):
    """A segment count no kernel holds is the cable's error at its line, from ``rswarp check``."""
    path = tmp_path / "h.rsxml"
    path.write_text(ID.read_text().replace(*change))
    code, out, err = run(["check", path], capsys)
    assert code == 1 and says in err[0] and err[0].startswith(f"{path}:") and "FAILED" in out


def test_thousands_of_control_points_are_checked_not_built(tmp_path, capsys):
    points = "".join(f'<ControlPoint position="{k}, 0, 1000"/>' for k in range(10_000))
    text = ID.read_text()
    start, end = text.index("<ControlPoints>"), text.index("</ControlPoints>")
    path = tmp_path / "many.rsxml"
    path.write_text((text[:start] + f"<ControlPoints>{points}" + text[end:]).replace(' desiredLength="700"', ""))
    code, _, err = run(["check", path], capsys)
    assert code == 1 and "a cable takes at most 4000" in err[0]


def test_a_cable_on_a_mechanism_without_joints_runs(tmp_path):
    """A hose hung from a base that never moves: random 'programs' stand still, and it settles."""
    static = tmp_path / "static.rsxml"
    static.write_text('''<?xml version="1.0"?>
<Mechanism xmlns="urn:abb-robotics-robotstudio-graphiccomponent" type="Other" name="Hose" lengthUnit="mm">
  <Links baseLink="Base"><Part name="Base"/></Links>
  <AdditionalComponents>
    <Cable radius="10" maxSegmentLength="50" name="Hose" desiredLength="1200">
      <ControlPoints><ControlPoint attachedTo="Base" position="0, 0, 1000"/>
        <ControlPoint attachedTo="Base" position="1000, 0, 1000"/></ControlPoints>
    </Cable>
  </AdditionalComponents>
  <Joints/>
</Mechanism>''')
    assert main(["cable", str(static), "--random", "--envs", "2", "--seconds", "1", "--out", str(tmp_path / "o")]) == 0
    doc = json.loads((tmp_path / "o" / "report.json").read_text())
    assert [e["status"] for e in doc["cables"][0]["environments"]] == ["ok", "ok"]


@pytest.mark.parametrize("make, says", [
    (lambda: trimesh.creation.box(extents=(1e9, 1e9, 1e9)), "reaches 5e+08 m from the origin"),
    (lambda: trimesh.Trimesh(np.zeros((3, 3)), np.array([[0, 1, 2]]), process=False), "it is flat"),
])
def test_huge_or_degenerate_environment_meshes_are_one_line(tmp_path, capsys, make, says):
    mesh = tmp_path / "env.stl"
    make().export(mesh)
    code, _, err = run(["collisions", FOLD, "--samples", 100, "--out", tmp_path / "o", "--env", f"{mesh}@0,0,0"], capsys)
    assert code == 1 and len(err) == 1 and says in err[0] and not (tmp_path / "o").exists()


def test_a_large_size_limit_allocates_nothing_up_front(capsys):
    """``--max-file-size`` near its bound reads a small file as a small file (no MemoryError)."""
    code, out, _ = run(["--max-file-size", 1 << 19, "check", IRB], capsys)
    assert code == 0 and "OK" in out


# -- unbounded numbers and work ---------------------------------------------------------------------


@pytest.mark.parametrize("argv", [
    ["cable", ID, "--random", "--substeps", "1e8"],
    ["cable", ID, "--random", "--envs", "1e9"],
    ["cable", ID, "--random", "--seconds", "1e12"],
    ["cable", ID, "--random", "--frame-rate", "1e6"],
    ["cable", ID, "--random", "--floor", "1e308"],
    ["cable", ID, "--random", "--floor", "2e6"],  # millimetres: 2 km
    ["build", DATA / "library" / "Robots.xml", "--size", "20000"],
    ["collisions", IRB, "--samples", "1e15"],
    ["collisions", IRB, "--samples", "100", "--env", f"{DATA / 'collisions' / 'room.stl'}@1e308,0,0"],
    ["collisions", IRB, "--samples", "100", "--env", f"{DATA / 'collisions' / 'room.stl'}@2000,0,0"],
    ["export", IRB, "-o", "x.usda", "--drive-hz", "1e308"],
    ["export", IRB, "-o", "x.usda", "--mass", "1e308"],
    ["export", IRB, "-o", "x.urdf", "--density", "1e300"],
])
def test_every_number_is_bounded_before_any_work(tmp_path, capsys, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    started = time.perf_counter()
    if argv[0] in ("cable", "collisions"):
        argv = [*argv, "--out", tmp_path / "o"]
    code, _, err = run(argv, capsys)
    assert code == 1 and len(err) == 1 and time.perf_counter() - started < 20, err
    assert any(says in err[0] for says in ("must be", "a run takes", "out of range", "within 1000 m")), err
    assert list(tmp_path.iterdir()) == []


def test_the_library_checks_the_same_bounds():
    """``CableOptions``, ``PhysicsOptions``, the sweeps: the table's bounds for Python callers too."""
    from rswarp.export.physics import PhysicsOptions

    with pytest.raises(rswarp.InputError, match="substeps must be at most 1000"):
        CableOptions(substeps=10 ** 8)
    with pytest.raises(rswarp.InputError, match="mass must be at most 1e\\+06 kg"):
        PhysicsOptions(mass=1e308)
    with pytest.raises(rswarp.InputError, match="samples must be at most 1e\\+11"):
        rswarp.collisions(rswarp.load(FOLD), samples=10 ** 15)
    assert all(b.high < np.inf or b.length for b in BOUNDS.values())  # every number has its bound


# -- files a mesh names, flooded warnings, far geometry ------------------------------------------------


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_files_a_mesh_names_are_read_as_inputs_are(tmp_path, capsys):
    """A glTF whose buffer is a FIFO (which would hang a plain open) or a file over the limit:
    one line, at once."""
    box = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    box.export(tmp_path / "box.gltf")
    doc = json.loads((tmp_path / "box.gltf").read_text())
    os.mkfifo(tmp_path / "fifo.bin")
    doc["buffers"][0]["uri"] = "fifo.bin"
    (tmp_path / "part.gltf").write_text(json.dumps(doc))
    (tmp_path / "m.rsxml").write_text('''<?xml version="1.0"?>
<Mechanism xmlns="urn:abb-robotics-robotstudio-graphiccomponent" type="Other" name="M">
  <Links baseLink="Base"><Part name="Base" source="part.SAT"/><Part name="L1"/></Links>
  <Joints><Joint name="J1" parent="Base" child="L1" type="Rotational" active="true" point1="0,0,0" point2="0,0,1"/>
  </Joints><Limits><Limit joint="J1" min="-1" max="1"/></Limits>
</Mechanism>''')
    started = time.perf_counter()
    code, _, err = run(["export", tmp_path / "m.rsxml", "-o", tmp_path / "m.usda"], capsys)
    assert code == 1 and "'fifo.bin', which it names: not a regular file" in err[0]
    assert time.perf_counter() - started < 30 and not (tmp_path / "m.usda").exists()


def test_a_flood_of_warnings_is_counted(tmp_path, capsys):
    """100 000 unknown elements: twenty lines and one that counts the rest."""
    text = (DATA / "branching.rsxml").read_text()
    start = text.index("<Links")
    (tmp_path / "f.rsxml").write_text(text[:start] + "<Unknown/>\n" * 100_000 + text[start:])
    code, out, err = run(["check", tmp_path / "f.rsxml"], capsys)
    assert len(err) <= 22 and "99980 more like: unknown element <Unknown> in <Mechanism> ignored" in err[-1]
    assert "100000 warnings" in out


def test_far_and_huge_geometry_keeps_the_walks_bounded(tmp_path):
    """A two-triangle open mesh 1 km across over the robot: the sweep runs in seconds (each body's
    boxes grown by its own size, not the largest body's); a mesh beyond 1 km is refused."""
    s = 499.0
    mesh = trimesh.Trimesh(np.array([[-s, -s, 0.5], [s, -s, 0.5], [0, s, 0.5], [0, 0, 0.5 + s]]),
                           np.array([[0, 1, 2], [0, 1, 3]]), process=False)
    mesh.export(tmp_path / "v.stl")
    from rswarp.sim.bodies import placed_environments

    mech = rswarp.load(IRB)
    started = time.perf_counter()
    c = rswarp.collisions(mech, samples=20_000, environment=placed_environments(mech, [f"{tmp_path / 'v.stl'}@0,0,0"]))
    assert time.perf_counter() - started < 60
    env = [p for p in c.pairs if p.environment]
    assert env and any(p.collisions for p in env)  # the sheet crosses the robot somewhere


# -- reports say what happened -----------------------------------------------------------------------------


def test_a_run_whose_environments_all_stopped_says_so(capsys, tmp_path):
    """Every environment blew up: no 'long enough: 2 of 2', no 'least inf m'."""
    from rswarp.kinematics.trajectory import Trajectory
    from rswarp.report.cables import cables_text

    mech = rswarp.load(DATA / "cables" / "catenary.rsxml")
    jump = Trajectory("jump", np.array([0.0, 0.5, 0.501, 1.0]), np.array([[0.0], [0.0], [np.pi], [np.pi]]))
    text = cables_text(simulate_cables(mech, [jump], envs=2), {})
    carried = text[text.index("Carried:"):]  # the cable on the arm that jumped; the hung one stays put
    assert "no answers: every environment stopped before the end (2 of 2)" in carried, text
    assert "long enough" not in carried and "inf m" not in carried and "nan s" not in carried


def test_env_options_and_addresses_say_what_is_wrong(tmp_path, capsys):
    for spec in ("box.stl", "box.stl@", "@0,0,0", "box.stl@1,2"):
        code, _, err = run(["collisions", FOLD, "--samples", 10, "--out", tmp_path / "o", "--env", spec], capsys)
        assert code == 1 and len(err) == 1 and "give MESH@x,y,z" in err[0], err


def test_bad_input_on_ray_fails_once_on_the_driver(tmp_path, capsys, monkeypatch):
    """A cable model that does not exist, a cable no kernel holds: one line and exit 1, and Ray is
    never asked for anything (no task fails four times to say it)."""
    pytest.importorskip("ray")
    from rswarp.sim import engine

    def refuse(*args, **kwargs):
        raise AssertionError("Ray was asked")

    monkeypatch.setattr(engine, "connect", refuse)
    huge = tmp_path / "h.rsxml"
    huge.write_text(ID.read_text().replace('maxSegmentLength="50"', 'maxSegmentLength="0.01"'))
    for argv in (["cable", ID, "--random", "--cable-model", "rope"], ["cable", huge, "--random"]):
        code, _, err = run([*argv, "--out", tmp_path / "o", "--ray"], capsys)
        assert code == 1 and len(err) == 1, err
    assert not (tmp_path / "o").exists()
