"""The state of a pose in Python: directions of motion and temperatures in `predict`, against closed
forms (1e-9) and the command line; `compensate` with a poses file (corrections.csv), against the
command line (same bytes)."""

import csv

import numpy as np
import pytest

import trueaxis as ta
from conftest import ROOT, cli_error, cli_json

EX = ROOT / "examples"
VMC3 = EX / "machines" / "vmc3.toml"
BACKLASH = EX / "errors" / "vmc3_backlash.toml"
POSES_T = EX / "thermal" / "poses_with_T.csv"


def state_columns(path, machine, sensors):
    """(directions (N, axes) int8, temperatures (N, sensors)) from the dir:<axis> and T:<sensor> columns."""
    rows = list(csv.DictReader(l for l in open(path) if not l.startswith("#")))
    sign = {"+": 1, "-": -1, "": 0}
    directions = np.array([[sign[r.get(f"dir:{a}", "")] for a in machine.axes] for r in rows], dtype=np.int8)
    temperatures = np.array([[float(r[s]) for s in sensors] for r in rows])
    return directions, temperatures


def test_predict_with_directions_and_temperatures_equals_the_cli():
    machine = ta.Machine.from_file(VMC3)
    errors = ta.Errors.from_file(BACKLASH, machine)
    assert errors.sensors == ["T:column"]
    poses = machine.read_poses(POSES_T)
    directions, temperatures = state_columns(POSES_T, machine, errors.sensors)
    assert set(directions[:, 0]) == {1, -1} and temperatures.std() > 1
    got = machine.predict(errors, poses, directions=directions, temperatures=temperatures, with_dl=True)
    expected = cli_json("predict", "--machine", VMC3, "--errors", BACKLASH, "--poses", POSES_T)
    rounded = np.array([[p[c] for c in ta.PREDICTION_COLUMNS_WITH_DL] for p in expected["poses"]])
    assert np.max(np.abs(got - rounded)) <= 0.5e-4 + 1e-12
    # the file's own path gives the same document
    assert machine.predict_file(errors, POSES_T) == expected


def test_directions_and_temperatures_equal_the_model_written_for_that_state():
    """A direction of motion selects EXX+ or EXX- (at rest their mean) and a temperature multiplies
    the term 0.0115 um/(mm K) Z (T - 20) of EZZ: the same predictions (1e-9 um) as an error model
    written for that state, with EXX a plain table and the term folded into EZZ's polynomial."""
    import tomllib

    machine = ta.Machine.from_file(VMC3)
    errors = ta.Errors.from_file(BACKLASH, machine)
    with open(BACKLASH, "rb") as f:
        d = tomllib.load(f)
    plus, minus = d["table"].pop("EXX+"), d["table"].pop("EXX-")
    del d["term"]
    rng = np.random.default_rng(5)
    n = 50
    poses = np.column_stack([rng.uniform(-400, 400, n), rng.uniform(-250, 250, n), rng.uniform(-400, 0, n)])
    ezz = d["polynomial"]["EZZ"]["coefficients"]
    for direction, table in [(1, plus), (-1, minus), (0, {"position": plus["position"],
                                                        "value": [(a + b) / 2 for a, b in zip(plus["value"], minus["value"])]})]:
        for t in (20.0, 25.5, 17.0):
            d["table"]["EXX"] = table
            d["polynomial"]["EZZ"]["coefficients"] = [ezz[0], ezz[1] + 0.0115 * (t - 20)]
            fixed = ta.Errors.from_dict(d, machine)
            assert fixed.sensors == []
            directions = np.zeros((n, 3), dtype=np.int8)
            directions[:, 0] = direction
            got = machine.predict(errors, poses, directions=directions, temperatures=np.full((n, 1), t), with_dl=True)
            want = machine.predict(fixed, poses, with_dl=True)
            assert np.max(np.abs(got - want)) < 1e-9, (direction, t)
    # the backlash is seen: 3 um between the directions along X (vmc3's table carries X: dx = -EXX)
    at = lambda k: machine.predict(errors, poses, directions=np.column_stack([np.full(n, k), np.zeros((n, 2))]),
                                   temperatures=np.full((n, 1), 20.0))
    assert np.max(np.abs(at(1)[:, 0] - at(-1)[:, 0] + 3.0)) < 1e-3
    # without directions: at rest
    assert np.array_equal(machine.predict(errors, poses, temperatures=np.full((n, 1), 20.0)), at(0))


def test_bad_directions_name_the_problem():
    machine = ta.Machine.from_file(VMC3)
    errors = ta.Errors.from_file(BACKLASH, machine)
    poses = np.zeros((2, 3))
    t = np.full((2, 1), 20.0)
    with pytest.raises(ta.InputError, match=r"directions: expected an array of shape \(2, 3\) of -1, 0, \+1 for the axes XYZ"):
        machine.predict(errors, poses, temperatures=t, directions=np.zeros((2, 2), dtype=np.int8))
    with pytest.raises(ta.InputError, match=r"directions: row 1, axis Y: 2(\.0)? is not -1, 0 or \+1"):
        machine.predict(errors, poses, temperatures=t, directions=np.array([[0, 0, 0], [0, 2, 0]]))


@pytest.mark.parametrize("fmt", ["csv", "siemens"])
def test_compensate_with_poses_equals_the_cli(tmp_path, fmt):
    machine = ta.Machine.from_file(VMC3)
    errors = ta.Errors.from_file(BACKLASH, machine)
    a, b = tmp_path / "cli", tmp_path / "py"
    expected = cli_json("compensate", "--machine", VMC3, "--errors", BACKLASH, "--format", fmt, "--out", a, "--poses", POSES_T,
                        "--points", "21", "--reference", "X=10,Z=-200")
    got = ta.compensate(machine, errors, fmt, b, poses=POSES_T, points=21, reference={"X": 10, "Z": -200}).to_dict()
    assert got.pop("out") == str(b) and expected.pop("out") == str(a)
    assert got == expected
    assert "corrections.csv" in got["files"] and got["poses"]["count"] == 5
    for name in expected["files"]:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    # each pose corrected in its state: the + and - rows of a pose differ by the backlash
    rows = list(csv.DictReader(open(b / "corrections.csv")))
    assert abs(float(rows[0]["dX"]) - float(rows[1]["dX"]) - 3.0) < 0.05


def test_compensate_poses_temperature_and_directory_errors(tmp_path):
    machine = ta.Machine.from_file(VMC3)
    errors = ta.Errors.from_file(BACKLASH, machine)
    poses = EX / "poses" / "vmc3.csv"  # no T:column
    code, message = cli_error("compensate", "--machine", VMC3, "--errors", BACKLASH, "--format", "csv", "--out", tmp_path / "a",
                              "--poses", poses)
    with pytest.raises(ta.InputError) as e:
        ta.compensate(machine, errors, "csv", tmp_path / "b", poses=poses)
    assert code == 2 and str(e.value) == message and "missing column `T:column`" in message
    # given as an option, it applies to every pose
    a, b = tmp_path / "c", tmp_path / "d"
    expected = cli_json("compensate", "--machine", VMC3, "--errors", BACKLASH, "--format", "csv", "--out", a, "--poses", poses,
                        "--temperature", "T:column=24.5")
    got = ta.compensate(machine, errors, "csv", b, poses=poses, temperatures={"T:column": 24.5}).to_dict()
    assert got.pop("out") == str(b) and expected.pop("out") == str(a) and got == expected
    assert (a / "corrections.csv").read_bytes() == (b / "corrections.csv").read_bytes()
    # an unknown sensor, and an output directory holding other files
    code, message = cli_error("compensate", "--machine", VMC3, "--errors", BACKLASH, "--format", "csv", "--out", tmp_path / "e",
                              "--temperature", "T:spindle=30")
    with pytest.raises(ta.InputError) as e:
        ta.compensate(machine, errors, "csv", tmp_path / "e", temperatures={"T:spindle": 30.0})
    assert code == 2 and str(e.value) == message
    code, message = cli_error("compensate", "--machine", VMC3, "--errors", BACKLASH, "--format", "heidenhain", "--out", a)
    with pytest.raises(ta.InputError) as e:
        ta.compensate(machine, errors, "heidenhain", a)
    assert code == 2 and str(e.value) == message and "nothing was written" in message
    with pytest.raises(ta.InputError, match="reference: machine `.*` has no axis Q"):
        ta.compensate(machine, errors, "csv", tmp_path / "f", reference={"Q": 1.0})
