"""ISO 230-2 (with the correction to 20 degC), ISO 230-4 and the rotary-axis ballbar test (identify,
sensitivity, simulate) against the command line: the same library entry points, so the same documents
(exact), the same warnings and the same error messages."""

import warnings

import pytest

import trueaxis as ta
from conftest import ROOT, cli_error, cli_json, run_cli

EX = ROOT / "examples"
C600U = EX / "machines" / "c600u.toml"
BALLBAR = EX / "ballbar"
STEPS = [BALLBAR / f"{s}.csv" for s in ("A1", "A2", "C1", "C2")]


def stderr_messages(*args):
    """The warnings and notes the command line prints on stderr, without their prefixes."""
    code, _, err = run_cli(*args)
    assert code == 0, err
    out = []
    for line in err.splitlines():
        line = line.removeprefix("trueaxis: ")
        out.append(line.removeprefix("warning: "))
    return out


def caught(fn, *args, **kwargs):
    """(result, messages of the TrueaxisWarnings issued)."""
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        result = fn(*args, **kwargs)
    assert all(issubclass(x.category, ta.TrueaxisWarning) for x in w), [x.category for x in w]
    return result, [str(x.message).removeprefix("warning: ") for x in w]


# ISO 230-2


def test_iso230_2_of_a_laser_file_applies_its_material_temperature_as_the_cli():
    rtl = EX / "data" / "laser_x.rtl"
    got, messages = caught(ta.iso230_2, rtl)
    expected = cli_json("iso230-2", rtl)
    assert got == expected
    assert got["temperature_correction"]["source"] == "file"
    assert got["metadata"]["environment"]
    assert messages == stderr_messages("iso230-2", rtl, "--json")
    assert any("readings corrected to 20 degC" in m for m in messages)
    # kept as read
    kept = ta.iso230_2(rtl, no_file_temperature=True)
    assert kept == cli_json("iso230-2", rtl, "--no-file-temperature")
    assert kept["temperature_correction"] is None and kept != got


def test_iso230_2_with_temperature_options_equals_the_cli(tmp_path):
    path = EX / "data" / "iso230_2_x.csv"
    got = ta.iso230_2(path, scale_temperature=23.4, scale_expansion=11.5, temperature_datum=100.0)
    assert got == cli_json("iso230-2", path, "--scale-temperature", "23.4", "--scale-expansion", "11.5", "--temperature-datum", "100")
    both = ta.iso230_2(path, scale_temperature=23.4, scale_expansion=11.5, artefact_temperature="21", artefact_expansion=8.0)
    assert both == cli_json("iso230-2", path, "--scale-temperature", "23.4", "--scale-expansion", "11.5",
                            "--artefact-temperature", "21", "--artefact-expansion", "8")
    # a temperature column, one value per reading
    lines = path.read_text().splitlines()
    rows = [l for l in lines if l and not l.startswith("#")]
    table = tmp_path / "with_t.csv"
    table.write_text("\n".join([rows[0] + ",T:scale"] + [f"{r},{20 + 0.01 * i:.2f}" for i, r in enumerate(rows[1:])]) + "\n")
    column = ta.iso230_2(table, scale_temperature="T:scale", scale_expansion=11.5)
    assert column == cli_json("iso230-2", table, "--scale-temperature", "T:scale", "--scale-expansion", "11.5")
    assert column["temperature_correction"]["corrections"][0]["temperature"] == "T:scale"
    # the correction changes the results by the expansion: E at 20 degC differs from the raw one
    raw = ta.iso230_2(path)
    assert raw["temperature_correction"] is None and raw["E"] != got["E"]


def test_iso230_2_refusals_carry_the_cli_messages(tmp_path):
    kelvin = tmp_path / "kelvin.rtl"
    text = (EX / "data" / "laser_x.rtl").read_text(encoding="latin-1")
    for sensor in ("1 : 21.1", "2 : 21.3", "3 : 21.2"):
        text = text.replace(f"Mat temp {sensor}", f"Mat temp {sensor[:4]}294.3")
    kelvin.write_text(text, encoding="latin-1")
    code, message = cli_error("iso230-2", kelvin)
    assert code == 2 and "no workshop temperature" in message and message.endswith("(or give --no-file-temperature)")
    with pytest.raises(ta.InputError) as e:
        ta.iso230_2(kelvin)
    assert str(e.value) == message
    # a missing temperature column
    path = EX / "data" / "iso230_2_x.csv"
    code, message = cli_error("iso230-2", path, "--scale-temperature", "T:none", "--scale-expansion", "11.5")
    with pytest.raises(ta.InputError) as e:
        ta.iso230_2(path, scale_temperature="T:none", scale_expansion=11.5)
    assert code == 2 and str(e.value) == message
    # a rotary axis is not corrected for expansion
    rotary = tmp_path / "rotary.csv"
    rotary.write_text("target [deg],dev [urad],dir,run\n" + "".join(
        f"{t},{1.0 + 0.1 * r},{d},{r}\n" for t in (0, 90, 180) for d in "+-" for r in (1, 2)))
    code, message = cli_error("iso230-2", rotary, "--scale-temperature", "21", "--scale-expansion", "11.5")
    with pytest.raises(ta.InputError) as e:
        ta.iso230_2(rotary, scale_temperature=21.0, scale_expansion=11.5)
    assert code == 2 and str(e.value) == message and "rotary axis" in message
    with pytest.raises(ta.InputError, match="scale_temperature and scale_expansion must be given together"):
        ta.iso230_2(path, scale_temperature=21.0)


# ISO 230-4


def test_iso230_4_equals_the_cli():
    vmc3 = EX / "machines" / "vmc3.toml"
    xy = BALLBAR / "vmc3_xy.csv"
    got = ta.iso230_4(xy, machine=ta.Machine.from_file(vmc3), radius=100, centre=(0, 0, -200), feed=1000, pitch=10)
    expected = cli_json("ballbar", "iso230-4", xy, "--machine", vmc3, "--radius", "100", "--centre", "0,0,-200",
                        "--feed", "1000", "--pitch", "10")
    assert got == expected
    assert {r["dir"] for r in got["runs"]} == {"ccw", "cw"} and got["H_um"] is not None and got["diagnostics"]
    # without a machine: the Cartesian one; radius, feed and plane from the export's header
    for name in ("export_xy.txt", "raw_xy.txt"):
        export = BALLBAR / name
        got, messages = caught(ta.iso230_4, export)
        assert got == cli_json("ballbar", "iso230-4", export)
        assert messages == stderr_messages("ballbar", "iso230-4", export, "--json")
    yz = ta.iso230_4(xy, radius=100, plane="xy", spike_width=5.0)
    assert yz == cli_json("ballbar", "iso230-4", xy, "--radius", "100", "--plane", "xy", "--spike-width", "5")


def test_iso230_4_errors_carry_the_cli_messages():
    xy = BALLBAR / "vmc3_xy.csv"
    code, message = cli_error("ballbar", "iso230-4", xy)
    assert code == 2 and "give the nominal radius" in message
    with pytest.raises(ta.InputError) as e:
        ta.iso230_4(xy)
    assert str(e.value) == message
    code, message = cli_error("ballbar", "iso230-4", xy, "--radius", "100", "--feed", "0")
    with pytest.raises(ta.InputError) as e:
        ta.iso230_4(xy, radius=100, feed=0)
    assert code == 2 and str(e.value) == message == "--feed must be a positive number, got 0"
    with pytest.raises(ta.InputError, match="is not a plane"):
        ta.iso230_4(xy, radius=100, plane="xw")


# the rotary-axis ballbar test (Jiang 2014)


def test_ballbar_identify_equals_the_cli():
    machine = ta.Machine.from_file(C600U)
    got = ta.ballbar_identify(machine, *STEPS)
    expected = cli_json("ballbar", "identify", "--machine", C600U, "--a1", STEPS[0], "--a2", STEPS[1], "--c1", STEPS[2],
                        "--c2", STEPS[3])
    assert got == expected
    assert len(got["parameters"]) == 8 and all(p["std_uncertainty"] > 0 for p in got["parameters"].values())
    # swapped steps: the residual warnings, as the command line prints them
    swapped = [STEPS[1], STEPS[0], STEPS[2], STEPS[3]]
    got, messages = caught(ta.ballbar_identify, machine, *swapped, noise=0.1)
    args = ["ballbar", "identify", "--machine", C600U, "--a1", swapped[0], "--a2", swapped[1], "--c1", swapped[2],
            "--c2", swapped[3], "--noise", "0.1"]
    assert got == cli_json(*args)
    assert messages == got["warnings"] == stderr_messages(*args, "--json") and messages


def test_ballbar_identify_four_setup_with_pivot_offsets_equals_the_cli(tmp_path):
    geometry = ["--method", "four-setup", "--outer-positions", "-200,250", "--inner-positions", "0,78"]
    files = []
    for k, step in enumerate(("a1", "a2", "c1", "c2")):
        out = tmp_path / f"{step}.csv"
        code, _, err = run_cli("ballbar", "simulate", "--machine", C600U, "--errors", BALLBAR / "c600u_piges.toml",
                               "--test", step, *geometry, "--noise", "0.3", "--seed", str(k + 1), "--out", out)
        assert code == 0, err
        files.append(out)
    machine = ta.Machine.from_file(C600U)
    got = ta.ballbar_identify(machine, *files, method="four-setup", outer_positions=(-200, 250), inner_positions=(0, 78),
                              pivot_offset_a=(0.5, -0.2), pivot_offset_c=(0.1, 0.3))
    expected = cli_json("ballbar", "identify", "--machine", C600U, "--a1", files[0], "--a2", files[1], "--c1", files[2],
                        "--c2", files[3], *geometry, "--pivot-offset-a", "0.5,-0.2", "--pivot-offset-c", "0.1,0.3")
    assert got == expected and got["method"] == "four-setup"


def test_ballbar_identify_errors_carry_the_cli_messages():
    machine = ta.Machine.from_file(C600U)
    files = ["--a1", STEPS[0], "--a2", STEPS[1], "--c1", STEPS[2], "--c2", STEPS[3]]
    cases = [
        (dict(pivot_offset_a=(20, 0)), ["--pivot-offset-a", "20,0"]),
        (dict(method="two-pivot"), ["--method", "two-pivot"]),
        (dict(extended_length=90), ["--extended-length", "90"]),
    ]
    for kwargs, options in cases:
        code, message = cli_error("ballbar", "identify", "--machine", C600U, *files, *options)
        assert code == 2
        with pytest.raises(ta.InputError) as e:
            ta.ballbar_identify(machine, *STEPS, **kwargs)
        assert str(e.value) == message
    with pytest.raises(ta.InputError, match="method `ch5`: expected extended-bar, two-pivot or four-setup"):
        ta.ballbar_identify(machine, *STEPS, method="ch5")
    vmc3 = ta.Machine.from_file(EX / "machines" / "vmc3.toml")
    code, message = cli_error("ballbar", "identify", "--machine", EX / "machines" / "vmc3.toml", *files)
    with pytest.raises(ta.InputError) as e:
        ta.ballbar_identify(vmc3, *STEPS)
    assert code == 2 and str(e.value) == message


def test_ballbar_sensitivity_equals_the_cli():
    machine = ta.Machine.from_file(C600U)
    assert ta.ballbar_sensitivity(machine) == cli_json("ballbar", "sensitivity", "--machine", C600U)
    got = ta.ballbar_sensitivity(machine, method="four-setup", outer_positions=(-200, 250), inner_positions=(0, 78), setup_u=2,
                                 bar_u=0.5, noise=0.5, normal_length=120, extended_length=170)
    expected = cli_json("ballbar", "sensitivity", "--machine", C600U, "--method", "four-setup", "--outer-positions", "-200,250",
                        "--inner-positions", "0,78", "--setup-u", "2", "--bar-u", "0.5", "--noise", "0.5",
                        "--normal-length", "120", "--extended-length", "170")
    assert got == expected and len(got["parameters"]) == 8
    code, message = cli_error("ballbar", "sensitivity", "--machine", C600U, "--noise", "2000")
    with pytest.raises(ta.InputError) as e:
        ta.ballbar_sensitivity(machine, noise=2000)
    assert code == 2 and str(e.value) == message


def test_ballbar_simulate_equals_the_cli():
    """The same CSV, byte for byte: a step of the four-setup method on an erroneous machine with noise,
    and a circle in both senses with noise; the same refusal of a bad step."""
    machine = ta.Machine.from_file(C600U)
    errors = ta.Errors.from_file(BALLBAR / "c600u_piges.toml", machine)
    got = ta.ballbar_simulate(machine, "a1", errors=errors, method="four-setup", outer_positions=(-200, 250),
                              inner_positions=(0, 78), noise=0.5, seed=3, step=5)
    code, expected, err = run_cli("ballbar", "simulate", "--machine", C600U, "--errors", BALLBAR / "c600u_piges.toml",
                                  "--test", "a1", "--method", "four-setup", "--outer-positions", "-200,250",
                                  "--inner-positions", "0,78", "--noise", "0.5", "--seed", "3", "--step", "5")
    assert code == 0 and got == expected, err
    vmc3 = ta.Machine.from_file(EX / "machines" / "vmc3.toml")
    circle = ["ballbar", "simulate", "--machine", EX / "machines" / "vmc3.toml", "--test", "circle", "--centre", "0,0,-200"]
    assert ta.ballbar_simulate(vmc3, "circle", centre=(0, 0, -200), step=10, noise=1) == run_cli(*circle, "--step", "10",
                                                                                                "--noise", "1")[1]
    code, message = cli_error(*circle, "--step", "0")
    with pytest.raises(ta.InputError) as e:
        ta.ballbar_simulate(vmc3, "circle", step=0)
    assert code == 2 and str(e.value) == message

