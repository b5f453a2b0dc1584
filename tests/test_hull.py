"""The convex hulls' separation test (``kernels/hull.py``, ``rswarp/geometry/hull.py``): each
support point the farthest vertex, every pair it calls apart apart by python-fcl's distance of the
same hulls, and the sweep's verdicts and gaps the same with the test or without it."""

import functools

import numpy as np
import pytest

import rswarp
from rswarp.geometry.hull import support_graph
from rswarp.sim import bodies as sim_bodies
from rswarp.sim.bodies import collision_bodies
from rswarp.sim.collisions import Checker

from conftest import DATA

IRB = DATA.parent.parent / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"


@pytest.fixture(scope="module")
def irb():
    mech = rswarp.load(str(IRB))
    bodies = collision_bodies(mech)
    return mech, bodies, Checker(mech, bodies, witnesses=False)


@functools.cache
def _kernels():
    """(farthest, apart): a direction's support vertex per body; the hull test per pose."""
    from rswarp.kernels.hull import hull_function, support_functions
    from rswarp.kernels.types import bodies_struct
    from rswarp.launch import init_warp

    wp = init_warp()
    arrays = bodies_struct(wp.float32)
    nearby, climb = support_functions(wp.float32)
    hulls_apart = hull_function(wp.float32)

    @wp.kernel(enable_backward=False, module="test_hull")
    def farthest(m: arrays, body: int, d: wp.array(dtype=wp.vec3), k_out: wp.array(dtype=wp.int32)):
        i = wp.tid()
        k_out[i] = climb(m, nearby(m, body, d[i]), d[i])

    @wp.kernel(enable_backward=False, module="test_hull")
    def apart(m: arrays, a: int, b: int, r: wp.array(dtype=wp.mat33), t: wp.array(dtype=wp.vec3), limit: float,
              apart_out: wp.array(dtype=wp.int32)):
        i = wp.tid()
        apart_out[i] = 0
        if hulls_apart(m, a, b, r[i], t[i], limit):
            apart_out[i] = 1

    return wp, farthest, apart


def _directions(n: int, seed: int) -> np.ndarray:
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def test_a_hull_is_the_mesh_own_vertices_and_edges_both_ways(irb):
    for body in irb[1].bodies:
        g = support_graph(body.vertices)
        rows = {tuple(v) for v in body.vertices.tolist()}
        assert all(tuple(v) in rows for v in g.vertices.tolist())  # no point moved: the mesh lies inside
        edges = {(i, int(j)) for i in range(len(g.vertices)) for j in g.neighbours[g.start[i]:g.start[i + 1]]}
        assert edges and all((j, i) in edges for i, j in edges)
        assert g.reach == pytest.approx(np.linalg.norm(g.vertices, axis=1).max())


def test_the_climb_ends_at_the_farthest_vertex(irb):
    """Against every vertex tried in NumPy: the climb's vertex is as far along each direction as the
    farthest, from the cube map's start in any cell (the climb compares in float64, where the
    float32 vertices' products are exact)."""
    mech, bodies, checker = irb
    wp, farthest, _ = _kernels()
    s = checker._device.struct(wp.float32)
    first = 0
    for index, body in enumerate(bodies.bodies):
        g = checker._device.hulls[index]
        d = _directions(4000, index).astype(np.float32)
        out = wp.zeros(len(d), dtype=wp.int32)
        wp.launch(farthest, len(d), inputs=[s, index, wp.array(d, dtype=wp.vec3), out])
        k = out.numpy() - first
        assert ((k >= 0) & (k < len(g.vertices))).all()
        v = g.vertices.astype(np.float32).astype(np.float64)  # as the kernel holds them
        d = d.astype(np.float64)
        best = (d @ v.T).max(axis=1)
        got = (d * v[k]).sum(axis=1)
        assert (best - got).max() < 1e-12, body.name
        first += len(g.vertices)


def _fcl_hull_distance(ga, gb, r, t) -> np.ndarray:
    """python-fcl's distance between two hulls (qhull's faces of their vertices), b posed by (r, t)."""
    import fcl
    from scipy.spatial import ConvexHull

    def convex(g):
        f = ConvexHull(g.vertices).simplices
        return fcl.Convex(g.vertices, len(f), np.c_[np.full(len(f), 3), f].ravel())

    ca, cb = convex(ga), convex(gb)
    oa = fcl.CollisionObject(ca, fcl.Transform())
    out = []
    for ri, ti in zip(r, t):
        ob = fcl.CollisionObject(cb, fcl.Transform(ri, ti))
        out.append(fcl.distance(oa, ob, fcl.DistanceRequest(), fcl.DistanceResult()))
    return np.array(out)


@pytest.mark.parametrize("limit", [0.0, 0.01])
def test_hulls_called_apart_are_apart_by_fcl(irb, limit):
    """Base and Link 3 at random poses about each other (a few centimetres apart to overlapping):
    every pose the test calls apart is further than the limit by python-fcl, and all but a few
    that fcl puts 5 mm beyond it are called apart."""
    from scipy.spatial.transform import Rotation

    mech, bodies, checker = irb
    wp, _, apart = _kernels()
    names = bodies.names
    a, b = names.index("Base"), names.index("Link3")
    ga, gb = checker._device.hulls[a], checker._device.hulls[b]
    rng = np.random.default_rng(3)
    n = 1500
    r = Rotation.random(n, random_state=rng).as_matrix()
    # B's centre placed about A's, at distances from overlap to clear
    ca, cb = checker._device.spheres[a][0], checker._device.spheres[b][0]
    reach = checker._device.spheres[a][1] + checker._device.spheres[b][1]
    t = ca + _directions(n, 4) * rng.uniform(0.2, 1.0, (n, 1)) * reach - np.einsum("nij,j->ni", r, cb)
    out = wp.zeros(n, dtype=wp.int32)
    s = checker._device.struct(wp.float32)
    wp.launch(apart, n, inputs=[s, a, b, wp.array(r, dtype=wp.mat33), wp.array(t, dtype=wp.vec3), limit, out])
    said = out.numpy().astype(bool)
    d = _fcl_hull_distance(ga, gb, r, t)
    assert said.sum() > 200 and (~said).sum() > 200  # both kinds are tried
    assert (d[said] > limit).all(), "called apart, but fcl has the hulls within the limit"
    clear = d > limit + 0.005
    assert said[clear].mean() > 0.99


def test_the_hulls_change_no_verdict(irb, monkeypatch):
    """The sweep with every body's hull, and with none (each pair then left to the walk): the same
    verdicts and gaps, padded or not."""
    mech, bodies, checker = irb
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(21).random((3000, len(lower)))
    with_hulls = [checker.verdicts(q), Checker(mech, bodies, padding=0.01, witnesses=False).verdicts(q)]
    monkeypatch.setattr(sim_bodies, "support_graph", lambda vertices: None)
    bare = Checker(mech, bodies, witnesses=False)
    assert all(h is None for h in bare._device.hulls)
    without = [bare.verdicts(q), Checker(mech, bodies, padding=0.01, witnesses=False).verdicts(q)]
    for (hit, gap), (bare_hit, bare_gap) in zip(with_hulls, without):
        assert hit.any() and not hit.all()
        np.testing.assert_array_equal(hit, bare_hit)
        np.testing.assert_array_equal(gap, bare_gap)


def test_a_flat_or_tiny_mesh_has_no_hull():
    from rswarp.geometry import hull as host
    from rswarp.kernels import hull as device

    assert host.CUBE == device.CUBE  # the host lays out the cube map the kernels index
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]], float)
    assert support_graph(square) is None
    assert support_graph(square[:3]) is None
    cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    g = support_graph(np.vstack([cube, [[0.5, 0.5, 0.5]]]))
    assert len(g.vertices) == 8 and len(g.cube) == 6 * 32 * 32


def test_the_usual_crossings_change_no_verdict(irb, monkeypatch):
    """A sweep of 10**6 samples' checker (certified cells) tries each pair's usual crossings before
    a walk: the same verdicts and gaps as without them; the same lists on every build."""
    from rswarp.sim import collisions as sim_collisions

    mech, bodies, _ = irb
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(22).random((4000, len(lower)))
    full = Checker(mech, bodies, certified_cells=True)
    usual = full.witnesses.usual
    assert (usual >= 0).sum() >= 3  # the base's pairs with the lower arm and the wrist, at least
    np.testing.assert_array_equal(Checker(mech, bodies, certified_cells=True).witnesses.usual, usual)
    hit, gap = full.verdicts(q)
    # what the lists are drawn from: the first crossing a walk finds, which does cross (float64)
    state, pair = np.nonzero(hit)
    first = full._first_at(q[state], pair.astype(np.int32))
    found = first[:, 0] >= 0
    assert found.mean() > 0.5
    tris = np.full((len(state), 2 * 8), -1, np.int32)
    tris[:, :2] = first
    cross = [full._crossing_at(q[state], pair, tris, np.zeros(len(state)), np.full(len(state), side, np.int32))
             for side in (0, 1)]  # an edge of B's triangle through A's, or of A's through B's
    assert (cross[0] | cross[1])[found].mean() > 0.99
    monkeypatch.setattr(sim_collisions, "usual_crossings", lambda grid, *args: grid)
    bare = Checker(mech, bodies, certified_cells=True)
    assert bare.witnesses.usual is None
    bare_hit, bare_gap = bare.verdicts(q)
    assert hit.any()
    np.testing.assert_array_equal(hit, bare_hit)
    np.testing.assert_array_equal(gap, bare_gap)
