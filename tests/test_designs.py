"""Designs of a dress pack for the design sweep (issue "Dress-pack verdicts an engineer signs",
item 3, its first part): ``--vary`` read and refused as the issue says, Sobol designs inside their
box and reproducible, each design's cable changed where it says, and a design whose clamp lies
inside a link at rest found before any work."""

from __future__ import annotations

import numpy as np
import pytest

from rswarp.errors import InputError
from rswarp.examples import IRB2600_DRESSPACK
from rswarp.rsxml.documents import load_mechanism
from rswarp.sim.designs import design, inside_links, parse_vary, sample


def hose():
    mech = load_mechanism(IRB2600_DRESSPACK)[0]
    return mech, mech.cables[0]  # control points: 1 on Link3, 2 free, 3 on Link6


@pytest.mark.parametrize("spec, message", [
    ("Link5.x=-0.05:0.05", r"link 'Link5' holds no control point of cable 'ProcessHose' \(held: 1 on Link3, 3 on "
                           r"Link6\)"),
    ("2.x=-0.05:0.05", "control point 2 of cable 'ProcessHose' is held by no link"),
    ("7.x=0:0.1", "has control points 1 to 3"),
    ("length=1.2:1.0", r"an empty range \(1.2 to 1\)"),
    ("Link6.x=0.05:0.05", "an empty range"),
    ("Link6.roll=-5:5", "give length=MIN:MAX"),
    ("Link6.pitch=-120:20", "within ±90 deg"),
    ("length=0:1", "a length above 0"),
    ("length=a:1", "'a' is not a number"),
    ("length", "give length=MIN:MAX"),
    ("length=1:2000", r"a hose of at most 1000 m, please \(1 km"),  # the bound of every length, not the floor
    ("length=1e9:2e9", "a hose of at most 1000 m"),
])
def test_a_vary_given_wrong_is_one_clear_line(spec, message):
    with pytest.raises(InputError, match=message):
        parse_vary([spec], hose()[1])


@pytest.mark.parametrize("specs, message", [
    (["Link6.z=0:0.01", "3.z=0:0.02"], "'Link6.z=0:0.01' already varies control point 3's z"),
    (["1.pitch=0:5", "Link3.pitch=-5:0"], "already varies control point 1's pitch"),
    (["length=1:1.1", " length = 1.1:1.2"], "already varies the hose's length"),
])
def test_one_number_varied_twice_under_any_names_is_refused(specs, message):
    with pytest.raises(InputError, match=message):
        parse_vary(specs, hose()[1])
    assert len(parse_vary(["Link6.z=0:0.01", "3.x=0:0.01", "Link3.z=0:0.01"], hose()[1])) == 3


def test_designs_fill_their_box_the_same_way_each_time():
    _, cable = hose()
    variables = parse_vary(["length=1.0:1.3", "Link6.x=-0.05:0.05", "Link3.pitch=-20:20"], cable)
    assert [v.point for v in variables] == [None, 2, 0]
    assert variables[2].high == pytest.approx(np.radians(20.0))
    x = sample(variables, 64, seed=3)
    assert x.shape == (64, 3) and np.array_equal(x, sample(variables, 64, seed=3))
    assert (x[:, 0] >= 1.0).all() and (x[:, 0] <= 1.3).all() and np.abs(x[:, 2]).max() <= np.radians(20.0)
    # a Sobol set: each half of each variable's range holds half of the 64 designs
    for k, v in enumerate(variables):
        assert np.count_nonzero(x[:, k] < (v.low + v.high) / 2) == 32
    with pytest.raises(InputError, match="--designs must be 1 to"):
        sample(variables, 0)


def test_a_design_changes_its_cable_where_it_says():
    mech, cable = hose()
    variables = parse_vary(["length=1.0:1.3", "Link6.z=-0.05:0.05", "Link3.pitch=-30:30"], cable)
    changed = design(mech, 0, variables, [1.2, 0.02, np.radians(30.0)])
    c = changed.cables[0]
    assert c.desired_length == 1.2
    assert np.allclose(c.control_points[2].position, np.add(cable.control_points[2].position, [0, 0, 0.02]))
    before, after = cable.control_points[0].unit_direction, np.asarray(c.control_points[0].direction)
    assert np.degrees(np.arccos(np.clip(before @ after, -1, 1))) == pytest.approx(30.0)
    assert after[1] == pytest.approx(0.0, abs=1e-12)  # a pitch turns it about y: it stays in the x-z plane
    assert mech.cables[0] is cable  # the mechanism it came from is untouched


def test_a_clamp_moved_into_a_link_is_found_at_rest():
    mech, cable = hose()
    assert inside_links(mech, 0) == []
    # Link3's clamp pushed 10 cm into the upper arm's housing, below it
    sunk = design(mech, 0, parse_vary(["Link3.z=-0.2:0.2"], cable), [-0.10])
    assert inside_links(sunk, 0) == ["point 1 in Link3"]
