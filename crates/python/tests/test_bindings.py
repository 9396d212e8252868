"""Every binding against the command line's JSON on the shipped examples, and the predictions
against the library's reference values (crates/trueaxis/tests/it/python_reference.rs) to 1e-9."""

import csv
import pickle
import shutil
import sys
import tomllib

import numpy as np
import pytest

import trueaxis as ta
from conftest import ROOT, assert_same, cli_json, pandas

EX = ROOT / "examples"
KX = EX / "machines" / "kx8five.toml"
KX_ERRORS = EX / "errors" / "kx8five.toml"
CAMPAIGN = EX / "campaigns" / "kx8five" / "campaign.toml"


@pytest.mark.parametrize("name", ["kx8five", "c600u", "vmc3"])
def test_predict_equals_the_library_on_random_poses(name):
    machine = ta.Machine.from_file(EX / "machines" / f"{name}.toml")
    errors = ta.Errors.from_file(EX / "errors" / f"{name}.toml", machine)
    with open(ROOT / "crates/python/tests/data" / f"predict_{name}.csv") as f:
        rows = list(csv.reader(f))
    n = machine.axis_count if hasattr(machine, "axis_count") else len(machine.axes)
    assert rows[0] == list(machine.axes) + ta.PREDICTION_COLUMNS_WITH_DL
    data = np.array(rows[1:], dtype=float)
    assert data.shape == (200, n + 7)
    got = machine.predict(errors, data[:, :n], frame="machine", with_dl=True)
    assert got.shape == (200, 7) and got.dtype == np.float64
    assert np.max(np.abs(got - data[:, n:])) < 1e-9
    six = machine.predict(errors, data[:, :n], frame="machine")
    assert six.shape == (200, 6) and np.array_equal(six, got[:, :6])
    assert np.abs(got).max() > 1.0, "the errors are not all zero"


def test_predict_file_equals_the_cli():
    machine = ta.Machine.from_file(KX)
    errors = ta.Errors.from_file(KX_ERRORS, machine)
    poses = EX / "poses" / "kx8five.csv"
    for frame in ("workpiece", "machine"):
        expected = cli_json("predict", "--machine", KX, "--errors", KX_ERRORS, "--poses", poses, "--frame", frame,
                            "--tool-point", "0,0,300", "--work-point", "10,-5,20")
        got = machine.predict_file(errors, poses, frame=frame, tool_point=(0, 0, 300), work_point=(10, -5, 20))
        assert got == expected
        # the array path gives the same numbers before rounding to 1e-4
        array = machine.predict(errors, machine.read_poses(poses), frame=frame, tool_point=(0, 0, 300),
                                work_point=(10, -5, 20), with_dl=True)
        rounded = [[p[c] for c in ta.PREDICTION_COLUMNS_WITH_DL] for p in expected["poses"]]
        assert np.max(np.abs(array - np.array(rounded))) <= 0.5e-4 + 1e-12


def test_machine_and_errors_from_dicts_equal_the_files():
    with open(KX, "rb") as f:
        m_dict = tomllib.load(f)
    with open(KX_ERRORS, "rb") as f:
        e_dict = tomllib.load(f)
    a = ta.Machine.from_file(KX)
    b = ta.Machine.from_dict(m_dict)
    assert (a.name, a.axes, a.tool_point) == (b.name, b.axes, b.tool_point) == (a.name, "XYZAC", (0.0, 0.0, 300.0))
    poses = a.read_poses(EX / "poses" / "kx8five.csv")
    pa = a.predict(ta.Errors.from_file(KX_ERRORS, a), poses)
    pb = b.predict(ta.Errors.from_dict(e_dict, b), poses)
    assert np.array_equal(pa, pb)
    # pickling keeps the description
    c = pickle.loads(pickle.dumps(a))
    e = pickle.loads(pickle.dumps(ta.Errors.from_file(KX_ERRORS, a)))
    assert np.array_equal(c.predict(e, poses), pa)
    assert np.array_equal(a.predict(ta.Errors.zero(a), poses), np.zeros_like(pa))


def test_identify_equals_the_cli(tmp_path):
    machine = ta.Machine.from_file(KX)
    campaign = ta.Campaign.from_file(CAMPAIGN, machine)
    result = ta.identify(machine, campaign)
    expected = cli_json("identify", "--machine", KX, "--campaign", CAMPAIGN, "--out", tmp_path / "identified.toml")
    assert_same(result.to_dict(), expected)
    assert result.names == campaign.parameters and sorted(result.names) == sorted(expected["parameters"])
    for j, name in enumerate(result.names):
        assert abs(result.values[j] - expected["parameters"][name]["value"]) < 1e-9 * max(1, abs(result.values[j]))
    assert result.covariance.shape == (12, 12) and result.residuals.shape == (3 * 807,)
    assert result.errors_toml() == (tmp_path / "identified.toml").read_text()
    # the identified model predicts like the file the CLI wrote
    poses = machine.read_poses(EX / "poses" / "kx8five.csv")
    written = ta.Errors.from_file(tmp_path / "identified.toml", machine)
    assert np.array_equal(machine.predict(result.errors(), poses), machine.predict(written, poses))
    # the table of the unknowns: the CLI's values and uncertainties, row by row
    pandas()
    table = result.to_dataframe()
    assert list(table.columns) == ["name", "unit", "value", "std_uncertainty"] and len(table) == 12
    for row in table.itertuples():
        p = expected["parameters"][row.name]
        assert abs(row.value - p["value"]) < 1e-9 * max(1, abs(row.value)) and row.unit == p["unit"]


def test_to_dataframe_without_pandas_says_how_to_install_it(monkeypatch):
    machine = ta.Machine.from_file(KX)
    result = ta.identify(machine, ta.Campaign.from_file(CAMPAIGN, machine))
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas fails as if not installed
    with pytest.raises(ImportError, match="Identification.to_dataframe needs pandas, which is not installed: pip install pandas"):
        result.to_dataframe()


def test_campaign_from_dict_equals_the_file():
    machine = ta.Machine.from_file(KX)
    with open(CAMPAIGN, "rb") as f:
        d = tomllib.load(f)
    a = ta.identify(machine, ta.Campaign.from_file(CAMPAIGN, machine)).to_dict()
    b = ta.identify(machine, ta.Campaign.from_dict(d, machine, base_dir=CAMPAIGN.parent)).to_dict()
    assert_same(a, b, rel=0)


def test_uncertainty_from_a_design_equals_the_cli():
    design = EX / "uncertainty" / "kx8five_design.csv"
    for sources_file in ("kx8five_cyclic.toml", "kx8five_statistical.toml"):
        sources = EX / "uncertainty" / sources_file
        expected = cli_json("uncertainty", "--design", design, "--sources", sources, "--seed", "7")
        plan = ta.UncertaintyPlan.from_design(design, ta.Sources.from_file(sources), seed=7)
        assert plan.stages == len(expected["sources"]) + (1 if len(expected["sources"]) > 1 else 0)
        assert_same(plan.run(), expected)


def test_uncertainty_of_a_campaign_with_poses_equals_the_cli():
    sources = EX / "uncertainty" / "kx8five_cyclic.toml"
    poses = EX / "poses" / "kx8five.csv"
    expected = cli_json("uncertainty", "--machine", KX, "--campaign", CAMPAIGN, "--sources", sources,
                        "--poses", poses, "--frame", "machine", "--no-budget")
    machine = ta.Machine.from_file(KX)
    plan = ta.UncertaintyPlan.from_campaign(machine, ta.Campaign.from_file(CAMPAIGN, machine),
                                            ta.Sources.from_file(sources), budget=False)
    got = plan.run(poses=machine.read_poses(poses), frame="machine")
    assert_same(got, expected)
    assert len(got["poses"]) == len(expected["poses"]) > 0


def test_chunks_merged_in_order_equal_one_process():
    plan = ta.UncertaintyPlan.from_design(EX / "uncertainty" / "kx8five_design.csv",
                                          ta.Sources.from_file(EX / "uncertainty" / "kx8five_cyclic.toml"), seed=3)
    single = plan.run()
    state = plan.start()
    for stage in range(plan.stages):
        while (h := state.next_sequence(stage)) is not None:
            # uneven chunks (7 blocks of 500 trials, then the rest), computed out of order
            chunks = plan.chunks(h, 7)
            values = {c: plan.run_chunk(stage, c) for c in reversed(chunks)}
            state.push(stage, [(c, values[c]) for c in chunks])
    assert state.finish() == single
    # a pickled plan draws the same trials
    other = pickle.loads(pickle.dumps(plan))
    c = plan.chunks(4, 3)[1]
    assert np.array_equal(other.run_chunk(0, c), plan.run_chunk(0, c))
    assert plan.run_chunk(0, c).shape == (3 * ta.BLOCK, len(plan.parameters))


def test_optimal_design_equals_the_cli(small_campaign):
    machine = ta.Machine.from_file(KX)
    campaign = ta.Campaign.from_file(small_campaign, machine)
    expected = cli_json("design", "optimal", "--machine", KX, "--campaign", small_campaign, "--count", "14", "--starts", "3",
                        "--seed", "5")
    candidates = ta.Candidates(campaign)
    assert len(candidates) == 41
    got = candidates.exchange(14, starts=3, seed=5)
    assert_same(got, expected)
    assert len(got["chosen"]) == 14 and got["criteria"]["d"] <= got["all_candidates"]["d"] * 41 / 14
    # starts in chunks, merged in any order
    outcomes = candidates.exchange_starts(14, 2, 3, seed=5) + candidates.exchange_starts(14, 0, 2, seed=5)
    assert candidates.best_of(14, outcomes) == got
    # with progress: rounds of starts, the same design; calls end at (starts, starts)
    calls = []
    assert candidates.exchange(14, starts=3, seed=5, progress=lambda done, total: calls.append((done, total))) == got
    assert calls[-1] == (3, 3) and all(t == 3 for _, t in calls) and [d for d, _ in calls] == sorted({d for d, _ in calls})


class Stop(Exception):
    pass


def test_progress_callbacks_stop_a_run_and_reject_non_callables(small_campaign):
    machine = ta.Machine.from_file(KX)
    candidates = ta.Candidates(ta.Campaign.from_file(small_campaign, machine))
    calls = []

    def stop(done, total):
        calls.append(done)
        raise Stop(f"{done} of {total}")

    with pytest.raises(Stop):
        candidates.exchange(14, starts=40, seed=5, progress=stop)
    assert len(calls) == 1 and calls[0] < 40, "the run stopped at the first round"
    with pytest.raises(ta.InputError, match="progress: expected a callable"):
        candidates.exchange(14, starts=2, progress=3)
    plan = ta.UncertaintyPlan.from_design(EX / "uncertainty" / "kx8five_design.csv",
                                          ta.Sources.from_file(EX / "uncertainty" / "kx8five_cyclic.toml"), seed=7)
    seen = []
    doc = plan.run(progress=lambda done, total: seen.append((done, total)))
    assert doc == plan.run(), "progress does not change the result"
    total = plan.stages * plan.max_sequences
    assert seen and all(t == total for _, t in seen) and all(0 < d <= total for d, _ in seen)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)
    with pytest.raises(Stop):
        plan.run(progress=stop)


def test_iso230_2_equals_the_cli():
    path = EX / "data" / "iso230_2_x.csv"
    assert ta.iso230_2(path) == cli_json("iso230-2", path)


@pytest.mark.parametrize("fmt", ["linuxcnc", "linuxcnc-hal", "isg", "heidenhain", "siemens", "fanuc", "lattice", "csv", "json"])
def test_compensate_equals_the_cli(tmp_path, fmt):
    vmc = EX / "machines" / "vmc3.toml"
    errors = EX / "errors" / "vmc3.toml"
    a, b = tmp_path / "cli", tmp_path / "py"
    # force: LinuxCNC's and Fanuc's own-axis files leave more than half of vmc3's error
    expected = cli_json("compensate", "--machine", vmc, "--errors", errors, "--format", fmt, "--out", a, "--points", "21",
                        "--grid", "5,4,3", "--limit-um", "200", "--force")
    machine = ta.Machine.from_file(vmc)
    got = ta.compensate(machine, ta.Errors.from_file(errors, machine), fmt, b, points=21, grid=(5, 4, 3), limit_um=200, force=True).to_dict()
    assert got.pop("out") == str(b) and expected.pop("out") == str(a)
    assert got == expected
    for name in expected["files"]:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name


def test_nc_equals_the_cli(tmp_path):
    vmc = EX / "machines" / "vmc3.toml"
    errors = EX / "errors" / "vmc3.toml"
    for program in ("pocket.ngc", "arcs.ngc"):
        expected = cli_json("nc", "--machine", vmc, "--errors", errors, EX / "nc" / program, "--limit-um", "50")
        machine = ta.Machine.from_file(vmc)
        got = ta.correct_nc(machine, ta.Errors.from_file(errors, machine), EX / "nc" / program, limit_um=50)
        assert got == expected
        assert got["moves"] > 0 and got["program"]


def test_compensate_refuses_files_that_leave_more_than_they_remove(tmp_path):
    machine = ta.Machine.from_file(EX / "machines" / "vmc3.toml")
    errors = ta.Errors.from_file(EX / "errors" / "vmc3.toml", machine)
    with pytest.raises(ta.InputError, match="more than they remove"):
        ta.compensate(machine, errors, "linuxcnc", tmp_path / "joint")
    assert not (tmp_path / "joint").exists()


def test_prediction_columns_match_what_predict_returns():
    machine = ta.Machine.from_file(KX)
    errors = ta.Errors.from_file(KX_ERRORS, machine)
    poses = machine.read_poses(EX / "poses" / "kx8five.csv")
    six = machine.predict(errors, poses)
    seven = machine.predict(errors, poses, with_dl=True)
    assert ta.PREDICTION_COLUMNS == ["dx", "dy", "dz", "drx", "dry", "drz"]
    assert ta.PREDICTION_COLUMNS_WITH_DL == ta.PREDICTION_COLUMNS + ["dL"]
    assert ta.PREDICTION_UNITS == ["um"] * 3 + ["urad"] * 3 and ta.PREDICTION_UNITS_WITH_DL[-1] == "um"
    assert six.shape[1] == len(ta.PREDICTION_COLUMNS) and seven.shape[1] == len(ta.PREDICTION_COLUMNS_WITH_DL)
    pd = pandas()
    table = pd.DataFrame(six, columns=ta.PREDICTION_COLUMNS)
    assert list(table.columns) == ta.PREDICTION_COLUMNS and np.array_equal(table.to_numpy(), six)
    table = pd.DataFrame(seven, columns=ta.PREDICTION_COLUMNS_WITH_DL)
    # dL is the change of the tool point's distance from the workpiece point (um)
    assert np.array_equal(table["dL"].to_numpy(), seven[:, 6]) and np.array_equal(table["dx"].to_numpy(), six[:, 0])


def test_predict_in_place_on_a_non_multiple_of_the_block_and_many_chunks():
    """The in-place path (blocks of 8 poses, chunks per thread) equals predict_file's numbers for
    counts that are not multiples of the block, down to one pose and zero poses."""
    machine = ta.Machine.from_file(KX)
    errors = ta.Errors.from_file(KX_ERRORS, machine)
    base = machine.read_poses(EX / "poses" / "kx8five.csv")
    many = np.tile(base, (6003 // len(base) + 1, 1))[:6003]
    full = machine.predict(errors, many, with_dl=True)
    for count in (0, 1, 7, 9, 8 * 64 + 5, 6003):
        got = machine.predict(errors, many[:count], with_dl=True)
        assert got.shape == (count, 7) and np.array_equal(got, full[:count])
    # rows equal to a pose-by-pose evaluation (each pose alone)
    one_by_one = np.vstack([machine.predict(errors, many[i:i + 1], with_dl=True) for i in range(0, len(many), 97)])
    assert np.max(np.abs(one_by_one - full[::97])) < 1e-9


def test_predict_into_out_writes_and_returns_that_array():
    machine = ta.Machine.from_file(KX)
    errors = ta.Errors.from_file(KX_ERRORS, machine)
    poses = machine.read_poses(EX / "poses" / "kx8five.csv")
    expected = machine.predict(errors, poses, with_dl=True)
    buffer = np.full((len(poses), 7), np.nan)
    got = machine.predict(errors, poses, with_dl=True, out=buffer)
    assert got is buffer and np.array_equal(buffer, expected)
    for bad, text in [(np.empty((len(poses), 6)), r"shape \(5, 7\)"), (np.empty((len(poses), 7), dtype=np.float32), "float64"),
                      (np.empty((7, len(poses))).T, "C-contiguous"), ([[0.0] * 7] * len(poses), "float64")]:
        with pytest.raises(ta.InputError, match=text):
            machine.predict(errors, poses, with_dl=True, out=bad)
    frozen = np.empty((len(poses), 7))
    frozen.flags.writeable = False
    with pytest.raises(ta.InputError, match="out: "):
        machine.predict(errors, poses, with_dl=True, out=frozen)
