//! `trueaxis fit` end to end on the shipped laser data (examples/data/laser_x.csv, simulated with a
//! known pitch error, backlash, drift and noise), the sign of a workpiece-carrying slide, the Abbe
//! subtraction of known angular errors, and bad input.

use crate::support::{arg, failed, json_of, root, trueaxis, vmc3};

/// The positioning error the example data were generated with (um, x in mm): the laser reading
/// (tool relative to workpiece, actual minus target) without backlash, drift and noise.
fn generated(x: f64) -> f64 {
    let mut e = 0.012 * x + 1.5e-5 * x * x;
    if x > -100.0 {
        e -= 4e-5 * (x + 100.0).powi(2);
    }
    if x > 200.0 {
        e += 6e-5 * (x - 200.0).powi(2);
    }
    e
}

/// The fitted EXX of the + direction (`[basis."EXX+"]`).
fn fitted_exx(errors_file: &std::path::Path) -> impl Fn(f64) -> f64 {
    fitted_exx_of(errors_file, trueaxis::error_model::Direction::Positive)
}

fn fitted_exx_of(errors_file: &std::path::Path, direction: trueaxis::error_model::Direction) -> impl Fn(f64) -> f64 {
    let machine = trueaxis::machine::Machine::load(root().join("examples/machines/vmc3.toml")).unwrap();
    let model = trueaxis::error_model::ErrorModel::load(errors_file, &machine).unwrap();
    let exx = trueaxis::machine::ParameterId::parse("EXX").unwrap();
    let f = model.directional_entries().find(|(id, d, _)| **id == exx && *d == Some(direction)).unwrap().2.clone();
    move |x| f.evaluate(x)
}

const FIT: [&str; 12] = [
    "fit",
    "--data",
    "examples/data/laser_x.csv",
    "--parameter",
    "EXX",
    "--knot-spacing",
    "100",
    "--stepwise",
    "0.9999",
    "--drift",
    "--direction",
    "both",
];

#[test]
fn fit_with_the_machine_recovers_the_error_with_the_sign_of_a_table_axis() {
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("errors.toml");
    std::fs::copy(root().join("examples/errors/vmc3.toml"), &errors).unwrap();
    let plot = dir.path().join("exx.svg");
    let mut args = FIT.to_vec();
    let (e, p) = (arg(&errors), arg(&plot));
    args.extend(["--machine", "examples/machines/vmc3.toml", "--at", "Z=-200", "--errors-out", e, "--plot", p, "--json"]);
    let out = trueaxis(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let both: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let doc = &both["plus"];
    assert_eq!(doc["parameter"], "EXX");
    assert_eq!(doc["unit"], "um");
    assert_eq!(doc["observations"], 205);
    // the simulated noise is 0.15 um
    let sigma = doc["residual_std"].as_f64().unwrap();
    assert!((sigma - 0.15).abs() < 0.03, "residual std {sigma}");
    // X carries the table (direction -x): the reading is -EXX, so EXX(x) - EXX(0) = -(e(x) - e(0))
    let exx = fitted_exx(&errors);
    for x in [-400.0, -250.0, -100.0, 0.0, 120.0, 260.0, 400.0] {
        let got = exx(x) - exx(0.0);
        let want = -(generated(x) - generated(0.0));
        assert!((got - want).abs() < 0.25, "at {x}: {got} vs {want}");
    }
    // bidirectional: the reading of the + approach is 0.8 um above that of the - approach (the
    // generated backlash), so EXX+ - EXX- = -0.8 um; tolerance 0.2 um = 4.5 standard uncertainties
    // of the difference of the two fitted constants (0.03 um each)
    let exx_minus = fitted_exx_of(&errors, trueaxis::error_model::Direction::Negative);
    for x in [-300.0, 0.0, 300.0] {
        let b = exx(x) - exx_minus(x);
        assert!((b + 0.8).abs() < 0.2, "EXX+ - EXX- at {x}: {b}");
    }
    // the file is still a valid error-values file for predict, with the other errors kept
    let text = std::fs::read_to_string(&errors).unwrap();
    assert!(text.contains("[basis.\"EXX+\"]") && text.contains("[basis.EXX-]") && text.contains("EC0X = 12.0"), "{text}");
    let pred = trueaxis(&vmc3(&["predict"], &["--errors", e, "--poses", "examples/poses/vmc3.csv"]));
    assert!(pred.status.success(), "{}", String::from_utf8_lossy(&pred.stderr));
    let svg = std::fs::read_to_string(dir.path().join("exx_plus.svg")).unwrap();
    assert!(!plot.exists(), "with both directions the plots are exx_plus.svg and exx_minus.svg");
    assert!(dir.path().join("exx_minus.svg").exists());
    assert!(svg.contains("95 % prediction interval") && svg.contains("EXX (um)"));
}

fn coefficients(doc: &serde_json::Value) -> Vec<f64> {
    doc["terms"].as_array().unwrap().iter().map(|t| t["coefficient"].as_f64().unwrap()).collect()
}

#[test]
fn without_a_machine_the_readings_are_the_values() {
    // with vmc3 the X slide carries the table, so EXX = -reading: every coefficient changes sign
    let mut args = FIT.to_vec();
    args.push("--json");
    let without = json_of(&args);
    args.extend(["--machine", "examples/machines/vmc3.toml"]);
    let with = json_of(&args);
    for direction in ["plus", "minus"] {
        let (a, b) = (coefficients(&without[direction]), coefficients(&with[direction]));
        assert_eq!(a.len(), b.len());
        for (a, b) in a.iter().zip(&b) {
            assert!((a + b).abs() <= 1e-9 * a.abs().max(1e-3), "{direction}: {a} vs {b}");
        }
    }
    // but a file for `predict` is only written for a machine it was checked against
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("new.toml");
    let mut args = FIT.to_vec();
    args.extend(["--errors-out", arg(&errors)]);
    let out = trueaxis(&args);
    failed(&out, 2, &["--errors-out needs --machine"]);
    assert!(!errors.exists());
}

#[test]
fn only_motion_errors_are_fitted_with_or_without_a_machine() {
    // a constant (location error, setup error) or an axis the machine lacks is refused before fitting,
    // and nothing is written
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("e.toml");
    let e = arg(&errors);
    for (parameter, machine, fragment) in [
        ("EC0Y", false, "EC0Y is not a motion error"),
        ("EC0Y", true, "EC0Y is not a motion error"),
        ("TX", false, "TX is not a motion error"),
        ("WZ", true, "WZ is not a motion error"),
        ("EXB", true, "EXB refers to axis B, which machine"),
    ] {
        let mut args = vec!["fit", "--data", "examples/data/laser_x.csv", "--parameter", parameter, "--errors-out", e];
        if machine {
            args.extend(["--machine", "examples/machines/vmc3.toml"]);
        }
        let out = trueaxis(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(fragment) && err.contains("--parameter"), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(!errors.exists());
    }
}

#[test]
fn readings_too_large_to_be_deviations_are_refused_with_status_2_and_nothing_written() {
    // 1e300 um: the fit would overflow (a failed computation, status 1); the plausibility check of
    // the readings' unit refuses them first as bad input
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("huge.csv");
    let text: String = (0..21).map(|i| format!("{},{}\n", -400 + 40 * i, if i % 2 == 0 { 1e300 } else { -1e300 })).collect();
    std::fs::write(&data, format!("target,dev\n{text}")).unwrap();
    let (errors, plot) = (dir.path().join("e.toml"), dir.path().join("p.svg"));
    for json in [false, true] {
        let mut args = vec!["fit", "--data", arg(&data), "--parameter", "EXX", "--machine", "examples/machines/vmc3.toml"];
        args.extend(["--errors-out", arg(&errors), "--plot", arg(&plot)]);
        if json {
            args.push("--json");
        }
        let out = trueaxis(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains("huge.csv: line 2: column `dev`") && err.contains("outside the physical range of a reading"), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(out.stdout.is_empty(), "nothing printed: {}", String::from_utf8_lossy(&out.stdout));
        assert!(!errors.exists() && !plot.exists(), "nothing written");
    }
}

#[test]
fn residual_periods_stay_above_the_sampling_limit() {
    // laser_x.csv: every 20 mm, so no period below 40 mm can be seen (the old bound, span / readings
    // = 800 / 205 mm, reported 12.32 and 8.38 mm)
    let args = ["fit", "--data", "examples/data/laser_x.csv", "--parameter", "EXX", "--knot-spacing", "100", "--drift", "--direction=+"];
    let doc = json_of(&[&args[..], &["--json"]].concat());
    let r = &doc["residual_period"];
    assert_eq!(r["sampling_limit"].as_f64().unwrap(), 40.0);
    assert_eq!(r["sampling_step"].as_f64().unwrap(), 20.0);
    assert!(r["period"].as_f64().unwrap() >= 40.0, "{r}");
    // noise only: the strongest residual sinusoid is not significant, and the text says so
    assert_eq!(r["significant"], false, "{r}");
    let out = trueaxis(&args);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("not significant at 1 %") && text.contains("periods from 40.0000") && !text.contains("warning"), "{text}");
}

#[test]
fn an_aliased_screw_wave_is_flagged_with_its_alias_family() {
    // a 0.635025 mm scale error of 1 um sampled every 10 mm (Soons 1993 §3.2.4) appears at 39.59 mm;
    // the fit cannot tell which, and warns
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("screw.csv");
    let text: String = (0..=80)
        .map(|i| {
            let x = 10.0 * i as f64;
            format!("{x},{}\n", 0.01 * x + (2.0 * std::f64::consts::PI * x / 0.635025).sin())
        })
        .collect();
    std::fs::write(&data, format!("target,dev\n{text}")).unwrap();
    let args = ["fit", "--data", arg(&data), "--parameter", "EXX", "--family", "legendre", "--degree", "1"];
    let mut json_args = args.to_vec();
    json_args.push("--json");
    let doc = json_of(&json_args);
    let r = &doc["residual_period"];
    let alias = trueaxis::identify::alias_wavelength(0.635025, 10.0).unwrap();
    assert!((r["period"].as_f64().unwrap() - alias).abs() < 0.01 * alias, "{r} vs alias {alias}");
    assert_eq!(r["significant"], true);
    assert!((r["amplitude"].as_f64().unwrap() - 1.0).abs() < 0.05, "{r}");
    let aliases: Vec<f64> = r["aliases"].as_array().unwrap().iter().map(|a| a.as_f64().unwrap()).collect();
    // the longest aliases 1/|1/10 -+ 1/39.59| = 13.38, 7.98 mm ..., all below the 20 mm limit
    assert!((aliases[0] - 1.0 / (0.1 - 1.0 / alias)).abs() < 0.05 && aliases.iter().all(|a| *a < 20.0), "{aliases:?}");
    let out = trueaxis(&args);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("warning: samples every 10.0000 cannot tell this period from its aliases") && text.contains("--periodic"),
        "{text}"
    );
}

#[test]
fn temperature_options_correct_the_readings_to_20c() {
    // a steel scale (11.5 um/m/K) at 21.3 degC reads short by 11.5 * 1.3 * x / 1000 um: the fit with the
    // options equals the fit of the hand-corrected data
    let dir = tempfile::tempdir().unwrap();
    let corrected = dir.path().join("corrected.csv");
    let table = trueaxis::data::CsvTable::read(root().join("examples/data/laser_x.csv")).unwrap();
    let (x, dev, dir_col) = (table.numbers("target").unwrap(), table.numbers("dev").unwrap(), table.texts("dir").unwrap());
    let mut text = String::from("target,dev,dir\n");
    for i in 0..x.len() {
        text += &format!("{},{},{}\n", x[i], dev[i] - 11.5 * 1.3 * x[i] * 1e-3, dir_col[i]);
    }
    std::fs::write(&corrected, text).unwrap();
    let base = ["--parameter", "EXX", "--machine", "examples/machines/vmc3.toml", "--knot-spacing", "200", "--direction=+", "--json"];
    let mut by_hand = vec!["fit", "--data", arg(&corrected)];
    by_hand.extend(base);
    let mut with_options = vec!["fit", "--data", "examples/data/laser_x.csv", "--scale-temperature", "21.3", "--scale-expansion", "11.5"];
    with_options.extend(base);
    let (a, b) = (coefficients(&json_of(&by_hand)), coefficients(&json_of(&with_options)));
    for (a, b) in a.iter().zip(&b) {
        assert!((a - b).abs() < 1e-9 * a.abs().max(1e-3), "{a} vs {b}");
    }
    // the correction changes the slope by -EXX = +0.01495 um/mm (the reading -EXX drops by 0.01495 x)
    let mut raw = vec!["fit", "--data", "examples/data/laser_x.csv"];
    raw.extend(base);
    let (c, d) = (coefficients(&json_of(&raw)), coefficients(&json_of(&with_options)));
    assert!((d[1] - c[1] - 11.5 * 1.3e-3).abs() < 1e-9, "x^1: {} -> {}", c[1], d[1]);
    // a positioning correction applies to positioning readings only
    let out = trueaxis(&[
        "fit",
        "--data",
        "examples/data/laser_x.csv",
        "--parameter",
        "EYX",
        "--scale-temperature",
        "21.3",
        "--scale-expansion",
        "11.5",
    ]);
    failed(&out, 2, &["applies to positioning readings along the axis"]);
}

/// `trueaxis ARGS` is refused with exit status 2 and a one-line message holding `fragment`.
fn refused_fit(args: &[&str], fragment: &str) {
    let out = trueaxis(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(err.contains(fragment), "{args:?}: expected `{fragment}` in {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: one line: {err}");
}

#[test]
fn the_instrument_description_puts_the_abbe_terms_into_the_chain() {
    // laser_x.csv read with linear optics 150 mm above the tool point (z) and the pitch EBX = 10 urad
    // known: the optics are 200 + 150 = 350 mm above the table, the Abbe term 350 mm * 10 urad =
    // 3.5 um is removed: EXX moves by -3.5 um everywhere against the fit without the pitch
    let dir = tempfile::tempdir().unwrap();
    let known = dir.path().join("known.toml");
    std::fs::write(&known, "[constant]\nEBX = 10.0\n").unwrap();
    let fitted = |extra: &[&str]| {
        let mut args = FIT.to_vec();
        args.extend(["--machine", "examples/machines/vmc3.toml", "--at", "Z=-200", "--instrument", "laser-linear", "--json"]);
        args.extend(["--optics-offset", "0,150"]);
        args.extend(extra);
        coefficients(&json_of(&args)["plus"])
    };
    let (with, without) = (fitted(&["--errors-in", arg(&known)]), fitted(&[]));
    assert!((with[0] - without[0] + 3.5).abs() < 1e-6, "constant: {} vs {}", with[0], without[0]);
    for k in 1..with.len() {
        assert!((with[k] - without[k]).abs() < 1e-9, "term {k}: {} vs {}", with[k], without[k]);
    }
    // an instrument that cannot see the parameter, and options without a machine, are refused
    for (args, fragment) in [
        (vec!["--parameter", "ECX", "--machine", "examples/machines/vmc3.toml", "--instrument", "level"], "never yaw"),
        (vec!["--parameter", "EBX", "--machine", "examples/machines/vmc3.toml", "--optics-offset", "0,10"], "--optics-offset"),
        (vec!["--parameter", "EXX", "--instrument", "laser-linear"], "--instrument needs --machine"),
        (
            vec!["--parameter", "EBX", "--machine", "examples/machines/vmc3.toml", "--instrument", "level", "--level-reference", "Q"],
            "--level-reference",
        ),
    ] {
        refused_fit(&[&["fit", "--data", "examples/data/laser_x.csv"][..], &args].concat(), fragment);
    }
}

#[test]
fn known_angular_errors_have_their_abbe_term_removed() {
    // table pitch EBX = 10 urad about the moving reference point; the tool point is 200 mm above the
    // table (Z = -200 from 400 mm): the table point under the tool moves +200 mm * 10 urad = +2 um
    // in x, so the reading moves -2 um, and EXX = -(reading) - 2 um after the Abbe subtraction.
    let dir = tempfile::tempdir().unwrap();
    let known = dir.path().join("known.toml");
    std::fs::write(&known, "[constant]\nEBX = 10.0\n").unwrap();
    let (with, without) = (dir.path().join("with.toml"), dir.path().join("without.toml"));
    for (out_file, extra) in [(&with, vec!["--errors-in", arg(&known)]), (&without, vec![])] {
        let mut args = FIT.to_vec();
        args.extend(["--machine", "examples/machines/vmc3.toml", "--at", "Z=-200", "--errors-out", arg(out_file)]);
        args.extend(extra);
        let out = trueaxis(&args);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    let (a, b) = (fitted_exx(&with), fitted_exx(&without));
    for x in [-400.0, -123.0, 0.0, 250.0, 400.0] {
        assert!(((a(x) - b(x)) + 2.0).abs() < 1e-6, "at {x}: {}", a(x) - b(x));
    }
}

#[test]
fn bad_fit_input_is_refused_with_status_2() {
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["fit", "--data", "examples/data/laser_x.csv", "--parameter", "EQX"], "not an ISO 230 parameter name"),
        (vec!["fit", "--data", "examples/data/laser_x.csv", "--parameter", "EXX", "--value", "reading"], "missing column `reading`"),
        (vec!["fit", "--data", "examples/data/laser_x.csv", "--parameter", "EXB", "--machine", "examples/machines/vmc3.toml"], "axis B"),
        (vec!["fit", "--data", "examples/data/laser_x.csv", "--parameter", "EXX", "--at", "Z=-200"], "--at needs --machine"),
        (
            vec![
                "fit",
                "--data",
                "examples/data/laser_x.csv",
                "--parameter",
                "EXX",
                "--machine",
                "examples/machines/vmc3.toml",
                "--at",
                "Q=1",
            ],
            "no axis `Q`",
        ),
        (vec!["fit", "--data", "examples/data/laser_x.csv", "--parameter", "EXX", "--periodic", "0.635025"], "cannot be resolved"),
        (vec!["fit", "--data", "examples/data/laser_x.csv", "--parameter", "EXX", "--knots", "900"], "inside the domain"),
        (vec!["fit", "--data", "missing.csv", "--parameter", "EXX"], "missing.csv"),
    ];
    for (args, fragment) in cases {
        refused_fit(&args, fragment);
    }
}

#[test]
fn one_direction_alone_is_refused_with_a_hint_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("one.toml");
    let out = trueaxis(&vmc3(
        &["fit", "--data", "examples/data/laser_x.csv", "--parameter", "EXX"],
        &["--direction=+", "--errors-out", arg(&errors)],
    ));
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("EXX+ is given without EXX-") && stderr.contains("--direction both"), "{stderr}");
    assert!(!errors.exists(), "nothing may be written");
}
