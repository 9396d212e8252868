"""A Monte Carlo budget and an optimal design on a dask.distributed LocalCluster equal the
single-process run for a fixed seed (bit for bit: the same dict)."""

import os

import pytest

import trueaxis as ta
from conftest import ROOT
from trueaxis.distributed import optimal_design, run_uncertainty

EX = ROOT / "examples"
if os.environ.get("TRUEAXIS_REQUIRE_DASK"):
    import dask.distributed  # noqa: F401  (CI installs it: the test must run)
distributed = pytest.importorskip("dask.distributed")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def test_uncertainty_budget_on_dask_equals_one_process(client):
    plan = ta.UncertaintyPlan.from_design(EX / "uncertainty" / "kx8five_design.csv",
                                          ta.Sources.from_file(EX / "uncertainty" / "kx8five_cyclic.toml"), seed=11)
    single = plan.run()
    assert single["converged"] and single["sequences"] >= 2
    assert run_uncertainty(plan, client, blocks_per_chunk=5, lookahead=3) == single
    assert run_uncertainty(plan, client) == single


def test_campaign_budget_with_poses_on_dask_equals_one_process(client):
    machine = ta.Machine.from_file(EX / "machines" / "kx8five.toml")
    campaign = ta.Campaign.from_file(EX / "campaigns" / "kx8five" / "campaign.toml", machine)
    plan = ta.UncertaintyPlan.from_campaign(machine, campaign, ta.Sources.from_file(EX / "uncertainty" / "kx8five_statistical.toml"))
    poses = machine.read_poses(EX / "poses" / "kx8five.csv")
    assert run_uncertainty(plan, client, poses=poses) == plan.run(poses=poses)


def test_optimal_design_on_dask_equals_one_process(client, small_campaign):
    machine = ta.Machine.from_file(EX / "machines" / "kx8five.toml")
    candidates = ta.Candidates(ta.Campaign.from_file(small_campaign, machine))
    single = candidates.exchange(14, starts=4, seed=9)
    assert optimal_design(candidates, client, 14, starts=4, seed=9) == single
    assert optimal_design(candidates, client, 14, starts=4, seed=9, starts_per_chunk=3) == single
