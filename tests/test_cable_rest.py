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


def _frames_in_numpy(tangents, directions):
    """The segments' frames as ``layout._frames`` makes them, with each 3-vector a NumPy array: the
    reference its Python floats must round alike. Its dot products and norms are written as the sums
    they are: NumPy hands ``a @ b`` and ``np.linalg.norm`` to its BLAS, which on some CPUs (AVX-512
    ones, OpenBLAS 0.3.31) fuses the multiply-adds, so those round differently from machine to
    machine; each product and sum of NumPy's own is one IEEE rounding everywhere."""
    def dot(a, b):
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

    def unit(v):
        return v / np.sqrt(sum(x * x for x in v))

    def cross(a, b):
        return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])

    def transport(n, a, b):
        c, axis = float(dot(a, b)), cross(a, b)
        if c > -0.999:
            n = c * n + cross(axis, n) + axis * dot(axis, n) / (1 + c)
        n = n - dot(n, b) * b
        return unit(n)

    def quaternion(d1, d3):
        m = np.stack([d1, cross(d3, d1), d3], axis=1)
        w = np.sqrt(max(1e-12, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
        if w > 0.1:
            q = np.array([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1], 4 * w ** 2]) / (4 * w)
        else:
            i = int(np.argmax(np.diag(m)))
            j, k = (i + 1) % 3, (i + 2) % 3
            s = np.sqrt(max(1e-12, 1 + m[i, i] - m[j, j] - m[k, k])) * 2
            q = np.zeros(4)
            q[i], q[j], q[k], q[3] = s / 4, (m[j, i] + m[i, j]) / s, (m[k, i] + m[i, k]) / s, (m[k, j] - m[j, k]) / s
        return unit(q)

    start = directions.get(0, tangents[0])
    helper = np.array([0.0, 0.0, 1.0]) if abs(start[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    normal = unit(cross(start, helper))
    t_prev, seg_q, node_q = start, [], []
    for i in range(len(tangents) + 1):
        t_node = directions.get(i, tangents[min(i, len(tangents) - 1)])
        normal = transport(normal, t_prev, t_node)
        node_q.append(quaternion(normal, t_node))
        t_prev = t_node
        if i < len(tangents):
            normal = transport(normal, t_prev, tangents[i])
            seg_q.append(quaternion(normal, tangents[i]))
            t_prev = tangents[i]
    return np.array(seg_q), np.array(node_q)


def test_the_frames_in_python_floats_round_as_numpy_does():
    """A design sweep lays out every design's segments in Python floats: the same bits as the same
    steps on NumPy's 3-vectors, over smooth and rough chains, half turns and clamp directions."""
    from rswarp.sim.cable.layout import _frames

    rng = np.random.default_rng(5)
    for trial in range(300):
        n = int(rng.integers(2, 60))
        steps = rng.normal(size=(n, 3)) * (0.05 if trial % 3 else 1.0) + (rng.normal(size=3) if trial % 2 else 0)
        if trial % 7 == 0:
            steps[n // 2] = -steps[n // 2 - 1]  # a half turn
        tangents = steps / np.linalg.norm(steps, axis=1, keepdims=True)
        directions = {int(k): v / np.linalg.norm(v) for k, v in
                      zip(rng.choice(n + 1, size=int(rng.integers(0, 3)), replace=False), rng.normal(size=(2, 3)))}
        for mine, numpy in zip(_frames(tangents, directions), _frames_in_numpy(tangents, directions)):
            assert np.array_equal(mine, numpy)
