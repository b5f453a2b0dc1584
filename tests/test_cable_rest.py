"""A cable's rest shape: through its control points, with its desired length, in segments no
longer than maxSegmentLength (issue "Cable dynamics in parallel environments")."""

from __future__ import annotations

import numpy as np
import pytest

import rswarp
from rswarp.geometry.cable import cable_rest

from conftest import DATA


def test_rest_shape_runs_through_the_control_points_with_the_desired_length():
    mech = rswarp.load(DATA / "cable.rsxml")
    (cable,) = mech.cables
    rest = cable_rest(mech, cable)
    np.testing.assert_allclose(rest.points[list(rest.anchors)], [cp.position for cp in cable.control_points],
                               atol=1e-12)
    assert rest.length == pytest.approx(0.9, rel=1e-12) and rest.rest.sum() == pytest.approx(0.9, rel=1e-12)
    assert rest.rest.max() <= 0.04 + 1e-12 and rest.segments == len(rest.rest)
    chords = np.linalg.norm(np.diff(rest.points, axis=0), axis=1)
    assert (chords <= rest.rest + 1e-12).all() and chords.sum() > 0.99 * 0.9  # the bow is resolved
    middle = rest.points[(rest.anchors[1] + rest.anchors[2]) // 2]
    assert middle[2] < 0.55  # the span from z 500 to 600 mm sags below its chord's middle


def test_without_a_desired_length_the_cable_is_the_polyline(tmp_path):
    text = (DATA / "cable.rsxml").read_text().replace(' desiredLength="900"', "")
    (tmp_path / "c.rsxml").write_text(text)
    mech = rswarp.load(tmp_path / "c.rsxml")
    rest = cable_rest(mech, mech.cables[0])
    pts = np.array([cp.position for cp in mech.cables[0].control_points])
    assert rest.length == pytest.approx(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum(), rel=1e-12)
    np.testing.assert_allclose(np.linalg.norm(np.diff(rest.points, axis=0), axis=1), rest.rest, rtol=1e-9)


def test_a_cable_shorter_than_its_control_points_allow_is_refused(tmp_path):
    text = (DATA / "cable.rsxml").read_text().replace('desiredLength="900"', 'desiredLength="500"')
    (tmp_path / "c.rsxml").write_text(text)
    with pytest.raises(rswarp.RsxmlError, match=r"c.rsxml:15: cable 'Hose': desiredLength 500 is shorter than "
                                                r"the path through its control points \(654.138\)"):
        rswarp.load(tmp_path / "c.rsxml")  # the check refuses what a cable run would: at the cable's line
    assert not rswarp.check(tmp_path / "c.rsxml").ok
