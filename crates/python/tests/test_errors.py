"""trueaxis errors raise the exception of their kind with the command line's message:
InputError where the CLI exits 2, ComputationError where it exits 1, ResourceError where it exits 3
(the environment: a full disk, a permission)."""

import os
import stat

import numpy as np
import pytest

import trueaxis as ta
from conftest import ROOT, cli_error

EX = ROOT / "examples"
KX = EX / "machines" / "kx8five.toml"


def test_the_classes():
    assert issubclass(ta.InputError, ta.TrueaxisError) and issubclass(ta.ComputationError, ta.TrueaxisError)
    assert issubclass(ta.TrueaxisError, Exception) and not issubclass(ta.InputError, ta.ComputationError)
    assert issubclass(ta.ResourceError, ta.TrueaxisError) and not issubclass(ta.ResourceError, ta.InputError)


def full_device(tmp_path):
    """A device on which every write fails with ENOSPC: as root a private node (the numbers of
    /dev/full), so that a regression could never replace the system's; else /dev/full."""
    if os.geteuid() != 0:
        return "/dev/full"
    device = tmp_path / "full"
    os.mknod(device, 0o666 | stat.S_IFCHR, os.makedev(1, 7))
    return str(device)


def test_a_full_disk_is_the_environment_with_the_cli_message(tmp_path):
    # a device is written in place, never replaced
    full = full_device(tmp_path)
    campaign = EX / "thermal" / "campaign.csv"
    code, message = cli_error("thermal", "fit", "--data", campaign, "--error", "dz", "--train-runs", "warmup", "--out", full)
    assert code == 3 and "No space left on device" in message
    with pytest.raises(ta.ResourceError) as e:
        ta.thermal_fit(campaign, "dz", train_runs=["warmup"], out=full)
    assert str(e.value) == message
    assert stat.S_ISCHR(os.stat(full).st_mode)


def test_a_missing_machine_file_is_bad_input_with_the_cli_message(tmp_path):
    missing = tmp_path / "nope.toml"
    code, message = cli_error("predict", "--machine", missing, "--errors", EX / "errors" / "kx8five.toml",
                              "--poses", EX / "poses" / "kx8five.csv")
    assert code == 2
    with pytest.raises(ta.InputError) as e:
        ta.Machine.from_file(missing)
    assert str(e.value) == message


def test_a_bad_error_file_is_bad_input_with_the_cli_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[constant]\nEXQ = 1.0\n")
    code, message = cli_error("predict", "--machine", KX, "--errors", bad, "--poses", EX / "poses" / "kx8five.csv")
    assert code == 2
    machine = ta.Machine.from_file(KX)
    with pytest.raises(ta.InputError) as e:
        ta.Errors.from_file(bad, machine)
    assert str(e.value) == message


def test_a_rank_deficient_campaign_is_a_failed_computation_with_the_cli_message():
    paper = EX / "campaigns" / "kx8five" / "paper14.toml"
    code, message = cli_error("identify", "--machine", KX, "--campaign", paper)
    assert code == 1
    machine = ta.Machine.from_file(KX)
    with pytest.raises(ta.ComputationError) as e:
        ta.identify(machine, ta.Campaign.from_file(paper, machine))
    assert str(e.value) == message
    assert "cannot be separated" in message
    # allowed, it is solved (minimum norm) and the unseen parameters have no uncertainty
    r = ta.identify(machine, ta.Campaign.from_file(paper, machine), allow_rank_deficient=True)
    assert np.isnan(r.std_uncertainty).any() and np.isfinite(r.values).all()


def test_bad_uncertainty_settings_are_bad_input_with_the_cli_message(tmp_path):
    sources = tmp_path / "s.toml"
    text = (EX / "uncertainty" / "kx8five_cyclic.toml").read_text().replace("trials_per_sequence = 10000", "trials_per_sequence = 10")
    sources.write_text(text)
    design = EX / "uncertainty" / "kx8five_design.csv"
    code, message = cli_error("uncertainty", "--design", design, "--sources", sources)
    assert code == 2
    with pytest.raises(ta.InputError) as e:
        ta.UncertaintyPlan.from_design(design, ta.Sources.from_file(sources))
    assert str(e.value) == message


def test_an_iso230_2_file_with_too_few_runs_is_bad_input_with_the_cli_message(tmp_path):
    f = tmp_path / "few.csv"
    f.write_text("target,dev,dir,run\n0,1.0,+,1\n0,1.2,-,1\n100,2.0,+,1\n100,2.1,-,1\n")
    code, message = cli_error("iso230-2", f)
    assert code == 2
    with pytest.raises(ta.InputError) as e:
        ta.iso230_2(f)
    assert str(e.value) == message


def test_array_shape_and_range_errors_name_the_problem():
    machine = ta.Machine.from_file(KX)
    errors = ta.Errors.from_file(EX / "errors" / "kx8five.toml", machine)
    with pytest.raises(ta.InputError, match=r"shape \(N, 5\) with the axes XYZAC"):
        machine.predict(errors, np.zeros((3, 4)))
    poses = np.zeros((2, 5))
    poses[1, 0] = 1e6
    with pytest.raises(ta.InputError, match="row 1: axis X at 1000000 mm is outside its range"):
        machine.predict(errors, poses)
    with pytest.raises(ta.InputError, match="frame `tool`"):
        machine.predict(errors, np.zeros((1, 5)), frame="tool")


def test_bad_points_and_pose_types_are_input_errors():
    machine = ta.Machine.from_file(KX)
    errors = ta.Errors.from_file(EX / "errors" / "kx8five.toml", machine)
    poses = np.zeros((2, 5))
    for point, text in [((1, 2), "expected 3 numbers x, y, z in mm, got 2"), ("abc", "expected 3 numbers"),
                        ((0, 0, float("nan")), "x, y, z must be finite")]:
        with pytest.raises(ta.InputError, match=f"tool_point: {text}"):
            machine.predict(errors, poses, tool_point=point)
        with pytest.raises(ta.InputError, match=f"work_point: {text}"):
            machine.predict(errors, poses, work_point=point)
    with pytest.raises(ta.InputError, match="poses: not an array of numbers"):
        machine.predict(errors, [["a", 0, 0, 0, 0]])
    with pytest.raises(ta.InputError, match="expected a 2-dimensional array, got 1"):
        machine.predict(errors, np.zeros(5))
    with pytest.raises(ta.InputError, match="not -1, 0 or"):
        machine.predict(errors, poses, directions=np.full((2, 5), 2))


def test_a_huge_number_gives_a_short_message():
    machine = ta.Machine.from_file(KX)
    errors = ta.Errors.from_file(EX / "errors" / "kx8five.toml", machine)
    poses = np.zeros((2, 5))
    poses[1, 1] = 1e300
    with pytest.raises(ta.InputError) as e:
        machine.predict(errors, poses)
    assert str(e.value).startswith("poses: row 1: axis Y at 1e300 mm is outside its range")
    assert len(str(e.value)) < 100, str(e.value)
    poses[1, 0] = 123456789.123456789
    with pytest.raises(ta.InputError, match=r"axis X at 1\.234568e8 mm is outside"):
        machine.predict(errors, poses)


def test_conversions_are_documented_and_give_the_same_numbers():
    """float32, int64 and nested lists are converted to float64 (docs/python.md)."""
    machine = ta.Machine.from_file(KX)
    errors = ta.Errors.from_file(EX / "errors" / "kx8five.toml", machine)
    poses = np.array([[100, -50, -200, 10, 30], [0, 0, 0, 0, 0]], dtype=np.int64)
    expected = machine.predict(errors, poses.astype(float))
    for p in (poses, poses.astype(np.float32), poses.tolist(), np.asfortranarray(poses.astype(float))):
        assert np.array_equal(machine.predict(errors, p), expected)
