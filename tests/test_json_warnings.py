"""Every documented output present (issue "Hardening the cell surfaces"): each warning and note a
command prints on stderr is in its JSON's ``warnings`` too, over the bundled examples; ``rswarp
info CELL.toml --json`` gives each external axis's travel and limits in SI."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rswarp import examples
from rswarp.cli import main

RUNS = [
    ["program", str(examples.CELLS / "track_cell.toml"), str(examples.CELLS / "track_transfer.mod")],
    ["program", str(examples.CELLS / "positioner_cell.toml"), str(examples.CELLS / "positioner_weld.mod")],
    ["program", str(examples.IRB2600), str(examples.IRB2600_CELL)],
    ["info", str(examples.CELLS / "positioner_cell.toml")],
    ["info", str(examples.MULTIMOVE_CELL)],
]


@pytest.mark.parametrize("command", RUNS, ids=lambda c: f"{c[0]}-{c[1].rsplit('/', 1)[-1]}")
def test_every_line_on_stderr_is_among_the_jsons_warnings(command, capsys):
    main(command + ["--json"])
    captured = capsys.readouterr()
    doc = json.loads(captured.out)
    said = [line for line in captured.err.splitlines() if line.strip()]
    if command[-1] in (str(examples.IRB2600_CELL), str(examples.MULTIMOVE_CELL)):
        assert said  # the palletizing task's WaitDI warnings, the MultiMove backup's notes
    assert [w for w in said if w not in doc["warnings"]] == []


def test_info_gives_each_external_axis_travel_and_limits_in_si(capsys):
    assert main(["info", str(examples.CELLS / "positioner_cell.toml"), "--json"]) == 0
    unit = json.loads(capsys.readouterr().out)["externals"][0]
    tilt, turn = unit["joints"]
    assert (tilt["axis"], turn["axis"]) == ("eax_a", "eax_b") and tilt["type"] == "rotational"
    assert tilt["travel"] == pytest.approx([-np.pi / 2, np.pi / 2])  # +-90 degrees, in rad
    assert tilt["velocity"] > 0 and tilt["acceleration"] > 0 and tilt["source"] == "IRBP_A250.robot.toml"
