"""The typed results (trueaxis.results): `to_dict()` equal to the command line's --json, named
fields as numpy arrays that agree with the document and with each other (closed relations of the
GUM and of a residual), tables as pandas DataFrames, the old dict access, pickling, clear errors."""

import pickle

import numpy as np
import pytest

import trueaxis as ta
from conftest import ROOT, assert_same, cli_json, pandas

EX = ROOT / "examples"
DESIGN = EX / "uncertainty" / "kx8five_design.csv"
CYCLIC = EX / "uncertainty" / "kx8five_cyclic.toml"


@pytest.fixture(scope="module")
def budget():
    return ta.UncertaintyPlan.from_design(DESIGN, ta.Sources.from_file(CYCLIC)).run()


def test_uncertainty_budget_arrays_equal_the_cli_document(budget):
    expected = cli_json("uncertainty", "--design", DESIGN, "--sources", CYCLIC)
    assert isinstance(budget, ta.UncertaintyBudget)
    assert_same(budget.to_dict(), expected)
    n = len(expected["parameter_order"])
    assert budget.names == expected["parameter_order"] and n == 14
    for j, name in enumerate(budget.names):
        p = expected["parameters"][name]
        assert budget.units[j] == p["unit"]
        assert budget.std_uncertainty[j] == pytest.approx(p["std_uncertainty"], rel=1e-12)
        assert budget.interval[j].tolist() == pytest.approx(p["interval"], rel=1e-12)
    assert budget.covariance.shape == budget.gum_covariance.shape == (n, n)
    assert budget.covariance.tolist() == expected["covariance"]["monte_carlo"]
    # the second formulation: standard uncertainties are the square roots of the covariance's
    # diagonal; with independent sources the GUM variances of the sources add up (JCGM 100 eq. 10)
    assert np.allclose(np.sqrt(np.diag(budget.covariance)), budget.std_uncertainty, rtol=1e-9)
    assert np.allclose(np.sqrt(np.diag(budget.gum_covariance)), budget.gum_std_uncertainty, rtol=1e-9)
    assert budget.sources == ["drift", "sensors", "transformation"] and budget.budget.shape == (n, 3)
    assert np.allclose(np.sqrt((budget.budget ** 2).sum(axis=1)), budget.gum_std_uncertainty, rtol=1e-9)
    # Monte Carlo and GUM agree on this linear model within the Monte Carlo's tolerance (0.1 of the
    # smallest uncertainty is far wider than the 2 % seen)
    assert np.allclose(budget.std_uncertainty, budget.gum_std_uncertainty, rtol=0.02)
    # plain fields: numbers, arrays of integers, Records
    assert budget.converged is True and budget.observations == 2421
    assert budget.budget_sequences.dtype == np.int64
    assert budget.history[0].sequence == expected["history"][0]["sequence"]


def test_uncertainty_budget_table_old_access_and_pickle(budget):
    pd = pandas()
    table = budget.to_dataframe()
    assert list(table["name"]) == budget.names and np.array_equal(table["std_uncertainty"].to_numpy(), budget.std_uncertainty)
    assert "gum.std_uncertainty" in table.columns and "gum_std_uncertainty_per_source.drift" in table.columns
    assert isinstance(table, pd.DataFrame) and budget.table_names == ["parameters", "poses", "history"]
    # the dict of earlier versions: keys give the plain JSON values, and the result equals its document
    assert budget["parameters"]["TX"]["unit"] == "um" and "covariance" in budget and budget == budget.to_dict()
    assert pickle.loads(pickle.dumps(budget)) == budget
    with pytest.raises(AttributeError, match="UncertaintyBudget has no field `covarience`"):
        budget.covarience
    with pytest.raises(AttributeError, match="read-only"):
        budget.seed = 3
    with pytest.raises(KeyError, match="no table `runs`"):
        budget.to_dataframe("runs")


def test_evaluations_are_typed_with_their_tables():
    pd = pandas()
    test = ta.iso230_2(EX / "data" / "iso230_2_x.csv")
    expected = cli_json("iso230-2", EX / "data" / "iso230_2_x.csv")
    assert isinstance(test, ta.PositioningTest) and test.to_dict() == expected
    assert test.A == expected["A"] and np.array_equal(test.targets, expected["targets"])
    positions = test.to_dataframe()
    assert len(positions) == len(expected["positions"]) and isinstance(positions, pd.DataFrame)
    assert np.array_equal(test.column("positions", "target"), [p["target"] for p in expected["positions"]])
    vmc3 = ta.Machine.from_file(EX / "machines" / "vmc3.toml")
    circle = ta.iso230_4(EX / "ballbar" / "vmc3_xy.csv", machine=vmc3, radius=100, centre=(0, 0, -200), feed=1000, pitch=10)
    assert isinstance(circle, ta.CircularTest) and circle.table_names == ["runs", "diagnostics"]
    runs = circle.to_dataframe()
    assert list(runs["dir"]) == [r["dir"] for r in circle["runs"]] and "G_um" in runs.columns
    assert circle.runs[0].centre_um.shape == (2,)
    c600u = ta.Machine.from_file(EX / "machines" / "c600u.toml")
    piges = ta.ballbar_identify(c600u, *[EX / "ballbar" / f"{s}.csv" for s in ("A1", "A2", "C1", "C2")])
    assert isinstance(piges, ta.BallbarIdentification) and len(piges.names) == 8
    assert np.array_equal(piges.values, [piges["parameters"][n]["value"] for n in piges.names])
    assert (piges.std_uncertainty > 0).all() and list(piges.to_dataframe()["name"]) == piges.names
    assert isinstance(ta.ballbar_sensitivity(c600u), ta.BallbarSensitivity)


def test_thermal_results_and_the_residual_relation(tmp_path):
    pandas()
    model = tmp_path / "dz.toml"
    fit = ta.thermal_fit(EX / "thermal" / "campaign.csv", "dz", train_runs=["warmup"], out=model)
    assert isinstance(fit, ta.ThermalFit) and fit.model.sensors == ["T:p1", "T:p5"]
    parts = fit.to_dataframe()
    assert list(parts["part"]) == ["training", *fit["validation"]] and parts["rms"].iloc[0] == fit.training.rms
    prediction = ta.thermal_predict(model, EX / "thermal" / "campaign.csv")
    samples = prediction.to_dataframe()
    # residual = measured - predicted, and the per-run rms of the samples is the document's
    assert np.allclose(samples["residual"], samples["measured"] - samples["predicted"], atol=1e-12)
    assert np.array_equal(prediction.predicted, samples["predicted"].to_numpy()) and prediction.t[1] == 120.0
    for _, row in prediction.to_dataframe("residuals").iterrows():
        r = samples[samples["run"] == row["run"]]["residual"].to_numpy()
        assert np.sqrt(np.mean(r ** 2)) == pytest.approx(row["rms"], rel=1e-9)


def test_to_dataframe_without_pandas_says_how_to_install(monkeypatch, budget):
    import builtins

    real = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas":
            raise ImportError("no pandas")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    with pytest.raises(ImportError, match="UncertaintyBudget.to_dataframe needs pandas, which is not installed: pip install pandas"):
        budget.to_dataframe()
