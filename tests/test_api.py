"""The package's front door: every name ``rswarp`` exports resolves (the lazy ones too, each module
found where ``_LAZY`` points), and ``rswarp.Cluster()``, as the README's Python section and
docs/ray.md write it, runs a batch on a local Ray instance with the results of a local run."""

from __future__ import annotations

import pytest

import rswarp

from conftest import DATA

FOLD = DATA / "collisions" / "fold.rsxml"


@pytest.mark.parametrize("name", sorted(set(rswarp.__all__) | set(rswarp._LAZY)))
def test_every_exported_name_resolves(name):
    assert getattr(rswarp, name) is not None


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'Clusters'"):
        rswarp.Clusters  # noqa: B018


def test_a_cluster_as_the_readme_makes_it_runs_a_small_batch(local_ray):
    """``rswarp.collisions(mech, samples=..., cluster=rswarp.Cluster())``: a local Ray instance
    (here the session's, used as it is), the batch cut into tasks, the local run's report."""
    from rswarp.sim.engine import identical

    cluster = rswarp.Cluster()
    assert cluster.address is None and cluster.device == "cpu"  # a local instance, CPU workers
    mech = rswarp.load(FOLD)
    here = rswarp.collisions(mech, samples=3000, seed=4)
    there = rswarp.collisions(mech, samples=3000, seed=4, cluster=cluster)
    assert identical(here, there) and here.report() == there.report()
    assert there.samples == here.samples >= 3000
