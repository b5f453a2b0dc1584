"""Videos (issue "A dress pack that means something", part 3; issue 36, "small truths"): the
expected frame count, frames that are not blank and that change, the hose drawn in its colours, a
file of the user's never replaced; each frame's time and program line, the legend in a band off
the robot, the floor grid at the floor, and a progress bar on stderr but never under --json."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import rswarp
from rswarp.cli import main
from rswarp.examples import IRB2600, IRB2600_DRESSPACK, IRB2600_PROGRAM
from rswarp.kinematics.kinematics import Kinematics
from rswarp.report.videos import VIDEO_FPS, captions, move_captions
from rswarp.sim.video import (
    BEND_COLOURS,
    GREY,
    GRID,
    RED,
    Band,
    Tube,
    bend_colours,
    floor_grid,
    project,
    render_frames,
    scene_camera,
    write_video,
)


def test_frames_move_are_not_blank_and_show_the_hose_in_its_colours(tmp_path):
    mech = rswarp.load(IRB2600)
    q = np.zeros((6, 6))
    q[:, 0] = np.linspace(0, 1.2, 6)  # J1 turns
    poses = Kinematics(mech).fk64(q)
    points = np.repeat(np.linspace([0.3, 0.0, 1.5], [1.0, 0.0, 1.6], 12)[None], 6, axis=0)
    tube = Tube(points, bend_colours(points, 0.3), 0.03)
    frames = render_frames(mech, poses, [tube], size=96)
    assert frames.shape == (6, 96, 96, 3)
    for f in frames:
        assert (f < 250).any(axis=2).mean() > 0.05  # something is drawn on the white
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).sum() > 0  # it moves
    green = np.round(np.asarray(BEND_COLOURS[0]) * 255)
    assert (np.abs(frames[0].astype(int) - green).max(axis=2) < 60).any()  # a straight hose: green
    path = tmp_path / "clip.gif"
    write_video(path, frames, 30.0)
    import imageio.v3 as iio

    back = iio.imread(path, index=None)
    assert back.shape[0] == 6 and back.shape[1:3] == (96, 96)


def test_bend_colours_follow_the_radius():
    """A quarter circle of radius 0.2 m against an allowed 0.3 m: orange; of 0.1 m: red."""
    for radius, colour in ((0.2, BEND_COLOURS[1]), (0.1, BEND_COLOURS[2]), (0.5, BEND_COLOURS[0])):
        a = np.linspace(0, np.pi / 2, 30)
        pts = np.stack([radius * np.cos(a), radius * np.sin(a), np.zeros_like(a)], axis=1)[None]
        c = bend_colours(pts, 0.3)[0]
        assert np.allclose(c[1:-1], colour)


def test_program_and_cable_videos_from_the_command_line(tmp_path):
    prog = tmp_path / "prog.mp4"
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--video", str(prog)]) == 0
    import imageio.v2 as iio2

    reader = iio2.get_reader(prog)
    count = reader.count_frames()
    reader.close()
    _, plan = rswarp.program(IRB2600, [IRB2600_PROGRAM])
    assert count == len(np.arange(0.0, plan.times[-1] + 1e-9, 1 / VIDEO_FPS))  # the routine at 30 frames a second
    mine = tmp_path / "mine.gif"
    mine.write_bytes(b"my file")
    assert main(["cable", str(IRB2600_DRESSPACK), "--program", str(IRB2600_PROGRAM), "--envs", "1",
                 "--out", str(tmp_path / "run"), "--video", str(mine)]) == 1
    assert mine.read_bytes() == b"my file"
    assert main(["cable", str(IRB2600_DRESSPACK), "--random", "--out", str(tmp_path / "r"), "--video-color",
                 "pink"]) == 1


# -- what a frame says, and where ------------------------------------------------------------------------


def _move(instruction, target, line, start, end):
    return SimpleNamespace(motion=SimpleNamespace(file="/cell/pick.mod", line=line, instruction=instruction),
                           target=target, start=start, end=end)


MOVES = [_move("MoveAbsJ", "jHome", 3, 0.0, 0.0), _move("MoveL", "p10", 4, 0.0, 1.0),
         _move("WaitTime", "0.3 s", 5, 1.0, 1.3), _move("MoveJ", "p20", 7, 1.3, 2.0)]


def test_each_frame_says_its_time_and_the_move_under_way():
    """The move whose time span holds the frame's time; at a boundary the one that starts there; a
    move of no duration never; past the end, the last."""
    times = np.array([0.0, 0.5, 1.0, 1.2, 1.3, 2.0, 2.5])
    assert move_captions(times, MOVES) == ["pick.mod:4  MoveL p10", "pick.mod:4  MoveL p10", "pick.mod:5  WaitTime 0.3 s",
                                           "pick.mod:5  WaitTime 0.3 s", "pick.mod:7  MoveJ p20", "pick.mod:7  MoveJ p20",
                                           "pick.mod:7  MoveJ p20"]
    text = captions(times[:2], MOVES)
    assert text == ["t = 0.00 s\npick.mod:4  MoveL p10", "t = 0.50 s\npick.mod:4  MoveL p10"]
    assert captions(np.array([1.234]), None) == ["t = 1.23 s"]  # a cable run of no program: the time alone


@pytest.fixture(scope="module")
def still():
    """Two frames of the IRB 2600 in one pose: the scene alike, the captions not."""
    mech = rswarp.load(IRB2600)
    poses = Kinematics(mech).fk64(np.zeros((2, 6)))
    return mech, poses


def test_the_caption_and_legend_are_in_a_band_the_robot_is_never_drawn_in(still):
    mech, poses = still
    legend = [(GREY, "pick_place.main"), (RED, "in collision"), ((0.2, 0.6, 0.3), "bend radius >= 300.0 mm")]
    text = ["t = 0.00 s\npick.mod:4  MoveL p10", "t = 0.03 s\npick.mod:4  MoveL p10"]
    size, ticks = 192, []
    frames = render_frames(mech, poses, [], size, legend=legend, captions=text, grid=False,
                           progress=lambda done, total: ticks.append((done, total)))
    assert ticks == [(1, 2), (2, 2)]
    band = Band.of(size, legend, text)
    assert 0 < band.height <= size // 2
    for f in range(2):
        assert np.array_equal(frames[f, :band.height], band.image(text[f]))  # the band is text on white, only
    assert not np.array_equal(frames[0, :band.height], frames[1, :band.height])  # the time changed
    assert np.array_equal(frames[0, band.height:], frames[1, band.height:])  # the robot did not
    robot = (frames[0, band.height:] < 250).any(axis=2)  # on white, with no grid: the robot's pixels
    rows, cols = np.nonzero(robot)
    assert robot.mean() > 0.05
    assert rows.min() > 0 and cols.min() > 0 and cols.max() < size - 1  # framed whole, below the band


def test_the_floor_grid_is_drawn_at_the_floor_under_the_robot(still):
    """The grid's crossings, projected from the floor's height, are grid-coloured; the middle of a
    square is not; with the grid off no pixel has its colour."""
    mech, poses = still
    floor, size = -0.2, 128
    frames = render_frames(mech, poses[:1], [], size, floor=floor)
    plain = render_frames(mech, poses[:1], [], size, grid=False)
    ink = np.round(np.asarray(GRID) * 255)
    assert (np.abs(frames[0].astype(int) - ink).max(axis=2) < 8).sum() > 50
    assert (np.abs(plain[0].astype(int) - ink).max(axis=2) < 8).sum() == 0
    box = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (floor, 1.0)])
    c = scene_camera(box, 100, 80)
    image = floor_grid(c, 100, 80, floor, 0.25, box)
    crossings = project(c, 100, 80, np.array([[x, y, floor] for x in (-0.25, 0.0, 0.25) for y in (-0.25, 0.0, 0.25)]))
    middles = project(c, 100, 80, np.array([[x, y, floor] for x in (-0.125, 0.125) for y in (-0.125, 0.125)]))
    for x, y in crossings:  # within a pixel of where the lines cross
        near = image[int(y) - 1:int(y) + 2, int(x) - 1:int(x) + 2].reshape(-1, 3)
        assert np.abs(near - GRID).max(axis=1).min() < 0.02
    for x, y in middles:
        assert np.allclose(image[int(y) - 1:int(y) + 2, int(x) - 1:int(x) + 2], 1.0)


def test_a_video_shows_a_progress_bar_on_stderr_but_never_under_json(tmp_path, capsys, monkeypatch):
    """The command line gives the frames a bar of their own; --json gives them none."""
    from rswarp.report import videos

    seen = []

    def frames(mech, poses, tubes, size, progress=None, **k):
        seen.append((progress, k["captions"][1]))
        if progress is not None:
            for f in range(len(poses)):
                progress(f + 1, len(poses))
        return np.full((len(poses), 16, 16, 3), 255, np.uint8)

    monkeypatch.setattr(videos, "render_frames", frames)
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--video", str(tmp_path / "a.gif")]) == 0
    err = capsys.readouterr().err
    assert seen[-1][0] is not None and "program video" in err and "frames" in err
    assert seen[-1][1].startswith("t = 0.03 s\npick_place.mod:")  # the time and the program's line
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--video", str(tmp_path / "b.gif"), "--json"]) == 0
    out = capsys.readouterr()
    assert seen[-1][0] is None and "video" not in out.err and out.out.lstrip().startswith("{")


def test_the_design_sweep_renders_its_chosen_design(tmp_path, monkeypatch):
    """``rswarp dresspack --video``: the chosen design's run, its legend naming the design; the
    command line takes the option (it was "unrecognized arguments")."""
    from rswarp.cli import build_parser
    from rswarp.config import VideoOptions
    from rswarp.report import videos
    from rswarp.report.dresspack import run_dresspack

    from conftest import DATA

    rigs = DATA / "verdicts"
    args = build_parser().parse_args(["dresspack", str(rigs / "taut.rsxml"), "--program", str(rigs / "pull_hold.mod"),
                                      "--vary", "length=1.15:1.25", "--out", "o", "--video", "best.gif"])
    assert args.video == "best.gif" and args.video_color == "bend"
    legends, render = [], videos.render_frames
    monkeypatch.setattr(videos, "render_frames", lambda *a, **k: legends.append(k["legend"]) or render(*a, **k))
    with videos.frame_rate(5.0):
        done = run_dresspack(str(rigs / "taut.rsxml"), [str(rigs / "pull_hold.mod")], str(tmp_path / "sweep"),
                             vary=["length=1.15:1.25"], designs=2, min_bend_radius=150.0,
                             video=VideoOptions(str(tmp_path / "best.gif"), video_size=64))
    best = done.doc["best"]["design"]
    assert done.doc["video"]["design"] == best and done.doc["video"]["path"] == str(tmp_path / "best.gif")
    assert f"video: {tmp_path / 'best.gif'} (design {best}, " in done.text
    assert legends[-1][0][1] == f"design {best}"
    import imageio.v3 as iio

    frames = iio.imread(tmp_path / "best.gif", index=None)
    assert len(frames) == done.doc["video"]["frames"] > 1 and frames.shape[1:3] == (64, 64)
