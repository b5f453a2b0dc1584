"""The example scripts run and print what they promise."""

import runpy
import sys

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
