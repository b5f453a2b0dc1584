"""The newest surfaces as a careless or hostile user meets them (issue "Hardening the newest
surfaces"): files of the user's never touched (a .rswarp.json of their own), videos written whole
or not at all and their options checked before any work, signals ending a run as 130/143 with no
partial file, poses that are not rigid transforms refused by the IK API, hoses at rest, and
messages that blame what is at fault."""

from __future__ import annotations

import fcntl
import json
import os
import pty
import signal
import struct
import subprocess
import sys
import termios
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

import rswarp
from rswarp.cli import main
from rswarp.errors import InputError
from rswarp.examples import IRB2600, IRB2600_DRESSPACK, IRB2600_PROGRAM

from conftest import DATA

CABLE = DATA / "cable.rsxml"


def test_a_users_own_rswarp_json_keeps_rswarp_out_of_its_folder(tmp_path, capsys):
    for name, text in (("notes", "my notes\n"), ("json", '{"files": {}}\n')):
        out = tmp_path / name
        out.mkdir()
        (out / ".rswarp.json").write_text(text)
        assert main(["sweep", str(IRB2600), "--samples", "100", "--out", str(out)]) == 1
        assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--csv", str(out / "t.csv")]) == 1
        assert (out / ".rswarp.json").read_text() == text and sorted(p.name for p in out.iterdir()) == [".rswarp.json"]
        assert "is not rswarp's manifest" in capsys.readouterr().err
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--csv", str(tmp_path / ".rswarp.json")]) == 1
    assert "is the name of rswarp's manifest" in capsys.readouterr().err
    assert not (tmp_path / ".rswarp.json").exists()


@pytest.mark.parametrize("video, extra, message", [
    ("{tmp}/folder.gif/", [], "is a folder"),
    ("{tmp}/missing/run.gif", [], "does not exist"),
    ("{tmp}/file.txt/run.gif", [], "is a file, not a folder"),
    ("{tmp}/run.avi", [], "name a .gif or .mp4 file"),
    (None, ["--video-env", "0"], "--video-env needs --video"),
    ("{tmp}/run.gif", ["--video-env", "5"], "--video-env must be 0 to 1"),
])
def test_video_options_are_refused_before_any_work(tmp_path, capsys, video, extra, message):
    (tmp_path / "folder.gif").mkdir()
    (tmp_path / "file.txt").write_text("x")
    args = ["cable", str(CABLE), "--random", "--envs", "2", "--seconds", "0.5", "--out", str(tmp_path / "run")]
    args += (["--video", video.format(tmp=tmp_path).rstrip("/")] if video else []) + extra
    start = time.perf_counter()
    assert main(args) == 1
    assert message in capsys.readouterr().err
    assert not (tmp_path / "run").exists() and time.perf_counter() - start < 10  # no run was made


def test_a_video_in_the_runs_folder_is_rswarps_on_a_rerun_and_written_whole(tmp_path, monkeypatch):
    args = ["cable", str(CABLE), "--random", "--envs", "1", "--seconds", "0.3", "--out", str(tmp_path / "run"),
            "--video", str(tmp_path / "run" / "run.gif")]
    assert main(args) == 0 and main(args) == 0
    assert (tmp_path / "run" / "run.gif").stat().st_size > 0
    from rswarp.sim import video

    frames = np.zeros((2, 16, 16, 3), np.uint8)
    target = tmp_path / "v.gif"
    target.write_bytes(b"earlier video")

    def broken(path, *a, **k):
        open(path, "wb").write(b"half a vid")
        raise KeyboardInterrupt

    monkeypatch.setattr("imageio.v3.imwrite", broken)
    with pytest.raises(KeyboardInterrupt):
        video.write_video(target, frames, 10.0)
    assert target.read_bytes() == b"earlier video" and [p.name for p in tmp_path.iterdir() if p.name != "run"] == \
        ["v.gif"]


def _until_progress(fd: int) -> bytes:
    """Read a run's stderr (``fd``, a terminal's: bars are drawn only there) until a progress bar
    shows (or it ends), and return what was read."""
    err = b""
    while b"%|" not in err:
        chunk = _read(fd)
        if not chunk:
            break
        err += chunk
    return err


def _read(fd: int) -> bytes:
    try:
        return os.read(fd, 4096)
    except OSError:  # the terminal's other end closed: the run ended
        return b""


@pytest.mark.parametrize("command", [
    ["program", str(IRB2600), str(DATA / "rapid" / "real" / "palletizer.mod"), "--csv", "{tmp}/t.csv"],
    ["cable", str(IRB2600_DRESSPACK), "--program", str(IRB2600_PROGRAM), "--envs", "2", "--out", "{tmp}/run"],
])
def test_ctrl_c_and_sigterm_end_a_run_as_130_and_143_with_no_partial_file(tmp_path, command):
    # A signal that lands while Python finalizes meets the default action: killed by it, which a
    # shell reports as 128 + the signal, as it does 130 and 143.
    for sig, codes in ((signal.SIGINT, (130, -signal.SIGINT)), (signal.SIGTERM, (143, -signal.SIGTERM))):
        args = [a.format(tmp=tmp_path) for a in command]
        terminal, stderr = pty.openpty()
        fcntl.ioctl(stderr, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))  # a terminal 100 wide
        p = subprocess.Popen([sys.executable, "-m", "rswarp.cli", *args], stdout=subprocess.DEVNULL, stderr=stderr)
        os.close(stderr)
        err = _until_progress(terminal)  # the run is under way: its first progress bar is drawn
        p.send_signal(sig)
        p.wait(timeout=120)
        while chunk := _read(terminal):
            err += chunk
        os.close(terminal)
        assert p.returncode in (*codes, 0), err.decode()[-500:]  # 0: it finished before the signal came
        assert b"Traceback" not in err and b"Segmentation" not in err
        assert not [f for f in tmp_path.rglob("*") if f.name.endswith(".tmp") or ".tmp." in f.name]


@pytest.mark.parametrize("pose, message", [
    (np.diag([2.0, 2.0, 2.0, 1.0]), "not orthonormal"),
    (np.diag([0.0, 0.0, 0.0, 1.0]), "not orthonormal"),
    (np.diag([1.0, 1.0, -1.0, 1.0]), "a mirror, not a rotation"),
    (np.array([[1, 0.3, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]), "not orthonormal"),
    (np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0.1, 0, 0, 1.0]]), "bottom row"),
    (np.full((4, 4), np.nan), "not finite"),
    (np.zeros((4, 4, 2)), r"must have the shape \(4, 4\) or \(N, 4, 4\)"),
    (np.eye(4) * (1 + 1j), "must hold real numbers, not complex128"),
    (np.full((4, 4), "a", dtype=object), "must hold real numbers"),
])
def test_ik_refuses_what_is_not_a_pose_and_says_why(pose, message):
    kin = rswarp.Kinematics(rswarp.load(IRB2600))
    for solve in (kin.ik64, kin.ik, kin.solutions64):
        with pytest.raises(InputError, match=message):
            solve(pose)
    if pose.shape == (4, 4) and pose.dtype == np.float64:  # a pose of its own, named
        good = kin.flange(np.zeros((1, 6))).astype(np.float64)
        with pytest.raises(InputError, match="pose 1 of 2"):
            kin.ik64(np.stack([good[0], pose]))


@pytest.mark.parametrize("x", [1e3 + 1, 1e19, 1e20, 3e38, 1e39, 1e300])
def test_a_pose_far_beyond_reach_is_out_of_reach_in_float32_and_float64(x):
    """float32's squares overflow past 1e19 m: a closed form read noise as solutions there."""
    kin = rswarp.Kinematics(rswarp.load(IRB2600))
    pose = np.eye(4)
    pose[0, 3] = x
    for solve in (kin.ik, kin.ik64):
        assert (solve(pose).status == 1).all()  # ik.NO_REACH
        assert not solve(pose, conf=[0, 0, 0, 0])[1].any()


def test_a_hose_at_rest_on_a_robot_that_never_moves(tmp_path, capsys):
    """One segment asked for between two clamps (a huge maxSegmentLength), with and without a
    floor: the clamps hold about the hose's weight, not kilonewtons, nothing is crushed, and
    without a floor there is no floor clearance."""
    text = CABLE.read_text().replace('maxSegmentLength="40"', 'maxSegmentLength="5000"').replace(
        '        <ControlPoint position="0, 150, 500"/>\n', "")
    robot = tmp_path / "one.rsxml"
    robot.write_text(text)
    still = tmp_path / "still.csv"
    still.write_text("time,J1\n0,0\n2,0\n")
    for extra in ([], ["--no-floor"]):
        out = tmp_path / f"run{len(extra)}"
        assert main(["cable", str(robot), "--trajectory", str(still), "--envs", "1", "--out", str(out), "--json",
                     *extra]) == 0
        cable = json.loads(capsys.readouterr().out)["cables"][0]
        assert cable["summary"]["stopped"] == 0
        assert max(cable["summary"]["clamp_force_N"]) < 5 * cable["weight_N"]  # not kilonewtons
        assert ("floor" in cable["environments"][0]["clearance"]) == (not extra)
    soft = tmp_path / "soft.rsxml"
    soft.write_text(CABLE.read_text().replace('youngsModulus="2e7"', 'youngsModulus="1e-20"'))
    assert main(["check", str(soft)]) == 1
    assert "youngsModulus must be 100000 to 1e+13 Pa" in capsys.readouterr().err


def test_a_hose_whose_rest_shape_crosses_a_link_is_refused_at_its_line(tmp_path, capsys):
    """The dress pack's routing point over the upper arm taken out: the span between the clamps,
    bowed down to its length, runs through the arm. The run used to stop at its first frame and
    blame the trajectory for a crush on a robot that never moved."""
    text = IRB2600_DRESSPACK.read_text().replace('<ControlPoint position="0.72, 0, 1.67"/>', "")
    assert text != IRB2600_DRESSPACK.read_text()
    robot = tmp_path / "unrouted.rsxml"
    robot.write_text(text)
    for mesh in IRB2600_DRESSPACK.parent.iterdir():  # the meshes beside it, by their relative sources
        if mesh.suffix != ".rsxml":
            (tmp_path / mesh.name).symlink_to(mesh)
    still = tmp_path / "still.csv"
    still.write_text("time,J1,J2,J3,J4,J5,J6\n0,0,0,0,0,30,0\n2,0,0,0,0,30,0\n")
    assert main(["cable", str(robot), "--trajectory", str(still), "--envs", "1", "--out", str(tmp_path / "run")]) == 1
    err = capsys.readouterr().err.strip()
    line = 1 + text[:text.index("<Cable ")].count("\n")
    assert err.startswith(f"{robot}:{line}: cable 'ProcessHose' at rest lies ") and "deep in 'Link" in err
    assert "between control points 1 and 2" in err and "add a ControlPoint" in err and "\n" not in err
    assert not (tmp_path / "run").exists()


def test_trajectories_that_last_no_time_or_too_long_are_said_as_such(tmp_path, capsys):
    for rows, message in (("0,0\n", "lasts 0 s (one row)"), ("0,0\n1e9,0\n", "lasts 1e+09 s, longer than a run"),
                          ("0,0\n86400,0\n", "t.csv: the trajectory lasts 86400 s; 86400 s at 60 frames per second")):
        csv = tmp_path / "t.csv"
        csv.write_text("time,J1\n" + rows)
        assert main(["cable", str(CABLE), "--trajectory", str(csv), "--envs", "1", "--out", str(tmp_path / "r")]) == 1
        err = capsys.readouterr().err
        assert message in err and "--seconds must" not in err


def test_a_missing_env_mesh_is_blamed_on_the_mesh(tmp_path, capsys):
    missing = tmp_path / "nothere.stl"
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--env", f"{missing}@0,0,0"]) == 1
    err = capsys.readouterr().err
    assert "nothere.stl" in err and "this robot has none" not in err
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--floor", "1e31"]) == 1
    assert "--floor must be within 1000 m" in capsys.readouterr().err


@pytest.mark.parametrize("robax, message", [
    ("0,1E30,0,0,30,0", "the robax of 'j' holds 1e+30, beyond 100000"),
    ("0,9E9,0,0,30,0", "'j' leaves J2 unset (9E9)"),
    ("0,-9E+09,0,0,30,0", "'j' leaves J2 unset (9E9)"),
])
def test_a_joint_value_too_large_is_not_called_unset(tmp_path, capsys, robax, message):
    path = tmp_path / "j.mod"
    path.write_text(f"MODULE J\n  CONST jointtarget j:=[[{robax}],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC main()\n"
                    "    MoveAbsJ j, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n")
    assert main(["program", str(IRB2600), str(path)]) == 1
    assert f"j.mod:4: MoveAbsJ: {message}" in capsys.readouterr().err


def test_a_csv_into_a_missing_folder_is_refused_before_any_work(tmp_path, capsys, monkeypatch):
    import rswarp.report.program as program

    monkeypatch.setattr(program, "plan_on", lambda *a, **k: pytest.fail("planned before the check"))
    out = tmp_path / "nodir" / "o.csv"
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--csv", str(out)]) == 1
    assert f"{out}: {out.parent} does not exist" in capsys.readouterr().err
    (tmp_path / "file").write_text("mine")
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--csv", str(tmp_path / "file" / "o.csv")]) == 1
    assert "is a file, not a folder" in capsys.readouterr().err


def test_copies_of_ray_workers_that_are_gone_are_swept(tmp_path, monkeypatch):
    """Ray ends its workers without their atexit handlers: the next worker removes their copies."""
    import tempfile

    from rswarp.sim import package

    monkeypatch.setattr(tempfile, "gettempdir", lambda: str(tmp_path))
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    gone = tmp_path / f"rswarp-0123456789abcdef-{dead.pid}-x1"
    alive = tmp_path / f"rswarp-0123456789abcdef-{os.getpid()}-x2"
    mine = tmp_path / "rswarp-notes"
    for folder in (gone, alive, mine):
        folder.mkdir()
    package._sweep_dead_workers()
    assert not gone.exists() and alive.exists() and mine.exists()


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_while_python_shuts_down_is_130_or_143_not_a_traceback(sig, code):
    """After main is done (threads joined, exit handlers run) a Ctrl-C used to escape as -2."""
    script = ("import atexit, os, time\nimport rswarp.cli as cli\ncli.main = lambda: 0\n"
              f"atexit.register(lambda: (os.kill(os.getpid(), {int(sig)}), time.sleep(5)))\nprint('out')\ncli.run()\n")
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=60)
    assert p.returncode == code and p.stdout == b"out\n" and b"Traceback" not in p.stderr


def test_a_ctrl_c_a_library_swallows_still_ends_the_run_with_130_and_no_output(tmp_path):
    """trimesh catches every exception around its optional imports, KeyboardInterrupt too: a
    Ctrl-C then used to be lost, and the run ended 0 with all its outputs."""
    csv = tmp_path / "t.csv"
    script = ("import os, signal, time\nimport rswarp.cli as cli\ncall = cli._call\n"
              "def swallowing(args):\n"
              "    try:\n        os.kill(os.getpid(), signal.SIGINT)\n        time.sleep(1)\n"
              "    except BaseException:\n        pass\n    return call(args)\n"
              f"cli._call = swallowing\nimport sys\nsys.argv = ['rswarp', 'program', {str(IRB2600)!r}, "
              f"{str(IRB2600_PROGRAM)!r}, '--csv', {str(csv)!r}]\ncli.run()\n")
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=300)
    assert p.returncode == 130 and b"Traceback" not in p.stderr, p.stderr.decode()[-500:]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("conf, message", [
    ([0, 0, 0], r"conf must have the shape \(4,\) or \(1, 4\) for 1 pose, not \(3,\)"),
    (np.zeros((3, 4)), r"not \(3, 4\)"),
    ([0, 0.5, 0, 0], "whole numbers .* not 0.5"),
    ([np.nan, 0, 0, 0], "whole numbers .* not nan"),
    (["a"] * 4, "whole numbers, not <U1"),
    ([0, 0, 0, 1e9], "is no quadrant"),
    ([0, 0, 0, 10**30], "1e[+]30 is no quadrant"),  # past int64: NumPy holds it as an object
])
def test_ik_refuses_a_conf_that_is_not_confdata(conf, message):
    kin = rswarp.Kinematics(rswarp.load(IRB2600))
    pose = kin.flange(np.zeros((1, 6))).astype(np.float64)
    with pytest.raises(InputError, match=message):
        kin.ik64(pose, conf=conf)
    q, found = kin.ik64(pose, conf=np.zeros((1, 4)))
    assert found.all() and np.allclose(q, 0.0, atol=1e-6)  # a float32 pose


def _robtarget(kin, q: np.ndarray) -> np.ndarray:
    """The flange pose of ``q`` as a RAPID robtarget holds it: mm to 3 decimals, a quaternion to 6."""
    from scipy.spatial.transform import Rotation

    link, m = kin.flange_frame()
    pose = kin.fk64(q[None])[0, link] @ m
    x, y, z, w = Rotation.from_matrix(pose[:3, :3]).as_quat()
    quat = np.round([w, x, y, z], 6)
    out = np.eye(4)
    out[:3, :3] = Rotation.from_quat([*quat[1:], quat[0]]).as_matrix()
    out[:3, 3] = np.round(pose[:3, 3] * 1000, 3) / 1000
    return out


def _reached(kin, q: np.ndarray, q_now: np.ndarray) -> None:
    """The robtarget of ``q``, with ``q``'s own confdata, is reached as the program reaches it: to
    within the target's rounding, with that confdata."""
    from rswarp.kinematics.ik import conf_matches, quadrant_axes, wrist_axis
    from rswarp.motion import targets as tg

    pose, conf = _robtarget(kin, q)[None], kin.confdata(q[None])[0]
    sol = kin.solutions64(pose)
    tg.off_the_axis(kin, pose, sol, float(q_now[0]), [conf])
    got, why = tg.pick(sol, 0, conf, q_now, True, "p", kin._ik_form(), kin.mech.bounds())
    assert why is None, (np.degrees(q).round(3), conf, why)
    link, m = kin.flange_frame()
    reached = kin.fk64(got[None])[0, link] @ m
    assert np.abs(reached[:3, 3] - pose[0, :3, 3]).max() < 2e-5
    assert np.abs(reached[:3, :3] - pose[0, :3, :3]).max() < 1e-4
    form = kin._ik_form()
    have = kin.confdata(got[None])
    wrist, _ = kin.wrist_flange64(got[None])
    if np.hypot(wrist[0, 0], wrist[0, 1]) < 1e-5:  # on axis 1 the centre's side is rounding's
        have[0, 3] = (have[0, 3] & 3) | (conf[3] & 4)
    assert conf_matches(got[None], have, conf, quadrant_axes(form), wrist_axis(form))[0], (have, conf)


@pytest.fixture(scope="module")
def irb2600_kinematics():
    return rswarp.Kinematics(rswarp.load(IRB2600))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(q1=st.floats(-170, 170), q2=st.floats(-60, 90), q3=st.floats(-60, 60), q4=st.floats(-300, 300),
       q6=st.floats(-300, 300))  # q3 clear of -81.8 deg, where the arm is stretched (the elbow's singularity)
@example(q1=10.0, q2=20.0, q3=10.0, q4=100.0, q6=-100.0)  # Kinematics.ik(conf=) held q4 at 0: not found
@example(q1=0.0, q2=0.0, q3=0.0, q4=89.99999999999999, q6=-2.5065280177407123e-93)  # q4 + q6 at its range's edge
def test_a_wrist_singular_robtarget_is_reached_with_its_own_confdata(irb2600_kinematics, q1, q2, q3, q4, q6):
    """q5 = 0: axes 4 and 6 in line, only q4 + q6 counts. Rounded to a robtarget's digits, q5 is
    1e-6 rad off zero and the closed form's split of q4 and q6 is noise; the target's confdata
    picks the split, and q4 stays where the robot is where the quadrants let it. The wrist centre
    anywhere, near axis 1 too (there rounding turns q1 by 0.5 um over its distance from the
    axis). ``Kinematics.ik`` and ``ik64`` with the confdata find it too (the pose as it is)."""
    kin = irb2600_kinematics
    q = np.radians([q1, q2, q3, q4, 0.0, q6])
    _reached(kin, q, np.zeros(6))
    wrist, _ = kin.wrist_flange64(q[None])
    if np.hypot(wrist[0, 0], wrist[0, 1]) > 0.01:  # ik(conf=) does not seek q1 over axis 1 (the program does)
        from rswarp.kinematics.ik import conf_matches, quadrant_axes, wrist_axis

        link, m = kin.flange_frame()
        exact, conf, form = kin.fk64(q[None])[:, link] @ m, kin.confdata(q[None]), kin._ik_form()
        for solve, pose, tol in ((kin.ik64, exact, 1e-9), (kin.ik, kin.flange(q[None]), 1e-4)):
            got, found = solve(pose, conf=conf)
            assert found.all(), (solve.__name__, conf)
            got = got.astype(np.float64)
            assert np.abs(kin.fk64(got)[:, link] @ m - exact).max() < tol
            assert conf_matches(got, kin.confdata(got), conf[0], quadrant_axes(form), wrist_axis(form)).all()


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(q1=st.floats(-170, 170), q2=st.floats(-60, 60), q4=st.floats(-170, 170),
       q5=st.one_of(st.just(0.0), st.floats(-100, 100)), q6=st.floats(-170, 170),
       off=st.one_of(st.just(0.0), st.floats(-0.05, 0.05)))
@example(q1=0.0, q2=0.0, q4=0.0, q5=0.03125, q6=1.0, off=0.0)  # cf4 -1 for 0: the wrist near in line
@example(q1=0.0, q2=-6.56640625, q4=0.0, q5=0.0, q6=0.0, off=0.0)  # the arm 1.6 deg from stretched as well
def test_a_robtarget_over_the_shoulder_singularity_is_reached_with_its_own_confdata(irb2600_kinematics, q1, q2, q4,
                                                                                     q5, q6, off):
    """The wrist centre on axis 1 (any q1 reaches it), or ``off`` (m) in front of or behind it:
    rounding leaves it a micrometre in front of or behind the axis, which the target's cfx must
    not be read against, and turns q1 by 0.5 um over its distance from the axis. The wrist in
    line or not (q5 = 0 as well: there q1 is the wrist's, q4 and q6 swinging a quarter turn as
    it turns), q1 anywhere, the robot at zero."""
    from scipy.optimize import brentq

    from rswarp.motion.targets import stretched_q3

    kin = irb2600_kinematics

    def ahead(q3: float) -> float:  # how far the wrist centre is in front of axis 1 at q1 = 0
        wrist, _ = kin.wrist_flange64(np.radians([[0.0, q2, q3, q4, q5, q6]]))
        return float(wrist[0, 0]) - off

    q3 = brentq(ahead, -179.0, 0.0, xtol=1e-12) if ahead(-179.0) * ahead(0.0) < 0 else None
    assume(q3 is not None and q3 > -175)
    # clear of the arm stretched (the elbow's singularity), where rounding can put the pose out of reach
    assume(abs(q3 - np.degrees(stretched_q3(kin._ik_form()))) > 1.0)
    q = np.radians([q1, q2, q3, q4, q5, q6])
    _reached(kin, q, np.zeros(6))


def test_the_no_solution_message_prints_plain_numbers(irb2600_kinematics):
    """A target refused its confdata says the confdata and the ones it has as plain numbers, not
    NumPy's reprs ("[np.int32(0), ...]"), whatever the confdata was given as."""
    from rswarp.motion import targets as tg

    kin = irb2600_kinematics
    q = np.radians([20.0, 10.0, 5.0, 35.0, 40.0, 25.0])
    pose = _robtarget(kin, q)[None]
    for conf in (np.array([2, 0, 0, 0], np.int32), [np.int64(2), np.int8(0), np.int32(0), np.int16(0)], (2, 0, 0, 0)):
        sol = kin.solutions64(pose)
        tg.off_the_axis(kin, pose, sol, 0.0, [conf])
        got, why = tg.pick(sol, 0, conf, np.zeros(6), True, "p", kin._ik_form(), kin.mech.bounds())
        assert got is None and why.startswith("'p' has no solution with confdata [2, 0, 0, 0]; the nearest it has: ")
        assert "np." not in why and "array(" not in why and "int32" not in why, why


@pytest.mark.parametrize("when", ["printing", "shutting down"])
def test_sigterm_once_every_output_is_written_ends_the_run_as_it_would_have(tmp_path, when):
    """One rule for SIGTERM: once the command's outputs are all in place, it stops nothing: the run
    ends with its own status (0), its outputs whole, and a line saying the signal came late."""
    csv = tmp_path / "t.csv"
    kill = "os.kill(os.getpid(), signal.SIGTERM); time.sleep(0.5)"
    script = ("import atexit, os, signal, sys, time\nimport rswarp.cli as cli\ncall = cli._call\n"
              f"def late(args):\n    code = call(args)\n    {kill if when == 'printing' else 'pass'}\n    return code\n"
              f"cli._call = late\n" + (f"atexit.register(lambda: ({kill.replace('; ', ', ')}))\n"
                                       if when == "shutting down" else "") +
              f"sys.argv = ['rswarp', 'program', {str(IRB2600)!r}, {str(IRB2600_PROGRAM)!r}, '--csv', {str(csv)!r}]\n"
              "cli.run()\n")
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=300)
    assert p.returncode == 0, p.stderr.decode()[-500:]
    assert b"SIGTERM came after every output was written" in p.stderr and b"Traceback" not in p.stderr
    assert csv.read_text().startswith("time,")


def test_a_sigint_the_command_was_started_ignoring_stays_ignored():
    """A script's background job (``rswarp ... &``) or ``nohup`` starts with SIGINT ignored, so that
    a Ctrl-C meant for the foreground leaves it running; rswarp used to take SIGINT back once its
    command began (lost in the first tenth of a second, a stop after), and now leaves it alone."""
    script = ("import os, signal, sys, time\nimport rswarp.cli as cli\nfrom rswarp import files\n"
              "def sleeping(args):\n"
              "    os.kill(os.getpid(), signal.SIGINT)\n    time.sleep(0.2)\n"
              "    print('ran', files.interrupted())\n    return 0\n"
              "cli._call = sleeping\n"
              f"sys.argv = ['rswarp', 'program', {str(IRB2600)!r}, {str(IRB2600_PROGRAM)!r}]\ncli.run()\n")
    for disposition, code, out in ((signal.SIG_IGN, 0, b"ran False\n"), (signal.SIG_DFL, 130, b"")):
        p = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=120,
                           preexec_fn=lambda d=disposition: signal.signal(signal.SIGINT, d))
        assert (p.returncode, p.stdout) == (code, out), p.stderr.decode()[-500:]
        assert b"Traceback" not in p.stderr
