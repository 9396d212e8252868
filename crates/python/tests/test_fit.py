"""`trueaxis.fit` against the command line: the library's direct fit that `trueaxis fit` runs, so
the document and the error-values file are the command's (exact); an exact quadratic is fitted
with no residual (a closed form); bad input raises the command's message."""

import warnings

import numpy as np
import pytest

import trueaxis as ta
from conftest import ROOT, cli_error, cli_json

EX = ROOT / "examples"
VMC3 = EX / "machines" / "vmc3.toml"
LASER = EX / "data" / "laser_x.csv"


def quiet(f, *args, **kwargs):
    """f(...) with the TrueaxisWarnings it issues recorded: (result, messages)."""
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always", ta.TrueaxisWarning)
        result = f(*args, **kwargs)
    assert all(issubclass(x.category, ta.TrueaxisWarning) for x in w)
    return result, [str(x.message) for x in w]


def test_fit_equals_the_cli_with_its_errors_file(tmp_path):
    a, b = tmp_path / "cli.toml", tmp_path / "py.toml"
    expected = cli_json("fit", "--data", LASER, "--parameter", "EXX", "--machine", VMC3, "--at", "Z=-200",
                        "--knot-spacing", "100", "--stepwise", "0.9999", "--direction", "both", "--errors-out", a)
    got, _ = quiet(ta.fit, LASER, "EXX", machine=ta.Machine.from_file(VMC3), at={"Z": -200}, knot_spacing=100,
                   stepwise=0.9999, direction="both", errors_out=b)
    assert isinstance(got, ta.DirectFit) and got.to_dict() == expected
    assert a.read_bytes() == b.read_bytes()
    # the file holds both directions and loads on the machine
    ta.Errors.from_file(b, ta.Machine.from_file(VMC3))
    assert "EXX+" in b.read_text() and "EXX-" in b.read_text()
    assert expected["plus"]["unit"] == "um" and expected["plus"]["observations"] > 0


def test_fit_with_the_temperature_correction_equals_the_cli():
    expected = cli_json("fit", "--data", LASER, "--parameter", "EXX", "--family", "legendre", "--degree", "3",
                        "--scale-temperature", "21.3", "--scale-expansion", "11.5")
    got, _ = quiet(ta.fit, LASER, "EXX", family="legendre", degree=3, scale_temperature=21.3, scale_expansion=11.5)
    assert got == expected and got["temperature_correction"]["source"] == "options"


def test_an_exact_quadratic_is_fitted_with_no_residual(tmp_path):
    # dev = 1 + 0.02 x - 1e-5 x^2 um over -400..400 mm: a degree-2 polynomial basis holds it exactly
    x = np.linspace(-400, 400, 33)
    data = tmp_path / "quadratic.csv"
    data.write_text("target,dev\n" + "".join(f"{p},{float(1 + 0.02 * p - 1e-5 * p * p)!r}\n" for p in x))
    got, _ = quiet(ta.fit, data, "EXX", degree=2)
    assert got["observations"] == 33
    assert got["residual_rms"] == pytest.approx(0.0, abs=1e-9)
    assert got["max_abs_residual"] == pytest.approx(0.0, abs=1e-9)
    assert got == cli_json("fit", "--data", data, "--parameter", "EXX", "--degree", "2")


def test_fit_errors_carry_the_cli_messages(tmp_path):
    code, message = cli_error("fit", "--data", LASER, "--parameter", "EC0Y")
    assert code == 2
    with pytest.raises(ta.InputError) as e:
        ta.fit(LASER, "EC0Y")
    assert str(e.value) == message and "--parameter" in message
    code, message = cli_error("fit", "--data", LASER, "--parameter", "EXX", "--knot-spacing=-5")
    with pytest.raises(ta.InputError, match="--knot-spacing -5") as e:
        ta.fit(LASER, "EXX", knot_spacing=-5)
    assert str(e.value) == message
    with pytest.raises(ta.InputError, match="needs --machine"):
        ta.fit(LASER, "EXX", errors_out=tmp_path / "e.toml")
    assert not (tmp_path / "e.toml").exists()
    with pytest.raises(ta.InputError, match="scale_temperature and scale_expansion"):
        ta.fit(LASER, "EXX", scale_temperature=21.3)
