"""Thermal error models from Python against `trueaxis thermal fit|predict --json`: the same library
entry points, so the same documents (exact), the same model and terms files (same bytes) and the
same error messages."""

import pytest

import trueaxis as ta
from conftest import ROOT, cli_error, cli_json

EX = ROOT / "examples"
CAMPAIGN = EX / "thermal" / "campaign.csv"
VMC3 = EX / "machines" / "vmc3.toml"

FITS = [
    (dict(train_runs=["warmup"]), ["--train-runs", "warmup"]),
    (dict(model="state-space", rates=1, train_runs=["warmup", "short"]),
     ["--model", "state-space", "--rates", "1", "--train-runs", "warmup,short"]),
    (dict(train_runs=["long"], validate="time-split:0.5"), ["--train-runs", "long", "--validate", "time-split:0.5"]),
    (dict(select="correlation:1", train_runs=["warmup"]), ["--select", "correlation:1", "--train-runs", "warmup"]),
    (dict(select="stepwise", train_runs=["warmup"]), ["--select", "stepwise", "--train-runs", "warmup"]),
    (dict(position="t", degree=1, no_intercept=True, sensors=["T:p1"]), ["--position", "t", "--degree", "1", "--no-intercept", "--sensors", "T:p1"]),
]


@pytest.mark.parametrize("kwargs,options", FITS)
def test_thermal_fit_equals_the_cli(tmp_path, kwargs, options):
    a, b = tmp_path / "cli.toml", tmp_path / "py.toml"
    expected = cli_json("thermal", "fit", "--data", CAMPAIGN, "--error", "dz", *options, "--out", a)
    got = ta.thermal_fit(CAMPAIGN, "dz", out=b, **kwargs)
    assert got == expected
    assert a.read_bytes() == b.read_bytes()
    assert got["training"]["samples"] > 0 and got["model"]["kind"] == kwargs.get("model", "regression").replace("-", "_")


def test_time_constants_equal_the_cli():
    expected = cli_json("thermal", "fit", "--data", CAMPAIGN, "--time-constants", "2", "--train-runs", "warmup", "--until", "14400")
    got = ta.thermal_fit(CAMPAIGN, time_constants=2, train_runs=["warmup"], until=14400)
    assert got == expected and len(got["tau_min"]) == 2 and len(got["amplitudes"]) == 2


def test_terms_file_equals_the_cli_and_loads_as_errors(tmp_path):
    a, b = tmp_path / "cli_terms.toml", tmp_path / "py_terms.toml"
    cli_json("thermal", "fit", "--data", CAMPAIGN, "--error", "dz", "--train-runs", "warmup", "--parameter", "EZZ",
             "--terms-out", a, "--machine", VMC3)
    machine = ta.Machine.from_file(VMC3)
    ta.thermal_fit(CAMPAIGN, "dz", train_runs=["warmup"], parameter="EZZ", terms_out=b, machine=machine)
    assert a.read_bytes() == b.read_bytes()
    errors = ta.Errors.from_file(b, machine)
    assert errors.sensors == ["T:p1", "T:p5"]


def test_thermal_predict_equals_the_cli_and_fits_round_trip(tmp_path):
    for kwargs, options in FITS[:2]:
        model = tmp_path / "model.toml"
        fitted = ta.thermal_fit(CAMPAIGN, "dz", out=model, **kwargs)
        got = ta.thermal_predict(model, CAMPAIGN)
        assert got == cli_json("thermal", "predict", "--model", model, "--data", CAMPAIGN)
        assert got["error"] == "dz" and len(got["samples"]) == 4 * 241
        # the training statistics of the fit are those of the prediction on the training run
        if "validate" not in kwargs and kwargs["train_runs"] == ["warmup"]:
            assert got["residuals"]["warmup"] == fitted["training"]
        # every validation run's statistics are those of the fit
        for run, stats in fitted["validation"].items():
            assert got["residuals"][run] == pytest.approx(stats, rel=1e-12, abs=1e-12)


def test_thermal_errors_carry_the_cli_messages(tmp_path):
    cases = [
        (dict(error="dz", validate="time-split:1.5"), ["--error", "dz", "--validate", "time-split:1.5"], 2, ta.InputError),
        (dict(error="dz", model="state-space", select="stepwise"), ["--error", "dz", "--model", "state-space", "--select", "stepwise"], 2,
         ta.InputError),
        (dict(error="nope"), ["--error", "nope"], 2, ta.InputError),
        (dict(error="dz", train_runs=["nope"]), ["--error", "dz", "--train-runs", "nope"], 2, ta.InputError),
        (dict(error="dz", model="state-space", rates=2, train_runs=["warmup"]),
         ["--error", "dz", "--model", "state-space", "--rates", "2", "--train-runs", "warmup"], 1, ta.ComputationError),
    ]
    for kwargs, options, status, kind in cases:
        code, message = cli_error("thermal", "fit", "--data", CAMPAIGN, *options)
        assert code == status
        with pytest.raises(kind) as e:
            ta.thermal_fit(CAMPAIGN, **kwargs)
        assert str(e.value) == message
    missing = tmp_path / "none.toml"
    code, message = cli_error("thermal", "predict", "--model", missing, "--data", CAMPAIGN)
    with pytest.raises(ta.InputError) as e:
        ta.thermal_predict(missing, CAMPAIGN)
    assert code == 2 and str(e.value) == message
    with pytest.raises(ta.InputError, match="model `ridge`: expected regression or state-space"):
        ta.thermal_fit(CAMPAIGN, "dz", model="ridge")
    with pytest.raises(ta.InputError, match="terms_out needs parameter"):
        ta.thermal_fit(CAMPAIGN, "dz", terms_out=tmp_path / "t.toml")


def test_screening_options_equal_the_cli(tmp_path):
    """skip_missing, split_gaps and robust as --skip-missing, --split-gaps and --robust: a logger
    dropout (one blank cell) and a gross dz reading (+40 um) in the warm-up run."""
    lines = CAMPAIGN.read_text().splitlines()
    cells = lines[11].split(",")
    cells[3] = ""
    lines[11] = ",".join(cells)
    cells = lines[50].split(",")
    cells[4] = f"{float(cells[4]) + 40.0:.2f}"
    lines[50] = ",".join(cells)
    damaged = tmp_path / "damaged.csv"
    damaged.write_text("\n".join(lines) + "\n")
    code, message = cli_error("thermal", "fit", "--data", damaged, "--error", "dz")
    assert code == 2 and "line 12" in message, message
    for robust in ["huber", "tukey"]:
        options = ["--train-runs", "warmup", "--skip-missing", "--split-gaps", "--robust", robust]
        expected = cli_json("thermal", "fit", "--data", damaged, "--error", "dz", *options)
        got = ta.thermal_fit(damaged, "dz", train_runs=["warmup"], skip_missing=True, split_gaps=True, robust=robust)
        assert got == expected
        assert [f["kind"] for f in got["data_quality"]] == ["missing cells"] and got["data_quality"][0]["lines"] == [12]
        assert got["robust"]["weighting"] == robust
        lines_down = [d["line"] for d in got["robust"]["downweighted"]]
        if robust == "huber":
            assert lines_down == [51]
        else:
            # Tukey's redescending weights also drop the heat-on and heat-off transients that the
            # regression model cannot follow (docs/screening.md): the +40 um reading among them
            assert 51 in lines_down and len(lines_down) < 40, lines_down
    with pytest.raises(ta.InputError, match="robust `bisquare`"):
        ta.thermal_fit(damaged, "dz", skip_missing=True, robust="bisquare")


MODES = [
    ("fin.toml", dict(count=6), ["--count", "6"]),
    ("plate.toml", dict(count=8, share=0.8), ["--count", "8", "--share", "0.8"]),
    ("fin.toml", dict(count=4, method="dense"), ["--count", "4", "--method", "dense"]),
    ("elongation.toml", dict(), []),
]


@pytest.mark.parametrize("model,kwargs,options", MODES)
def test_thermal_modes_equal_the_cli(model, kwargs, options):
    path = EX / "thermal" / model
    expected = cli_json("thermal", "modes", "--model", path, *options)
    calls = []
    got = ta.thermal_modes(path, progress=lambda done, total: calls.append((done, total)), **kwargs)
    assert isinstance(got, ta.ThermalModes) and got.to_dict() == expected
    # the weights' shares add up to one, the time constants fall, and the dominant modes are the
    # fewest, taken by weight, whose shares reach `share` (the rule, applied here again)
    share = kwargs.get("share", 0.9)
    assert got.share.sum() == pytest.approx(1.0, abs=1e-12)
    assert all(a >= b for a, b in zip(got.tau_s, got.tau_s[1:]))
    by_weight = sorted(expected["modes"], key=lambda m: -m["weight"])
    total, dominant = 0.0, []
    for m in by_weight:
        if total >= share - 1e-12 or m["weight"] == 0:
            break
        total += m["share"]
        dominant.append(m["mode"])
    assert sorted(dominant) == sorted(got.dominant)
    assert len(got.to_dataframe("modes")) == len(expected["modes"]) if _has_pandas() else True
    # progress: from the solver as modes converge, ending at (total, total)
    assert calls and calls[-1][0] == calls[-1][1] == len(expected["modes"])
    assert all(a[0] <= b[0] for a, b in zip(calls, calls[1:]))


def _has_pandas():
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


@pytest.mark.parametrize(
    "kwargs,message",
    [
        (dict(share=0.0), "the share 0 of the weight must lie in (0, 1]"),
        (dict(count=0), "the number of modes must be at least 1"),
        (dict(method="qr"), "method `qr`: expected auto, dense, lanczos or lobpcg"),
    ],
)
def test_thermal_modes_refuse_bad_input(kwargs, message):
    with pytest.raises(ta.InputError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")):
        ta.thermal_modes(EX / "thermal" / "fin.toml", **kwargs)


ELONGATION = ROOT / "examples" / "thermal" / "elongation.toml"


def test_thermal_place_with_scores_equals_the_cli():
    expected = cli_json("thermal", "place", "--model", ELONGATION, "--count", "3", "--share", "1", "--sensors", "2", "--score")
    got = ta.thermal_place(ELONGATION, count=3, share=1, sensors=2, score=True)
    assert isinstance(got, ta.ThermalPlacement) and got == expected
    methods = [s["method"] for s in got["scores"]]
    assert methods[0] == "modal" and "gauss (baseline)" in methods
    # the exhaustive yardstick has the smallest training error of all
    rms = got.column("scores", "training_rms_um")
    assert methods[-1] == "exhaustive (smallest training error)" and rms[-1] == rms.min()


def test_thermal_place_gauss_points_and_bad_input():
    # Gauss-Legendre points 0.5 -+ 0.5/sqrt(3) = 0.2113, 0.7887 m of the 1 m bar: nodes 6 and 18
    got = ta.thermal_place(ELONGATION, count=3, share=1, method="gauss", sensors=2)
    assert got.nodes.tolist() == [6, 18] and got == cli_json("thermal", "place", "--model", ELONGATION, "--count", "3",
                                                             "--share", "1", "--method", "gauss", "--sensors", "2")
    code, message = cli_error("thermal", "place", "--model", ELONGATION, "--share", "1.5")
    with pytest.raises(ta.InputError) as e:
        ta.thermal_place(ELONGATION, share=1.5)
    assert code == 2 and str(e.value) == message
    with pytest.raises(ta.InputError, match="method `best`"):
        ta.thermal_place(ELONGATION, method="best")
