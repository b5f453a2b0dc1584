"""The example scripts run and print what they promise."""

import re
import runpy
import sys
from pathlib import Path

import imageio.v3 as iio
import pytest

from rswarp import examples


@pytest.mark.parametrize("script, expected", [
    ("inspect_robot.py", "Link6: 390 triangles"),
    ("newton_worlds.py", "largest difference between Newton's and rswarp's link positions"),
])
def test_example_runs(script, expected, capsys, monkeypatch, tmp_path):
    argv = [script] + (["--worlds", "8", "--out", str(tmp_path / "r.usdc")] if script == "newton_worlds.py" else [])
    monkeypatch.setattr(sys, "argv", argv)
    runpy.run_path(str(examples.FOLDER / script), run_name="__main__")
    out = capsys.readouterr().out
    assert expected in out
    if script == "newton_worlds.py":
        err = float(out.rsplit(": ", 1)[1].split()[0])
        assert err < 1e-5


def test_the_demo_writes_what_the_readme_says_it_does(demo_run):
    """Every output the README's set-up section names (a file or a folder/) is in the demo's
    folder, a video of each kind of dress-pack run among them; every GIF 480 px or more a side."""
    folder, code, _ = demo_run
    assert code == 0
    readme = (Path(__file__).parents[1] / "README.md").read_text(encoding="utf-8")
    setup = readme.split("## Set-up on a fresh machine", 1)[1].split("```", 1)[0]
    promised = re.findall(r"`([^`\s]+(?:/|\.(?:gif|mp4|rsxml|csv|json|png|usdc|urdf|srdf)))`", setup)
    assert {"dresspack-program.gif", "dresspack-random.gif"} <= set(promised)
    assert [p for p in promised if not (folder / p).exists()] == []
    for gif in folder.glob("*.gif"):
        assert min(iio.imread(gif, index=0).shape[:2]) >= 480, gif
