"""The link graph is built in one place and everyone asks it: validation, kinematics and the
exporters agree on the tree and the closing joints."""

import random
import re

from hypothesis import given, settings
from hypothesis import strategies as st

import rswarp
from rswarp.rsxml.graph import LinkGraph
from rswarp.rsxml.model import Joint, Mechanism, Part

from conftest import DATA


def _exported_joints(mech, tmp_path):
    """Joint names in the USD export, and those excluded from the articulation."""
    from pxr import Usd, UsdPhysics

    from rswarp.export.usd_layout import to_usd

    to_usd(mech, tmp_path / "m.usda")
    stage = Usd.Stage.Open(str(tmp_path / "m.usda"))
    joints, excluded = set(), set()
    for prim in stage.Traverse():
        j = UsdPhysics.Joint(prim)
        if j and not prim.IsA(UsdPhysics.FixedJoint):
            joints.add(prim.GetDisplayName())
            if j.GetExcludeFromArticulationAttr().Get():
                excluded.add(prim.GetDisplayName())
    return joints, excluded


def test_parallel_rod_closing_joint_is_the_same_everywhere(tmp_path):
    mech = rswarp.load(DATA / "parallel_rod.rsxml")
    graph = mech.graph
    assert graph is LinkGraph.of(mech) is mech.graph  # built once
    assert [j.name for j in graph.closing] == ["Rod2"]
    # up from the closing joint's parent to the common ancestor, down to its child, then itself
    assert [j.name for j in graph.loop(graph.closing[0])] == ["Rod1", "J3", "J2", "Elbow", "Rod2"]
    assert graph.joints_in_loops == {"J2", "J3", "Rod1", "Elbow", "Rod2"}
    # validation: the loop has passive joints, and every passive joint is in it
    report = rswarp.check(DATA / "parallel_rod.rsxml")
    assert not [d for d in report.all_diagnostics if "loop" in d.message]
    # USD: the closing joint, and only it, leaves the articulation; every graph joint is written
    joints, excluded = _exported_joints(mech, tmp_path)
    assert joints == {j.name for j in graph.joints} and excluded == {"Rod2"}
    # kinematics solves the parallelogram (tests/test_loops.py); URDF leaves the closing joint out,
    # Newton adds it outside the articulation
    from rswarp.export.newton import to_newton
    from rswarp.export.urdf import to_urdf

    to_urdf(mech, tmp_path / "m.urdf")
    assert 'name="Rod2"' not in (tmp_path / "m.urdf").read_text() and "<mimic" in (tmp_path / "m.urdf").read_text()
    model = to_newton(mech, shapes=False).finalize(device="cpu")
    labels = [label.rsplit("/", 1)[-1] for label in model.joint_label]
    assert labels[-1] == "Rod2" and model.joint_articulation.numpy()[-1] == -1


def test_branching_tree_is_the_same_everywhere(tmp_path):
    mech = rswarp.load(DATA / "branching.rsxml")
    graph = mech.graph
    assert graph.is_tree and [graph.links[k] for k in graph.order] == ["Column", "Slide", "Arm", "Swivel", "Forearm"]
    tree_joints = [j.name for _, j in graph.tree_order]
    assert tree_joints == ["Lift", "Shoulder", "Twist", "Elbow"]
    joints, excluded = _exported_joints(mech, tmp_path)
    assert joints == set(tree_joints) and not excluded
    from rswarp.export.newton import newton_q_columns, to_newton
    from rswarp.export.urdf import to_urdf_text

    model = to_newton(mech, shapes=False).finalize(device="cpu")
    depth_first = ["Lift", "Twist", "Shoulder", "Elbow"]  # parents first, each subtree whole (MuJoCo's order)
    assert [label.rsplit("/", 1)[-1] for label in model.joint_label[1:]] == depth_first
    assert list(newton_q_columns(mech)) == [graph.column(n) for n in depth_first] == [0, 3, 1, 2]
    urdf, _ = to_urdf_text(mech, tmp_path / "m.urdf")
    assert re.findall(r'<joint name="(\w+)" type="(?:revolute|prismatic)"', urdf) == tree_joints


def test_a_passive_joint_closes_the_loop_where_one_can():
    """Breadth-first in file order would reach Link3 through the passive Elbow first and make the
    active J4 close the loop; the graph spans the tree with active joints first."""
    links = tuple(Part(n) for n in ("Base", "Link1", "Link2", "Link3"))
    joints = (Joint("J1", "Base", "Link1"), Joint("Elbow", "Link1", "Link3", active=False),
              Joint("J2", "Link1", "Link2"), Joint("J4", "Link2", "Link3"))
    graph = Mechanism("M", base_link="Base", links=links, joints=joints).graph
    assert [j.name for j in graph.closing] == ["Elbow"]
    assert not graph.closes_all_active_loop(graph.closing[0])


def test_broken_references_are_left_out_and_reported():
    links = tuple(Part(n) for n in ("Base", "A", "B", "Loose"))
    joints = (Joint("J1", "Base", "A"), Joint("J1", "A", "B"), Joint("Bad", "A", "Nowhere"),
              Joint("Self", "A", "A"), Joint("Up", "A", "Base"), Joint("J2", "A", "B"))
    graph = Mechanism("M", base_link="Base", links=links, joints=joints).graph
    assert [j.name for j in graph.ignored] == ["J1", "Bad", "Self", "Up"]
    assert [j.name for j in graph.joints] == ["J1", "J2"] and graph.unreachable == ("Loose",)
    assert graph.path("B") == (joints[0], joints[5])


def test_adjacency_contracts_links_without_geometry():
    """MoveIt's rule: a link without geometry between two links makes them adjacent."""
    links = tuple(Part(n) for n in ("Base", "Hub", "A", "B"))
    joints = (Joint("J1", "Base", "Hub"), Joint("J2", "Hub", "A"), Joint("J3", "A", "B"))
    graph = Mechanism("M", base_link="Base", links=links, joints=joints).graph
    pairs = {tuple(sorted(p)) for p in graph.adjacent_pairs(has_geometry={"Base", "A", "B"})}
    assert pairs == {("A", "Base"), ("A", "B")}
    assert {tuple(sorted(p)) for p in graph.adjacent_pairs()} == {("Base", "Hub"), ("A", "Hub"), ("A", "B")}


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 40), st.integers(0, 30), st.integers(0, 10_000))
def test_joints_in_loops_equals_the_union_of_the_loops(n, extra, seed):
    """The near-linear marking gives what walking every loop gives, on random graphs."""
    rng = random.Random(seed)
    names = [f"L{i}" for i in range(n)]
    joints = [Joint(f"T{i}", names[rng.randrange(i)], names[i], active=rng.random() < 0.7) for i in range(1, n)]
    for k in range(extra):
        a, b = rng.randrange(n), rng.randrange(1, n)
        if a != b:
            joints.append(Joint(f"C{k}", names[a], names[b], active=False))
    graph = Mechanism("M", base_link="L0", links=tuple(Part(x) for x in names), joints=tuple(joints)).graph
    naive = {j.name for c in graph.closing for j in graph.loop(c)}
    assert graph.joints_in_loops == naive


def test_loops_of_a_long_chain_with_many_closing_joints():
    """20 000 links and 20 000 closing joints: each tree joint is marked once (a walk per loop
    would visit 200 million joints)."""
    n = 20_000
    names = [f"L{i}" for i in range(n)]
    joints = [Joint(f"T{i}", names[i - 1], names[i]) for i in range(1, n)]
    joints += [Joint(f"C{i}", names[0], names[i], active=False) for i in range(1, n)]
    mech = Mechanism("M", base_link="L0", links=tuple(Part(x) for x in names), joints=tuple(joints))
    assert len(mech.graph.joints_in_loops) == 2 * (n - 1)
