"""Videos (issue "A dress pack that means something", part 3): the expected frame count, frames
that are not blank and that change, the hose drawn in its colours, and a file of the user's
never replaced."""

from __future__ import annotations

import numpy as np

import rswarp
from rswarp.cli import main
from rswarp.examples import IRB2600, IRB2600_DRESSPACK, IRB2600_PROGRAM
from rswarp.kinematics.kinematics import Kinematics
from rswarp.sim.video import BEND_COLOURS, Tube, bend_colours, render_frames, write_video


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
    assert count == int(np.ceil(8.78 * 30))  # the 8.78 s routine at 30 frames a second
    mine = tmp_path / "mine.gif"
    mine.write_bytes(b"my file")
    assert main(["cable", str(IRB2600_DRESSPACK), "--program", str(IRB2600_PROGRAM), "--envs", "1",
                 "--out", str(tmp_path / "run"), "--video", str(mine)]) == 1
    assert mine.read_bytes() == b"my file"
    assert main(["cable", str(IRB2600_DRESSPACK), "--random", "--out", str(tmp_path / "r"), "--video-color",
                 "pink"]) == 1
