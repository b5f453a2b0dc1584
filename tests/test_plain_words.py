"""Every message a user reads is in plain numbers: the findings and errors of programs that make
each kind (collisions, the floor, joint limits, the singularity, paths, configurations, a tool,
targets out of reach, past a limit, with no such confdata, live input), in text and JSON, never
NumPy's reprs (``np.int32(0)``, ``array([...])``) — one once said "has no solution with confdata
[np.int32(0), ...]"."""

from __future__ import annotations

import json

import pytest

from rswarp.examples import IRB2600, IRB2600_PROGRAM
from rswarp.report.program import run_program

from conftest import DATA

RAPID = DATA / "rapid"
NUMPY = ("np.", "array(", "int32", "int64", "float64", "float32")
CASES = [
    ([IRB2600_PROGRAM.parent / "service.mod"], {}),  # collisions and the floor
    ([RAPID / "over_base.mod"], {}),  # a path past a joint limit, a target only outside the limits
    ([RAPID / "pallet_reach"], {}),  # targets out of reach, grouped over passes
    ([RAPID / "near_singular.mod"], {}),  # the wrist singularity
    ([RAPID / "wrong_confdata.mod"], {}),  # no solution with the robtarget's confdata
    ([RAPID / "movec.mod"], {}),
    ([RAPID / "tool_fold.mod"], {"tool": str(DATA / "tool" / "gripper.stl")}),  # a tool against the links
    ([RAPID / "live" / "socket_pick.mod"], {}),  # stopped for a live input
    ([RAPID / "wild" / "grasshopper.mod"], {}),  # speeds capped, external axes ignored
]


@pytest.mark.parametrize("paths, options", CASES, ids=[c[0][0].name for c in CASES])
def test_messages_are_in_plain_numbers(paths, options):
    said = []
    out = run_program(str(IRB2600), [str(p) for p in paths], warn=said.append, **options)
    text = "\n".join([out.text, *out.errors, *said, json.dumps(out.doc, default=str)])
    assert not [w for w in NUMPY if w in text], [line for line in text.splitlines() if any(w in line for w in NUMPY)]
