//! `trueaxis fit` end to end on the shipped laser data (examples/data/laser_x.csv, simulated with a
//! known pitch error, backlash, drift and noise), the sign of a workpiece-carrying slide, the Abbe
//! subtraction of known angular errors, and bad input.

use std::process::{Command, Output};

fn trueaxis(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_trueaxis")).args(args).current_dir(env!("CARGO_MANIFEST_DIR")).output().unwrap()
}

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
    fitted_exx_of(errors_file, trueaxis::errors::Direction::Positive)
}

fn fitted_exx_of(errors_file: &std::path::Path, direction: trueaxis::errors::Direction) -> impl Fn(f64) -> f64 {
    let machine = trueaxis::machine::Machine::load(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/machines/vmc3.toml")).unwrap();
    let model = trueaxis::errors::ErrorModel::load(errors_file, &machine).unwrap();
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
    std::fs::copy(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/errors/vmc3.toml"), &errors).unwrap();
    let plot = dir.path().join("exx.svg");
    let mut args = FIT.to_vec();
    let (e, p) = (errors.to_str().unwrap(), plot.to_str().unwrap());
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
    let exx_minus = fitted_exx_of(&errors, trueaxis::errors::Direction::Negative);
    for x in [-300.0, 0.0, 300.0] {
        let b = exx(x) - exx_minus(x);
        assert!((b + 0.8).abs() < 0.2, "EXX+ - EXX- at {x}: {b}");
    }
    // the file is still a valid error-values file for predict, with the other errors kept
    let text = std::fs::read_to_string(&errors).unwrap();
    assert!(text.contains("[basis.\"EXX+\"]") && text.contains("[basis.EXX-]") && text.contains("EC0X = 12.0"), "{text}");
    let pred = trueaxis(&["predict", "--machine", "examples/machines/vmc3.toml", "--errors", e, "--poses", "examples/poses/vmc3.csv"]);
    assert!(pred.status.success(), "{}", String::from_utf8_lossy(&pred.stderr));
    let svg = std::fs::read_to_string(dir.path().join("exx_plus.svg")).unwrap();
    assert!(!plot.exists(), "with both directions the plots are exx_plus.svg and exx_minus.svg");
    assert!(dir.path().join("exx_minus.svg").exists());
    assert!(svg.contains("95 % prediction interval") && svg.contains("EXX (um)"));
}

#[test]
fn without_a_machine_the_readings_are_the_values() {
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("new.toml");
    let mut args = FIT.to_vec();
    args.extend(["--errors-out", errors.to_str().unwrap()]);
    let out = trueaxis(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let exx = fitted_exx(&errors);
    for x in [-400.0, -100.0, 200.0, 400.0] {
        assert!(((exx(x) - exx(0.0)) - (generated(x) - generated(0.0))).abs() < 0.25, "at {x}");
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
    for (out_file, extra) in [(&with, vec!["--errors-in", known.to_str().unwrap()]), (&without, vec![])] {
        let mut args = FIT.to_vec();
        args.extend(["--machine", "examples/machines/vmc3.toml", "--at", "Z=-200", "--errors-out", out_file.to_str().unwrap()]);
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
        (vec!["fit", "--data", "examples/data/laser_x.csv", "--parameter", "EXX", "--at", "Z=-200"], "need --machine"),
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
        let out = trueaxis(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(fragment), "{args:?}: expected `{fragment}` in {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    }
}

#[test]
fn one_direction_alone_is_refused_with_a_hint_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("one.toml");
    let out = trueaxis(&[
        "fit",
        "--data",
        "examples/data/laser_x.csv",
        "--parameter",
        "EXX",
        "--machine",
        "examples/machines/vmc3.toml",
        "--direction=+",
        "--errors-out",
        errors.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("EXX+ is given without EXX-") && stderr.contains("--direction both"), "{stderr}");
    assert!(!errors.exists(), "nothing may be written");
}
